"""End to end: the open-loop window-regulator system benches (issue 4 acceptance) with params/rail_wr_8p5nm.txt.

Numbers asserted are those of the thesis where the models reach them, else the measured deviations the benches
report as KNOWN (testbenches/known.toml, docs/door-physics.md)."""

from __future__ import annotations

import pytest

from wrsim.benches.system import DRIVE_CLASSES, select_drive
from wrsim.report.results import write_bench_result


def test_stroke_matches_fig_5_7_and_5_8_and_reports_the_table_5_1_conflict(bench_run, tmp_path):
    result, m = bench_run("stroke")
    assert result.passed  # every metric passes or is a documented deviation (testbenches/known.toml)
    # the drive is identified from Fig. 5.7/5.8 (params/drive_8p5nm.txt): speed and current within 10 % at the
    # model's own drum torque (measured -2.5 / -2.2 %, +7.1 / +6.3 %)
    for where in ("bottom", "top"):
        assert abs(m[f"speed {where} deviation"].value) < 10.0 and m[f"speed {where} deviation"].passed
        assert abs(m[f"current {where} deviation"].value) < 10.0 and m[f"current {where} deviation"].passed
    # drum torque 1.4 -> 2.5 N*m (Fig. 5.7): top within 10 % (+7.5 %); the bottom +12.8 % is KNOWN (the
    # mechanism loses more than the thesis's constant 20 N when the drum drives it)
    assert abs(m["torque top deviation"].value) < 10.0
    assert 10.0 < m["torque bottom deviation"].value < 15.0 and m["torque bottom deviation"].known
    # Table 5.1's 3.11 s at 44 mm: 2.82 s, -9.2 %, KNOWN (Table 5.1's mean drum speed is below Fig. 5.8's)
    assert -10.0 < m["stroke time deviation"].value < -8.0 and m["stroke time deviation"].known
    assert m["upper spring in block while lifting"].value > 95.0
    assert 1.0 < m["lower spring tension min before the sealing"].value < 49.0
    out = write_bench_result(tmp_path / "results", result)
    header = (out / "waveforms.csv").read_text().splitlines()[0].split(",")
    assert {"time[s]", "speed_up[rpm]", "current_up[A]", "drum_torque_up[N*m]", "tension_upper_up[N]"} <= set(header)
    assert (out / "speed_current.png").stat().st_size > 10_000


def test_drum_diameter_sweep_reproduces_table_5_1_in_parallel(bench_run):
    result, m = bench_run("drum-diameter-sweep")
    assert result.passed  # the stroke times are documented deviations
    times = [m[f"stroke time deviation {d} mm"].value for d in (40, 42, 44, 46, 48)]
    for d in (40, 42, 44, 46, 48):
        assert abs(m[f"drum revolutions deviation {d} mm"].value) < 5.0
        assert m[f"stroke time deviation {d} mm"].known
    # 8.5 .. 9.9 % faster than Table 5.1 at every drum, and Table 5.1's trend over the drums within 1.5 points
    assert all(-10.0 < t < -8.0 for t in times) and max(times) - min(times) < 1.5
    times = [float(m[f"stroke time deviation {d} mm"].note.split(" s")[0]) for d in (40, 44, 48)]
    assert times[0] > times[1] > times[2]  # a larger drum lifts faster
    assert len(result.plots) == 1


def test_startup_first_peak_only_from_the_opposite_direction(bench_run):
    result, m = bench_run("startup")
    assert result.passed
    assert m["first peak / running speed, opposite direction"].value > 1.05
    assert m["first peak / running speed, same direction"].value < 1.0
    redistribution = m["extra drum angle before the glass moves, opposite vs same"]
    assert redistribution.value == pytest.approx(redistribution.reference, rel=0.3)


def test_pinch_resultant_stiffness_eq_4_42(bench_run):
    result, m = bench_run("stiffness")
    assert result.passed
    resultant = m["resultant stiffness deviation"]
    assert resultant.reference == 0.0 and abs(resultant.value) < 10.0  # 6.9 N/mm within 10 % (measured -5 %)
    assert "6.899 N/mm" in resultant.note


def test_select_drive_reproduces_the_thesis_choice():
    # thesis 5.3.1: 2.5 N*m load -> 8.5 N*m (40 %: 3.4 N*m; 15 % low: 7.2 N*m -> 2.9 N*m)
    rows, chosen = select_drive(2.5)
    assert chosen == 8.5
    assert [r.torque_class for r in rows] == list(DRIVE_CLASSES)
    assert rows[0].limit_nominal == pytest.approx(3.4)
    assert rows[0].limit_worst == pytest.approx(2.89)
    assert select_drive(3.0)[1] == 10.0
    assert select_drive(5.0)[1] is None


def test_select_drive_on_the_simulated_load(capsys, tmp_path):
    from wrsim.cli import main

    assert main(["select-drive", "--results", str(tmp_path / "results")]) == 0
    out = capsys.readouterr().out
    assert "working point: 2.69 N*m" in out
    assert "choice: 8.5 N*m" in out
