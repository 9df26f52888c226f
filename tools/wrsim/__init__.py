"""wrsim: window-regulator simulation toolkit.

The pipeline, one subpackage per stage::

    frontend/   VHDL-AMS source -> tokens -> design units (file:line:col on every node)
    elab/       library, scopes, symbolic evaluation -> the design IR (one equation system per architecture),
                pairing pass
    backend/    ngspice (readable netlist, batch runs, raw files); ghdl (digital units, d_cosim co-simulation);
                the reference solver (the same equations in SUNDIALS IDAS)
    runner.py   the one simulation path: lower -> build the run folder -> run
    benches/    the thesis's experiments and their judges, one module per chapter; scenarios, record and replay
    study/      tolerance studies: spreads sampled, samples run on local processes or Dask, resumable results,
                statistics and page; the anti-pinch fleet score and calibration on replayed records
    report/     results on disk, plots, pages and the index, MDF4, regression, the pages in a browser
    data/       file formats (parameter sets, measurements, raw curves, CAN); results.py the result types;
                closed_form/ closed-form references
    identify/   parameter identification and its reports; paths.py where files are; cli.py (arguments) and
                commands.py the command line

The public API::

    import wrsim
    lib = wrsim.load_library()                       # vhdl/ and testbenches/, or any paths
    design = wrsim.elaborate(lib, "tb_motor_characteristic", wrsim.load_params("fpg2_12nm"), {"direction": -1.0})
    waves = wrsim.simulate(design, wrsim.Analysis(stop=3.0, max_step=1e-3), Path("build/work/demo"))
    waves["dut.omega"]                               # np.ndarray, by hierarchical VHDL-AMS name
    result = wrsim.run_bench(wrsim.BENCHES["motor-characteristic"], lib, ...)
"""

from __future__ import annotations

import importlib
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from wrsim import paths
from wrsim.errors import SourceError, WrsimError

if TYPE_CHECKING:
    from wrsim.backend.ngspice import Analysis, Netlist, NgspiceBatch, Waveforms, lower
    from wrsim.benches import BENCHES, Bench, Judgement, Run, Simulated, run_bench
    from wrsim.benches.core import bench_params, run_params
    from wrsim.benches.run import run_benches
    from wrsim.data.params import ParamSet
    from wrsim.elab import Design, Library, elaborate
    from wrsim.runner import Runner, simulate

__all__ = [
    "load_library",
    "elaborate",
    "lower",
    "simulate",
    "run_bench",
    "run_benches",
    "load_params",
    "bench_params",
    "run_params",
    "Library",
    "Design",
    "Analysis",
    "Netlist",
    "Waveforms",
    "Runner",
    "NgspiceBatch",
    "Bench",
    "Run",
    "Simulated",
    "Judgement",
    "BENCHES",
    "ParamSet",
    "WrsimError",
    "SourceError",
    "paths",
]

# The API's names, imported on first use: `import wrsim` stays light (the command line starts quickly, and an
# interrupt during start-up reaches wrsim.cli.main as a KeyboardInterrupt, not as a traceback from an import).
_LAZY = {
    "Analysis": "wrsim.backend.ngspice",
    "Netlist": "wrsim.backend.ngspice",
    "NgspiceBatch": "wrsim.backend.ngspice",
    "Waveforms": "wrsim.backend.ngspice",
    "lower": "wrsim.backend.ngspice",
    "BENCHES": "wrsim.benches",
    "Bench": "wrsim.benches",
    "Judgement": "wrsim.benches",
    "Run": "wrsim.benches",
    "Simulated": "wrsim.benches",
    "run_bench": "wrsim.benches",
    "bench_params": "wrsim.benches.core",
    "run_params": "wrsim.benches.core",
    "run_benches": "wrsim.benches.run",
    "ParamSet": "wrsim.data.params",
    "Design": "wrsim.elab",
    "Library": "wrsim.elab",
    "elaborate": "wrsim.elab",
    "Runner": "wrsim.runner",
    "simulate": "wrsim.runner",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        value = getattr(importlib.import_module(_LAZY[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'wrsim' has no attribute '{name}'")


def load_library(sources: Sequence[str | Path] = paths.LIBRARY) -> Library:
    """Parse every VHDL-AMS file under `sources` (folders or files; default: the model library and the
    testbenches). Files in a folder named `ieee` go to library IEEE, the rest to WORK."""
    from wrsim.elab import load_library as load

    return load(list(sources))


def load_params(name_or_path: str | Path) -> ParamSet:
    """A parameter set by name (params/<name>.txt) or file path; lay it over another with `ParamSet.overlay`."""
    from wrsim.data.params import find_param_set
    from wrsim.data.params import load_params as load

    return load(find_param_set(name_or_path))
