"""Where wrsim finds its files and where it writes: the one module that knows the repository layout.

Everything else takes paths as arguments and defaults to these. `WRSIM_BUILD` moves the build folder (results,
work folders, GHDL builds) elsewhere, e.g. to keep a read-only checkout clean."""

from __future__ import annotations

import os
from pathlib import Path

__all__ = [
    "ROOT",
    "VHDL",
    "TESTBENCHES",
    "LIBRARY",
    "GOLDEN",
    "KNOWN",
    "SCENARIOS",
    "PARAMS",
    "ECUS",
    "MEASUREMENTS",
    "CAN",
    "SEQUENCES",
    "ALGORITHMS",
    "PARAM_PACKAGES",
    "COSIM",
    "BUILD",
    "RESULTS",
    "WORK",
    "EXPORT",
    "NATIVE",
    "DEFAULT_PARAMS",
    "beside_results",
    "shown",
]

ROOT = Path(__file__).resolve().parents[2]  # the repository: tools/wrsim/paths.py -> ../..
VHDL = ROOT / "vhdl"  # the VHDL-AMS model library
TESTBENCHES = ROOT / "testbenches"  # the benches' VHDL-AMS testbench entities
LIBRARY = (VHDL, TESTBENCHES)  # what `load_library` reads by default
GOLDEN = TESTBENCHES / "golden"  # the benches' reference waveforms (waveform regression)
KNOWN = TESTBENCHES / "known.toml"  # documented deviations from the thesis (verdict KNOWN)
SCENARIOS = TESTBENCHES / "scenarios"  # closed-loop scenario files (TOML): compliance/ and cases/
PARAMS = ROOT / "params"  # parameter sets <name>.txt
MEASUREMENTS = PARAMS / "measurements"  # the thesis's measured data (CSV)
CAN = PARAMS / "can"  # DBC and replay logs
SEQUENCES = PARAMS / "sequences"  # switch sequences of the closed-loop benches
ECUS = PARAMS / "ecu"  # the ECU concepts beside the thesis's relays: ECU settings laid over a system set
ALGORITHMS = PARAMS / "antipinch"  # anti-pinch algorithms: ECU settings laid over a system set
# the packages every model generic reads its default from (`wrsim export` writes them with a set's values)
PARAM_PACKAGES = (VHDL / "common" / "wr_params.vhd", VHDL / "digital" / "wr_digital_params.vhd")
COSIM = ROOT / "tools" / "cosim"  # C: GHDL (VPI) <-> ngspice (d_cosim) glue, crossing driver
BUILD = Path(os.environ.get("WRSIM_BUILD") or ROOT / "build")
RESULTS = BUILD / "results"  # published bench results
WORK = BUILD / "work"  # run folders (netlists, raw files, logs)
EXPORT = BUILD / "export"  # parameter sets exported as VHDL packages
NATIVE = BUILD / "native"  # built native code: digital units, glue, crossing driver
DEFAULT_PARAMS = "fpg2_12nm"  # the default parameter set


def beside_results(results: str | Path, name: str) -> Path:
    """Where a command that publishes to `results` keeps its folder `name` (run folders: "work"): in the build folder
    beside the default results (BUILD/name), else inside the results folder given (results/name): a command writes
    nothing outside the folder it is given and the build folder."""
    results = Path(results)
    return BUILD / name if results.resolve() == RESULTS.resolve() else results / name


def shown(path: str | Path) -> str:
    """`path` relative to the repository when it lies inside it (what reports and exported files name, the same on
    any machine), else as it is."""
    full = Path(path).resolve()
    return str(full.relative_to(ROOT)) if full.is_relative_to(ROOT) else str(path)
