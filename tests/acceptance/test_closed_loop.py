"""The closed-loop window-regulator system (issue 5): ECU software and switch in GHDL, the plant in ngspice
(testbenches/tb_closed_loop.vhd). The normalization, pinch and pinch-drum-diameter benches run end to end
here, and the compliance matrix on a subset of its cells (the whole matrix is `make testbench`)."""

from __future__ import annotations

import shutil

import numpy as np
import pytest


def test_closed_loop_bench_lowers_with_the_digital_units(lib):
    from wrsim.backend.ngspice.netlist import Analysis, lower
    from wrsim.data.params import load_params
    from wrsim.elab.elaborate import elaborate
    from wrsim.paths import ROOT

    seq = str(ROOT / "params" / "sequences" / "pinch.txt")
    design = elaborate(
        lib,
        "tb_closed_loop",
        load_params(ROOT / "params" / "rail_wr_8p5nm.txt"),
        {"sequence_file": seq, "pinch_position": 0.36, "gauge_travel": 0.2, "gauge_insert": 10.0},
    )
    net = lower(design, Analysis(1.0, 5e-5), "closed loop")
    units = {u.entity: u for u in net.digital}
    assert set(units) == {"ecu_software", "switch"}
    assert units["switch"].generics["sequence_file"] == seq
    # the parameter set calibrates the digital unit too ([ecu_software] of params/rail_wr_8p5nm.txt)
    assert units["ecu_software"].generics["rpm_per_volt"] == 480
    assert units["ecu_software"].generics["threshold_rpm"] == 400
    widths = {p.name: p.width or 1 for p in units["ecu_software"].ports}
    assert widths["position"] == 32 and widths["supply_code"] == 8 and widths["hall_a"] == 1
    assert {"supply.ua", "pinch_force", "plant.door.pane.pos", "position", "normalized", "pinch"} <= set(net.probes)
    # digital outputs no equation reads are recorded by ngspice's event log, not by D->A bridges (which would add
    # breakpoints); a save list records only the signals it names
    assert "__dac [position_0]" not in net.text and net.events["position_0__a"] == "position_0"
    lean = lower(design, Analysis(1.0, 5e-5, save=("pinch_force", "normalized")), "closed loop")
    assert set(lean.events.values()) == {"normalized"}
    # the event log also records what equations read (relays, supply bits), for the reference solver's replay
    assert "eprvcd normalized relay_down relay_up voltage_offset_0 " in lean.text
    # the A->D bridges' 0/1 inputs may switch in one Newton iteration (XSPICE's default limit is 0.1 per iteration)
    assert " convabsstep=1" in net.text
    # relay_up: read by ecu_hardware's equations, so bridged once inside its .subckt
    assert net.text.count("a_relay_up__dac [relay_up]") == 1 and net.events["relay_up__a"] == "relay_up"


def test_normalization_runs_in_closed_loop(bench_run):
    """Thesis 5.2.1 / Fig. 5.3: the ECU (GHDL) counts the Hall edges of the plant (ngspice) negative on the
    way up, sets position 0 after the 500 ms stall in the top frame, and counts up on the way down."""
    result, m = bench_run("normalization")
    assert result.passed
    assert m["normalized after the stall at the top"].value == 1.0
    assert abs(m["stall time before normalization"].value - 500.0) <= 0.01  # the ECU's stall compare timer
    assert m["electronic position at the top"].value == 0.0
    # edges per metre on the way down: the ECU's 2112 within 3 % (cable springs)
    assert abs(m["edges per metre (-d position / d glass, down run)"].value / 2112.0 - 1.0) < 0.03
    assert m["Hall edges lost or gained on the way down"].value == 0.0  # every plant edge counted once


def test_a_list_for_a_digital_generic_names_the_key(lib, tmp_path):
    from wrsim.data.params import load_params
    from wrsim.elab.elaborate import elaborate
    from wrsim.errors import WrsimError
    from wrsim.paths import ROOT

    bad = tmp_path / "bad.txt"
    good = (ROOT / "params" / "rail_wr_8p5nm.txt").read_text()
    assert "rpm_per_volt = 480 rpm/V" in good
    shutil.copy(ROOT / "params" / "drive_8p5nm.txt", tmp_path)  # the set's include
    bad.write_text(good.replace("rpm_per_volt = 480 rpm/V", "rpm_per_volt = [440, 450] rpm/V"))
    with pytest.raises(
        WrsimError, match=r"bad\.txt:\d+: \[ecu_software\] rpm_per_volt: expected one value, got a list"
    ):
        elaborate(
            lib, "tb_closed_loop", load_params(bad), {"sequence_file": str(ROOT / "params" / "sequences" / "pinch.txt")}
        )


def test_pinch_at_9_13_and_16_volts(bench_run):
    """Thesis 5.3.2 / Fig. 5.11: after the normalization, three pinch events on the 10 N/mm gauge 40 mm below
    the lower edge of the top door frame (where the glass meets the sealing); the baseline algorithm; one set of
    ECU parameters; peaks within 15 % of the thesis's simulation at 9 and 13 V, rising with the voltage, below
    100 N, and the window reverses by reverse_mm every time. At 16 V the identified drive's faster glass
    overruns more: +21 %, a documented deviation (measured 49.2 / 67.5 / 74.8 N)."""
    result, m = bench_run("pinch")
    peaks = [m[f"peak force at {v} V"].value for v in (9, 13, 16)]
    for peak, thesis in zip(peaks[:2], (54.4, 58.7)):
        assert abs(peak / thesis - 1.0) <= 0.15
    assert 0.15 < peaks[2] / 61.6 - 1.0 < 0.25 and m["peak force at 16 V"].known
    assert peaks[0] < peaks[1] < peaks[2] < 100.0
    for v in (9, 13, 16):
        assert m[f"reversed at {v} V"].value == 1.0
        assert abs(m[f"glass travel down after the peak at {v} V"].value - 100.0) <= 20.0
    assert result.passed
    # the ECU's estimate (the algorithm's load above its reference / rpm_per_newton) passed the threshold
    # (400 rpm / 13 rpm/N = 30.8 N) at the detections and stays a force of the order of the gauge's
    estimate = next(w.values for w in result.waveforms if w.name == "estimated_force_pinch")
    assert 400 / 13 < estimate.max() < max(peaks)


def test_the_c_algorithm_in_the_loop_gives_the_vhdl_peaks(bench_run, tmp_path):
    """The example C algorithm (vhdl/digital/antipinch.c, linked into the ECU's GHDL unit through VHPIDIRECT)
    against its VHDL twin in the closed loop: the same detections, so the same peaks (issue 14: within one Hall
    edge)."""
    overlay = tmp_path / "c_algorithm.txt"
    overlay.write_text("[ecu_software]\nalgorithm = 1 1   # the C twin of the anti-pinch algorithm\n")
    _, vhdl = bench_run("pinch")
    _, c = bench_run("pinch", overlay)
    for v in (9, 13, 16):
        assert c[f"peak force at {v} V"].value == vhdl[f"peak force at {v} V"].value
        assert c[f"reversed at {v} V"].value == 1.0


def _algorithm_runs(labels: tuple[str, ...], algorithms: tuple[str, ...]):
    """The compliance bench cut to the runs `labels`, each run once per algorithm (params/antipinch/<name>.txt)."""
    import dataclasses

    from wrsim import BENCHES
    from wrsim.benches.closed_loop import algorithm_runs
    from wrsim.paths import ALGORITHMS

    full = BENCHES["compliance"]
    return dataclasses.replace(
        full,
        runs=algorithm_runs(
            tuple(r for r in full.runs if r.label in labels), {a: ALGORITHMS / f"{a}.txt" for a in algorithms}
        ),
    )


def test_a_supply_dip_reverses_all_but_the_supply_filter(lib, tmp_path):
    """Closing without an obstacle through a 13 -> 9 V dip of 10 ms (an engine crank), early, mid-stroke and late
    in three runs up (params/sequences/supply_dip.txt). The baseline compares the speed with the no-load speed of
    the supply as measured, and the speed lags the supply by the drive's time constant: back at 13 V the deficit
    jumps by rpm_per_volt * 4 V and the window reverses at every dip. Algorithm 2 filters the supply with that
    time constant: no false reversal. The observer, whose threshold rises by what a step not yet followed
    explains, was shaped on the family drive and reverses at the mid-stroke and the late dip on the identified
    drive (a documented out-of-sample failure, testbenches/known.toml)."""
    from wrsim import bench_params
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.benches.closed_loop import compliance_cells
    from wrsim.benches.core import simulate_runs

    algorithms = ("baseline", "supply_filtered", "observer")
    bench = _algorithm_runs(("supply_dip",), algorithms)
    sims, _ = simulate_runs(bench, lib, bench_params(bench), NgspiceBatch(), tmp_path)
    cells = compliance_cells(bench, sims)
    reversed_ = {a: [c.event.detected is not None for c in cells if c.run == f"{a}-supply_dip"] for a in algorithms}
    assert reversed_ == {"baseline": [True] * 3, "supply_filtered": [False] * 3, "observer": [False, True, True]}


def test_the_observer_keeps_the_stiff_rod_under_100_newtons(lib, tmp_path):
    """FMVSS 118's 65 N/mm rod at a 4 mm opening: the baseline's speed over a revolution lags the load by the
    drive's mechanical time constant, and at 16 V the force passes 100 N before it reverses; the load observer
    (mean deficit + tau x deceleration) reverses below 100 N at 9, 13 and 16 V."""
    from wrsim import bench_params
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.benches.closed_loop import compliance_cells
    from wrsim.benches.core import simulate_runs

    bench = _algorithm_runs(("65npmm_4mm",), ("baseline", "observer"))
    sims, _ = simulate_runs(bench, lib, bench_params(bench), NgspiceBatch(), tmp_path)
    peaks = {}
    for c in compliance_cells(bench, sims):
        assert c.law == "FMVSS 118" and c.event.detected is not None
        assert c.event.touch is not None and c.event.touch < c.event.detected
        peaks.setdefault(c.run.split("-")[0], []).append(c.event.peak)
    assert max(peaks["observer"]) < 100.0
    assert peaks["baseline"][2] > 100.0  # 16 V
    assert all(o < b for o, b in zip(peaks["observer"], peaks["baseline"]))


def test_pinch_drum_diameter(bench_run):
    """Thesis 5.3.3 / Fig. 5.12 says the peak force grows as the drum shrinks from 48 to 44 mm (a fixed
    detection torque is less force on a larger drum). With the baseline algorithm one Hall edge (about 5 N) is
    more than the curves differ by, and the faster glass of the larger drum overruns more: the peaks differ by
    under 10 % and do not fall monotonically with the diameter (measured 67.5, 63.8, 64.9 N). The bench keeps the
    thesis's trend as a metric (KNOWN); this test asserts what the model does."""
    result, m = bench_run("pinch-drum-diameter")
    peaks = [m[f"peak force with the {mm} mm drum"].value for mm in (44, 46, 48)]
    for mm in (44, 46, 48):
        assert m[f"reversed with the {mm} mm drum"].value == 1.0
    assert max(peaks) < 100.0
    assert max(peaks) / min(peaks) - 1.0 < 0.10
    assert m["peak force grows as the drum diameter shrinks"].passed is (peaks[0] > peaks[1] > peaks[2])


def test_can_replay_drives_a_full_cycle_and_the_status_log_decodes(bench_run):
    """Issue 5, CAN: the committed ASC log (up at 0.1 s, stop at 5 s, down at 5.5 s, stop at 10 s) becomes the
    switch sequence; the ECU's status, written as an ASC log, decodes with the DBC frame by frame."""
    result, m = bench_run("can-replay")
    assert m["status frames decoded with the DBC"].value == 1051  # 10.5 s every 10 ms, from 0 s
    assert m["motor state follows the logged command 1 at 0.1 s"].value <= 10.0
    assert m["motor state follows the logged command 2 at 5.5 s"].value <= 10.0
    assert abs(m["glass position reported at the top"].value - 400.0) <= 5.0
    assert abs(m["glass position reported at the end"].value) <= 5.0
    assert m["pinch events reported"].value == 0.0
    assert result.passed


def test_compliance_cells_and_the_top_seal(lib, tmp_path):
    """A subset of the compliance matrix (the whole one is `make testbench`; the ECU runs algorithm 6,
    params/antipinch/observer_rise.txt): the EU rod at the largest gap and
    the 20 N/mm US rod at 50 mm reverse at no more than 100 N at 9, 13 and 16 V; the 20 N/mm rod at 10 mm, which
    no regulation asks for (FMVSS 118 wants 65 N/mm there), is an information row without a verdict; the window
    closes into the top seal and frame without a false reversal; the matrix is written as CSV and HTML with a
    verdict and a margin per law cell, the HTML a heat map of the margins."""
    import dataclasses

    from wrsim import BENCHES, bench_params, run_bench
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.report.results import write_bench_result

    full = BENCHES["compliance"]
    bench = dataclasses.replace(
        full,
        runs=tuple(r for r in full.runs if r.label in ("10npmm_200mm", "20npmm_50mm", "20npmm_10mm", "no_obstacle")),
    )
    result = run_bench(bench, lib, bench_params(bench), NgspiceBatch(), tmp_path / "work")
    m = {x.name: x for x in result.metrics}
    assert not any("gap 10 mm" in name for name in m)  # the information row has no metrics
    for k, gap in ((10, 200), (20, 50)):
        for v in (9, 13, 16):
            assert m[f"reversed {k} N/mm, gap {gap} mm, {v} V"].value == 1.0
            assert m[f"peak force {k} N/mm, gap {gap} mm, {v} V"].value < 100.0
    for v in (9, 13, 16):
        assert m[f"no false reversal into the top seal at {v} V"].value == 0.0
    folder = write_bench_result(tmp_path / "results", result)
    rows = (folder / "compliance.csv").read_text().splitlines()
    assert rows[0] == "gauge [N/mm],gap [mm],regulation,9 V,13 V,16 V" and len(rows) == 5
    law = {tuple(r.split(",")[:3]): r.split(",")[3:] for r in rows[1:]}
    assert set(law) == {
        ("10", "200", "ECE R21"),
        ("20", "50", "FMVSS 118"),
        ("20", "10", "information"),
        ("none", "-", "-"),
    }
    assert all(c.startswith("INFO ") for c in law[("20", "10", "information")])
    for key in (("10", "200", "ECE R21"), ("20", "50", "FMVSS 118")):
        for cell, v in zip(law[key], (9, 13, 16)):
            peak = m[f"peak force {key[0]} N/mm, gap {key[1]} mm, {v} V"].value
            assert cell == f"PASS {peak:.1f} N (margin {100.0 - peak:+.1f} N)"
    page = (folder / "compliance.html").read_text()
    assert '<table class="grid">' in page and page.count('style="background:rgb(') == 6  # the law cells' margins
    assert '<a href="run-10npmm_200mm.html">PASS' in page  # a cell opens its run's page, its three closings drawn
    assert (folder / "run-10npmm_200mm.html").read_text().count("Plotly.newPlot(") == 3


def test_the_pwm_ecu_holds_the_stiff_rod_reopens_and_closes_in_time(lib, tmp_path):
    """The PWM compliance bench (params/ecu/pwm.txt, the current observer) on its hardest cells: the 65 N/mm rod at
    200 mm, which the relay ECU cannot keep under 100 N at 16 V (KNOWN there), and at 4 mm, reverses below 100 N at
    9, 13 and 16 V and reopens as FMVSS 118 S5(b) asks; without an obstacle the window closes at every supply, the
    full stroke at 13 V in at most 4 s (the whole matrix at -40, 20 and 85 degC is `make testbench`)."""
    import dataclasses

    from wrsim import BENCHES, bench_params, run_bench
    from wrsim.backend.ngspice.batch import NgspiceBatch

    full = BENCHES["compliance-pwm"]
    bench = dataclasses.replace(
        full, runs=tuple(r for r in full.runs if r.label in ("65npmm_200mm", "65npmm_4mm", "no_obstacle"))
    )
    result = run_bench(bench, lib, bench_params(bench), NgspiceBatch(), tmp_path / "work")
    m = {x.name: x for x in result.metrics}
    for gap in (200, 4):
        for v in (9, 13, 16):
            assert m[f"reversed 65 N/mm, gap {gap} mm, {v} V"].value == 1.0
            assert m[f"reopened 65 N/mm, gap {gap} mm, {v} V"].value == 1.0
            assert m[f"peak force 65 N/mm, gap {gap} mm, {v} V"].value < 100.0
    for v in (9, 13, 16):
        assert m[f"no false reversal into the top seal at {v} V"].value == 0.0
    assert 3.0 < m["stroke time at 13 V"].value <= 4.0
    assert result.passed


def test_the_averaged_h_bridge_agrees_with_the_switched_one_over_a_closing(lib, tmp_path):
    """The window closing from the bottom for 3 s at duty 0.80 on 13 V (0.2 .. 3 s, the glass to some 0.33 m) through
    h_bridge(averaged) and h_bridge(switched) (each MOSFET switched at 20 kHz with its dead time): the mean motor
    current within 2 % and the mean drum speed within 1 %, as issue 48 asks. Measured: 0.2 % and 0.2 %."""
    from wrsim import Analysis, elaborate, load_library, simulate
    from wrsim.benches.scenario import scenario_params
    from wrsim.paths import ROOT

    checks = load_library([ROOT / "vhdl", ROOT / "tests" / "fixtures" / "pwm"])
    means = {}
    for switched, label in ((False, "averaged__hb"), (True, "pwm__hb")):
        design = elaborate(checks, "tb_bridge_check", scenario_params(), {"switched": switched})
        w = simulate(design, Analysis(stop=3.0, max_step=1e-4, reltol=1e-4), tmp_path / label)
        t = w.time
        m = t >= 0.2
        span = t[m][-1] - t[m][0]
        means[switched] = (
            np.trapezoid(w[f"{label}.i_m"][m], t[m]) / span,
            np.trapezoid(w["plant.dut.speed_rpm"][m], t[m]) / span,
        )
    (i_avg, n_avg), (i_sw, n_sw) = means[False], means[True]
    assert i_avg > 2.0 and n_avg > 40.0  # the glass moves
    assert abs(i_avg / i_sw - 1.0) < 0.02
    assert abs(n_avg / n_sw - 1.0) < 0.01


def test_a_users_c_algorithm_replaces_the_shipped_one(lib, tmp_path):
    """A C file of the user's (here: one that never reports a pinch) is linked into the ECU instead of
    vhdl/digital/antipinch.c (`wrsim testbench --c-algorithm FILE`, which runs it as algorithm 1): the
    pinch bench then runs into the gauge without a reversal and stalls on it."""
    from wrsim import BENCHES, bench_params, run_bench
    from wrsim.benches.run import simulator
    from wrsim.paths import ALGORITHMS

    mine = tmp_path / "never.c"
    mine.write_text(
        "#include <stdint.h>\n"
        "void wrsim_ap_start(int32_t t, int32_t p, int32_t a, int32_t b, int32_t c, int32_t d, int32_t e,\n"
        "                    int32_t f, int32_t g, int32_t h, int32_t i, int32_t j) {}\n"
        "int32_t wrsim_ap_edge(int32_t t, int32_t p, int32_t n, int32_t up, int32_t u, int32_t i, int32_t norm)\n"
        "{ return 0; }\n"
        "void wrsim_ap_top(int32_t shift) {}\n"
        "int32_t wrsim_ap_load(void) { return 0; }\n"
    )
    bench = BENCHES["pinch"]
    result = run_bench(bench, lib, bench_params(bench, ALGORITHMS / "c_twin.txt"), simulator(mine), tmp_path / "w")
    m = {x.name: x for x in result.metrics}
    for v in (9, 13, 16):
        assert m[f"reversed at {v} V"].value == 0.0
    assert m["peak force at 16 V"].value > 100.0


def test_a_c_algorithm_that_is_not_a_c_file_is_one_error(tmp_path):
    from wrsim.benches.run import simulator
    from wrsim.errors import WrsimError

    with pytest.raises(WrsimError, match=r"missing\.c: not found"):
        simulator(tmp_path / "missing.c")
    (tmp_path / "algo.txt").write_text("x")
    with pytest.raises(WrsimError, match=r"algo\.txt: not a C file"):
        simulator(tmp_path / "algo.txt")


def test_a_one_touch_closing_runs_on_after_the_switch_is_released_reverses_and_reopens(tmp_path):
    """The catalog's one-touch case (testbenches/scenarios/catalog/tuning/one_touch_65npmm_100mm_16v.toml) with the
    PWM ECU and the current observer: the switch gives "11" for 0.1 s and is released; the ECU closes on its own into
    the 65 N/mm rod, reverses below 100 N and reopens as FMVSS 118 S5(b) asks (judged with the PWM ECU)."""
    from wrsim.benches.scenario_run import run_scenarios
    from wrsim.paths import SCENARIOS

    case = SCENARIOS / "catalog" / "tuning" / "one_touch_65npmm_100mm_16v.toml"
    (s,), (result,) = run_scenarios([case], ["antipinch/current_observer"], results=tmp_path, ecu="pwm")
    assert not isinstance(result, dict), result
    m = {x.name: x for x in result.metrics}
    assert m["closings (runs up after the normalization)"].value == 1
    assert m["reversed closing 1 (16.0 V)"].value == 1.0
    assert m["reopened closing 1 (16.0 V)"].value == 1.0
    assert m["peak force closing 1 (16.0 V)"].value < 100.0
    assert result.passed
