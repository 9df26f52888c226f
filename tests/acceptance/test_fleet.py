"""The fleet score (wrsim.study.fleet, docs/anti-pinch.md "Fleet score"): doors drawn reproducibly, every case
recorded once per door and kept (a killed recording resumes with the records it finished), every algorithm replayed;
the same seed gives the same numbers."""

from __future__ import annotations

import os

import pytest

from wrsim import paths
from wrsim.benches.scenario import load_scenario
from wrsim.study.fleet import OVERRUN_S, case_scores, doors, fleet_folder, fleet_outcomes, law, reach, upper_bound

TOLERANCES = ["tolerances/production", "tolerances/ambient"]
SEED = 3
CASES = [
    paths.SCENARIOS / "catalog" / "tuning" / "rod_10npmm_25mm_13v.toml",
    paths.SCENARIOS / "catalog" / "tuning" / "startup_65npmm_20mm_above_250mm_16v.toml",
]


def test_doors_are_the_same_for_a_seed_whatever_the_fleet_size():
    three, five = doors(TOLERANCES, 3, 7), doors(TOLERANCES, 5, 7)
    assert [d.sections for d in three] == [d.sections for d in five[:3]]
    other = doors(TOLERANCES, 1, 8)[0]
    assert other.sections != three[0].sections
    temps = [d.number_in("ambient", "temperature", "degC") for d in five]
    assert all(-40.0 <= t <= 85.0 for t in temps) and len(set(temps)) == 5


def test_what_a_case_states_holds_on_every_door():
    # a door is the set a case starts from: the case's own temperature and sets lie over the door's draws (the
    # armature resistance scales with the temperature: at the case's 85 degC by the same factor on every door)
    from wrsim.benches.core import Run
    from wrsim.benches.scenario import own_sets

    hot = load_scenario(paths.SCENARIOS / "catalog" / "validation" / "hot_85c_16v.toml")
    aged = load_scenario(paths.SCENARIOS / "catalog" / "validation" / "aged_mechanism_13v.toml")
    free = load_scenario(paths.SCENARIOS / "catalog" / "tuning" / "no_obstacle_9v.toml")
    factors = {}
    for i, door in enumerate(doors(TOLERANCES, 2, SEED)):
        ra = door.number_in("dcpm_motor", "ra", "Ohm")
        at = {s.name: Run(s.name, {}, own_sets(s) or None).parameters(door) for s in (hot, aged, free)}
        factors[i] = [at[s.name].number_in("dcpm_motor", "ra", "Ohm") / ra for s in (hot, free)]
        assert at[aged.name].number_in("slider", "f_0", "N") == 16.5 != door.number_in("slider", "f_0", "N")
    assert factors[0][0] == pytest.approx(factors[1][0], rel=1e-12)  # 85 degC on both doors
    assert factors[0][1] != pytest.approx(factors[1][1], rel=1e-3)  # each door's own drawn temperature
    assert factors[0][0] > max(factors[0][1], factors[1][1])


def test_a_door_txt_starts_a_case_as_the_fleet_did(tmp_path):
    # `wrsim scenario CASE --door door.txt` lays the door beneath the case's own sets, as the fleet does
    from wrsim.benches.core import Run
    from wrsim.benches.scenario import own_sets, scenario_params
    from wrsim.study.fleet import save_door

    door = doors(TOLERANCES, 1, SEED)[0]
    txt = save_door(tmp_path, door, scenario_params(TOLERANCES), "door 0")
    for case in ("validation/hot_85c_16v.toml", "tuning/no_obstacle_9v.toml", "validation/aged_mechanism_13v.toml"):
        s = load_scenario(paths.SCENARIOS / "catalog" / case)
        run = Run(s.name, {}, own_sets(s) or None)
        fleet, again = run.parameters(door), run.parameters(scenario_params((), door=txt))
        for entity, key, unit in (("dcpm_motor", "ra", "Ohm"), ("slider", "f_0", "N"), ("glass", "m", "kg")):
            assert again.number_in(entity, key, unit) == pytest.approx(fleet.number_in(entity, key, unit), rel=1e-12)


def test_law_cells_read_fmvss_as_written():
    rod = load_scenario(CASES[0])  # 10 N/mm at 25 mm
    start = load_scenario(CASES[1])  # 65 N/mm at 270 mm glass position: 100 mm below the sealing
    free = load_scenario(paths.SCENARIOS / "catalog" / "tuning" / "no_obstacle_9v.toml")
    soft = load_scenario(paths.SCENARIOS / "catalog" / "tuning" / "soft_rod_5npmm_100mm_13v.toml")
    assert (law(rod), law(start), law(free), law(soft)) == ("ECE R21", "FMVSS 118", None, None)


def test_reach_is_the_latest_detection_that_keeps_the_peak_at_the_limit(tmp_path):
    import numpy as np

    from wrsim.benches.replay import Record

    t = np.linspace(0.0, 1.0, 10001)
    force = np.clip(2000.0 * (t - 0.5), 0.0, None)  # touch at 0.5 s, 2 N/ms: 100 N at 0.55 s
    rec = Record("r", tmp_path, 0, t, force, t)
    assert reach(rec, 100.0) == pytest.approx(0.05 - OVERRUN_S, abs=2e-4)
    assert reach(rec, 10.0) == pytest.approx(0.005 - OVERRUN_S, abs=2e-4) and reach(rec, 10.0) < 0  # out of reach
    assert reach(rec, 5000.0) == float("inf")
    assert reach(Record("free", tmp_path, 0, t, 0 * t, t), 100.0) is None


def test_the_clopper_pearson_bound():
    assert abs(upper_bound(0, 100) - (1 - 0.05 ** (1 / 100))) < 1e-12  # no event: 1 - alpha^(1/n), about 3 %
    assert upper_bound(3, 3) == 1.0 and 0.0 < upper_bound(1, 50) < 0.1


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """The results folder of this module's fleet: the calibration test reuses the fleet test's records."""
    return tmp_path_factory.mktemp("fleet") / "results"


def test_a_fleet_is_reproducible_and_resumes(results):
    fleet = doors(TOLERANCES, 1, SEED)
    algorithms = ["baseline", "observer"]
    workdir = fleet_folder(TOLERANCES, SEED, results)
    scenarios, first = fleet_outcomes(CASES, algorithms, fleet, workdir)
    assert len(first) == 4 and all(o.door == 0 for o in first)
    kept = workdir / "door-0" / CASES[0].stem / "trace.npz"
    other = workdir / "door-0" / CASES[1].stem / "trace.npz"
    stamp = other.stat().st_mtime_ns
    os.remove(kept)  # a recording killed before its trace was written: that case runs again, the other is kept
    _, again = fleet_outcomes(CASES, algorithms, fleet, workdir)
    assert again == first and kept.is_file() and other.stat().st_mtime_ns == stamp
    scores = case_scores(scenarios, again)
    by = {(c.algorithm, c.case): c for c in scores}
    rod = by[("observer", CASES[0].stem)]
    assert rod.obstacle and rod.law == "ECE R21" and rod.doors == 1
    assert 10.0 < rod.peaks[2] < 100.0 and rod.failures == 0 and 0.0 < rod.latency[0] < 200.0
    assert rod.reach[1] == 0 and rod.latency[0] < rod.reach[0] < 1000.0  # detected within its reach


def test_a_fleet_recorded_on_dask_equals_the_local_one(results, tmp_path):
    """The same door and cases recorded on a Dask LocalCluster: the records (their files travel back) and the
    decisions equal the local fleet's; a worker with another model library is one error."""
    import numpy as np
    from distributed import Client

    from wrsim.benches.replay import record_files
    from wrsim.errors import WrsimError
    from wrsim.study.engine import local_cluster

    fleet = doors(TOLERANCES, 1, SEED)
    algorithms = ["baseline", "observer"]
    _, local = fleet_outcomes(CASES, algorithms, fleet, fleet_folder(TOLERANCES, SEED, results))
    with local_cluster(1) as cluster, Client(cluster) as client:
        _, remote = fleet_outcomes(CASES, algorithms, fleet, tmp_path / "fleet", client)
    assert remote == local
    for case in CASES:
        here = np.load(fleet_folder(TOLERANCES, SEED, results) / "door-0" / case.stem / "trace.npz")
        there = np.load(tmp_path / "fleet" / "door-0" / case.stem / "trace.npz")
        assert all(np.array_equal(here[k], there[k]) for k in ("time", "force", "glass", "key"))
    with pytest.raises(WrsimError, match="model library .* differs from the one the fleet records with"):
        record_files([], fleet[0], "0" * 64)


def test_calibration_end_to_end(results, tmp_path):
    """Three trials on one door's two tuning cases (the fleet test's records): the shipped values are the first
    trial, the best is written as a set with its provenance, and a second call resumes the study (no trial run
    again)."""
    from wrsim.data.params import load_params
    from wrsim.study.calibrate import calibrate, knobs

    declared = {k.key: (k.low, k.high) for k in knobs(paths.ALGORITHMS / "observer.txt")}
    assert declared == {"threshold_rpm": (150, 700), "startup_rpm": (0, 800), "startup_ms": (100, 1500)}
    args = dict(tuning=CASES, validation=CASES[:1], results=results, out=tmp_path / "cal.txt")
    best, tuned, checked, target = calibrate("observer", TOLERANCES, 1, SEED, 3, **args)
    assert set(best) == set(declared) and all(declared[k][0] <= v <= declared[k][1] for k, v in best.items())
    assert 0.0 < tuned and 0.0 < checked
    cal = load_params(target)
    assert cal.sections["ecu_software"]["algorithm"].value == 4.0
    assert {k: cal.sections["ecu_software"][k].value for k in best} == {k: float(v) for k, v in best.items()}
    assert "calibrated by `wrsim calibrate` on 1 doors" in target.read_text()
    journal = fleet_folder(TOLERANCES, SEED, results) / "calibrate-observer.journal"
    again = calibrate("observer", TOLERANCES, 1, SEED, 3, **args)
    assert again[:3] == (best, tuned, checked)
    import optuna
    from optuna.storages.journal import JournalFileBackend

    storage = optuna.storages.JournalStorage(JournalFileBackend(str(journal)))
    (summary,) = optuna.get_all_study_summaries(storage)
    assert summary.n_trials == 3  # resumed: no trial ran twice


def test_a_pwm_fleet_keeps_its_records_apart_and_replays_as_its_closed_loop(results, tmp_path):
    """The same door and the 10 N/mm rod recorded with the PWM ECU (`wrsim score --fleet --ecu pwm`): its records
    lie apart from the relay ECU's and carry the current; the current observer replayed on them decides on the
    closed loop's Hall edge (the closed-loop run of the case on the same door with the PWM ECU) and keeps the rod
    under 100 N."""
    from wrsim.benches.replay import against_closed_loop
    from wrsim.study.fleet import save_door

    fleet = doors(TOLERANCES, 1, SEED)
    workdir = fleet_folder(TOLERANCES, SEED, results, "pwm")
    assert workdir != fleet_folder(TOLERANCES, SEED, results) and workdir.name.endswith("-pwm")
    scenarios, outcomes = fleet_outcomes(CASES[:1], ["current_observer"], fleet, workdir, ecu="pwm")
    (o,) = outcomes
    assert o.detected is not None and o.touch is not None and 0.0 < o.latency < 0.2 and o.peak < 100.0
    rows = (workdir / "door-0" / CASES[0].stem / "inputs.txt").read_text().splitlines()[1:]
    assert rows and all(len(r.split()) == 6 for r in rows)  # t_us hall_a hall_b supply_dv command current_code
    from wrsim.benches.replay import load_record
    from wrsim.benches.scenario import scenario_params

    door = save_door(tmp_path, fleet[0], scenario_params(TOLERANCES), "door 0")
    (check,) = against_closed_loop(
        [load_record(workdir / "door-0" / CASES[0].stem)], CASES[:1], ["current_observer"], tmp_path, [door], ecu="pwm"
    )
    assert check.same, check
