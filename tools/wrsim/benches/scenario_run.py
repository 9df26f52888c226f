"""Running scenario files (benches.scenario): the judge of a scenario, warm starts (the ECU's learned state from one
normalization run per parameter set, and its counter at the glass height the plant starts at), and `run_scenarios`,
which runs many side by side and publishes a page per scenario and a summary."""

from __future__ import annotations

import hashlib
import threading
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.benches.closed_loop import (
    SAVE_ESTIMATE,
    Event,
    ecu_position,
    events,
    pinch_plot,
    pinch_signals,
    reopening,
)
from wrsim.benches.core import Bench, Judgement, Run, Session, Simulated, flag, instance, metric, simulate_runs
from wrsim.benches.scenario import (
    ECUS,
    MAX_STEP,
    RELTOL,
    SYSTEM_PARAMS,
    TESTBENCH,
    Scenario,
    check_runs,
    extra_generics,
    find_scenarios,
    load_scenario,
    load_scenarios,
    own_sets,
    scenario_params,
    scenario_run,
    with_ecu,
)
from wrsim.data.params import ParamSet
from wrsim.data.publish import unique_folder
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.results import BenchResult, Grid, Metric
from wrsim.runner import Runner

__all__ = [
    "WarmStart",
    "WarmCheck",
    "scenario_bench",
    "run_scenarios",
    "summary_rows",
    "warm_checks",
    "SUMMARY_COLUMNS",
]

LEARN_STOP = 10.0  # [s] the normalization run of a warm start: up 6 s into the frame, down 4 s
_LEARN_SEQUENCE = "T 0.0 1\nT 6.0 2\n"


@dataclass
class _Learned:
    file: Path  # the ECU's learned state after the normalization
    glass: np.ndarray  # [m] glass position on the learning run up, rising
    position: np.ndarray  # [edges] the ECU's counter at those glass positions, 0 at the top it found
    edges_per_m: float  # [1/m] the switch's conversion of its targets (its generic edges_per_m)


class WarmStart:
    """What a normalization run tells scenarios (benches.scenario.Learning): per parameter set (by its digest) one
    normalization run, from which the ECU's learned state (ecu_software's learned_out) and its counter against the
    glass position on the learning run up are taken. A warm-started run gets the learned state, the counter the
    glass height had in that run, and the glass at that height (tb_closed_loop: learned_file, start_position,
    glass_start); a glass height of a switch unit becomes the counter there, in the switch's metres."""

    def __init__(self, lib: Library, runner: Runner, workdir: Path, record: bool = False):
        self.lib, self.runner, self.workdir, self.record = lib, runner, workdir, record
        self.cache: dict[str, _Learned] = {}
        self.lock = threading.Lock()

    def generics(self, s: Scenario, pset: ParamSet | None) -> dict[str, float | str]:
        learned = self.learned(with_ecu(Run("", {}, own_sets(s) or None), s.ecu).parameters(pset), plant(s))
        position = float(np.rint(self._count(s, learned, s.glass0, "[start] glass")))
        return {"learned_file": str(learned.file), "start_position": position, "glass_start": s.glass0}

    def below_top(self, s: Scenario, pset: ParamSet | None, glass: float) -> float:
        learned = self.learned(with_ecu(Run("", {}, own_sets(s) or None), s.ecu).parameters(pset), plant(s))
        return float(self._count(s, learned, glass, "a glass height") / learned.edges_per_m)

    @staticmethod
    def _count(s: Scenario, learned: _Learned, glass: float, what: str) -> float:
        if not learned.glass[0] <= glass <= learned.glass[-1]:
            raise WrsimError(
                f"{s.file}: {what} {glass:g} m is outside the stroke of the normalization run "
                f"({learned.glass[0]:.3f} .. {learned.glass[-1]:.3f} m)"
            )
        return float(np.interp(glass, learned.glass, learned.position))

    def learned(self, pset: ParamSet | None, generics: dict[str, float | str] | None = None) -> _Learned:
        """The normalization run of the parameter set `pset` with the testbench generics `generics` (`plant`)."""
        generics = generics or {}
        key = hashlib.sha256(
            repr(
                (
                    None
                    if pset is None
                    else sorted(
                        (e, sorted((k, (p.value, p.unit)) for k, p in keys.items()))
                        for e, keys in pset.sections.items()
                    ),
                    sorted(generics.items()),
                )
            ).encode()
        ).hexdigest()[:16]
        with self.lock:
            if key not in self.cache:
                self.cache[key] = self._normalize(pset, generics, self.workdir / f"learn-{key}")
            return self.cache[key]

    def _normalize(self, pset: ParamSet | None, generics: dict[str, float | str], folder: Path) -> _Learned:
        folder.mkdir(parents=True, exist_ok=True)
        sequence = folder / "learn_sequence.txt"
        sequence.write_text(_LEARN_SEQUENCE, encoding="utf-8")
        out = (folder / "learn" / "learned.txt").resolve()
        run = Run("learn", {**generics, "sequence_file": str(sequence.resolve()), "learned_out": str(out)})
        if self.record:  # the ECU's inputs beside its learned state (benches.replay)
            run = Run(run.label, {**run.generics, "record_out": str(out.parent / "inputs.txt")})
        bench = Bench(
            name="learn",
            entity=TESTBENCH,
            description="normalization run of a warm start",
            stop=LEARN_STOP,
            max_step=MAX_STEP,
            runs=(run,),
            judge=_no_judge,
            params=SYSTEM_PARAMS,
            reltol=RELTOL,
            save=("normalized", "position", "plant.door.pane.pos", "motor_state"),
        )
        sims, _ = simulate_runs(bench, self.lib, pset, self.runner, folder)
        w = sims[0].waves
        normalized = w["normalized"] > 0.5
        if not normalized.any() or not out.is_file():
            raise WrsimError(
                f"warm start: the ECU did not normalize in the {LEARN_STOP:g} s normalization run ({folder})"
            )
        count = ecu_position(sims[0])
        # The counter against the glass on the learning run up, re-based to the top it found: the scale the learned
        # state is on, with the cable loop as at t = 0 (each later stall at the bottom winds it up by some 40 edges
        # more, so the run down is on another scale; docs/anti-pinch.md, "Warm start").
        k_norm = int(np.argmax(normalized))
        up = ~normalized & (np.rint(w["motor_state"]) == 1)
        glass = w["plant.door.pane.pos"][up]
        order = np.argsort(glass, kind="stable")
        switch = instance(sims[0].design.tree, "sw").generics["edges_per_m"]
        return _Learned(out, glass[order], count[up][order] - count[k_norm - 1], float(switch))


def plant(s: Scenario) -> dict[str, float | str]:
    """The testbench generics of `s` that its normalization run shares: the door and its ECU as they are (the supply,
    the [generics] such as another drum, the ECU concept), not what happens after the learning (obstacle,
    disturbances)."""
    shared: dict[str, float | str] = {k: v for k, v in s.values.items() if k == "u_nominal"}
    if s.ecu != "relay":
        shared["ecu_kind"] = ECUS[s.ecu][0]
    return {**shared, **extra_generics(s)}


def _no_judge(bench: Bench, sims: list[Simulated], table: object, session: Session) -> Judgement:
    return Judgement(metrics=[])


def _judge(s: Scenario) -> Callable[[Bench, list[Simulated], object, Session], Judgement]:
    """Every closing (run up after the normalization) of a scenario with its peak force and reversal against
    [expect], and the glass at the end."""

    def judge(bench: Bench, sims: list[Simulated], table: object, session: Session) -> Judgement:
        sim = sims[0]
        found = events(bench, sim)
        metrics: list[Metric] = []
        if s.closings is not None:
            metrics.append(
                metric(
                    "closings (runs up after the normalization)",
                    len(found),
                    s.closings,
                    0.0,
                    "1",
                    ", ".join(f"{e.start:.2f} s" for e in found) or "none",
                )
            )
        for k, e in enumerate(found, start=1):
            tag = f"closing {k} ({e.supply:.1f} V)"
            if s.reversal is not None:
                metrics.append(
                    flag(
                        f"reversed {tag}",
                        e.detected is not None,
                        bool(s.reversal),
                        f"pinch detected at {e.detected:.3f} s" if e.detected is not None else "no pinch detection",
                    )
                )
            if e.detected is not None and (s.reopening if s.reopening is not None else s.ecu == "pwm"):
                metrics.append(reopening(tag, e))
            if s.peak_max is not None:
                metrics.append(
                    metric(
                        f"peak force {tag}", e.peak, s.peak_max / 2, s.peak_max / 2, "N", f"at most {s.peak_max:g} N"
                    )
                )
        if s.glass_end is not None:
            end = float(sim.waves["plant.door.pane.pos"][-1])
            metrics.append(
                metric(
                    "glass position at the end",
                    end * 1e3,
                    s.glass_end * 1e3,
                    s.glass_tolerance * 1e3,
                    "mm",
                    "asked in [expect] glass",
                )
            )
        plots = [pinch_plot(bench, sim, e, f"closing {k}", f"closing_{k}.png") for k, e in enumerate(found, 1)]
        return Judgement(metrics=metrics, plots=plots, waveforms=pinch_signals(bench, sims))

    return judge


def scenario_bench(s: Scenario, pset: ParamSet | None, learning: WarmStart | None = None) -> Bench:
    """A bench of one run: scenario `s` on the closed-loop testbench, judged by its [expect]."""
    return Bench(
        name=s.name,
        entity=TESTBENCH,
        description=s.purpose,
        stop=s.stop,
        max_step=s.max_step,
        runs=(scenario_run(s, pset, learning),),
        judge=_judge(s),
        params=SYSTEM_PARAMS,
        reltol=s.reltol,
        save=SAVE_ESTIMATE,
    )


SUMMARY_COLUMNS = ["scenario", "verdict", "closings (peak force, reversal)", "purpose"]


def summary_rows(scenarios: Sequence[Scenario], results: Sequence[BenchResult | dict]) -> list[list[str]]:
    """One row per scenario: its name, verdict, each closing's peak force and reversal, and its purpose."""
    rows = []
    for s, r in zip(scenarios, results):
        if isinstance(r, dict):
            rows.append([s.name, "ERROR", r["error"].splitlines()[0][:80], s.purpose])
            continue
        peaks = {m.name.removeprefix("peak force "): m.value for m in r.metrics if m.name.startswith("peak force ")}
        reversed_ = {m.name.removeprefix("reversed "): m.value for m in r.metrics if m.name.startswith("reversed ")}
        closings = [
            f"{tag}: {peaks[tag]:.1f} N" + ("" if tag not in reversed_ else " rev" if reversed_[tag] else " no rev")
            for tag in peaks
        ] or [f"{tag}: {'rev' if v else 'no rev'}" for tag, v in reversed_.items()]
        rows.append([s.name, "PASS" if r.passed else "FAIL", "; ".join(closings) or "-", s.purpose])
    return rows


def run_scenarios(
    targets: Sequence[str | Path],
    user: Sequence[str | Path] = (),
    results: Path = paths.RESULTS,
    runner: Runner | None = None,
    door: str | Path | None = None,
    ecu: str | None = None,
) -> tuple[list[Scenario], list[BenchResult | dict]]:
    """Run the scenario files `targets` (files or folders) side by side, one simulator process per core, with the
    user's parameter sets over each scenario's (`door`: a set beneath them, `scenario_params`); a page per scenario
    under results/scenario/<name>/ and the summary page results/scenario/summary/. Every file is checked before
    anything runs. `ecu`: every scenario with this ECU concept instead of its own."""
    from wrsim.benches.run import run_benches, simulator

    scenarios = load_scenarios(targets, ecu)
    base = scenario_params(user, door)
    lib = load_library(paths.LIBRARY)
    check_runs(lib, scenarios, base)  # before anything runs (a warm start's learning run included)
    runner = runner or simulator()
    runner.check()
    warm = WarmStart(lib, runner, unique_folder(paths.beside_results(results, "work") / "scenario-learn"))
    sets: dict[str, ParamSet | None] = {s.name: base for s in scenarios}
    benches = [scenario_bench(s, base, warm) for s in scenarios]
    out = run_benches(
        benches,
        user,
        results / "scenario",
        lib=lib,
        sets=sets,
        runner=runner,
        work=paths.beside_results(results, "work"),
    )
    grid = Grid(
        f"scenarios: {len(scenarios)} from {', '.join(map(str, targets))}",
        SUMMARY_COLUMNS,
        summary_rows(scenarios, out),
        "summary.csv",
    )
    passing = sum(1 for r in out if not isinstance(r, dict) and r.passed)
    count = metric(
        "scenarios that meet their expectation",
        passing,
        len(out),
        0.0,
        "1",
        "a scenario that could not be simulated counts as missing it",
    )
    page = BenchResult(
        "summary", "every scenario: verdict, closings, purpose", None, [], [count], [grid], {}, count.passed
    )
    from wrsim.report.results import write_bench_result, write_index

    write_bench_result(results / "scenario", page)
    write_index(results / "scenario")
    return scenarios, out


@dataclass(frozen=True)
class WarmCheck:
    """A bench run cold against its warm-started twin (testbenches/scenarios/warm/): every closing's peak force and
    detection time after the touch, and the wall time of each run."""

    name: str
    cold_peaks: tuple[float, ...]  # [N]
    warm_peaks: tuple[float, ...]  # [N]
    cold_latency: tuple[float | None, ...]  # [s] detection after the touch
    warm_latency: tuple[float | None, ...]
    cold_wall: float  # [s]
    warm_wall: float  # [s] the warm run alone (its normalization run is shared by every warm run)
    cold_simulated: float  # [s]
    warm_simulated: float  # [s]


def warm_checks(workdir: Path, runner: Runner | None = None, names: Sequence[str] = ()) -> list[WarmCheck]:
    """Each warm twin of testbenches/scenarios/warm/ (`pinch`: the pinch bench's run; `compliance_<run>`: that
    compliance run; only those `names` names when given) against the cold bench run, simulated one after the other
    so that the wall times compare."""
    import time

    from wrsim.benches import BENCHES
    from wrsim.benches.core import bench_params
    from wrsim.benches.run import simulator

    runner = runner or simulator()
    runner.check()
    lib = load_library(paths.LIBRARY)
    warm = WarmStart(lib, runner, workdir / "learn")
    out = []
    for file in find_scenarios([paths.SCENARIOS / "warm"]):
        if names and file.stem not in names:
            continue
        s = load_scenario(file)
        bench_name, _, label = s.name.partition("_")
        cold_bench = BENCHES[bench_name]
        cold_run = next(r for r in cold_bench.runs if r.label == (label or bench_name))
        t0 = time.perf_counter()
        (cold,), _ = simulate_runs(cold_bench, lib, bench_params(cold_bench), runner, workdir / "cold", (cold_run,))
        cold_wall = time.perf_counter() - t0
        pset = scenario_params()
        bench = scenario_bench(s, pset, warm)
        warm.learned(Run("", {}, own_sets(s) or None).parameters(pset), plant(s))  # shared: not timed
        t0 = time.perf_counter()
        (hot,), _ = simulate_runs(bench, lib, pset, runner, workdir / "warm")
        warm_wall = time.perf_counter() - t0
        ce, we = events(cold_bench, cold), events(bench, hot)
        if len(ce) != len(we):
            raise WrsimError(f"warm twin {file}: {len(we)} closings, the cold run has {len(ce)}")
        out.append(
            WarmCheck(
                s.name,
                tuple(e.peak for e in ce),
                tuple(e.peak for e in we),
                tuple(_latency(e) for e in ce),
                tuple(_latency(e) for e in we),
                cold_wall,
                warm_wall,
                cold_bench.stop,
                bench.stop,
            )
        )
    return out


def _latency(e: Event) -> float | None:
    return None if e.detected is None or e.touch is None else e.detected - e.touch
