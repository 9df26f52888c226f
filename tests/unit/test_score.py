"""The anti-pinch score's aggregation of the compliance cells (wrsim.benches.score), on made-up events."""

from __future__ import annotations

import math

import pytest


def _event(peak: float, touch: float | None, detected: float | None):
    from wrsim.benches.closed_loop import Event

    return Event(start=10.0, supply=13.0, peak=peak, touch=touch, detected=detected, stop=None, drop=0.0)


def test_score_counts_law_cells_false_reversals_and_latency():
    from wrsim.benches.closed_loop import Cell
    from wrsim.benches.score import score_cells

    cells = [
        Cell("a-10npmm_4mm", "10npmm_4mm", 10, 4, "ECE R21", "9 V", _event(60.0, 11.000, 11.020)),
        Cell("a-10npmm_4mm", "10npmm_4mm", 10, 4, "ECE R21", "16 V", _event(100.5, 11.0, 11.04)),  # over 100 N
        Cell("a-65npmm_4mm", "65npmm_4mm", 65, 4, "FMVSS 118", "9 V", _event(80.0, 12.000, None)),  # no reversal
        Cell("a-20npmm_10mm", "20npmm_10mm", 20, 10, None, "9 V", _event(150.0, 12.0, 12.1)),  # information
        Cell("a-no_obstacle", "no_obstacle", None, None, None, "13 V", _event(0.0, None, 13.5)),  # reversed
        Cell("a-supply_dip", "supply_dip", None, None, None, "early", _event(0.0, None, None)),
        Cell("a-rough_road_1g", "rough_road_1g", None, None, None, "16 V", _event(0.0, None, 25.0)),
    ]
    s = score_cells("mine", cells, [], None)
    assert s.worst == {"ECE R21": 100.5, "FMVSS 118": 80.0}  # the information row does not count
    assert (s.failed, s.cells) == (2, 3)
    assert (s.false_reversals, s.disturbances, s.beyond_reversals, s.beyond) == (1, 2, 1, 1)
    assert s.latency_ms == pytest.approx((40.0, 100.0))  # median and largest over the rods, info row too
    assert not s.passed and s.drum_peaks == () and s.drum_trend


def test_score_without_a_detection_has_no_latency():
    from wrsim.benches.closed_loop import Cell
    from wrsim.benches.score import score_cells

    s = score_cells(
        "none", [Cell("10npmm_4mm", "10npmm_4mm", 10, 4, "ECE R21", "9 V", _event(40.0, 11.0, None))], [], None
    )
    assert all(math.isnan(x) for x in s.latency_ms) and s.failed == 1


def test_score_names_an_unknown_algorithm():
    from wrsim.benches.score import score_algorithms
    from wrsim.errors import WrsimError

    with pytest.raises(WrsimError, match=r"unknown anti-pinch algorithm 'nope' .*observer"):
        score_algorithms(["nope"])


def test_the_score_page_is_written_with_a_table_and_a_plot(tmp_path):
    from wrsim.benches.score import Score, score_page
    from wrsim.report.results import write_bench_result

    good = Score("observer", {"ECE R21": 51.3, "FMVSS 118": 78.5}, 0, 24, 0, 15, 1, 6, (22.0, 48.5), (58.0, 57.0, 56.0))
    bad = Score(
        "baseline", {"ECE R21": 69.6, "FMVSS 118": 117.8}, 5, 24, 2, 15, 4, 6, (60.0, 110.0), (56.4, 58.0, 57.2)
    )
    page = score_page([bad, good])
    assert page.passed and page.metrics[0].note == "observer"
    folder = write_bench_result(tmp_path, page)
    rows = (folder / "score.csv").read_text().splitlines()
    assert rows[1].startswith(
        "baseline,69.6 N (margin +30.4 N),117.8 N (margin -17.8 N),FAIL 5 of 24,FAIL 2 of 15,4 of 6,"
    )
    assert rows[2].endswith("PASS 0 of 24,PASS 0 of 15,1 of 6,22.0 / 48.5,58.0 / 57.0 / 56.0 (rises)")
    assert (folder / "score.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not score_page([bad]).passed


def test_a_drum_run_without_a_closing_is_a_dash_not_an_error(tmp_path):
    """On a cold door set the drum bench's short normalization run does not reach the top (-40 degC): the ECU
    never closes, the run has no peak, and the page says so instead of stopping the whole score."""
    from wrsim.benches.score import Score, score_page
    from wrsim.report.results import write_bench_result

    cold = Score("observer", {"ECE R21": 55.5, "FMVSS 118": 83.0}, 0, 45, 0, 15, 0, 6, (30.0, 60.0), (math.nan,) * 3)
    folder = write_bench_result(tmp_path, score_page([cold]))
    row = (folder / "score.csv").read_text().splitlines()[1]
    assert row.endswith("PASS 0 of 45,PASS 0 of 15,0 of 6,30.0 / 60.0,- / - / - (-: not normalized: no closing)")
