"""End to end: worm-gear self-locking and the three architectures (issue 3; thesis 4.1.2.6, Fig. 4.28-4.30),
plus the 2D/3D models against the thesis's closed-form efficiencies and their generic checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from wrsim.closed_form.worm_gear import eta_2d, eta_3d
from wrsim.data.params import load_params
from wrsim.elab.elaborate import elaborate
from wrsim.elab.library import load_library
from wrsim.errors import WrsimError
from wrsim.paths import ROOT

SET = ROOT / "params" / "self_locking_bench.txt"


def test_self_locking_holds_at_046_and_back_drives_above_05(bench_run):
    result, m = bench_run("worm-gear-self-locking")
    assert result.passed
    for pause, seconds in (("pause", 0.829), ("end", 0.829)):
        held = m[f"eta046 {pause}: gear angle change"]
        # creeps just below the threshold speed (1e-3 rad/s at the gear): 0.82 mrad in 0.82 s, never faster
        assert held.value <= held.tolerance
        assert held.value == pytest.approx(1e-3 * seconds * 1e3, rel=0.02)
        assert m[f"eta046 {pause}: creep speed vs regularized Coulomb law"].value < 0.01
        moved = m[f"eta055 {pause}: gear angle change"]
        assert abs(moved.value) > 100 * held.tolerance  # the spring visibly back-drives the gear
        assert moved.value == pytest.approx(moved.reference, rel=0.02)
        assert m[f"eta055 {pause}: back-drive speed vs closed form"].value < 0.5
    # after +4 s the spring pushes the gear back (angle decreases), after -4 s forward
    assert m["eta055 pause: gear angle change"].value == pytest.approx(-343.0, rel=0.02)
    assert m["eta055 end: gear angle change"].value == pytest.approx(134.5, rel=0.02)


def test_architectures_reach_46_3_percent_and_hold(bench_run):
    result, m = bench_run("worm-gear-architectures")
    assert result.passed
    for arch in ("behavioral", "two_d", "three_d"):
        assert abs(m[f"{arch}: efficiency"].value - 46.3) < 0.463  # within 1 % of 46.3 %
        for pause in ("pause", "end"):
            held = m[f"{arch} {pause}: gear angle change"]
            assert held.value <= held.tolerance
    # the contact alone would not self-lock (friction angle < lead angle): the bearings hold the gear
    assert m["two_d: contact efficiency vs Eq. 4.19e"].value == pytest.approx(54.75, abs=0.01)
    assert m["three_d: contact efficiency vs Eq. 4.26b"].value == pytest.approx(54.95, abs=0.01)
    for arch in ("two_d", "three_d"):
        assert abs(m[f"{arch}: armature angle at 4.00 s vs behavioral"].value) < 1e-3


# ------------------------------------------------------------------------------------------------
# the 2D/3D models with the thesis's worked example (entity defaults: lead angle 6 deg, mu_c = tan 6 deg,
# no bearing friction, press angle 11.5 deg) under a constant load
_EXAMPLE = """
library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
entity tb_worm_example is
end entity tb_worm_example;
architecture structural of tb_worm_example is
  terminal supply_p : electrical;
  terminal armature_2d, armature_3d, wheel_2d, wheel_3d : rotational_v;
begin
  supply: entity work.dc_supply(behavioral) generic map (u => 13.0) port map (p => supply_p, n => electrical_ref);
  motor_2d: entity work.dcpm_motor(simple) port map (p => supply_p, n => electrical_ref, shaft => armature_2d);
  gear_2d: entity work.worm_gear(two_d) port map (worm => armature_2d, gear => wheel_2d);
  load_2d: entity work.torque_ramp(behavioral) generic map (torque_end => 5.0, ramp_time => 0.01)
    port map (shaft => wheel_2d);
  motor_3d: entity work.dcpm_motor(simple) port map (p => supply_p, n => electrical_ref, shaft => armature_3d);
  gear_3d: entity work.worm_gear(three_d) port map (worm => armature_3d, gear => wheel_3d);
  load_3d: entity work.torque_ramp(behavioral) generic map (torque_end => 5.0, ramp_time => 0.01)
    port map (shaft => wheel_3d);
end architecture structural;
"""


def test_two_d_and_three_d_reproduce_eq_4_20b_and_4_26b(simulate, tmp_path):
    (tmp_path / "tb_worm_example.vhd").write_text(_EXAMPLE)
    w = simulate("tb_worm_example", 0.3, 1e-3, files=("vhdl/drive", "vhdl/equipment", tmp_path))
    at = w.time > 0.2
    lead, mu = math.radians(6.0), math.tan(math.radians(6.0))
    for tag, gear, expected in (
        ("2d", "gear_2d.plane", eta_2d(lead, mu)),
        ("3d", "gear_3d", eta_3d(lead, mu, math.radians(11.5))),
    ):
        p_in = w[f"{gear}.torque_w"] * w[f"motor_{tag}.omega"]
        p_out = -w[f"{gear}.torque_g"] * w[f"{gear}.omega_g"]
        assert np.allclose(p_out[at] / p_in[at], expected, rtol=1e-6, atol=0.0)
    assert eta_2d(lead, mu) == pytest.approx(0.494476, abs=1e-6)  # thesis: 49.4476 %
    assert eta_3d(lead, mu, math.radians(11.5)) == pytest.approx(0.489351, abs=1e-6)
    # ratio 73 from the radii and the lead angle (Eq. 4.14e)
    assert w["motor_2d.angle"][-1] / w["gear_2d.plane.angle_g"][-1] == pytest.approx(73.0, rel=1e-6)


# ------------------------------------------------------------------------------------------------
# bad generics: a message naming the generic, with file:line:col of the assertion
@pytest.mark.parametrize(
    "entity, overrides, message",
    [
        ("tb_worm_gear_self_locking", {"eta": 1.0}, "worm_gear: eta must be > 0 and < 1"),
        ("tb_worm_gear_self_locking", {"eta": 0.0}, "worm_gear: eta must be > 0 and < 1"),
        ("tb_worm_gear_self_locking", {"stiffness": 0.0}, "rotational_spring: stiffness must be > 0"),
        ("tb_worm_gear_self_locking", {"ramp_time": 0.0}, "tb_worm_gear_self_locking: ramp_time must be > 0"),
        (
            "tb_worm_gear_architectures",
            {"eta_target": 1.0},
            "tb_worm_gear_architectures: eta_target must be > 0 and < 1",
        ),
        ("tb_worm_gear_architectures", {"r_gear": -0.03}, "worm_gear: r_worm must be > 0"),
        ("tb_worm_gear_architectures", {"r_bearing_gear": -1e-3}, "worm_gear: r_bearing_gear must be >= 0"),
        ("tb_worm_gear_architectures", {"mu_bearing": 0.5}, "tb_worm_gear_architectures: eta_target is unreachable"),
    ],
)
def test_bad_generics_are_named(lib, entity, overrides, message):
    with pytest.raises(WrsimError, match=r"\.vhd:\d+:\d+: " + message):
        elaborate(lib, entity, load_params(SET), overrides)


_BAD_GEAR = """
library IEEE;
use IEEE.MECHANICAL_SYSTEMS.all;
entity tb_bad_gear is
  generic (lead_angle : real := 0.1;    -- [rad]
           r_worm     : real := 4.0e-3; -- [m]
           r_gear     : real := 0.03;   -- [m]
           press      : real := 0.2;    -- [rad]
           mu         : real := 0.1);   -- [1]
end entity tb_bad_gear;
architecture structural of tb_bad_gear is
  terminal worm, wheel : rotational_v;
begin
  gear: entity work.worm_gear(three_d)
    generic map (lead_angle => lead_angle, r_worm => r_worm, r_gear => r_gear, press_angle => press, mu_contact => mu)
    port map (worm => worm, gear => wheel);
end architecture structural;
"""


@pytest.mark.parametrize(
    "overrides, message",
    [
        ({"lead_angle": 0.0}, "worm_gear: lead_angle must be > 0 and < pi/2 rad"),
        ({"lead_angle": 1.6}, "worm_gear: lead_angle must be > 0 and < pi/2 rad"),
        ({"r_worm": 0.0}, "worm_gear: r_worm must be > 0"),
        ({"r_gear": -0.01}, "worm_gear: r_gear must be > 0"),
        ({"press": -0.1}, "worm_gear: press_angle must be >= 0 and < pi/2 rad"),
        ({"mu": -0.1}, "worm_gear: mu_contact must be >= 0"),
        (
            {"mu": 20.0},
            r"worm_gear: mu_contact\*tan\(lead_angle\) must be < cos\(press_angle\) \(else Eq\. 4\.26b <= 0: "
            r"the worm cannot drive the gear\)",
        ),
    ],
)
def test_three_d_generic_checks(tmp_path, overrides, message):
    (tmp_path / "tb_bad_gear.vhd").write_text(_BAD_GEAR)
    library = load_library([ROOT / "vhdl", tmp_path])
    with pytest.raises(WrsimError, match=r"worm_gear\.vhd:\d+:\d+: " + message + r" \(instance tb_bad_gear\.gear"):
        elaborate(library, "tb_bad_gear", None, overrides)


def test_pwl_supply_checks_its_table(tmp_path):
    (tmp_path / "tb_bad_pwl.vhd").write_text("""
library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
entity tb_bad_pwl is
end entity tb_bad_pwl;
architecture structural of tb_bad_pwl is
  terminal p : electrical;
begin
  supply: entity work.pwl_supply(behavioral) generic map (times => (0.0, 2.0, 1.0), values => (0.0, 1.0, 1.0))
    port map (p => p, n => electrical_ref);
end architecture structural;
""")
    library = load_library([ROOT / "vhdl", tmp_path])
    with pytest.raises(WrsimError, match=r"pwl_supply\.vhd:\d+:\d+: pwl_supply: times must be strictly increasing"):
        elaborate(library, "tb_bad_pwl", None, {})
