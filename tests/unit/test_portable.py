"""Portability to 1076.1 tools (issue 18, part): the digital units are written in the common subset of VHDL-93 and
VHDL-2008, so a VHDL-AMS analyzer on the VHDL-93 base (Saber, SystemVision) reads them as GHDL does; GHDL's
VHDL-93 mode (--std=93c) analyses every digital file of the library in dependency order."""
from __future__ import annotations

import shutil
import subprocess

from wrsim import paths
from wrsim.backend.ghdl.build import GHDL
from wrsim.frontend import parse_file


def test_every_digital_file_analyses_as_vhdl_93(tmp_path):
    files = [f for root in paths.LIBRARY for f in sorted(root.rglob("*.vhd")) if parse_file(f).digital]
    assert {f.name for f in files} >= {"antipinch.vhd", "switch.vhd", "ecu_software.vhd", "tb_ecu_software_unit.vhd"}
    order = sorted(files, key=lambda f: (f.name != "antipinch.vhd", f.parent.name == "testbenches"))  # packages first
    for f in order:
        out = subprocess.run([shutil.which(GHDL) or GHDL, "-a", "--std=93c", f"--workdir={tmp_path}", str(f)],
                             capture_output=True, text=True, cwd=tmp_path)
        assert out.returncode == 0, f"{f}: {out.stderr.strip()}"
