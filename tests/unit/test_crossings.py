"""Exact 'above crossings (IEEE 1076.1: an 'above event is an analog solution point): the runner predicts each
guard's zero from the accepted points and shortens the step to end just past it, so an A->D edge lands within
1 us of the analytic crossing at a 1 ms step."""

from __future__ import annotations

import math
import subprocess

import numpy as np
import pytest

from conftest import netlist
from wrsim.backend.ngspice import shared
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.paths import ROOT

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
    assert len(w.time) < 90  # 50 steps of 1 ms, ngspice's start-up doubling, the landing, the follower


@pytest.mark.parametrize("f", [3.0, 30.0, 300.0, 700.0])
def test_sine_crosses_both_ways_at_the_analytic_times(simulate, f):
    # at 300 and 700 Hz the sine turns back between two crossings within one 1 ms step, where no course of the
    # last three points foresees the zero: once a guard has crossed twice, no step is longer than a quarter of
    # the time between its last two crossings (the Hall sensor of a fast drive); the second crossing may be late
    w = simulate("tb_cross_sine", 1.0, max_step=1e-3, files=FILES, overrides={"f": f})
    t, d = edges(w, "s")
    a = math.asin(0.3) / (2 * math.pi)
    exact = sorted([(a + k) / f for k in range(int(f) + 1)] + [(0.5 - a + k) / f for k in range(int(f) + 1)])
    exact = np.array([x for x in exact if x < 1.0])
    assert len(t) == len(exact) and list(d) == [1, -1] * (len(exact) // 2)
    late = t - exact
    assert np.all(late >= 0.0) and np.max(late[2:]) <= 1e-6
    assert late[1] <= (1e-6 if f < 100.0 else 1e-3)
    assert w.statistics.late == int(np.sum(late > 1e-6))  # the driver counts the crossings it saw late


def test_guards_are_lowered_with_their_source_line():
    net = netlist("tb_cross_rc", 0.05, 1e-3, files=FILES)
    assert net.crossings == ["x_det.above__1"]
    assert "b_above__1 above__1 0 v = (v(p) - ({threshold}))" in net.text
    assert "t_crossings.vhd:29:3: q <= '1' when v'above(threshold) else '0';" in net.text


def test_an_above_that_nothing_reads_gets_no_guard(tmp_path):
    folder = tmp_path / "bench"
    folder.mkdir()
    text = (ROOT / "tests/fixtures/signals/t_crossings.vhd").read_text()
    (folder / "t_crossings.vhd").write_text(
        text.replace("  fol: entity work.t_follower port map (p => b, s => s);\n", "")
    )
    net = netlist("tb_cross_rc", 0.05, 1e-3, files=(folder,))
    assert net.crossings == [] and "b_above__1" not in net.text
    assert NgspiceBatch().argv(tmp_path / "n.cir", net)[1] == "-b"  # plain ngspice, as before


def test_the_driver_refuses_bad_usage(tmp_path):
    exe = shared.driver(tmp_path)
    proc = subprocess.run([str(exe), "0", "1", "1e-6", "n.cir", "-"], capture_output=True, text=True)
    assert proc.returncode == 2 and "MAX_STEP, STOP and RESOLUTION must be > 0" in proc.stderr
    proc = subprocess.run([str(exe)], capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.startswith("usage:")


def test_after_an_edge_only_crossing_the_step_resumes(simulate):
    # the comparator's edges go to a GHDL counter only (max_edges is never reached): landing on them is no
    # discontinuity of the analog system, and the driver resumes the step planned before the approach instead of
    # letting ngspice grow it back from the landing step by a factor of 2 per step
    net = netlist("tb_counted", 0.5, 1e-3, files=FILES, overrides={"max_edges": 15})
    assert net.edge_only == set(net.crossings) and "x_cmp.above__1" in net.crossings
    assert net.digital[0].lazy == ["count"]  # `done` switches the source; `count` is only recorded
    w = simulate("tb_counted", 0.5, max_step=1e-3, files=FILES, overrides={"max_edges": 15})
    t, d = edges(w, "pulse")
    assert len(t) == 10  # sin(2*pi*10*t) > 0.5: 5 rising and 5 falling edges
    steps = np.diff(w.time)
    for k in np.searchsorted(w.time, t):  # the landing point of each edge
        back = int(np.argmax(steps[k:] >= 0.5e-3))  # steps until the step is long again
        assert back <= 5, (w.time[k], steps[k : k + 8])  # ngspice alone: about 20 (from the 1 ns of the A->D event)
    assert np.all(w["done"] == 0)
