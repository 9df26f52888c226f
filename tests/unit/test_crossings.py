"""Exact 'above crossings (IEEE 1076.1: an 'above event is an analog solution point): the runner predicts each
guard's zero from the accepted points and sets a breakpoint just past it, so an A->D edge lands within 1 us of
the analytic crossing at a 1 ms step."""
from __future__ import annotations

import math

import numpy as np
import pytest

from conftest import netlist
from wrsim.backend.ngspice.shared import CrossingGuards, predict_crossing

FILES = ("tests/fixtures/signals",)


def edges(w, name):
    """Times of the first time point after each change of a 0/1 signal, and the direction (+1 rising)."""
    s = w[name] > 0.5
    k = np.nonzero(s[1:] != s[:-1])[0] + 1
    return w.time[k], np.where(s[k], 1, -1)


def test_rc_charge_crosses_at_tau_ln2(simulate):
    w = simulate("tb_cross_rc", 0.05, max_step=1e-3, files=FILES)
    t, d = edges(w, "s")
    assert list(d) == [1]
    # the edge is the first point at or past the crossing of the computed v, within 1 us of it ...
    k = int(np.searchsorted(w.time, t[0]))
    v = w["det.v"]
    assert v[k - 1] < 0.5 <= v[k]
    crossing = w.time[k - 1] + (0.5 - v[k - 1]) / (v[k] - v[k - 1]) * (w.time[k] - w.time[k - 1])
    assert 0.0 <= t[0] - crossing <= 1e-6
    # ... and the computed v crosses where the analytic one does to the integration's accuracy at 1 ms steps
    # (measured 2.4e-3 early: the 'dot capacitor's truncation floor chgtol is vntol/reltol); the sine below has
    # no integration error and is held to 1 us
    assert t[0] == pytest.approx(0.01 * math.log(2.0), rel=3e-3)
    assert len(w.time) < 80          # 50 steps of 1 ms, the start and one landing


@pytest.mark.parametrize("f", [3.0, 30.0])
def test_sine_crosses_both_ways_at_the_analytic_times(simulate, f):
    w = simulate("tb_cross_sine", 1.0, max_step=1e-3, files=FILES, overrides={"f": f})
    t, d = edges(w, "s")
    a = math.asin(0.3) / (2 * math.pi)
    exact = sorted([(a + k) / f for k in range(int(f) + 1)] + [(0.5 - a + k) / f for k in range(int(f) + 1)])
    exact = [x for x in exact if x < 1.0]
    assert len(t) == len(exact) and list(d) == [1, -1] * (len(exact) // 2)
    assert np.all(t - exact >= 0.0) and np.max(t - exact) <= 1e-6


def test_guards_are_lowered_with_their_source_line():
    net = netlist("tb_cross_rc", 0.05, 1e-3, files=FILES)
    assert net.crossings == ["x_det.above__1"]
    assert "b_above__1 above__1 0 v = (v(p) - ({threshold}))" in net.text
    assert "t_crossings.vhd:12:3: q <= '1' when v'above(threshold) else '0';" in net.text


def test_prediction_uses_the_course_of_the_last_points():
    # a parabola g = 1 - t^2 sampled at 0, 0.5, 0.8 crosses at exactly 1
    h = [(t, 1.0 - t * t) for t in (0.0, 0.5, 0.8)]
    assert predict_crossing(h) == pytest.approx(1.0, abs=1e-12)
    assert predict_crossing(h[1:]) == pytest.approx(0.8 + 0.36 / 1.3)          # secant
    assert predict_crossing([(0.0, 1.0), (1.0, 2.0)]) is None                 # moving away
    policy = CrossingGuards(1, window=1.0, resolution=1e-6)
    assert policy.observe(0.0, [1.0]) == []
    assert policy.observe(0.5, [0.75]) == []                                  # secant: 1.5, beyond the window
    (b,) = policy.observe(0.8, [0.36])
    assert b == pytest.approx(0.8 + 0.9 * 0.2, abs=1e-9)                     # far: 90 % of the way first
    assert policy.observe(0.85, [1.0 - 0.85 ** 2]) == []                      # that breakpoint is pending
    (b,) = policy.observe(1.0 - 1e-5, [1.0 - (1.0 - 1e-5) ** 2])
    assert b == pytest.approx(1.0 + 0.5e-6, abs=1e-9)                         # near: just past the crossing
