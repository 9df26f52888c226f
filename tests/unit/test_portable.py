"""Portability to 1076.1 tools (issue 18, part): every file of vhdl/ and testbenches/ analyses with a VHDL-AMS
analyzer in 1076.1 mode on the VHDL-93 base, as Saber and SystemVision import them: GHDL 5 (Debian trixie, unpacked
privately by ci/setup.sh) with --ams --std=93c. The digital units are in the common subset of VHDL-93 and -2008:
bookworm's GHDL, which runs them, analyses them with --std=93c too."""

from __future__ import annotations

import shutil
import subprocess

from wrsim import paths
from wrsim.backend.ghdl.build import GHDL
from wrsim.benches.export import export_set
from wrsim.elab import load_library
from wrsim.frontend import ast


def test_every_digital_file_analyses_as_vhdl_93(tmp_path):
    lib = load_library(paths.LIBRARY)
    tops = [u.name for f in lib.files if f.digital for u in f.units if isinstance(u, ast.Entity)]
    files = lib.digital_files(tops)  # each after the packages it uses, wr_digital_params among them
    assert {f.name for f in files} >= {
        "wr_digital_params.vhd",
        "antipinch.vhd",
        "switch.vhd",
        "ecu_software.vhd",
        "tb_ecu_software_unit.vhd",
    }
    for f in files:
        out = subprocess.run(
            [shutil.which(GHDL) or GHDL, "-a", "--std=93c", f"--workdir={tmp_path}", str(f)],
            capture_output=True,
            text=True,
            cwd=tmp_path,
        )
        assert out.returncode == 0, f"{f}: {out.stderr.strip()}"


GHDL5 = paths.NATIVE / "ghdl5" / "ghdl"  # ci/setup.sh
GHDL5_IEEE = (
    "v93/std_logic_1164.vhdl",
    "v93/std_logic_1164-body.vhdl",
    "v93/numeric_std.vhdl",
    "v93/numeric_std-body.vhdl",
    "math_real.vhdl",
    "math_real-body.vhdl",
)


def _analyse(workdir, files: list, library: str = "work") -> dict:
    """Analyse `files` into `library` with GHDL 5 --ams --std=93c, each after those it needs (analysed again until
    no more succeed); the files that still fail, with GHDL's first error."""
    failing = {}
    pending = list(files)
    while pending:
        failing = {}
        for f in pending:
            out = subprocess.run(
                [str(GHDL5), "-a", "--std=93c", "--ams", "--ieee=none", f"--work={library}", str(f)],
                capture_output=True,
                text=True,
                cwd=workdir,
            )
            if out.returncode != 0:
                failing[f] = next((line for line in out.stderr.splitlines() if "error" in line), out.stderr.strip())
        if len(failing) == len(pending):
            break
        pending = list(failing)
    return failing


def test_every_file_analyses_as_vhdl_ams_on_the_vhdl_93_base(tmp_path):
    assert GHDL5.exists(), f"{GHDL5} missing: run `make setup` (ci/setup.sh unpacks GHDL 5 of Debian trixie)"
    src = GHDL5.parent / "root" / "usr" / "lib" / "ghdl" / "src" / "ieee"
    assert _analyse(tmp_path, [src / f for f in GHDL5_IEEE], "ieee") == {}
    assert _analyse(tmp_path, sorted((paths.VHDL / "ieee").glob("*.vhd")), "ieee") == {}
    files = [f for root in paths.LIBRARY for f in sorted(root.rglob("*.vhd")) if f.parent.name != "ieee"]
    assert len(files) >= 35
    assert _analyse(tmp_path, files) == {}


def test_exported_packages_analyse_in_place_of_the_librarys(tmp_path):
    """`wrsim export` writes standard VHDL: the library analyses with the exported packages instead of its own
    (GHDL 5, --ams --std=93c), and the digital package with bookworm's GHDL as well."""
    analog = export_set("fpg2_12nm_m30c", None, tmp_path / "analog")[0].path
    digital = export_set(paths.ALGORITHMS / "observer.txt", None, tmp_path / "digital")[1].path
    assert "-- set:" in analog.read_text() and "-- set:" in digital.read_text()
    work = tmp_path / "ghdl5"
    work.mkdir()
    src = GHDL5.parent / "root" / "usr" / "lib" / "ghdl" / "src" / "ieee"
    assert _analyse(work, [src / f for f in GHDL5_IEEE], "ieee") == {}
    assert _analyse(work, sorted((paths.VHDL / "ieee").glob("*.vhd")), "ieee") == {}
    replaced = {f.name: f for f in (analog, digital)}
    files = [
        replaced.get(f.name, f)
        for root in paths.LIBRARY
        for f in sorted(root.rglob("*.vhd"))
        if f.parent.name != "ieee"
    ]
    assert analog in files and digital in files
    assert _analyse(work, files) == {}
    lib = load_library(paths.LIBRARY, over=[digital])
    for f in lib.digital_files(["ecu_software"]):
        out = subprocess.run(
            [shutil.which(GHDL) or GHDL, "-a", "--std=93c", f"--workdir={tmp_path}", str(f)],
            capture_output=True,
            text=True,
            cwd=tmp_path,
        )
        assert out.returncode == 0, f"{f}: {out.stderr.strip()}"
    assert digital in lib.digital_files(["ecu_software"])
