"""The benches: which VHDL-AMS testbench entity to simulate, how long, with which top-level generics, and
how to judge the waveforms (metrics with references and tolerances, plots, the waveform table).

A bench's testbench entity names its measurement CSV in its header comment (`-- measurement: path`);
this module reads it from there, so the VHDL file stays the one place that says what it is compared with."""
from __future__ import annotations

import concurrent.futures
import importlib
import os
import pkgutil
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from .. import identify
from ..elaborate import Design, InstanceInfo, Library, elaborate
from ..errors import WrsimError
from ..measurements import Table, read_table
from ..ngspice import Analysis, lower
from ..report import BenchResult, Metric, Plot, Signal
from ..runner import Runner, Waveforms
from ..units import convert

__all__ = ["Bench", "Run", "Simulated", "BENCHES", "run_bench", "measurement_of", "ROOT"]

ROOT = Path(__file__).resolve().parents[3]
RPM = convert(1.0, "rad/s", "rpm")


@dataclass(frozen=True)
class Run:
    """One simulation of a bench: a label and top-level generic values. A value may be a function of the run's
    work folder that makes a file there and returns the generic (e.g. a switch sequence from a CAN log)."""

    label: str
    generics: dict[str, float | str | Callable[[Path], float | str]]

    def resolved(self, folder: Path) -> dict[str, float | str]:
        """The generic values; a function value makes its file in `folder` (the run's work folder)."""
        return {k: v(folder) if callable(v) else v for k, v in self.generics.items()}


@dataclass
class Simulated:
    run: Run
    design: Design
    waves: Waveforms
    folder: Path | None = None    # the run's work folder (netlist, logs, files made for the run)


@dataclass(frozen=True)
class Bench:
    name: str
    entity: str
    description: str
    stop: float                   # [s]
    max_step: float               # [s]
    runs: tuple[Run, ...]
    judge: Callable[["Bench", list[Simulated], Table | None], tuple[list[Metric], list[Plot], list[Signal]]]
    params: str = "fpg2_12nm"     # the bench's parameter set (params/<name>.txt); `--params` overrides it
    reltol: float = 1e-4          # ngspice's relative tolerance (see the bench module for a bench that differs)
    save: tuple[str, ...] = ()    # the quantities/signals the judge reads (all when empty; see ngspice.Analysis)


def measurement_of(lib: Library, entity: str) -> Path | None:
    """The CSV named by `-- measurement: <path>` in the testbench's header comment."""
    for line in lib.entity(entity).header.splitlines():
        if line.lower().startswith("measurement:"):
            return ROOT / line.split(":", 1)[1].strip()
    return None


def run_bench(bench: Bench, lib: Library, params, runner: Runner, workdir: Path) -> BenchResult:
    """Elaborate and lower every run of `bench`, simulate the runs concurrently (one ngspice process per core),
    then judge the waveforms."""
    t0 = time.perf_counter()
    jobs = []
    for run in bench.runs:
        design = elaborate(lib, bench.entity, params, run.resolved(workdir / run.label))
        jobs.append((run, design, lower(design, Analysis(bench.stop, bench.max_step, bench.reltol, save=bench.save),
                                          f"{bench.name} ({run.label})")))
    timings = {"lower": time.perf_counter() - t0}
    t0 = time.perf_counter()
    with concurrent.futures.ThreadPoolExecutor(max_workers=min(len(jobs), os.cpu_count() or 1)) as pool:
        waves = list(pool.map(lambda job: runner.run(job[2], workdir / job[0].label), jobs))
    timings["simulate"] = time.perf_counter() - t0
    sims = [Simulated(run, design, w, workdir / run.label) for (run, design, _), w in zip(jobs, waves)]
    csv = measurement_of(lib, bench.entity)
    table = read_table(csv, require_source=True) if csv else None
    metrics, plots, signals = bench.judge(bench, sims, table)
    return BenchResult(bench.name, bench.description, str(csv.relative_to(ROOT)) if csv else None, signals,
                       metrics, plots, timings, all(m.passed for m in metrics))


# ------------------------------------------------------------------------------------------------
# helpers shared by the judges
def instance(tree: InstanceInfo, path: str) -> InstanceInfo:
    node = tree
    for label in path.split("."):
        node = next((c for c in node.children if c.path.endswith("." + label)), None)
        if node is None:
            raise WrsimError(f"internal: no instance {path} in {tree.path}")
    return node


def motor_params(info: InstanceInfo) -> identify.MotorParams:
    g = info.generics
    return identify.MotorParams(g["ke"], g["kt"], g["ra"], g["laa"], g["j"], g["visc"], g["mc"])


def rel_error_pct(sim: np.ndarray, ref: np.ndarray) -> np.ndarray:
    return np.abs(sim / ref - 1.0) * 100.0


def on_load(torque: np.ndarray, values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Values of a characteristic line at load torques `at` (torque rises monotonically over the ramp)."""
    return np.interp(at, torque, values)


def metric(name: str, value: float, reference: float, tolerance: float, unit: str, note: str = "") -> Metric:
    return Metric(name, float(value), float(reference), float(tolerance), unit,
                  bool(abs(value - reference) <= tolerance), note)


def resampled(sims: list[Simulated], columns: dict[str, tuple[str, Callable[[Simulated], np.ndarray]]],
              stop: float, points: int = 2001) -> list[Signal]:
    """The waveform table: every run resampled on one uniform time grid (runs have their own steps)."""
    t = np.linspace(0.0, stop, points)
    out = [Signal("time", "s", t)]
    for s in sims:
        for name, (unit, get) in columns.items():
            out.append(Signal(f"{name}_{s.run.label}", unit, np.interp(t, s.waves.time, get(s))))
    return out




def _registry() -> dict[str, Bench]:
    """Every module of this package contributes its `BENCHES` list (one module per model family)."""
    out: dict[str, Bench] = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        for b in importlib.import_module(f"{__name__}.{info.name}").BENCHES:
            if b.name in out:
                raise WrsimError(f"internal: bench '{b.name}' is defined twice")
            out[b.name] = b
    return out


BENCHES: dict[str, Bench] = _registry()
