"""The anti-pinch score's aggregation of the compliance cells (wrsim.benches.score), on made-up events."""
from __future__ import annotations

import math

import pytest


def _event(peak: float, touch: float | None, detected: float | None):
    from wrsim.benches.closed_loop import Event
    return Event(start=10.0, supply=13.0, peak=peak, touch=touch, detected=detected, stop=None, drop=0.0)


def test_score_counts_law_cells_false_reversals_and_latency():
    from wrsim.benches.closed_loop import Cell
    from wrsim.benches.score import _score

    cells = [Cell("a-10npmm_4mm", "10npmm_4mm", 10, 4, "ECE R21", "9 V", _event(60.0, 11.000, 11.020)),
             Cell("a-10npmm_4mm", "10npmm_4mm", 10, 4, "ECE R21", "16 V", _event(100.5, 11.0, 11.04)),  # over 100 N
             Cell("a-65npmm_4mm", "65npmm_4mm", 65, 4, "FMVSS 118", "9 V", _event(80.0, 12.000, None)),  # no reversal
             Cell("a-20npmm_10mm", "20npmm_10mm", 20, 10, None, "9 V", _event(150.0, 12.0, 12.1)),       # information
             Cell("a-no_obstacle", "no_obstacle", None, None, None, "13 V", _event(0.0, None, 13.5)),    # reversed
             Cell("a-supply_dip", "supply_dip", None, None, None, "early", _event(0.0, None, None))]
    s = _score("mine", cells, [], None)
    assert s.worst == {"ECE R21": 100.5, "FMVSS 118": 80.0}   # the information row does not count
    assert (s.failed, s.cells) == (2, 3)
    assert (s.false_reversals, s.disturbances) == (1, 2)
    assert s.latency_ms == pytest.approx((40.0, 100.0))         # median and largest over the rods, info row too
    assert not s.passed and s.drum_peaks == () and s.drum_trend


def test_score_without_a_detection_has_no_latency():
    from wrsim.benches.closed_loop import Cell
    from wrsim.benches.score import _score

    s = _score("none", [Cell("10npmm_4mm", "10npmm_4mm", 10, 4, "ECE R21", "9 V", _event(40.0, 11.0, None))], [], None)
    assert all(math.isnan(x) for x in s.latency_ms) and s.failed == 1


def test_score_names_an_unknown_algorithm():
    from wrsim.benches.score import score_algorithms
    from wrsim.errors import WrsimError

    with pytest.raises(WrsimError, match=r"unknown anti-pinch algorithm 'nope' .*observer"):
        score_algorithms(["nope"])
