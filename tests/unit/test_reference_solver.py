"""Tests for wrsim.backend.reference_solver: the IR's equations integrated by SUNDIALS IDAS, the reference `wrsim bench`
measures ngspice against (docs/performance.md)."""

import numpy as np
import pytest

from conftest import ANALYTIC
from wrsim import elaborate, load_library, paths
from wrsim.backend.reference_solver import flatten, integrate
from wrsim.errors import WrsimError

SIGNALS = paths.ROOT / "tests" / "fixtures" / "signals"


def _library(*folders):
    return load_library([paths.ROOT / "vhdl" / "ieee", paths.ROOT / "vhdl" / "common", *folders])


def _inline(folder, entity, text):
    """The flattened system of the design `text` (one entity, written into `folder`)."""
    (folder / f"{entity}.vhd").write_text(text)
    return flatten(elaborate(load_library([paths.ROOT / "vhdl" / "ieee", folder]), entity, None, None))


def test_rl_step_follows_the_closed_form():
    # t_rl_step: i(t) = u/r (1 - exp(-t r/l)), u = 5 V, r = 10 Ohm, l = 10 mH (tau = 1 ms), from i = 0
    times = [0.5e-3, 1e-3, 2e-3, 5e-3]
    run = integrate(flatten(elaborate(_library(ANALYTIC), "t_rl_step", None, None)), times, 1e-4, 1e-4)
    expected = 0.5 * (1 - np.exp(-np.array(times) / 1e-3))
    np.testing.assert_allclose(run.values["x_coil.i"], expected, rtol=1e-4)
    np.testing.assert_allclose(run.values["b"], 5.0 - 10.0 * expected, rtol=1e-3)  # the coil's voltage
    assert run.steps > 0


def test_integ_charge_follows_the_closed_form():
    # t_integ_charge: q = i'integ of i = i_dc + i_amp sin(omega t), held at 0 in the quiescent domain
    i_dc, i_amp, omega = 2e-3, 5e-3, 2e3
    system = flatten(elaborate(_library(ANALYTIC), "t_integ_charge", None, None))
    times = np.array([1e-3, 2.5e-3, 1e-2])
    (node,) = system.integrals
    charge = integrate(system, list(times), 1e-6, 1e-5).values[node]
    np.testing.assert_allclose(charge, i_dc * times + i_amp / omega * (1 - np.cos(omega * times)), rtol=1e-4)


def test_a_digital_unit_is_replayed_from_its_record():
    # tb_counted: a GHDL counter's `done` switches t_switched_source from 1 V to 5 V + code (the comparator's bits,
    # an A->D signal of the analog side, computed, not replayed)
    system = flatten(elaborate(_library(SIGNALS), "tb_counted", None, None))
    assert set(system.inputs.values()) == {"done"}
    with pytest.raises(WrsimError, match="needs a record of the digital signals done"):
        integrate(system, [0.1], 1e-4, 1e-3)
    run = integrate(system, [0.1, 0.2, 0.225], 1e-4, 1e-3, {"done": (np.array([0.0, 0.15]), np.array([0.0, 1.0]))})
    # code(1) is always 1, code(0) is sin(2 pi 10 t) > 0.5: 0 at t = 0.2 (sin = 0), 1 at 0.225 (sin = 1)
    np.testing.assert_allclose(run.values["b"], [1.0, 7.0, 8.0])


FREE_ANGLE = """
entity t_free_angle is
end entity t_free_angle;

architecture a of t_free_angle is
  quantity angle, speed : real;
begin
  angle'dot == speed;
  if domain = quiescent_domain use
    speed == 0.0;
  else
    speed == 2.0;
  end use;
end architecture a;
"""


def test_a_quiescent_point_that_leaves_an_angle_free_keeps_it_where_it_starts(tmp_path):
    # at the quiescent point angle'dot == speed == 0 says nothing of the angle (the worm-gear benches' motor angle
    # and load deformation): Newton's least-norm step leaves it at its start; then angle = angle(0) + 2 t
    run = integrate(_inline(tmp_path, "t_free_angle", FREE_ANGLE), [0.5, 1.0], 1e-6, 1e-2)
    np.testing.assert_allclose(run.values["angle"], [1.0 + 1e-3, 2.0 + 1e-3], rtol=1e-6)


SWITCHED_SLOPE = """
entity t_switched_slope is
end entity t_switched_slope;

architecture a of t_switched_slope is
  quantity x, z, rate : real;
begin
  if domain = quiescent_domain use
    x == 0.0;
    z == 0.0;
  else
    x'dot == 1.0;
    z'dot == rate;
  end use;
  if x > 0.3 use
    rate == 2.0;
  else
    rate == 0.0;
  end use;
end architecture a;
"""


def test_a_condition_the_states_depend_on_is_located_where_it_switches(tmp_path):
    # x = t; z grows at 2 once x > 0.3: z(t) = 2 (t - 0.3) after 0.3 s, located, not stepped past
    run = integrate(_inline(tmp_path, "t_switched_slope", SWITCHED_SLOPE), [0.2, 1.0], 1e-6, 0.1)
    np.testing.assert_allclose(run.values["z"], [0.0, 1.4], atol=1e-9)
    assert run.events == 1


def test_above_crossings_are_located_and_a_condition_nothing_reads_back_is_no_event():
    # tb_cross_rc: v = 1 - exp(-t/tau) passes 0.5 V at tau ln 2; a follower's voltage (which no state depends on)
    # switches there without an event of its own
    tau = 0.01
    system = flatten(elaborate(_library(SIGNALS), "tb_cross_rc", None, None))
    run = integrate(system, [0.05], 1e-8, 1e-3)
    ((guard, crossed),) = run.crossings.items()
    # within what IDAS's absolute tolerance (1e-6 V) leaves of v, over its slope (50 V/s) there
    np.testing.assert_allclose(crossed, [tau * np.log(2.0)], atol=2e-8)
    assert run.events == 0
    assert run.values["b"][0] == 1.0
    # tb_cross_sine: v = sin(2 pi f t) with no state at all crosses 0.3 V up at (asin(0.3)/(2 pi) + k)/f, down at
    # (0.5 - asin(0.3)/(2 pi) + k)/f; located on IDAS's interpolant of an algebraic unknown, which its error test does
    # not hold: within 1 us, as the ngspice driver's crossings (test_crossings.py)
    f, phase = 3.0, np.arcsin(0.3) / (2 * np.pi)
    run = integrate(flatten(elaborate(_library(SIGNALS), "tb_cross_sine", None, None)), [1.0], 1e-8, 1e-3)
    expected = np.sort([(k + phase) / f for k in range(3)] + [(k + 0.5 - phase) / f for k in range(3)])
    np.testing.assert_allclose(next(iter(run.crossings.values())), expected, atol=1e-6)
