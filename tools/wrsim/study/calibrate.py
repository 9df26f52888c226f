"""Calibration of an anti-pinch algorithm (docs/anti-pinch.md, "Calibration"): the values its parameter set declares
with `in LOW .. HIGH UNIT calibrate` are searched with optuna (TPE, seeded) for the lowest worst-case p99 peak force
over the law cells with no failure (no false reversal, no missed or early detection, no peak over the limit) on the
tuning cases of a fleet of doors. Every trial replays the fleet's records (benches.replay, benches.fleet): the doors
are recorded once, and the study is kept in a journal file, so an interrupted calibration resumes. The result is the
algorithm's set with the best values and its provenance; the same values are scored on the validation cases."""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.benches.replay import Record, Replayer, record
from wrsim.benches.scenario import Scenario, check_runs, load_scenarios, scenario_params
from wrsim.benches.score import algorithm_file
from wrsim.data.params import load_params, save_params
from wrsim.elab.library import load_library
from wrsim.errors import WrsimError
from wrsim.study.fleet import (
    CaseScore,
    case_scores,
    door_generics,
    doors,
    fleet_folder,
    limits,
    replay_outcomes,
)

__all__ = ["Knob", "knobs", "objective", "calibrate"]

_FAILURE_N = 1000.0  # [N] what one failing door-case adds to the objective: any failure outweighs any peak


@dataclass(frozen=True)
class Knob:
    """One calibration value: an ECU generic, its range and unit as the set declares them."""

    key: str
    low: float
    high: float
    unit: str
    line: str  # file:line of the declaration


def knobs(algorithm: Path) -> list[Knob]:
    """The calibration values the algorithm's set declares (`in LOW .. HIGH UNIT calibrate`); only the ECU
    software's generics can be calibrated on records."""
    pset = load_params(algorithm)
    out = []
    for entity, keys in pset.tolerances.items():
        for key, t in keys.items():
            if t.law != "calibrate":
                continue
            if entity != "ecu_software":
                raise WrsimError(
                    f"{t.file}:{t.line}: [{entity}] {key}: only [ecu_software] values can be calibrated (the replay "
                    f"runs the ECU software alone)"
                )
            assert t.limits is not None
            out.append(Knob(key, t.limits[0], t.limits[1], t.unit, f"{paths.shown(t.file)}:{t.line}"))
    if not out:
        raise WrsimError(
            f"{algorithm}: declares no calibration value (`key = value unit in LOW .. HIGH unit calibrate`)"
        )
    return out


def objective(scores: Sequence[CaseScore]) -> float:
    """[N] the worst p99 peak over the law cells plus `_FAILURE_N` per failing door and case."""
    laws = [c.peaks[1] for c in scores if c.obstacle and c.law is not None and math.isfinite(c.peaks[1])]
    return max(laws, default=0.0) + _FAILURE_N * sum(c.failures for c in scores if c.law is not None or not c.obstacle)


def _score(
    replayer: Replayer,
    records: dict[int, list[Record]],
    generics: dict[int, dict],
    values: dict[str, int],
    scenarios: Sequence[Scenario],
    tag: str,
) -> list[CaseScore]:
    """Replay the records of every door with the calibration `values` laid into its ECU generics."""
    calibrated = {i: {**g, **values} for i, g in generics.items()}
    return case_scores(scenarios, replay_outcomes(replayer, records, calibrated, tag, limits(scenarios)))


def calibrate(
    algorithm: str | Path,
    tolerances: Sequence[str | Path],
    samples: int,
    seed: int,
    trials: int,
    tuning: Sequence[str | Path] = (paths.SCENARIOS / "catalog" / "tuning",),
    validation: Sequence[str | Path] = (paths.SCENARIOS / "catalog" / "validation",),
    out: Path | None = None,
    results: Path = paths.RESULTS,
    ecu: str = "relay",
) -> tuple[dict[str, int], float, float, Path]:
    """Calibrate `algorithm` on the tuning cases of `samples` doors (`tolerances`, `seed`) with the ECU concept `ecu`
    in `trials` optuna trials (more on a resumed study), write the calibrated set (`out`, default
    build/calibrated/<name>.txt) and return the values, the tuning objective and the validation objective of the same
    values, and the set's file."""
    import optuna
    from optuna.storages.journal import JournalFileBackend

    file = algorithm_file(algorithm)
    declared = knobs(file)
    lib = load_library(paths.LIBRARY)
    fleet = doors(tolerances, samples, seed)
    workdir = fleet_folder(tolerances, seed, results, ecu)
    sets = {"tuning": tuning, "validation": validation}
    scenarios = {k: load_scenarios(v, ecu) for k, v in sets.items()}
    for split in scenarios.values():
        check_runs(lib, split, scenario_params())

    def recorded(split: str) -> dict[int, list[Record]]:
        return {i: record(scenarios[split], workdir / f"door-{i}", door, lib=lib) for i, door in enumerate(fleet)}

    # the tuning cases of every door first: the search needs only them (some 40 % of the closings); the validation
    # cases after it, for the check of the values found (a door's normalization run is made again then)
    generics = {i: door_generics(lib, door, file, ecu) for i, door in enumerate(fleet)}
    if any(g.get("algorithm") == 1 for g in generics.values()):  # before any recording
        raise WrsimError(f"{file}: the C algorithm takes no warm start, and the catalog's cases start warm")
    records = {"tuning": recorded("tuning")}
    replayer = Replayer(workdir / "calibrate", lib)
    journal = workdir / f"calibrate-{file.stem}.journal"
    storage = optuna.storages.JournalStorage(JournalFileBackend(str(journal)))
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    study = optuna.create_study(
        study_name=f"{file.stem}-{samples}-doors",
        storage=storage,
        load_if_exists=True,
        direction="minimize",
        sampler=optuna.samplers.TPESampler(seed=seed),
    )
    nominal = {k.key: int(generics[0][k.key]) for k in declared if k.key in generics[0]}
    if not study.trials:
        study.enqueue_trial(nominal)  # the set as it ships is the first trial

    def trial(t: optuna.Trial) -> float:
        values = {k.key: t.suggest_int(k.key, math.ceil(k.low), math.floor(k.high)) for k in declared}
        return objective(_score(replayer, records["tuning"], generics, values, scenarios["tuning"], f"t{t.number}"))

    done = sum(1 for t in study.trials if t.state == optuna.trial.TrialState.COMPLETE)
    study.optimize(trial, n_trials=max(0, trials - done))
    best = {k: int(v) for k, v in study.best_params.items()}
    tuned = study.best_value
    records["validation"] = recorded("validation")
    checked = objective(_score(replayer, records["validation"], generics, best, scenarios["validation"], "validation"))
    target = out or paths.beside_results(results, "calibrated") / f"{file.stem}.txt"
    units = {k.key: k.unit for k in declared}
    base = load_params(file).sections.get("ecu_software", {})
    rows = [
        (key, float(best[key]) if key in best else p.value, p.unit, "calibrated" if key in best else "")
        for key, p in base.items()
    ]
    rows += [(key, float(v), units[key], "calibrated") for key, v in best.items() if key not in base]
    save_params(
        target,
        [
            f"{file.stem} calibrated by `wrsim calibrate` on {samples} doors ({', '.join(map(str, tolerances))}, seed "
            f"{seed}, the {ecu} ECU), {len(study.trials)} trials on the tuning cases "
            f"({', '.join(map(paths.shown, tuning))}).",
            f"Tuning objective {tuned:.1f} N, validation objective {checked:.1f} N (worst p99 peak over the law cells "
            f"+ {_FAILURE_N:g} N per failing door and case). Declared ranges: "
            + ", ".join(f"{k.key} {k.low:g} .. {k.high:g} {k.unit} ({k.line})" for k in declared),
            f"Laid over the system set like {file.name}; a calibrated set ships only after closed-loop runs "
            "confirm it.",
        ],
        {"ecu_software": rows},
    )
    return best, tuned, checked, target
