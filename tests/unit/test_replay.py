"""Record and replay (wrsim.benches.replay, testbenches/tb_replay.vhd): the input record's format and its errors,
and the ECU software replayed by GHDL alone on a record written by hand."""

from __future__ import annotations

import shutil

import pytest

from wrsim import paths
from wrsim.benches.replay import Replayer, ecu_generics, plant_digest, read_inputs
from wrsim.benches.scenario import scenario_params
from wrsim.cli import main
from wrsim.data.params import load_params
from wrsim.elab import load_library
from wrsim.errors import WrsimError

needs_ghdl = pytest.mark.skipif(shutil.which("ghdl-llvm") is None, reason="GHDL not installed (make setup)")


def test_a_record_outlives_a_changed_algorithm_but_not_a_changed_plant(tmp_path):
    """The record key's library digest leaves out the algorithm package (a held-off reversal makes the plant
    independent of it), so that an engineer changing an algorithm replays on the records already made; in the plant
    a comment or the layout keeps the records, any other edit does not."""
    copy = tmp_path / "vhdl"
    shutil.copytree(paths.VHDL, copy)
    digest = plant_digest(load_library([copy]))
    package = copy / "digital" / "antipinch.vhd"
    package.write_text(package.read_text().replace("60_000_000", "60_000_001"))  # a changed algorithm
    assert plant_digest(load_library([copy])) == digest
    door = copy / "door" / "door.vhd"
    text = door.read_text()
    door.write_text("-- a note on the door\n" + text.replace(";", " ;", 1))
    assert plant_digest(load_library([copy])) == digest
    door.write_text(text + "\nlibrary ieee;\n")
    assert plant_digest(load_library([copy])) != digest


def test_an_input_record_is_read_from_blanks_or_commas(tmp_path):
    csv = tmp_path / "door.csv"
    csv.write_text("t_us,hall_a,hall_b,supply_dv,command\n0,0,0,130,00\n200001,0,0,130,01  # up\n\n204886,1,0,-1,01\n")
    out = tmp_path / "checked.txt"
    assert read_inputs(csv, out) == 3
    assert out.read_text().splitlines()[1:] == ["0 0 0 130 00", "200001 0 0 130 01", "204886 1 0 -1 01"]
    pwm = tmp_path / "pwm.txt"  # a PWM ECU's record: the current's ADC code in a sixth column
    pwm.write_text("0 0 0 130 00 512\n5 1 0 97 01 590\n")
    assert read_inputs(pwm, out) == 2
    assert out.read_text().splitlines()[1:] == ["0 0 0 130 00 512", "5 1 0 97 01 590"]


@pytest.mark.parametrize(
    ("line", "error"),
    [
        ("5 0 0 130", "door.txt:2: expected 5 or 6 columns"),
        ("5 0 0 130 01 1024", "door.txt:2: column 6 (current_code): '1024' is not an ADC code (0 .. 1023)"),
        ("x 0 0 130 01", "door.txt:2: column 1 (t_us): 'x' is not a time in us"),
        ("3 0 0 130 01", "door.txt:2: column 1 (t_us): 3 us goes back (the line before is at 4 us)"),
        ("5 2 0 130 01", "door.txt:2: column 2 (hall_a): '2' is not a std_logic level"),
        ("5 0 0 256 01", "door.txt:2: column 4 (supply_dv): '256' is not a supply in 0.1 V"),
        ("5 0 0 130 1", "door.txt:2: column 5 (command): '1' is not two std_logic levels"),
    ],
)
def test_a_bad_input_record_names_its_line_and_column(tmp_path, line, error):
    bad = tmp_path / "door.txt"
    bad.write_text(f"4 0 0 130 00\n{line}\n")
    with pytest.raises(WrsimError, match=error.replace("(", r"\(").replace(")", r"\)")):
        read_inputs(bad, tmp_path / "out.txt")
    assert not (tmp_path / "out.txt").exists()


def test_replay_of_a_bad_record_is_one_error_with_exit_2(tmp_path, capsys):
    bad = tmp_path / "door.txt"
    bad.write_text("0 0 0 130 00\n7 0 0 130\n")
    assert main(["replay", str(bad), "--algorithm", "baseline"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{bad}:2: expected 5 or 6 columns" in err


def _door(run_us: int, edge_us: list[int], supply: int = 130) -> str:
    """An input record by hand: up from power-up, Hall-A edges at the given periods (B in phase for lifting)."""
    lines, t, a = ["0 0 0 130 00", f"{run_us} 0 0 {supply} 01"], run_us, 0
    for period in edge_us:
        t += period
        a ^= 1
        lines.append(f"{t} {a} {1 - a} {supply} 01")
    return "\n".join(lines) + "\n"


def _learned_door(edge_us: int, closing: list[int]) -> tuple[list[str], int]:
    """An input record by hand: a normalization run up of 900 Hall-A edges `edge_us` apart that stalls at the top,
    a run down as long, a stop, and a run up with its edges at the periods `closing` [us]; its lines and [us] when
    that last run starts."""
    lines = _door(200_000, [edge_us] * 900).splitlines()
    t, a = int(lines[-1].split()[0]) + 600_000, int(lines[-1].split()[1])
    lines.append(f"{t} {a} {1 - a} 130 10")
    for _ in range(900):
        t += edge_us
        a ^= 1
        lines.append(f"{t} {a} {a} 130 10")
    t += 600_000
    lines.append(f"{t} {a} {a} 130 00")
    t += 100_000
    start = t
    lines.append(f"{t} {a} {a} 130 01")
    for period in closing:
        t += period
        a ^= 1
        lines.append(f"{t} {a} {1 - a} 130 01")
    return lines, start


@needs_ghdl
def test_the_ecu_replays_a_hand_written_record(tmp_path):
    """A learning run up that stalls (normalization), down, then up with a speed that drops by a third over a
    few edges: every VHDL algorithm detects it, at an edge of the record; the C twin on the same edge as the
    baseline it implements. A record without the drop: no detection."""
    lib = load_library(paths.LIBRARY)
    replayer = Replayer(tmp_path / "build", lib)
    rev = 60e6 / 5800  # [us] one revolution at 5800 rpm (13 V, no load, 450 rpm/V)
    closing = [round(rev / 4)] * 600 + [round(rev / 4 * (1 + 0.05 * k)) for k in range(1, 12)]
    lines, _ = _learned_door(round(rev / 4), closing)
    t = int(lines[-1].split()[0])
    record = tmp_path / "door.txt"
    record.write_text("\n".join(lines) + "\n")
    edges = {int(ln.split()[0]) for ln in lines}
    base = scenario_params()
    decided = {}
    for name in ("baseline", "c_twin", "observer", "observer_rise"):
        generics = ecu_generics(lib, base.beneath(load_params(paths.ALGORITHMS / f"{name}.txt")))
        decided[name] = replayer.run(record, generics, tmp_path / name)
    assert decided["baseline"] == decided["c_twin"]
    for d in decided.values():
        assert d.detected is not None and round(d.detected * 1e6) in edges and d.detected * 1e6 > t - sum(closing[-11:])
    steady = tmp_path / "steady.txt"
    steady.write_text("\n".join(lines[: -len(closing) + 600]) + "\n")
    assert replayer.run(steady, generics, tmp_path / "steady").detected is None


@needs_ghdl
def test_the_settled_reference_does_not_learn_the_glass_swing(tmp_path):
    """A learning run whose speed swings by 300 rpm with the period of the glass on its cable (67 ms, the set's
    mode_ms): the observer (4) learns the swing into its bins of 8 edges, a pattern over the position (its deficit
    swings by about 1100 rpm peak to peak: tau x the deceleration adds to the speed's own 600); the observer with a
    settled reference (5) learns the mean over one swing, flat to what a window of whole edges leaves (one edge,
    3 ms, of the 67 ms: about 5 % of the swing's amplitude). Inner bins: at the ends of the learned stretch the
    mean covers half a swing."""
    import math

    lib = load_library(paths.LIBRARY)
    replayer = Replayer(tmp_path / "build", lib)
    periods, t = [], 0.0
    while len(periods) < 1200:
        rpm = 5000.0 + 300.0 * math.sin(2 * math.pi * t / 67_000.0)
        periods.append(round(15e6 / rpm))
        t += periods[-1]
    record = tmp_path / "learning.txt"
    record.write_text(_door(200_000, periods))
    base = scenario_params()
    spread = {}
    for name in ("observer", "observer_settled"):
        generics = ecu_generics(lib, base.beneath(load_params(paths.ALGORITHMS / f"{name}.txt")))
        learned = tmp_path / f"{name}.learned"
        assert replayer.run(record, {**generics, "learned_out": str(learned)}, tmp_path / name).detected is None
        bins = [int(ln.split()[2]) for ln in learned.read_text().splitlines() if ln.startswith("bin ")]
        assert len(bins) > 60
        spread[name] = max(bins[2:-2]) - min(bins[2:-2])
    assert spread["observer"] > 500 and spread["observer_settled"] < 30, spread


@needs_ghdl
def test_the_settled_observer_holds_where_the_observer_reverses_on_a_swinging_door(tmp_path):
    """Records of a door of the fleet (tests/fixtures/records/fleet-seed1-door2: 52 degC, a learning run that swings
    throughout, docs/anti-pinch.md "Algorithm 5"): the observer, its reference holding the swing, reverses without an
    obstacle at 9 V, on a rough road at 13 V, and before the glass reaches a 10 N/mm rod; the observer with a settled
    reference makes none of these and detects the rod 57 ms after the touch (3.974 s in the closed loop's record)."""
    import numpy as np

    from wrsim.benches.replay import Record

    fixture = paths.ROOT / "tests" / "fixtures" / "records" / "fleet-seed1-door2"
    records = {}
    for case in ("no_obstacle_9v", "rod_10npmm_25mm_9v", "rough_road_8hz_13v"):
        folder = tmp_path / case
        folder.mkdir()
        shutil.copy(fixture / "learning.txt", folder / "learning.txt")
        shutil.copy(fixture / f"{case}.txt", folder / "inputs.txt")
        records[case] = Record(case, folder, 887, np.zeros(1), np.zeros(1), np.zeros(1))
    lib = load_library(paths.LIBRARY)
    replayer = Replayer(tmp_path / "build", lib)
    base = scenario_params()
    found = {}
    for name in ("observer", "observer_settled"):
        generics = ecu_generics(lib, base.beneath(load_params(paths.ALGORITHMS / f"{name}.txt")))
        found[name] = {case: replayer.replay(rec, generics, f"{name}-{case}").detected for case, rec in records.items()}
    touch = 3.974
    old, new = found["observer"], found["observer_settled"]
    assert old["no_obstacle_9v"] is not None and old["rough_road_8hz_13v"] is not None
    assert old["rod_10npmm_25mm_9v"] is not None and old["rod_10npmm_25mm_9v"] < touch - 1.0
    assert new["no_obstacle_9v"] is None and new["rough_road_8hz_13v"] is None
    assert new["rod_10npmm_25mm_9v"] is not None and touch < new["rod_10npmm_25mm_9v"] < touch + 0.1


def test_calibrate_input_errors_are_one_line_with_exit_2(tmp_path, capsys):
    assert main(["calibrate", "baseline", "--fleet", "tolerances/production", "--samples", "1", "--trials", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "baseline.txt: declares no calibration value" in err
    bad = tmp_path / "alg.txt"
    bad.write_text("[glass]\nm = 2.55 kg in 2 .. 3 kg calibrate\n")
    assert main(["calibrate", str(bad), "--fleet", "tolerances/production"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "alg.txt:2: [glass] m: only [ecu_software] values can be calibrated" in err
    assert main(["score", "--fleet", "tolerances/production", "--samples", "0"]) == 2
    assert "--samples 0: a fleet needs at least one door" in capsys.readouterr().err
    c_set = tmp_path / "c.txt"  # the C twin with a declared value: refused before a door is recorded
    c_set.write_text("[ecu_software]\nalgorithm = 1 1\nthreshold_rpm = 400 rpm in 150 .. 700 rpm calibrate\n")
    assert main(["calibrate", str(c_set), "--fleet", "tolerances/production", "--samples", "1"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "c.txt: the C algorithm takes no warm start" in err


def test_a_closed_loop_check_needs_record_folders(tmp_path, capsys):
    door = tmp_path / "door.txt"
    door.write_text("0 0 0 130 00\n")
    args = ["replay", str(door), "--closed-loop", str(paths.SCENARIOS / "catalog"), "--algorithm", "baseline"]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "door.txt: an input record file has no scenario to run in closed loop" in err
    assert main(["replay", str(tmp_path), "--algorithm", "baseline"]) == 2
    assert "no records in this folder (wrsim record writes them)" in capsys.readouterr().err


def _swinging_door(speed) -> tuple[str, float]:
    """A normalization run up at a steady 5000 rpm that stalls at the top, a run down, and a run up whose speed
    [rpm] is `speed`(t) [s since its start] (at least 500 rpm): an input record by hand, cut 1.2 s into the last
    run, and [s] when that run starts."""
    closing, run = [], 0
    while run < 1_200_000:
        closing.append(round(15e6 / max(500.0, speed(run * 1e-6))))
        run += closing[-1]
    lines, start = _learned_door(3000, closing)
    return "\n".join(lines) + "\n", start * 1e-6


@needs_ghdl
def test_the_rise_over_one_swing_sees_a_rod_the_swing_hides(tmp_path):
    """A run up that swings with the glass on its cable (300 rpm at the set's mode_ms, 67 ms: the observer's load
    swings by some 640 rpm, 50 N) from its start on, as a glass stick-slipping in its seals, and meets a rod 400 ms
    after the start (the speed falls by 20 rpm/ms, some 100 N in 67 ms): algorithm 5's threshold has risen by the
    swing and the start-up term, so it sees the rod 43 ms after the touch; algorithm 6 compares the load with its
    value one swing earlier, in which the swing cancels, and reverses 14 ms after it. The same run with a 6 Hz road
    (another period, so it does not cancel; 250 rpm) instead of the rod: algorithm 6 rides through it (tested only
    after half the 5 Hz road's period; after half a swing's, 33 ms, it reversed 149 ms into the run)."""
    import math

    lib = load_library(paths.LIBRARY)
    replayer = Replayer(tmp_path / "build", lib)
    base = scenario_params()
    touch = 0.4

    def rod(t: float) -> float:
        return 5000.0 + 300.0 * math.sin(2 * math.pi * t / 0.067) - 20_000.0 * max(0.0, t - touch)

    def road(t: float) -> float:
        return 5000.0 + 300.0 * math.sin(2 * math.pi * t / 0.067) + 250.0 * math.sin(2 * math.pi * 6.0 * t + 5.0)

    found = {}
    for case, speed in (("rod", rod), ("road", road)):
        record = tmp_path / f"{case}.txt"
        text, run = _swinging_door(speed)
        record.write_text(text)
        for name in ("observer_settled", "observer_rise"):
            generics = ecu_generics(lib, base.beneath(load_params(paths.ALGORITHMS / f"{name}.txt")))
            found[case, name] = replayer.run(record, generics, tmp_path / f"{name}-{case}").detected
    t5, t6 = found["rod", "observer_settled"], found["rod", "observer_rise"]
    assert t6 is not None and run + touch < t6 < run + touch + 0.02, (run, found)
    assert t5 is not None and t5 > run + touch + 0.035, (run, found)
    assert found["road", "observer_rise"] is None, found


@needs_ghdl
def test_the_rise_waits_for_the_wind_up_to_crest_on_a_hot_door(tmp_path):
    """The compliance bench's first closing without an obstacle at 85 degC (tests/fixtures/records/compliance-85c,
    9 V from the bottom into the top seal). The hot drive's observer load falls for some 90 ms after the start (its
    time constant is twice the 20 degC one the ECU keeps) before the cable winds up by some 146 N: a crest taken as
    the first fall from the highest load so far fell on the first edge, and algorithm 6 reversed on the wind-up at
    10.237 s. Taken as a rise from the lowest load and a fall from the highest since, the crest is the breakaway and
    the closing runs into the top seal, as with algorithm 5."""
    record = paths.ROOT / "tests" / "fixtures" / "records" / "compliance-85c" / "no_obstacle_9v.txt"
    lib = load_library(paths.LIBRARY)
    replayer = Replayer(tmp_path / "build", lib)
    base = scenario_params(["rail_wr_8p5nm_85c"])
    for name in ("observer_settled", "observer_rise"):
        generics = ecu_generics(lib, base.beneath(load_params(paths.ALGORITHMS / f"{name}.txt")))
        assert replayer.run(record, generics, tmp_path / name).detected is None, name
