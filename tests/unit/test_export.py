"""Parameter sets as VHDL for Saber and SystemVision (issue 18): every model generic reads its default from the
packages wr_params / wr_digital_params, and `wrsim export` writes them with a set's values. Elaborated with the
exported packages in place of the library's, a bench gives the waveforms of the parameter-set overlay."""

from __future__ import annotations

import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from wrsim import paths
from wrsim.backend.export import vhdl_literal
from wrsim.benches import BENCHES
from wrsim.benches.core import bench_params, instance, simulate_runs
from wrsim.benches.export import export_set
from wrsim.benches.run import simulator
from wrsim.cli import main
from wrsim.elab import load_library
from wrsim.frontend import ast


def test_every_model_generic_reads_its_default_from_the_parameter_packages():
    lib = load_library(paths.LIBRARY)
    models = [
        u
        for f in lib.files
        for u in f.units
        if isinstance(u, ast.Entity)
        if f.path.startswith(str(paths.VHDL)) and "/ieee/" not in f.path
    ]
    constants = {d.name for p in ("wr_params", "wr_digital_params") for d in lib.packages[("work", p)].decls}
    assert len(models) >= 30
    for ent in models:
        for g in ent.generics:
            assert isinstance(g.default, ast.Name) and g.default.ident == f"{ent.name}_{g.name}", (ent.name, g.name)
            assert g.default.ident in constants


@pytest.mark.parametrize(
    "value, type_mark, text",
    [
        (1e-05, "real", "1.0e-5"),
        (73.0, "real", "73.0"),
        (-2.5e20, "real", "-2.5e20"),
        (0.1, "real", "0.1"),
        (3.0, "positive", "3"),
        (1.0, "boolean", "true"),
        (0.0, "boolean", "false"),
        ([1.5], "real_vector", "(0 => 1.5)"),
        ([0.0, 1e-3], "real_vector", "(0.0, 0.001)"),
    ],
)
def test_vhdl_literals_are_exact_and_valid(value, type_mark, text):
    assert vhdl_literal(value, type_mark) == text
    if type_mark == "real":
        assert float(text) == value


@settings(max_examples=500, derandomize=True, deadline=None)
@given(st.floats(allow_nan=False, allow_infinity=False))
def test_every_finite_real_is_written_as_a_vhdl_real_literal_that_reads_back_exactly(value):
    text = vhdl_literal(value, "real")
    assert re.fullmatch(r"-?\d+\.\d+(e-?\d+)?", text), text  # VHDL: digits on both sides of the point
    assert float(text) == value


def test_an_export_changes_only_the_sets_lines(tmp_path):
    files = export_set("fpg2_12nm_m30c", None, tmp_path)
    assert [f.path.name for f in files] == ["wr_params.vhd", "wr_digital_params.vhd"]
    ours = (paths.VHDL / "common" / "wr_params.vhd").read_text().splitlines()
    theirs = files[0].path.read_text().splitlines()
    body = theirs[next(i for i, line in enumerate(theirs) if not line.startswith("--")) :]
    assert len(body) == len(ours) - next(i for i, line in enumerate(ours) if not line.startswith("--"))
    changed = [line for line in body if "-- set: params/fpg2_12nm_m30c.txt:" in line]
    assert len(changed) == len(files[0].changed) == 13  # 7 motor, 2 gear, m_gc, 2 damper tables, bowden mu
    assert "constant dcpm_motor_ra              : resistance       := 0.4879139826;" in "\n".join(changed)
    assert "constant bowden_mu          : real     := 0.2;" in "\n".join(changed)
    assert set(body) - set(ours) == set(changed)
    assert files[1].changed == ()


def test_an_algorithm_set_fills_the_digital_package(tmp_path):
    files = export_set(paths.ALGORITHMS / "observer.txt", None, tmp_path)
    text = files[1].path.read_text()
    assert "constant ecu_software_algorithm        : natural  := 4;  -- set: params/antipinch/observer.txt:" in text


def test_an_algorithm_set_is_a_c_header_too(tmp_path):
    """The digital package is also written as wr_digital_params.h, for ECU code built from the set: a C compiler
    reads the set's values (algorithm 5's mode_ms, the threshold), booleans as 1/0 and strings as literals."""
    import shutil
    import subprocess

    export_set(paths.ALGORITHMS / "observer_settled.txt", None, tmp_path)
    header = tmp_path / "wr_digital_params.h"
    text = header.read_text()
    assert "#define WR_ECU_SOFTWARE_ALGORITHM 5  /* set: params/antipinch/observer_settled.txt:" in text
    assert '#define WR_SWITCH_SEQUENCE_FILE "switch_sequence.txt"' in text
    check = tmp_path / "check.c"
    check.write_text(
        '#include "wr_digital_params.h"\n'
        '_Static_assert(WR_ECU_SOFTWARE_ALGORITHM == 5 && WR_ECU_SOFTWARE_MODE_MS == 67, "algorithm 5");\n'
        '_Static_assert(WR_ECU_SOFTWARE_THRESHOLD_RPM == 400 && WR_ECU_SOFTWARE_REVERSE_ON_PINCH == 1, "set");\n'
        '_Static_assert(sizeof WR_ECU_SOFTWARE_LEARNED_FILE == 1, "an empty string");\n'
    )
    cc = shutil.which("cc") or shutil.which("gcc")
    assert cc is not None
    done = subprocess.run(
        [cc, "-std=c11", "-Wall", "-Werror", "-fsyntax-only", str(check)], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr


def test_bad_sets_stop_with_the_key_and_write_nothing(tmp_path, capsys):
    bad = tmp_path / "bad.txt"
    out = tmp_path / "out"
    for text, expected in [
        ("[tb_drive_characteristic]\nu_supply = 9 V\n", "bad.txt:2: [tb_drive_characteristic] u_supply: no constant"),
        (
            "[ecu_software]\nthreshold_rpm = 0 rpm\n",
            "bad.txt:2: [ecu_software] threshold_rpm = 0: ecu_software.threshold_rpm is positive (at least 1)",
        ),
        ("[dcpm_motor]\nkx = 1 1\n", "bad.txt:2: [dcpm_motor] kx: dcpm_motor has no generic 'kx'"),
    ]:
        bad.write_text(text)
        assert main(["export", "--params", str(bad), "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert expected in err and "Traceback" not in err
        assert not out.exists()
    assert main(["export", "--out", str(out)]) == 2
    assert "give --params SET, --bench BENCH or both" in capsys.readouterr().err


@pytest.mark.parametrize("overlay", ["fpg2_12nm", "fpg2_12nm_m30c"])
def test_exported_sets_reproduce_the_drive_characteristic(tmp_path, overlay):
    """The acceptance of issue 18: the exported package, elaborated in place of the library's and without any
    parameter set, gives the overlay's waveforms within 1e-6 (of each signal's range)."""
    bench = BENCHES["drive-characteristic"]
    runner = simulator()
    overlaid, _ = simulate_runs(
        bench, load_library(paths.LIBRARY), bench_params(bench, overlay), runner, tmp_path / "overlay"
    )
    export_set(overlay, bench.name, tmp_path / "export")
    exported_lib = load_library(paths.LIBRARY, over=[tmp_path / "export"])
    exported, _ = simulate_runs(bench, exported_lib, None, runner, tmp_path / "exported")
    for a, b in zip(overlaid, exported, strict=True):
        assert a.run.label == b.run.label
        assert sorted(a.waves.probes) == sorted(b.waves.probes)
        np.testing.assert_array_equal(a.waves.time, b.waves.time)
        for name in ["dut.motor.ia", "dut.gear.omega_g", "dut.speed_rpm", *a.waves.probes]:
            x, y = a.waves[name], b.waves[name]
            assert np.max(np.abs(x - y)) <= 1e-6 * max(np.ptp(x), 1e-12), name
    motor = instance(exported[0].design.tree, "dut.motor").generics
    assert motor["ke"] == bench_params(bench, overlay).number_in("dcpm_motor", "ke", "V*s/rad") != 21.7e-3
    ia = {s.run.label: s.waves["dut.motor.ia"] for s in exported}
    assert np.max(np.abs(ia["cw"])) > 5.0  # the drive ran up to stall: the comparison is not of zeros


def test_a_bench_export_names_its_runs_generics_and_brings_their_files(tmp_path):
    export_set(None, "pinch", tmp_path)
    text = (tmp_path / "wr_params.vhd").read_text()
    assert "-- Bench pinch: simulate entity tb_closed_loop for 27 s;" in text
    assert 'pinch: sequence_file => "files/pinch/pinch.txt", pinch_position => 0.33' in text
    assert (tmp_path / "files" / "pinch" / "pinch.txt").read_bytes() == (paths.SEQUENCES / "pinch.txt").read_bytes()
    assert "constant glass_m         : mass         := 2.55;  -- set: params/rail_wr_8p5nm.txt:" in text
