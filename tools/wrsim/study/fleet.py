"""The fleet score (docs/anti-pinch.md, "Fleet score"): every anti-pinch algorithm on a scenario catalog for N doors
drawn from production spreads and the ambient temperature (study.sampling: door i of a seed is the same whatever the
fleet's size, and the same door for every algorithm). Each door and case is recorded once in closed loop with the
reversal held off (benches.replay.record, resumable: a record on disk is kept), then every algorithm is replayed on
the records. Per algorithm and case: false reversals with a 95 % upper bound, the peak force of the obstacle cases
(p50 / p99 / max; the force after a detection estimated from the record, `peak_after`), detection latency, and how
late after the touch any detection may come (`reach`: the doors out of reach fail for every algorithm); a page with
the table per case, one row per algorithm and set, and the worst doors."""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
import os
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from wrsim import paths
from wrsim.benches.closed_loop import LIMIT_N, regulation
from wrsim.benches.replay import (
    Record,
    Replayer,
    ecu_generics,
    kept_record,
    plant_digest,
    record,
    record_files,
    store_record,
)
from wrsim.benches.scenario import Scenario, check_runs, concept_over, load_scenarios, scenario_params
from wrsim.benches.score import algorithm_file
from wrsim.data.params import ParamSet, load_params
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError
from wrsim.results import BenchResult
from wrsim.study.sampling import draw, factors, sample_set

__all__ = [
    "OVERRUN_S",
    "fleet_folder",
    "door_generics",
    "touch",
    "reach",
    "Outcome",
    "CaseScore",
    "doors",
    "peak_after",
    "law",
    "limits",
    "fleet_outcomes",
    "replay_outcomes",
    "case_scores",
    "upper_bound",
    "fleet_page",
    "save_door",
    "score_fleet",
    "SUMMARY_COLUMNS",
]

OVERRUN_S = 0.013  # [s] the glass runs on into the obstacle after a detection (docs/anti-pinch.md, "Record and replay")
_SEAL_M = 0.370  # [m] the top-frame sealing of the system set: gaps are measured from it
_TOUCH_N = 0.1  # [N] the gauge force that counts as the touch


def fleet_folder(
    tolerances: Sequence[str | Path], seed: int, results: Path = paths.RESULTS, ecu: str = "relay"
) -> Path:
    """Where a fleet's records are kept: build/work/fleet/seed<S>-<digest of the tolerance files>[-<ecu>]/door-<i>/
    (the relay ECU's without a suffix)."""
    import hashlib

    from wrsim.data.params import find_param_set

    files = [find_param_set(t) for t in tolerances]
    key = hashlib.sha256(repr((seed, [f.read_bytes() for f in files])).encode()).hexdigest()[:16]
    return (
        paths.beside_results(results, "work") / "fleet" / (f"seed{seed}-{key}" + ("" if ecu == "relay" else f"-{ecu}"))
    )


def door_generics(lib: Library, door: ParamSet, algorithm: Path, ecu: str) -> dict:
    """The ECU software's generics on `door` with the ECU concept `ecu` and `algorithm`'s set over both, as the
    door's closings ran (what a replay gives tb_replay)."""
    return ecu_generics(lib, concept_over(door, ecu).beneath(load_params(algorithm)))


def doors(tolerances: Sequence[str | Path], samples: int, seed: int) -> list[ParamSet]:
    """`samples` doors: the scenario start set (system set with `tolerances` over it: production spreads, the
    ambient temperature) at Monte Carlo draws 0 .. samples-1 of `seed`. A door is the set a case starts from, not a
    user's set over it: what a case states itself (its ambient temperature, an aged mechanism's friction) holds on
    every door, over the door's own draw of the same value."""
    pset = scenario_params(tolerances)
    fs = factors(pset)
    if not fs:
        raise WrsimError(f"{', '.join(map(str, tolerances))}: no spreads to draw doors from")
    return [dataclasses.replace(sample_set(pset, draw(fs, seed, i), f"door{i}"), user=None) for i in range(samples)]


def law(s: Scenario) -> str | None:
    """The regulation whose law cell `s`'s obstacle is (closed_loop.regulation), None for no obstacle or another
    rod."""
    if "gauge_stiffness" not in s.values or "pinch_position" not in s.values and s.gap is None:
        return None
    gap_mm = 1e3 * (s.gap if s.gap is not None else _SEAL_M - s.values["pinch_position"])
    return regulation(s.values["gauge_stiffness"] / 1e3, gap_mm)


def peak_after(rec: Record, detected: float | None) -> float:
    """[N] the gauge force a closing reaches when the ECU reverses at `detected`: the record's largest force up to
    OVERRUN_S after it (the drive needs that long to stop the glass); without a detection the record's largest."""
    if detected is None:
        return float(rec.force.max())
    k = rec.time <= detected + OVERRUN_S
    return float(rec.force[k].max())


def touch(rec: Record) -> float | None:
    """[s] when the glass first touches the obstacle in the record, None without one."""
    k = np.flatnonzero(rec.force > _TOUCH_N)
    return float(rec.time[k[0]]) if k.size else None


def reach(rec: Record, limit: float) -> float | None:
    """[s] how long after the touch a detection may come for `peak_after` to stay at or below `limit`: the record's
    force passes the limit OVERRUN_S after that. Infinite if it never passes it; negative if even a detection at the
    touch comes too late (out of any detection's reach, by the run-on model); None without a touch."""
    t0 = touch(rec)
    if t0 is None:
        return None
    over = np.flatnonzero(rec.force > limit)
    return float(rec.time[over[0]]) - OVERRUN_S - t0 if over.size else math.inf


@dataclass(frozen=True)
class Outcome:
    """One algorithm on one door's record of one case."""

    door: int
    case: str
    algorithm: str
    detected: float | None  # [s]
    peak: float  # [N] `peak_after`
    touch: float | None  # [s] the glass touches the obstacle (None: no touch until the detection or the end)
    reach: float | None  # [s] `reach` at the case's limit (the same for every algorithm)

    @property
    def latency(self) -> float | None:
        """[s] from the touch to the detection (None without either)."""
        return None if self.detected is None or self.touch is None else self.detected - self.touch

    @property
    def early(self) -> bool:
        """A detection before the glass touches the obstacle: the window reverses short of the top."""
        return self.detected is not None and (self.touch is None or self.detected < self.touch)


def fleet_outcomes(
    catalog: Sequence[str | Path],
    algorithms: Sequence[str | Path],
    fleet: Sequence[ParamSet],
    workdir: Path,
    client: Any = None,
    ecu: str = "relay",
) -> tuple[list[Scenario], list[Outcome]]:
    """Record every case of `catalog` on every door of `fleet` with the ECU concept `ecu` under `workdir`/door-<i>/
    (kept records are reused: a fleet resumes), and replay every algorithm on them. `client`: a Dask client whose
    cluster records the doors (one task per door with cases to record; the records are kept here as they arrive)."""
    scenarios = load_scenarios(catalog, ecu)
    files = [algorithm_file(a) for a in algorithms]
    lib = load_library(paths.LIBRARY)
    check_runs(lib, scenarios, scenario_params())
    replayer = Replayer(workdir, lib)
    if client is not None:
        record_on_cluster(client, scenarios, fleet, workdir, plant_digest(lib))
    records = {i: record(scenarios, workdir / f"door-{i}", door, lib=lib) for i, door in enumerate(fleet)}
    outcomes = []
    for f in files:
        generics = {i: door_generics(lib, door, f, ecu) for i, door in enumerate(fleet)}
        if any(g.get("algorithm") == 1 for g in generics.values()):
            raise WrsimError(f"{f}: the C algorithm takes no warm start, and the catalog's cases start warm")
        outcomes += replay_outcomes(replayer, records, generics, f.stem, limits(scenarios))
    return scenarios, outcomes


def record_on_cluster(
    client: Any, scenarios: Sequence[Scenario], fleet: Sequence[ParamSet], workdir: Path, models: str
) -> None:
    """Record on the Dask cluster of `client` the cases each door of `fleet` has no record of under
    `workdir`/door-<i>/ (models: the plant_digest the records are made with): one task per door, its files written
    here as each task ends, so that a fleet stopped halfway resumes with the doors it finished. The scheduler runs
    the task of a lost worker again; a door whose task keeps killing its worker is one error."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    futures = {}
    for i, door in enumerate(fleet):
        missing = [s for s in scenarios if kept_record(s, workdir / f"door-{i}" / s.name, door, models) is None]
        if missing:
            futures[client.submit(record_files, missing, door, models, pure=False)] = i
    for f in as_completed(list(futures)):
        i = futures[f]
        try:
            recorded = f.result()
        except KilledWorker as e:
            raise WrsimError(f"door {i}: its recording killed every worker it ran on ({e})") from None
        for name, data in recorded.items():
            store_record(workdir / f"door-{i}" / name, data)


def limits(scenarios: Sequence[Scenario]) -> dict[str, float]:
    """[N] each case's peak force limit: its `peak_max`, else the law's LIMIT_N."""
    return {s.name: s.peak_max if s.peak_max is not None else LIMIT_N for s in scenarios}


def replay_outcomes(
    replayer: Replayer,
    records: dict[int, list[Record]],
    generics: dict[int, dict],
    algorithm: str,
    caps: Mapping[str, float],
) -> list[Outcome]:
    """Replay the records of every door (door number -> its records) with that door's ECU generics, on every core.
    `caps`: [N] each case's peak force limit (`limits`), for `reach`."""
    jobs = [(i, rec) for i, some in records.items() for rec in some]

    def one(job: tuple[int, Record]) -> Outcome:
        i, rec = job
        d = replayer.replay(rec, generics[i], f"{algorithm}-door{i}")
        return Outcome(
            i, rec.name, algorithm, d.detected, peak_after(rec, d.detected), touch(rec), reach(rec, caps[rec.name])
        )

    with concurrent.futures.ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        return list(pool.map(one, jobs))


def upper_bound(events: int, trials: int, level: float = 0.95) -> float:
    """The one-sided `level` upper confidence bound of a rate with `events` in `trials` (Clopper-Pearson)."""
    from scipy.stats import beta

    if trials == 0:
        return 1.0
    if events >= trials:
        return 1.0
    return float(beta.ppf(level, events + 1, trials - events))


@dataclass(frozen=True)
class CaseScore:
    """One algorithm on one case over the fleet."""

    case: str
    algorithm: str
    law: str | None
    obstacle: bool  # the case must reverse (an obstacle) or must not (a false reversal)
    doors: int
    failures: int  # obstacle: no detection, a detection before the touch or the peak over the limit; else: reversals
    peaks: tuple[float, float, float]  # [N] p50, p99, max (obstacle cases)
    latency: tuple[float, float]  # [ms] median, largest (obstacle cases with a detection)
    worst_door: int
    early: int = 0  # obstacle: doors that reversed before the touch
    reach: tuple[float, int] = (math.nan, 0)  # obstacle: [ms] the least `reach` over the doors, doors out of reach


def case_scores(scenarios: Sequence[Scenario], outcomes: Sequence[Outcome]) -> list[CaseScore]:
    """Per algorithm and case: failures, their 95 % bound, peaks and latency over the doors."""
    by: dict[tuple[str, str], list[Outcome]] = {}
    for o in outcomes:
        by.setdefault((o.algorithm, o.case), []).append(o)
    kinds = {s.name: s for s in scenarios}
    caps = limits(scenarios)
    out = []
    for (alg, case), some in by.items():
        s = kinds[case]
        limit = caps[case]
        obstacle = bool(s.reversal)
        peaks = np.array([o.peak for o in some])
        if obstacle:
            failures = sum(1 for o in some if o.detected is None or o.early or o.peak > limit)
            worst = max(some, key=lambda o: (o.detected is None or o.early, o.peak))
        else:
            failures = sum(1 for o in some if o.detected is not None)
            worst = next((o for o in some if o.detected is not None), some[0])
        lat = [o.latency * 1e3 for o in some if o.latency is not None and not o.early]
        reaches = [o.reach for o in some if o.reach is not None]
        out.append(
            CaseScore(
                case,
                alg,
                law(s),
                obstacle,
                len(some),
                failures,
                (
                    float(np.percentile(peaks, 50)),
                    float(np.percentile(peaks, 99)),
                    float(peaks.max()),
                )
                if obstacle
                else (math.nan, math.nan, math.nan),
                (float(np.median(lat)), float(max(lat))) if lat else (math.nan, math.nan),
                worst.door,
                sum(1 for o in some if obstacle and o.early),
                (1e3 * min(reaches), sum(1 for r in reaches if r < 0)) if obstacle and reaches else (math.nan, 0),
            )
        )
    return out


def _split(s: Scenario) -> str:
    """The catalog set a case belongs to: its folder's name (tuning, validation) or '-'."""
    return s.file.parent.name if s.file.parent.name in ("tuning", "validation") else "-"


def _summary(alg: str, split: str, some: list[CaseScore]) -> list[str]:
    laws = [c for c in some if c.obstacle and c.law is not None]
    free = [c for c in some if not c.obstacle]
    closings = sum(c.doors for c in free)
    false = sum(c.failures for c in free)
    lat = [c.latency for c in laws if math.isfinite(c.latency[0])]
    return [
        alg,
        split,
        f"{sum(c.failures for c in laws)} of {sum(c.doors for c in laws)}",
        f"{sum(c.reach[1] for c in laws)}",
        f"{max((c.peaks[1] for c in laws), default=math.nan):.1f}",
        f"{max((c.peaks[2] for c in laws), default=math.nan):.1f}",
        f"{false} of {closings} (<= {100 * upper_bound(false, closings):.1f} %)",
        f"{np.median([m for m, _ in lat]):.1f} / {max(x for _, x in lat):.1f}" if lat else "-",
    ]


SUMMARY_COLUMNS = [
    "algorithm",
    "set",
    "law closings failed",
    "of them out of reach",
    "worst p99 peak [N]",
    "max peak [N]",
    "false reversals (95 % bound)",
    "latency median / largest [ms]",
]


def _margin(c: CaseScore) -> float | None:
    """The heat map's value of a case: an obstacle's margin of its largest peak to the legal limit."""
    return LIMIT_N - c.peaks[2] if c.obstacle and c.law else None


def fleet_page(scenarios: Sequence[Scenario], scores: Sequence[CaseScore], doors: int, what: str) -> BenchResult:
    """The result page `fleet`: one row per algorithm and set, the Pareto plot (worst p99 peak against the false
    reversal rate), a table per case and the worst doors."""
    from wrsim.benches.core import metric
    from wrsim.results import Grid, Overlay, Plot, Signal

    split = {s.name: _split(s) for s in scenarios}
    algorithms = list(dict.fromkeys(c.algorithm for c in scores))
    sets = sorted({split[c.case] for c in scores})
    summary = Grid(
        f"fleet score over {doors} doors ({what}): per algorithm and catalog set",
        SUMMARY_COLUMNS,
        [
            _summary(a, t, [c for c in scores if c.algorithm == a and split[c.case] == t])
            for a in algorithms
            for t in sets
        ],
        "fleet.csv",
    )
    cases = list(dict.fromkeys(c.case for c in scores))
    by = {(c.algorithm, c.case): c for c in scores}

    def cell(c: CaseScore) -> str:
        if c.obstacle:
            text = f"{c.peaks[1]:.1f} / {c.peaks[2]:.1f} N" + (f", {c.early} reversed short" if c.early else "")
        else:
            text = f"{c.failures} of {c.doors} rev"
        return ("FAIL " if c.failures else "") + text + (f" (door {c.worst_door})" if c.failures else "")

    def reached(c: CaseScore) -> str:
        if not c.obstacle or math.isnan(c.reach[0]):
            return "-"
        least = "any" if math.isinf(c.reach[0]) else f"{c.reach[0]:.1f} ms"
        return least + (f", {c.reach[1]} of {c.doors} out of reach" if c.reach[1] else "")

    per_case = Grid(
        "per case: obstacles p99 / max peak force, cases without one: false reversals (FAIL: a failing door, the "
        "worst named); reach: the latest a detection may come after the touch on the tightest door (out of reach: "
        "too late even at the touch, by the run-on model)",
        ["case", "set", "regulation", "reach", *algorithms],
        [
            [k, split[k], by[(algorithms[0], k)].law or "-", reached(by[(algorithms[0], k)])]
            + [cell(by[(a, k)]) for a in algorithms]
            for k in cases
        ],
        "fleet_cases.csv",
        margins=[[None, None, None, None, *(_margin(by[(a, k)]) for a in algorithms)] for k in cases],
        scale=LIMIT_N / 2,
    )
    points = []
    for a in algorithms:
        for t in sets:
            some = [c for c in scores if c.algorithm == a and split[c.case] == t]
            laws = [c.peaks[1] for c in some if c.obstacle and c.law is not None]
            free = [c for c in some if not c.obstacle]
            rate = sum(c.failures for c in free) / max(1, sum(c.doors for c in free))
            if laws:
                points.append(
                    Overlay(
                        f"{a} ({t})",
                        Signal("false reversal rate", "%", np.array([100 * rate])),
                        Signal("worst p99 peak", "N", np.array([max(laws)])),
                        "left",
                    )
                )
    plot = Plot(
        "fleet: worst p99 peak force over the law cells against the false-reversal rate (line: legal limit)",
        Signal("false reversal rate", "%", np.array([-1.0, 100.0])),
        [Signal("worst p99 peak force", "N", np.array([LIMIT_N, LIMIT_N]))],
        [],
        points,
        "fleet.png",
    )
    holds = [
        a
        for a in algorithms
        if all(c.failures == 0 for c in scores if c.algorithm == a and (c.law is not None or not c.obstacle))
    ]
    count = metric(
        "an algorithm holds on every door: law cells <= 100 N with a reversal, no false reversal",
        float(bool(holds)),
        1.0,
        0.0,
        "1",
        ", ".join(holds) or "none does",
    )
    return BenchResult(
        "fleet",
        f"anti-pinch algorithms on the scenario catalog over {doors} doors ({what}), replayed on records",
        None,
        [],
        [count],
        [summary, plot, per_case],
        {},
        bool(holds),
    )


def save_door(folder: Path, door: ParamSet, base: ParamSet, title: str) -> Path:
    """Write the values `door` drew (those that differ from `base`) as `folder`/door.txt: the set `wrsim scenario
    --door` starts a case from, to run it as the fleet recorded it."""
    from wrsim.data.params import save_params

    folder.mkdir(parents=True, exist_ok=True)
    drawn = {
        e: [(k, p.value, p.unit, "drawn") for k, p in keys.items() if p.value != base.sections[e][k].value]
        for e, keys in door.sections.items()
    }
    save_params(folder / "door.txt", [title], {e: v for e, v in drawn.items() if v})
    return folder / "door.txt"


def score_fleet(
    tolerances: Sequence[str | Path],
    samples: int,
    seed: int,
    catalog: Sequence[str | Path],
    algorithms: Sequence[str | Path],
    results: Path = paths.RESULTS,
    client: Any = None,
    ecu: str = "relay",
) -> tuple[list[CaseScore], BenchResult]:
    """`wrsim score --fleet`: the doors, their records (kept under build/work/fleet/<digest>/, so that a second run
    with the same tolerances and seed resumes), the replays, the page `fleet` under `results`. Each door's drawn
    values are written beside its records (door.txt: `wrsim scenario CASE --door door.txt --params ALGORITHM` runs
    that door's case in closed loop). `client`: a Dask client to record the doors on (fleet_outcomes). `ecu`: the ECU
    concept every closing runs with (its records apart from the other concept's)."""
    from wrsim.report.results import write_bench_result, write_index

    if samples < 1:
        raise WrsimError(f"--samples {samples}: a fleet needs at least one door")
    workdir = fleet_folder(tolerances, seed, results, ecu)
    fleet = doors(tolerances, samples, seed)
    base = scenario_params(tolerances)
    for i, door in enumerate(fleet):
        title = f"door {i} of seed {seed}: {', '.join(map(str, tolerances))}"
        if ecu != "relay":  # what `wrsim scenario CASE --door door.txt` needs besides, to run a case as recorded
            title += f"; recorded with the {ecu} ECU (wrsim scenario --ecu {ecu})"
        save_door(workdir / f"door-{i}", door, base, title)
    scenarios, outcomes = fleet_outcomes(catalog, algorithms, fleet, workdir, client, ecu)
    scores = case_scores(scenarios, outcomes)
    page = fleet_page(scenarios, scores, samples, f"{', '.join(map(str, tolerances))}, seed {seed}, {ecu} ECU")
    write_bench_result(results, page)
    write_index(results)
    return scores, page
