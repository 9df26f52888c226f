"""The anti-pinch score: the compliance bench's closings and the drum bench's pinch events (Fig. 5.12) run once
per anti-pinch algorithm, then one row per algorithm: worst peak force and smallest margin per regulation, law
cells failed, false reversals, detection latency and the drum trend. An algorithm is a parameter set laid over
the system set (params/antipinch/*.txt, or a user's file, e.g. `[ecu_software] algorithm = 1` with an own C
file). Written as the result page `score` (table as CSV and HTML, plot of the worst peak force against the
false reversals) beside the benches' pages."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.benches.closed_loop import BENCHES as CLOSED_LOOP
from wrsim.benches.closed_loop import LIMIT_N, Cell, algorithm_runs, compliance_cells, events
from wrsim.benches.core import Bench, Simulated, bench_params, flag, simulate_runs
from wrsim.benches.run import simulator
from wrsim.data.params import load_params
from wrsim.data.publish import unique_folder
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.report.results import write_bench_result, write_index
from wrsim.results import BenchResult, Grid, Overlay, Plot, Signal

__all__ = ["Score", "algorithm_sets", "algorithm_file", "score_algorithms", "score_cells", "score_page"]

_BENCHES = {b.name: b for b in CLOSED_LOOP}
_REGULATIONS = ("ECE R21", "FMVSS 118")


@dataclass(frozen=True)
class Score:
    """What one algorithm makes of the compliance matrix and the drum bench."""

    algorithm: str  # the parameter set's name (file stem)
    worst: dict[str, float]  # regulation -> worst peak force over its law cells [N]
    failed: int  # law cells over LIMIT_N or without a reversal
    cells: int  # law cells
    false_reversals: int  # closings without an obstacle that reversed
    disturbances: int  # closings without an obstacle
    beyond_reversals: int  # the same on the information rows (disturbances beyond the bench's set)
    beyond: int  # closings on those rows
    latency_ms: tuple[float, float]  # median and largest time from the touch to the detection [ms]
    drum_peaks: tuple[float, ...]  # peak force with the 44, 46, 48 mm drum [N] (nan: the run had no closing)

    @property
    def passed(self) -> bool:
        """Every law cell passed and no false reversal."""
        return self.failed == 0 and self.false_reversals == 0

    @property
    def drum_trend(self) -> bool:
        """Fig. 5.12: the force grows as the drum shrinks from 48 to 44 mm."""
        return all(a > b for a, b in zip(self.drum_peaks, self.drum_peaks[1:]))


CURRENT_ALGORITHMS = (7,)  # the antipinch package's algorithms that read the motor current (the PWM ECU measures it)


def algorithm_sets(ecu: str = "relay") -> list[Path]:
    """The algorithms that ship (params/antipinch/*.txt) that can run on the ECU concept `ecu`: the relay ECU measures
    no current, so the algorithms on it (CURRENT_ALGORITHMS) are the PWM ECU's only."""
    out = []
    for path in sorted(paths.ALGORITHMS.glob("*.txt")):
        given = load_params(path).sections.get("ecu_software", {}).get("algorithm")
        if ecu == "pwm" or given is None or round(float(given.value)) not in CURRENT_ALGORITHMS:  # type: ignore[arg-type]
            out.append(path)
    return out


def algorithm_file(name: str | Path) -> Path:
    """An algorithm's parameter set: a file, or a name in params/antipinch/."""
    if Path(name).is_file():
        return Path(name)
    shipped = paths.ALGORITHMS / f"{name}.txt"
    if Path(name).suffix or len(Path(name).parts) > 1 or not shipped.is_file():
        raise WrsimError(
            f"unknown anti-pinch algorithm '{name}' (not a file; in {paths.ALGORITHMS}: "
            f"{', '.join(p.stem for p in algorithm_sets())})"
        )
    return shipped


def score_cells(name: str, cells: list[Cell], drum: list[Simulated], bench: Bench) -> Score:
    """The score of algorithm `name` from its compliance cells and its drum runs (the drum bench `bench`)."""
    law = [c for c in cells if c.law is not None]
    free = [c for c in cells if c.gauge is None and c.judged]
    beyond = [c for c in cells if c.gauge is None and not c.judged]
    worst = {r: max((c.event.peak for c in law if c.law == r), default=float("nan")) for r in _REGULATIONS}
    failed = sum(c.event.peak > LIMIT_N or c.event.detected is None for c in law)
    latency = [
        (c.event.detected - c.event.touch) * 1e3
        for c in cells
        if c.gauge is not None and c.event.detected is not None and c.event.touch is not None
    ]
    # the drum bench's short normalization run does not reach the top on a cold door set: no closing, no peak
    peaks = tuple(ups[0].peak if (ups := events(bench, s)) else float("nan") for s in drum)
    return Score(
        name,
        worst,
        failed,
        len(law),
        sum(c.event.detected is not None for c in free),
        len(free),
        sum(c.event.detected is not None for c in beyond),
        len(beyond),
        (float(np.median(latency)), float(np.max(latency))) if latency else (float("nan"),) * 2,
        peaks,
    )


def _row(s: Score) -> list[str]:
    def worst(r: str) -> str:
        return f"{s.worst[r]:.1f} N (margin {LIMIT_N - s.worst[r]:+.1f} N)"

    return [
        s.algorithm,
        *(worst(r) for r in _REGULATIONS),
        f"{'PASS' if s.failed == 0 else 'FAIL'} {s.failed} of {s.cells}",
        f"{'PASS' if s.false_reversals == 0 else 'FAIL'} {s.false_reversals} of {s.disturbances}",
        f"{s.beyond_reversals} of {s.beyond}",
        f"{s.latency_ms[0]:.1f} / {s.latency_ms[1]:.1f}",
        _drum(s),
    ]


def _drum(s: Score) -> str:
    """The drum column: the three peaks and the trend, or which runs had no closing."""
    if any(np.isnan(p) for p in s.drum_peaks):
        return " / ".join("-" if np.isnan(p) else f"{p:.1f}" for p in s.drum_peaks) + " (-: not normalized: no closing)"
    return " / ".join(f"{p:.1f}" for p in s.drum_peaks) + (" (rises)" if s.drum_trend else " (does not rise)")


def score_algorithms(
    algorithms: Sequence[str | Path],
    overlay: str | Path | None = None,
    results: Path = paths.RESULTS,
    lib: Library | None = None,
    c_algorithm: str | Path | None = None,
) -> tuple[list[Score], BenchResult]:
    """Run the compliance and drum benches once per algorithm (a parameter-set name or file each), write the
    result page `score` under `results` and return the scores and the page. `overlay` (the user's `--params`)
    is laid over every run, beneath the algorithm. `c_algorithm`: a C file that replaces antipinch.c, i.e. what
    the algorithm `c_twin` (algorithm = 1) runs; its row is named after the file."""
    files = [algorithm_file(a) for a in algorithms]
    if not files:
        raise WrsimError(f"no anti-pinch algorithm to score (none given, none in {paths.ALGORITHMS})")
    names = [Path(c_algorithm).stem if c_algorithm is not None and f.stem == "c_twin" else f.stem for f in files]
    if len(set(names)) != len(names):
        raise WrsimError(f"two algorithms share a name: {', '.join(names)}")
    runner = simulator(c_algorithm)
    runner.check()
    lib = lib or load_library(paths.LIBRARY)
    workdir = unique_folder(paths.beside_results(results, "work") / "score")
    sims: dict[str, dict[str, list[Simulated]]] = {n: {} for n in names}
    for bench in (_BENCHES["compliance"], _BENCHES["pinch-drum-diameter"]):
        # the algorithm replaces the run's own set and goes over the user's, which is what is scored
        runs = algorithm_runs(bench.runs, dict(zip(names, files)))
        base = dataclasses.replace(bench_params(bench, overlay), user=None)
        done, _ = simulate_runs(bench, lib, base, runner, workdir / bench.name, runs)
        for k, s in enumerate(done):
            sims[names[k // len(bench.runs)]].setdefault(bench.name, []).append(s)
    scores = [
        score_cells(
            n,
            compliance_cells(_BENCHES["compliance"], sims[n]["compliance"]),
            sims[n]["pinch-drum-diameter"],
            _BENCHES["pinch-drum-diameter"],
        )
        for n in names
    ]
    page = score_page(scores)
    write_bench_result(results, page)
    write_index(results)
    return scores, page


def score_page(scores: list[Score]) -> BenchResult:
    """The result page `score`: the table (score.csv / .html), the plot (score.png) and one metric, whether an
    algorithm passes every law cell with no false reversal."""
    best = [s.algorithm for s in scores if s.passed]
    grid = Grid(
        "anti-pinch score per algorithm: worst peak force per regulation over its law cells "
        "(docs/regulation.md), law cells failed, false reversals (top seal, supply dips, rough road 0.5 g, "
        "seals +20 / -10 N; beyond the set: road 1 g, seals +30 N), "
        "detection latency from the touch (median / largest over the rods), Fig. 5.12 peaks",
        [
            "algorithm",
            *(f"{r} worst peak" for r in _REGULATIONS),
            "law cells failed",
            "false reversals",
            "false reversals beyond the set",
            "latency [ms]",
            "drum 44 / 46 / 48 mm [N]",
        ],
        [_row(s) for s in scores],
        "score.csv",
        margins=[[None, *(LIMIT_N - s.worst[r] for r in _REGULATIONS), None, None, None, None, None] for s in scores],
        scale=LIMIT_N / 2,
    )
    top = max([max(s.worst.values()) for s in scores] + [LIMIT_N]) * 1.1
    limit_x = Signal("false reversals", "1", np.array([-0.5, max(s.disturbances for s in scores) + 0.5]))
    points: dict[tuple[float, float], list[str]] = {}  # algorithms on the same point share one marker
    for s in scores:
        points.setdefault((float(s.false_reversals), min(max(s.worst.values()), top)), []).append(s.algorithm)
    plot = Plot(
        "anti-pinch score: worst peak force over the law cells against false reversals",
        limit_x,
        [Signal("worst peak force (line: legal limit)", "N", np.array([LIMIT_N, LIMIT_N]))],
        [],
        [
            Overlay(
                ", ".join(names),
                Signal("false reversals", "1", np.array([x])),
                Signal("worst peak force", "N", np.array([y])),
                "left",
            )
            for (x, y), names in points.items()
        ],
        "score.png",
    )
    metrics = [
        flag(
            "an algorithm passes every law cell with no false reversal",
            bool(best),
            True,
            ", ".join(best) if best else "none does",
        )
    ]
    return BenchResult(
        "score",
        "anti-pinch algorithms on the compliance matrix and the drum bench (wrsim score)",
        None,
        [],
        metrics,
        [grid, plot],
        {},
        bool(best),
    )
