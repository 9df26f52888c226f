"""What a bench is (which VHDL-AMS testbench entity to simulate, how long, with which top-level generics, how
to judge the waveforms), how its runs are simulated, and the helpers the judges share.

A bench's testbench entity names its measurement CSV in its header comment (`-- measurement: path`);
this module reads it from there, so the VHDL file stays the one place that says what it is compared with."""

from __future__ import annotations

import concurrent.futures
import contextlib
import dataclasses
import functools
import math
import os
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import overload

import numpy as np

from wrsim import paths
from wrsim.backend.ngspice.netlist import Analysis, Netlist
from wrsim.backend.ngspice.raw import Waveforms
from wrsim.benches.known import DEFAULT_SETS, mark
from wrsim.closed_form.motor import MotorParams
from wrsim.data.measurements import Table, read_table
from wrsim.data.params import ParamSet, find_param_set, load_params
from wrsim.data.temperature import at_temperature
from wrsim.elab.design import Design, InstanceInfo, instance
from wrsim.elab.elaborate import elaborate
from wrsim.elab.library import Library
from wrsim.errors import WrsimError
from wrsim.results import BenchResult, Grid, Metric, Plot, Signal
from wrsim.runner import Runner, prepare

__all__ = [
    "Bench",
    "Run",
    "Layers",
    "bench_params",
    "run_params",
    "testbench_params",
    "Simulated",
    "Judgement",
    "Judge",
    "Output",
    "Session",
    "run_bench",
    "simulate_runs",
    "measurement_of",
    "instance",
    "motor_params",
    "measured",
    "rel_error_pct",
    "on_load",
    "metric",
    "resampled",
    "every_waveform",
    "RPM",
]

RPM = 30.0 / math.pi  # [rpm per rad/s], what pint converts (a constant, so that importing a bench loads no pint)


@dataclass(frozen=True)
class Run:
    """One simulation of a bench: a label and top-level generic values. A value may be a function of the run's
    work folder that makes a file there and returns the generic (e.g. a switch sequence from a CAN log).
    `params`: the run's own parameter set, a file or several laid in order (or sets made in memory, e.g. a scenario's
    ambient temperature), laid over the bench's set for this run and beneath the user's `--params`."""

    label: str
    generics: dict[str, float | str | Callable[[Path], float | str]]
    params: Path | ParamSet | tuple[Path | ParamSet, ...] | None = None

    @property
    def layers(self) -> tuple[Path | ParamSet, ...]:
        """The run's own parameter sets in the order they are laid."""
        return self.params if isinstance(self.params, tuple) else () if self.params is None else (self.params,)

    def parameters(self, bench_set: ParamSet | None) -> ParamSet | None:
        """The parameter set of this run from `bench_params`'s set: the run's own set laid beneath the user's sets,
        at the result's `[ambient] temperature` (data.temperature.at_temperature)."""
        own = None
        for layer in self.layers:
            one = layer if isinstance(layer, ParamSet) else load_params(layer)
            own = one if own is None else own.overlay(one)
        if own is None:
            return None if bench_set is None else at_temperature(bench_set)
        return at_temperature(own if bench_set is None else bench_set.beneath(own))

    def resolved(self, folder: Path) -> dict[str, float | str]:
        """The generic values; a function value makes its file in `folder` (the run's work folder)."""
        return {k: v(folder) if callable(v) else v for k, v in self.generics.items()}

    def number(self, name: str) -> float:
        """The value of the numeric generic `name` of this run."""
        v = self.generics[name]
        if callable(v) or isinstance(v, str):
            raise WrsimError(f"internal: generic '{name}' of run {self.label} is not a number")
        return v


@dataclass
class Simulated:
    """One simulated run: its design (instance tree with the generic values) and waveforms."""

    run: Run
    design: Design
    waves: Waveforms
    folder: Path  # the run's work folder (netlist, logs, files made for the run)


@dataclass(frozen=True, kw_only=True)
class Judgement:
    """What a judge makes of a bench's runs: metrics against references, plots and grids, the waveform table
    (`waveforms[0]` is time[s])."""

    metrics: list[Metric]
    plots: Sequence[Plot | Grid] = field(default_factory=list)
    waveforms: list[Signal] = field(default_factory=list)


@dataclass(frozen=True)
class Session:
    """What a bench runs with: the library, the parameter set, the simulator and the bench's work folder. A judge
    that needs further simulations (the identification bench) runs them through `simulate_runs` with it."""

    lib: Library
    params: ParamSet | None
    runner: Runner
    workdir: Path


Judge = Callable[["Bench", list[Simulated], Table | None, Session], Judgement]


@dataclass(frozen=True)
class Output:
    """A quantity a bench's runs produce, for a tolerance study: its value and the specification limits it is held
    to (None: no limit on that side), with where the limits come from."""

    name: str
    value: float
    unit: str
    lower: float | None = None
    upper: float | None = None
    note: str = ""


Outputs = Callable[["Bench", list[Simulated]], list[Output]]


class LazyRuns(Sequence["Run"]):
    """A bench's runs, built at their first use: the closed-loop benches read their runs from scenario files, which
    a command that only lists or selects benches need not read (`build`: a module-level function, so that a bench
    travels to a Dask worker)."""

    def __init__(self, build: Callable[[], Sequence[Run]]) -> None:
        self._build = build
        self._runs: tuple[Run, ...] | None = None

    def _all(self) -> tuple[Run, ...]:
        if self._runs is None:
            self._runs = tuple(self._build())
        return self._runs

    @overload
    def __getitem__(self, index: int) -> Run: ...
    @overload
    def __getitem__(self, index: slice) -> tuple[Run, ...]: ...

    def __getitem__(self, index: int | slice) -> Run | tuple[Run, ...]:
        return self._all()[index]

    def __len__(self) -> int:
        return len(self._all())


@dataclass(frozen=True, kw_only=True)
class Bench:
    """A thesis experiment: the testbench entity, the runs (top-level generics), the analysis, and the judge."""

    name: str
    entity: str  # the testbench entity (testbenches/tb_<...>.vhd)
    description: str
    stop: float  # [s] end of the transient analysis
    max_step: float | None  # [s] ngspice's largest step (None: Analysis.step's default)
    runs: Sequence[Run]  # a tuple, or LazyRuns
    judge: Judge
    params: str = paths.DEFAULT_PARAMS  # the bench's parameter set (params/<name>.txt); `--params` overlays it
    reltol: float = 1e-4  # ngspice's relative tolerance (see the bench module for a bench that differs)
    save: tuple[str, ...] = ()  # the quantities/signals the judge reads (all when empty; see Analysis)
    exact_crossings: bool = True  # see Analysis (a bench that turns it off says why)
    outputs: Outputs | None = None  # what a tolerance study records of the runs (default: the judge's metrics)
    timeout: float = 600.0  # [s] wall time one run's simulator may take before it is stopped (an error)
    ac: tuple[float, float, int] | None = None  # a small-signal analysis instead (Analysis.ac)
    noise: tuple[str, float, float, int, str | None] | None = None  # a noise analysis instead (Analysis.noise)

    def analysis(self) -> Analysis:
        """The transient analysis of every run."""
        return Analysis(
            self.stop,
            self.max_step,
            self.reltol,
            save=self.save,
            exact_crossings=self.exact_crossings,
            ac=self.ac,
            noise=self.noise,
        )


Layers = str | Path | Sequence[str | Path] | None  # the user's parameter sets: one, or several in order


@overload
def bench_params(base: Bench, user: Layers = None) -> ParamSet: ...
@overload
def bench_params(base: str | Path | None, user: Layers = None) -> ParamSet | None: ...


def bench_params(base: Bench | str | Path | None, user: Layers = None) -> ParamSet | None:
    """The parameter set a run starts from: `base` (a bench, whose own set it takes, or a set's name or file; None:
    the models' defaults) with each of the user's sets (`--params`, in the order given) laid over it. The user's
    sets stay on top when a run lays its own set over the bench's (`Run.parameters`, which also applies the ambient
    temperature): `run.parameters(bench_params(bench, user))` is the one parameter resolution of every command
    (testbench, run, lower, dump, study, score, export, regression, scenario). None: no set at all."""
    if isinstance(base, Bench) and not base.params:
        raise WrsimError(f"internal: bench {base.name} has no parameter set")
    base = base.params if isinstance(base, Bench) else base
    given = None
    for name in [user] if isinstance(user, (str, Path)) else user or ():
        one = load_params(find_param_set(name))
        given = one if given is None else given.overlay(one)
    if not base:
        return None if given is None else dataclasses.replace(given, user=given)
    below = load_params(find_param_set(base))
    return below.overlay(given, user=True) if given else below


def run_params(base: Bench | str | Path | None, user: Layers = None, run: Run | None = None) -> ParamSet | None:
    """The parameter set of `run` (None: a run without a set of its own, e.g. `wrsim run`, `lower`, `export`): the
    base set, the run's own set, each of the user's sets in order, at the result's ambient temperature."""
    return (run or Run("", {})).parameters(bench_params(base, user))


def testbench_params(lib: Library, entity: str) -> Path | None:
    """The parameter set a testbench names in its header comment (`parameter set: <path>`, relative to the
    testbench's folder or to the repository), the base of every run of it; None when it names none."""
    unit = lib.entity(entity)
    for line in unit.header.splitlines():
        for part in line.split(";"):
            key, colon, value = part.strip().partition(":")
            if colon and key.strip().lower() == "parameter set":
                name = value.strip()
                beside = Path(unit.loc.file).parent / name
                path = beside if beside.is_file() else paths.ROOT / name
                if not path.is_file():
                    raise WrsimError(
                        f"{unit.loc.file}: the header names parameter set '{name}', which is neither "
                        f"beside the file nor in the repository"
                    )
                return path
    return None


def measurement_of(lib: Library, entity: str) -> Path | None:
    """The CSV named by `-- measurement: <path>` in the testbench's header comment (relative to the repository)."""
    for line in lib.entity(entity).header.splitlines():
        if line.lower().startswith("measurement:"):
            return paths.ROOT / line.split(":", 1)[1].strip()
    return None


_SIMULATORS = threading.BoundedSemaphore(os.cpu_count() or 1)  # simulator processes at once, over all benches


def simulate_runs(
    bench: Bench,
    lib: Library,
    params: ParamSet | None,
    runner: Runner,
    workdir: Path,
    runs: tuple[Run, ...] | None = None,
    parallel: int | None = None,
    on_run: Callable[[Run], None] | None = None,
) -> tuple[list[Simulated], dict[str, float]]:
    """Elaborate every run of `bench` (or `runs`), lower it and build its folder `workdir/<label>`, then simulate
    the runs concurrently (at most one simulator process per core, also with other benches running; at most
    `parallel` of these runs at once; `on_run` is told of each simulated run). Returns the runs and the time spent
    per phase."""
    t0 = time.perf_counter()
    jobs = []
    for run in runs if runs is not None else bench.runs:
        folder = workdir / run.label
        design = elaborate(lib, bench.entity, run.parameters(params), run.resolved(folder))
        title = bench.name if run.label == bench.name else f"{bench.name} ({run.label})"
        jobs.append((run, design, prepare(design, bench.analysis(), folder, runner, title)))
    timings = {"lower": time.perf_counter() - t0}
    t0 = time.perf_counter()

    def simulate(job: tuple[Run, Design, Netlist]) -> Waveforms:
        with _SIMULATORS:
            waves = runner.run(job[2], workdir / job[0].label, bench.timeout)
        if on_run is not None:
            on_run(job[0])
        return waves

    with concurrent.futures.ThreadPoolExecutor(max_workers=min(len(jobs), parallel or os.cpu_count() or 1)) as pool:
        waves = list(pool.map(simulate, jobs))
    timings["simulate"] = time.perf_counter() - t0
    return [Simulated(run, design, w, workdir / run.label) for (run, design, _), w in zip(jobs, waves)], timings


def run_bench(
    bench: Bench,
    lib: Library,
    params: ParamSet | None,
    runner: Runner,
    workdir: Path,
    on_run: Callable[[Run], None] | None = None,
) -> BenchResult:
    """Simulate every run of `bench` (`simulate_runs`), then judge the waveforms against the measurement."""
    sims, timings = simulate_runs(bench, lib, params, runner, workdir, on_run=on_run)
    csv = measurement_of(lib, bench.entity)
    table = read_table(csv, require_source=True) if csv else None
    j = bench.judge(bench, sims, table, Session(lib, params, runner, workdir))
    measurement = None if csv is None else paths.shown(csv)
    user = params.user if params is not None else None
    metrics = mark(bench.name, j.metrics, user.name if user is not None else DEFAULT_SETS)  # documented: KNOWN
    return BenchResult(
        bench.name,
        bench.description,
        measurement,
        j.waveforms,
        metrics,
        list(j.plots),
        timings,
        all(m.passed or m.known for m in metrics),
    )


# ------------------------------------------------------------------------------------------------
# helpers shared by the judges
def measured(bench: Bench, table: Table | None) -> Table:
    """The bench's measurement table (named in its testbench header)."""
    if table is None:
        raise WrsimError(f"bench {bench.name}: its testbench names no measurement file (-- measurement: ...)")
    return table


def motor_params(info: InstanceInfo) -> MotorParams:
    g = info.generics
    return MotorParams(g["ke"], g["kt"], g["ra"], g["laa"], g["j"], g["visc"], g["mc"])


def rel_error_pct(sim: np.ndarray, ref: np.ndarray) -> np.ndarray:
    return np.abs(sim / ref - 1.0) * 100.0


def on_load(torque: np.ndarray, values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Values of a characteristic line at load torques `at` (torque rises monotonically over the ramp)."""
    return np.interp(at, torque, values)


def metric(name: str, value: float, reference: float, tolerance: float, unit: str, note: str = "") -> Metric:
    """`value` within `reference` +- `tolerance`."""
    return Metric(
        name, float(value), float(reference), float(tolerance), unit, bool(abs(value - reference) <= tolerance), note
    )


def at_most(name: str, value: float, limit: float, unit: str, note: str = "") -> Metric:
    """`value` in 0 .. `limit` (a legal limit on a force: reported as <= limit)."""
    return dataclasses.replace(metric(name, value, limit / 2, limit / 2, unit, note), kind="limit")


def flag(name: str, holds: bool, expected: bool = True, note: str = "") -> Metric:
    """Whether something holds, expected to (or not to): reported as yes / no."""
    return Metric(name, float(holds), float(expected), 0.0, "1", bool(holds) == bool(expected), note, kind="flag")


def every_waveform(sims: list[Simulated], stop: float) -> list[Signal]:
    """The waveform table of every quantity and signal that all of `sims` saved (a bench may save only some),
    resampled like `resampled`: for a run nothing judges (a user's testbench, a sample a judge cannot judge)."""

    def saved(s: Simulated) -> set[str]:
        out = set()
        for name in s.waves.probes:
            with contextlib.suppress(WrsimError):
                s.waves[name]
                out.add(name)
        return out

    names = sorted(set.intersection(*(saved(s) for s in sims)))
    return resampled(sims, {n: ("", functools.partial(_wave, n)) for n in names}, stop)


def _wave(name: str, s: Simulated) -> np.ndarray:
    return s.waves[name]


def resampled(
    sims: list[Simulated],
    columns: dict[str, tuple[str, Callable[[Simulated], np.ndarray]]],
    stop: float,
    points: int = 2001,
) -> list[Signal]:
    """The waveform table: every run resampled on one uniform time grid (runs have their own steps)."""
    t = np.linspace(0.0, stop, points)
    out = [Signal("time", "s", t)]
    for s in sims:
        for name, (unit, get) in columns.items():
            out.append(Signal(f"{name}_{s.run.label}", unit, np.interp(t, s.waves.time, get(s))))
    return out
