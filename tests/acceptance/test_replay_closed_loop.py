"""Record and replay against the closed loop (docs/anti-pinch.md, "Record and replay"): a scenario recorded once
with the reversal held off, then each algorithm replayed by GHDL alone, detects on the Hall edge the closed-loop
run of the same scenario reverses on, and learns the same state on the replayed normalization run."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.benches.closed_loop import events
from wrsim.benches.core import simulate_runs
from wrsim.benches.replay import Replayer, ecu_generics, record
from wrsim.benches.run import simulator
from wrsim.benches.scenario import load_scenario, scenario_params
from wrsim.benches.scenario_run import WarmStart, scenario_bench
from wrsim.data.params import load_params
from wrsim.elab import load_library

CASE = paths.SCENARIOS / "cases" / "rod_right_after_start_16v.toml"


def test_replayed_decisions_are_the_closed_loops(tmp_path):
    lib, runner = load_library(paths.LIBRARY), simulator()
    (rec,) = record([CASE], tmp_path / "records", lib=lib, runner=runner)
    assert rec.learning is not None and rec.start_position > 0 and rec.force.max() > 300.0  # held off: the rod stalls
    replayer = Replayer(tmp_path / "replay", lib, keep=True)
    base = scenario_params()
    warm = WarmStart(lib, runner, tmp_path / "learn")
    for name in ("baseline", "observer"):
        algorithm = paths.ALGORITHMS / f"{name}.txt"
        decision = replayer.replay(rec, ecu_generics(lib, base.beneath(load_params(algorithm))), name)
        scenario = dataclasses.replace(load_scenario(CASE), params=(algorithm,))
        bench = scenario_bench(scenario, base, warm)
        (sim,), _ = simulate_runs(bench, lib, base, runner, tmp_path / name)
        (closing,) = events(bench, sim)
        assert closing.detected is not None and decision.detected is not None
        assert abs(closing.detected - decision.detected) < 2e-6, name  # the same edge (1 us timer, 1 us d_cosim delay)
        # the replayed normalization run taught the algorithm what the closed loop's taught it
        learned = Path(str(warm.generics(scenario, base)["learned_file"]))
        replayed = tmp_path / "replay" / "replays" / rec.name / name / "learned.txt"
        assert replayed.read_text() == learned.read_text()
        # the peak after the reversal lies above the force the record has at the detection
        assert closing.peak >= rec.force_at(decision.detected) - 0.5
        assert np.isfinite(closing.peak)
