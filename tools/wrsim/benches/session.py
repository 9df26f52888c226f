"""Running benches as a user does: each bench with its own parameter set (optionally overlaid), its work folder
and its published result; a bench that fails to run is recorded as failed and the others still run."""
from __future__ import annotations

import concurrent.futures
import os
import shutil
import sys
import time
import traceback
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from tqdm import tqdm

from wrsim import paths
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import EVENT_FILE, Analysis, Netlist
from wrsim.backend.ngspice.raw import SolverStatistics, Waveforms, read_events
from wrsim.benches import BENCHES
from wrsim.benches.core import Bench, Judgement, Run, Simulated, bench_params, run_bench, run_params, testbench_params
from wrsim.benches.known import deviations
from wrsim.data.params import ParamSet
from wrsim.data.publish import unique_folder
from wrsim.elab.elaborate import elaborate
from wrsim.elab.generics import GenericValue, top_generics
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.report.results import write_bench_result, write_failure, write_index
from wrsim.results import BenchResult, Plot, Signal
from wrsim.runner import Runner

__all__ = ["simulator", "select_benches", "run_benches", "run_files", "solver_waveforms", "export_set", "BenchTiming",
           "time_benches"]


def select_benches(names: list[str] | None) -> list[Bench]:
    """The benches named (all when none); an unknown name is a WrsimError listing the known ones."""
    if not names:
        return list(BENCHES.values())
    unknown = [n for n in names if n not in BENCHES]
    if unknown:
        raise WrsimError(f"unknown bench '{unknown[0]}' (benches: {', '.join(BENCHES)})")
    return [BENCHES[n] for n in names]


def simulator(c_algorithm: str | Path | None = None) -> NgspiceBatch:
    """The simulator of the benches; `c_algorithm`: a C file linked into the ECU instead of the shipped
    vhdl/digital/antipinch.c (the functions of that file; the ECU calls them with `[ecu_software] algorithm = 1`,
    params/antipinch/c_twin.txt)."""
    if c_algorithm is None:
        return NgspiceBatch()
    path = Path(c_algorithm)
    if path.suffix != ".c" or not path.is_file():
        raise WrsimError(f"{path}: {'not found' if not path.exists() else 'not a C file'} (an anti-pinch algorithm "
                         f"in C implements the functions of vhdl/digital/antipinch.c)")
    return NgspiceBatch(c_files={"antipinch.c": path})


def run_benches(benches: list[Bench], user: Sequence[str | Path] = (), results: Path = paths.RESULTS,
                lib: Library | None = None, c_algorithm: str | Path | None = None,
                sets: Mapping[str, ParamSet | None] | None = None,
                runner: Runner | None = None) -> list[BenchResult | dict]:
    """Run `benches`, each in a work folder of its own (results/../work/<bench>/<run id>/), publish each result
    under `results/<bench>/` and rewrite the index. A bench that fails keeps its last good result and gets a
    failure record beside it; the others still run. Returns the results (a failed bench as {"bench", "passed":
    False, "error"}). User errors (unknown parameter set, bad library) are raised before anything runs.
    `c_algorithm`: see `simulator`. `sets`: each bench's parameter set by name, instead of `bench_params(bench,
    user)` (scenarios lay their own sets); `runner`: instead of `simulator(c_algorithm)`."""
    runner = runner or simulator(c_algorithm)
    runner.check()
    lib = lib or load_library(paths.LIBRARY)
    params = dict(sets) if sets is not None else {bench.name: bench_params(bench, user) for bench in benches}
    deviations()                        # a malformed testbenches/known.toml stops before anything runs
    # progress on a terminal: a bar over every run of every bench (elapsed, ETA) and a line per finished bench
    bar = tqdm(total=sum(len(b.runs) for b in benches), unit="run", desc="benches", disable=None,
               bar_format="{desc}: {n_fmt}/{total_fmt} runs |{bar}| {elapsed} elapsed, ETA {remaining} {postfix}")

    def run(bench: Bench) -> BenchResult | dict:
        workdir = unique_folder(results.parent / "work" / bench.name)
        t0 = time.perf_counter()

        def done(r: Run) -> None:
            bar.set_postfix_str(f"{bench.name} ({r.label})", refresh=False)
            bar.update(1)
        try:
            result = run_bench(bench, lib, params[bench.name], runner, workdir, on_run=done)
            write_bench_result(results, result)
            if not bar.disable:
                bar.write(f"{bench.name}: {'PASS' if result.passed else 'FAIL'} in {time.perf_counter() - t0:.1f} s")
            return result
        except WrsimError as e:
            message = str(e)
        except Exception as e:  # noqa: BLE001 - a defect in one bench must not stop the others
            log = workdir / "traceback.txt"
            log.write_text("".join(traceback.format_exception(e)), encoding="utf-8")
            message = f"internal error: {type(e).__name__}: {e} (traceback: {log})"
        write_failure(results, bench.name, message)
        if not bar.disable:
            bar.write(f"{bench.name}: error after {time.perf_counter() - t0:.1f} s")
        return {"bench": bench.name, "passed": False, "error": message, "metrics": {}}

    # Benches run side by side (their simulator processes share the cores, benches.core), so that a bench of one
    # run does not leave a core idle; results keep the order of `benches`.
    try:
        with concurrent.futures.ThreadPoolExecutor(max_workers=min(len(benches), os.cpu_count() or 1)) as pool:
            out = list(pool.map(run, benches))
    finally:
        bar.close()
    write_index(results)
    return out


_PLOTTED = 6          # signals in a user run's plot (the waveform table has all)


def run_files(files: Sequence[str | Path], top: str, stop: float, max_step: float | None = None,
              libraries: dict[str, list[str | Path]] | None = None, params: Sequence[str | Path] = (),
              generics: Mapping[str, GenericValue] | None = None, results: Path = paths.RESULTS,
              with_models: bool = False, reltol: float | None = None, save: Sequence[str] = (),
              resample: int | None = None) -> BenchResult:
    """Simulate a user's testbench `top` from `files` (files or folders, with the IEEE 1076.1.1 packages of
    vhdl/ieee and `libraries`: name -> files or folders; `with_models`: also wrsim's model library) and publish
    the waveforms (CSV and MDF4 at the solver's own time points, or `resample` uniform points; a plot of the first
    few) as results/run/<top>/. The parameter set is `bench_params`'s: the one the testbench's header names (`parameter
    set: ...`), then each of `params` in order, at the set's ambient temperature. `generics`: top-level generic
    values as users write them (elab.generics). `reltol` (default: the transient analysis's), `save`: the
    quantities and signals to write (all when empty). A file that does not parse stops the run only when `top`
    needs a unit it would give. With the models, a unit of `files` replaces the library's unit of the same name
    (e.g. the packages of `wrsim export`)."""
    if with_models:
        lib = load_library([paths.VHDL], libraries, tolerant=True, over=files)
    else:
        lib = load_library([paths.VHDL / "ieee", *files], libraries, tolerant=True)
    values = top_generics(lib, top.lower(), generics or {})
    base = testbench_params(lib, top.lower())
    pset = bench_params(base, params)
    runner = simulator()
    runner.check()

    notes: list[str] = []       # what the lowering accepted and left out (frequency-domain sources)

    def judge(bench: Bench, sims: list[Simulated], table: object, session: object) -> Judgement:
        notes.extend(n for s in sims for m in [*s.design.models, s.design.top] for n in m.notes)
        waves = solver_waveforms(sims[0], resample, bench.save)
        plot = Plot(f"{top}: {', '.join(w.name for w in waves[1:_PLOTTED + 1])}", waves[0], waves[1:_PLOTTED + 1], [],
                    [], "waveforms.png")
        return Judgement(metrics=[], plots=[plot] if len(waves) > 1 else [], waveforms=waves)

    bench = Bench(name=top.lower(), entity=top.lower(), description=f"{top} from {', '.join(map(str, files))}",
                  stop=stop, max_step=max_step, runs=(Run(top.lower(), dict(values)),), judge=judge,
                  params=str(base or ""), save=tuple(save), reltol=reltol or Analysis(stop).reltol)
    result = run_bench(bench, lib, pset, runner, unique_folder(paths.WORK / "run" / bench.name))
    write_bench_result(results / "run", result)
    write_index(results / "run")
    for note in dict.fromkeys(notes):
        print(f"note: {note}", file=sys.stderr)
    return result


def solver_waveforms(sim: Simulated, resample: int | None = None, save: Sequence[str] = ()) -> list[Signal]:
    """The quantities and signals `save` names (every one saved when empty) of one run by hierarchical name with its
    unit, at the solver's time points (or `resample` uniform points over the run); `[0]` is time[s]."""
    t = sim.waves.time
    grid = t if resample is None else np.linspace(float(t[0]), float(t[-1]), resample)
    out = [Signal("time", "s", grid)]
    for name in sorted(save or sim.waves.probes):
        try:
            values = sim.waves[name]
        except WrsimError:              # not saved
            continue
        out.append(Signal(name, sim.waves.probes[name].unit, values if resample is None else
                          np.interp(grid, t, values)))
    return out


@dataclass(frozen=True)
class BenchTiming:
    """Where a bench's wall time goes (summed over its runs), from the timers and the solver statistics of the
    runs (`Waveforms.statistics`)."""

    bench: str
    runs: int
    wall: float           # [s]
    lower: float          # [s] elaboration, lowering, build of the run folders
    simulate: float       # [s] the simulator processes (concurrent)
    simulated: float      # [s] simulated time per run
    points: int           # ngspice's accepted time points
    rejected: int         # ngspice's rejected time points
    iterations: int       # Newton iterations of the transient
    analysis: float       # [s] ngspice's own analysis time (CPU of the simulator processes)
    ghdl: float           # [s] wall time inside the digital units' steps
    landed: int           # steps shortened to land on an 'above crossing
    reference: float | None = None    # [s] the reference solver, IDAS on the same equations
                                      # (backend.reference_solver), summed over the runs
    reference_note: str = ""          # why there is no reference solver time

    @property
    def python(self) -> float:
        """[s] everything but the simulator processes: elaboration, lowering, reading and judging."""
        return self.wall - self.simulate


def time_benches(benches: list[Bench], user: Sequence[str | Path] = (), work: Path = paths.WORK,
                 lib: Library | None = None) -> list[BenchTiming]:
    """Run each bench once and time it."""
    runner = _Recording(NgspiceBatch())
    runner.check()
    lib = lib or load_library(paths.LIBRARY)
    params = {bench.name: bench_params(bench, user) for bench in benches}
    out = []
    for bench in benches:
        workdir = unique_folder(work / bench.name)
        t0 = time.perf_counter()
        r = run_bench(bench, lib, params[bench.name], runner, workdir)
        wall = time.perf_counter() - t0
        # the bench's own runs (not the simulations a judge adds)
        s = sum((runner.statistics[workdir / run.label] for run in bench.runs), SolverStatistics())
        seconds, note = _reference(bench, lib, params[bench.name], workdir)
        out.append(BenchTiming(bench.name, len(bench.runs), wall, r.timings["lower"], r.timings["simulate"],
                               bench.stop, s.points, s.rejected, s.iterations, s.analysis, s.ghdl, s.landed,
                               seconds, note))
    return out


def _reference(bench: Bench, lib: Library, params: ParamSet | None, workdir: Path) -> tuple[float | None, str]:
    """The reference solver's time for `bench`: its runs' equations integrated by IDAS (backend.reference_solver)
    to the same stop with the same relative tolerance and largest step, the digital signals replayed from the
    ngspice run; (seconds, "") or (None, why not)."""
    from wrsim.backend import reference_solver
    seconds = 0.0
    for run in bench.runs:
        design = elaborate(lib, bench.entity, run.parameters(params), run.resolved(workdir / run.label))
        try:
            system = reference_solver.flatten(design)
            replay = read_events(workdir / run.label / EVENT_FILE) if system.inputs else None
            seconds += reference_solver.integrate(system, [bench.stop], bench.reltol, bench.analysis().step,
                                                  replay).seconds
        except WrsimError as e:
            return None, f"{bench.name}: {e}"
    return seconds, ""


class _Recording:
    """The simulator of `time_benches`: runs as `runner` does and keeps the solver statistics of each run folder."""

    def __init__(self, runner: Runner) -> None:
        self.runner = runner
        self.name = runner.name
        self.statistics: dict[Path, SolverStatistics] = {}

    def check(self) -> str:
        return self.runner.check()

    def build(self, netlist: Netlist, workdir: Path) -> Path:
        return self.runner.build(netlist, workdir)

    def run(self, netlist: Netlist, workdir: Path, timeout: float = 600.0) -> Waveforms:
        waves = self.runner.run(netlist, workdir, timeout)
        self.statistics[workdir] = waves.statistics
        return waves


def export_set(user: str | Path | Sequence[str | Path] | None, bench: str | None, out: Path,
               lib: Library | None = None) -> list:
    """Write the parameter set of `user`'s sets laid in order (over bench `bench`'s own set when a bench is given)
    as the VHDL packages wr_params and wr_digital_params into `out` (backend.export); with a bench whose runs use
    different sets, one folder per run under `out`. The header says which simulator top and top-level generics
    each run has. Returns the backend's ExportedFile list."""
    from wrsim.backend.export import export_params
    user = [user] if isinstance(user, (str, Path)) else list(user or ())
    if not user and bench is None:
        raise WrsimError("export: give --params SET, --bench BENCH or both")
    lib = lib or load_library(paths.LIBRARY)
    b = select_benches([bench])[0] if bench else None
    given = bench_params(b, user)
    assert given is not None
    command = "wrsim export" + "".join(f" --params {u}" for u in user) + (f" --bench {bench}" if bench else "")
    ambient = given.sections.get("ambient", {}).get("temperature")
    where = f" at {given.number_in('ambient', 'temperature', 'degC'):g} degC" if ambient else ""
    header = [f"parameter set {given.name}{where} as VHDL, written by `{command}`; do not edit.",
              "Lines marked `set:` carry the set's values, in the unit the generic declares; the others keep the "
              "library's defaults."]
    if b is None:
        pset = run_params(None, user)
        assert pset is not None
        return export_params(lib, pset, out, header)
    runs = [(run, run.parameters(given) or given) for run in b.runs]
    shared = all(run.params == runs[0][0].params for run, _ in runs)
    written = []
    for run, pset in runs[:1] if shared else runs:
        told = [r for r, _ in runs] if shared else [run]
        lines = [f"Bench {b.name}: simulate entity {b.entity} for {b.stop:g} s; top-level generics of the run"
                 f"{'s' if len(told) > 1 else ''} (files: copied beside this one, paths relative to it):"]
        lines += [f"  {r.label}: " + (_generics(r, out) or "the defaults") for r in told]
        written += export_params(lib, pset, out if shared else out / run.label, header + lines)
    return written


def _generics(run: Run, out: Path) -> str:
    """A run's top-level generics as the simulator takes them (`Run.resolved`, the files it makes put into
    `out`/files/<run>); a file a generic names is copied there too, and named relative to `out`."""
    from wrsim.backend.export import vhdl_literal
    files = out / "files" / run.label
    if any(callable(v) for v in run.generics.values()):
        files.mkdir(parents=True, exist_ok=True)
    shown = []
    for name, value in run.resolved(files).items():
        if isinstance(value, str) and Path(value).is_file():
            if Path(value).resolve().parent != files.resolve():
                files.mkdir(parents=True, exist_ok=True)
                value = str(shutil.copyfile(value, files / Path(value).name))
            value = str(Path(value).resolve().relative_to(out.resolve()))
        text = f'"{value}"' if isinstance(value, str) else str(value) if isinstance(value, int) else \
            vhdl_literal(float(value), "real")
        shown.append(f"{name} => {text}")
    return ", ".join(shown)
