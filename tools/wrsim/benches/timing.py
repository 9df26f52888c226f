"""Where a bench's time goes (`wrsim bench`): each bench run once and timed, with the solver statistics of its runs
and the reference solver's time on the same equations."""

from __future__ import annotations

import concurrent.futures
import os
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import EVENT_FILE, Netlist
from wrsim.backend.ngspice.raw import SolverStatistics, Waveforms, read_events
from wrsim.benches.core import Bench, bench_params, run_bench
from wrsim.data.params import ParamSet
from wrsim.data.publish import unique_folder
from wrsim.elab.elaborate import elaborate
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.runner import Runner

__all__ = ["BenchTiming", "time_benches"]


@dataclass(frozen=True)
class BenchTiming:
    """Where a bench's wall time goes (summed over its runs), from the timers and the solver statistics of the
    runs (`Waveforms.statistics`)."""

    bench: str
    runs: int
    wall: float  # [s]
    lower: float  # [s] elaboration, lowering, build of the run folders
    simulate: float  # [s] the simulator processes (concurrent)
    simulated: float  # [s] simulated time per run
    points: int  # ngspice's accepted time points
    rejected: int  # ngspice's rejected time points
    iterations: int  # Newton iterations of the transient
    analysis: float  # [s] ngspice's own analysis time (CPU of the simulator processes)
    ghdl: float  # [s] wall time inside the digital units' steps
    landed: int  # steps shortened to land on an 'above crossing
    late: int  # crossings seen more than the resolution after they happened
    reference: float | None = None  # [s] the reference solver, IDAS on the same equations
    # (backend.reference_solver), summed over the runs
    reference_note: str = ""  # why there is no reference solver time

    @property
    def python(self) -> float:
        """[s] everything but the simulator processes: elaboration, lowering, reading and judging."""
        return self.wall - self.simulate


def time_benches(
    benches: list[Bench], user: Sequence[str | Path] = (), work: Path = paths.WORK, lib: Library | None = None
) -> list[BenchTiming]:
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
        out.append(
            BenchTiming(
                bench.name,
                len(bench.runs),
                wall,
                r.timings["lower"],
                r.timings["simulate"],
                bench.stop,
                s.points,
                s.rejected,
                s.iterations,
                s.analysis,
                s.ghdl,
                s.landed,
                s.late,
                seconds,
                note,
            )
        )
    return out


def _reference(bench: Bench, lib: Library, params: ParamSet | None, workdir: Path) -> tuple[float | None, str]:
    """The reference solver's time for `bench`: its runs' equations integrated by IDAS (backend.reference_solver)
    to the same stop with the same relative tolerance and largest step, the digital signals replayed from the
    ngspice run; as many programs at once as the bench's runs (two at once take longer each than one alone on the
    2-core machine); (seconds, "") or (None, why not)."""
    from wrsim.backend import reference_solver

    try:
        built = []
        for run in bench.runs:
            design = elaborate(lib, bench.entity, run.parameters(params), run.resolved(workdir / run.label))
            system = reference_solver.flatten(design)
            replay = read_events(workdir / run.label / EVENT_FILE) if system.inputs else None
            built.append(reference_solver.prepare(system, [bench.stop], bench.reltol, bench.analysis().step, replay))
        with concurrent.futures.ThreadPoolExecutor(max_workers=min(len(built), os.cpu_count() or 1)) as pool:
            return sum(r.seconds for r in pool.map(reference_solver.Integration.run, built)), ""
    except WrsimError as e:
        return None, f"{bench.name}: {e}"


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
