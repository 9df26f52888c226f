"""The generic VHDL-AMS -> ngspice lowering against closed-form solutions, in every nature
(docs/vhdl-ams-subset.md, "Lowering"). Models: tests/fixtures/analytic/t_*.vhd.

Tolerances. Every comparison allows `bound(scale, rate, h, span)`:
- RELTOL*scale: ngspice converges each time point to reltol = 1e-4 (the engine's default) of the quantity's size;
- (rate*h)**2*(1 + rate*span)*scale: truncation error of the gear (BDF2) integration at steps h <= max_step for a
  solution that varies at `rate` [1/s]. The first step is backward Euler (local error (rate*h)**2/2*scale), each
  further step adds (2/9)*(rate*h)**3*scale; decaying solutions forget these (span = 0), an oscillation
  accumulates them over `span` (rate*span/h steps).
max_step is chosen so that the truncation part is at most about 10*RELTOL: ngspice's own step control (trtol = 7)
would let the local error grow to several reltol per step (measured: 0.7 % on the RC step with a free step,
14 % after 5 periods of the oscillator), so the step bound is what makes reltol meaningful.
Waveforms are compared from T_SKIP on: the quiescent -> time domain switch happens within the first time step.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from conftest import netlist
from wrsim.backend.ngspice.netlist import Analysis

RELTOL = Analysis(stop=1.0).reltol
T_SKIP = 1e-6  # [s]


def bound(scale: float, rate: float = 0.0, h: float = 0.0, span: float = 0.0) -> float:
    """Allowed deviation from a closed form of magnitude `scale` (see the module docstring)."""
    return RELTOL * scale + (rate * h) ** 2 * (1.0 + rate * span) * scale


def deviation(w, name: str, expected) -> float:
    """Largest |simulated - expected(t)| of quantity `name` over the time points after T_SKIP."""
    t = w.time[w.time > T_SKIP]
    return float(np.max(np.abs(w[name][w.time > T_SKIP] - expected(t))))


def crossing(t: np.ndarray, y: np.ndarray, level: float) -> float:
    """First time after T_SKIP at which y falls to `level` (linear interpolation between time points)."""
    k = int(np.argmax((t > T_SKIP) & (y <= level)))
    assert k > 0 and y[k] <= level, f"never falls to {level}"
    return float(np.interp(level, [y[k], y[k - 1]], [t[k], t[k - 1]]))


# ------------------------------------------------------------------------------------------------
# 1. electrical
def test_rc_step(simulate):
    u, r, c, h = 10.0, 1e3, 1e-6, 5e-6
    w = simulate("t_rc_step", 5 * r * c, h)
    assert deviation(w, "cap.v", lambda t: u * (1 - np.exp(-t / (r * c)))) <= bound(u, 1 / (r * c), h)
    assert deviation(w, "res.i", lambda t: u / r * np.exp(-t / (r * c))) <= bound(u / r, 1 / (r * c), h)


def test_rl_step(simulate):
    u, r, l, h = 5.0, 10.0, 10e-3, 5e-6
    w = simulate("t_rl_step", 5 * l / r, h)
    assert deviation(w, "coil.i", lambda t: u / r * (1 - np.exp(-t * r / l))) <= bound(u / r, r / l, h)
    assert deviation(w, "coil.v", lambda t: u * np.exp(-t * r / l)) <= bound(u, r / l, h)


# ------------------------------------------------------------------------------------------------
# 2. translational: released spring-mass-damper, five periods (phase and decay)
def test_spring_mass_damper_release(simulate):
    m, k, b, x0, h = 0.5, 2e3, 2.0, 0.01, 1e-4
    w0, zeta = np.sqrt(k / m), b / (2 * np.sqrt(k * m))
    wd = w0 * np.sqrt(1 - zeta**2)
    stop = 5 * 2 * np.pi / wd

    def x(t):
        return x0 * np.exp(-zeta * w0 * t) * (np.cos(wd * t) + zeta * w0 / wd * np.sin(wd * t))

    w = simulate("t_smd_release", stop, h)
    assert w["weight.x"][0] == pytest.approx(x0, rel=RELTOL)
    assert deviation(w, "weight.x", x) <= bound(x0, w0, h, stop)
    # decay: the envelope after five periods is exp(-5*zeta*w0*T) = 37 % of x0
    assert np.abs(w["weight.x"][w.time > 4 * 2 * np.pi / wd]).max() == pytest.approx(
        np.abs(x(np.linspace(4, 5, 2001) * 2 * np.pi / wd)).max(), abs=bound(x0, w0, h, stop)
    )


# ------------------------------------------------------------------------------------------------
# 3. translational_velocity, 4. rotational and rotational_velocity: first-order lag under a step
def test_mass_damper_force_step_translational_velocity(simulate):
    m, b, f, h = 2.0, 40.0, 8.0, 1e-4
    w = simulate("t_mass_damper_v", 0.3, h)
    assert deviation(w, "weight.v", lambda t: f / b * (1 - np.exp(-b * t / m))) <= bound(f / b, b / m, h)
    assert deviation(w, "damper.f", lambda t: f * (1 - np.exp(-b * t / m))) <= bound(f, b / m, h)


def test_inertia_friction_torque_step_rotational(simulate):
    j, d, tau, h = 2e-3, 4e-3, 0.2, 2e-3
    w = simulate("t_inertia_damper", 2.0, h)
    assert deviation(w, "flywheel.omega", lambda t: tau / d * (1 - np.exp(-t * d / j))) <= bound(tau / d, d / j, h)
    phi_end = tau / d * (2.0 - j / d)
    assert deviation(w, "flywheel.phi", lambda t: tau / d * (t - j / d * (1 - np.exp(-t * d / j)))) <= bound(
        phi_end, d / j, h
    )


def test_inertia_friction_torque_step_rotational_velocity(simulate):
    j, d, tau, h = 2e-3, 4e-3, 0.2, 2e-3
    w = simulate("t_inertia_damper_v", 2.0, h)
    assert deviation(w, "flywheel.omega", lambda t: tau / d * (1 - np.exp(-t * d / j))) <= bound(tau / d, d / j, h)
    assert deviation(w, "friction.torque", lambda t: tau * (1 - np.exp(-t * d / j))) <= bound(tau, d / j, h)


# ------------------------------------------------------------------------------------------------
# 5. ideal gear between two inertias: accelerations per the reflected inertia
def test_ideal_gear_reflected_inertia(simulate):
    j_a, j_b, ratio, tau = 1e-3, 5e-2, 5.0, 0.03
    alpha_a = tau / (j_a + j_b / ratio**2)  # 10 rad/s**2 (j_a alone would give 30)
    w = simulate("t_gear_inertias", 1.0, 1e-3)
    assert deviation(w, "rotor_a.alpha", lambda t: np.full_like(t, alpha_a)) <= bound(alpha_a)
    assert deviation(w, "rotor_b.alpha", lambda t: np.full_like(t, alpha_a / ratio)) <= bound(alpha_a / ratio)
    assert deviation(w, "rotor_a.omega", lambda t: alpha_a * t) <= bound(alpha_a)
    assert deviation(w, "rotor_b.phi", lambda t: alpha_a / ratio * t**2 / 2) <= bound(alpha_a / ratio / 2)
    assert deviation(w, "gear.torque_a", lambda t: np.full_like(t, j_b / ratio**2 * alpha_a)) <= bound(tau)


# ------------------------------------------------------------------------------------------------
# 6. Coulomb friction (smooth_sign with a velocity threshold)
def test_coulomb_friction_stop(simulate):
    m, v0, f_c, v_th, h = 2.0, 1.5, 3.0, 1e-3, 1e-3
    w = simulate("t_coulomb_stop", 1.5, h)
    t, v = w.time, w["weight.v"]
    sliding = (t > T_SKIP) & (t < 0.9)
    slope = np.polyfit(t[sliding], v[sliding], 1)[0]
    assert slope == pytest.approx(-f_c / m, rel=RELTOL)
    # |v| reaches the threshold at m*(v0 - v_th)/f_c: the stop at m*v0/f_c, less the smoothing band
    t_stop = crossing(t, v, v_th)
    assert t_stop == pytest.approx(m * (v0 - v_th) / f_c, abs=RELTOL * m * v0 / f_c)
    assert abs(t_stop - m * v0 / f_c) <= m * v_th / f_c
    # and stays at rest: below the threshold, no reversal, decayed to nothing at the end
    after = t > t_stop
    assert np.all(np.abs(v[after]) <= v_th)
    assert v[after].min() >= -RELTOL * v_th
    assert abs(v[-1]) <= RELTOL * v_th


# ------------------------------------------------------------------------------------------------
# 7. table look-up with real_vector generics (default table and generic map aggregate)
def test_table_lookup_equals_interp(simulate):
    w = simulate("t_table_springs", 1.0, 1e-3)
    x = w["ramp.x"]
    assert w.time.size > 500 and x.min() < -0.02 and x.max() > 0.05  # both ends of both tables are passed
    tables = {
        "spring_default": ([0.0, 0.01, 0.03, 0.04], [0.0, 20.0, 25.0, 60.0]),
        "spring_mapped": ([-0.02, -0.005, 0.0, 0.015, 0.02, 0.05], [-8.0, 3.0, 0.0, 12.5, 7.0, 30.0]),
    }
    for name, (xs, ys) in tables.items():
        expected = np.interp(x, xs, ys)  # clamps beyond the ends
        assert np.abs(w[f"{name}.f"] - expected).max() <= bound(max(map(abs, ys))), name


# ------------------------------------------------------------------------------------------------
# 8. conditional equations
def test_if_use_above_switches_resistor(simulate):
    u, c, v_th, r_above, r_below, h = 10.0, 1e-6, 4.0, 1e3, 250.0, 1e-6
    tau1, tau2 = r_above * c, r_below * c
    t_s = tau1 * np.log(u / v_th)  # 0.916 ms

    def v_c(t):
        return np.where(t <= t_s, u * (1 - np.exp(-t / tau1)), u - v_th * np.exp(-(t - t_s) / tau2))

    w = simulate("t_switched_rc", 3e-3, h)
    # `break on` does not place a time point on the crossing: the switch lands within one step, which shifts
    # the curve by at most the jump of its slope times h
    assert crossing(w.time, w["res.v"], v_th) == pytest.approx(t_s, abs=h)
    slope_jump = v_th / tau2 - v_th / tau1
    assert deviation(w, "cap.v", v_c) <= bound(u, 1 / tau2, h) + slope_jump * h
    late = w.time > t_s + 2 * h
    assert np.abs(w["res.v"][late] / w["res.i"][late] - r_below).max() <= bound(r_below)
    early = (w.time > T_SKIP) & (w.time < t_s - 2 * h)
    assert np.abs(w["res.v"][early] / w["res.i"][early] - r_above).max() <= bound(r_above)


@pytest.mark.parametrize("mode_c, r_3", [(3, 500.0), (2, 2000.0)])
def test_case_use_on_integer_generic(simulate, mode_c, r_3):
    u, c, h = 10.0, 1e-6, 5e-6
    w = simulate("t_case_rc", 5e-3, h, overrides={"mode_c": mode_c})
    for name, r in (("cap_1.v", 1e3), ("cap_2.v", 2e3), ("cap_3.v", r_3)):
        assert deviation(w, name, lambda t: u * (1 - np.exp(-t / (r * c)))) <= bound(u, 1 / (r * c), h), name


# ------------------------------------------------------------------------------------------------
# 9. q'integ
def test_integ_charge(simulate):
    i_dc, i_amp, omega, h, stop = 2e-3, 5e-3, 2e3, 1e-5, 1e-2
    w = simulate("t_integ_charge", stop, h)
    q_scale = i_dc * stop
    assert w["meter.q"][0] == 0.0  # held at 0 in the quiescent domain
    assert deviation(w, "meter.q", lambda t: i_dc * t + i_amp / omega * (1 - np.cos(omega * t))) <= bound(
        q_scale
    ) + bound(i_amp / omega, omega, h, stop)


# ------------------------------------------------------------------------------------------------
# 10. quiescent domain: static equilibrium, no transient
def test_quiescent_domain_solves_the_statics(simulate):
    m, k, force = 1.0, 1e3, 9.81
    w = simulate("t_preload", 0.5, 1e-3)
    x_eq = force / k  # 9.81 mm
    assert np.abs(w["weight.x"] - x_eq).max() <= bound(x_eq)
    # an oscillation from a wrong start would move at x_eq*sqrt(k/m) = 0.31 m/s
    assert np.abs(w["weight.v"]).max() <= bound(x_eq * np.sqrt(k / m))
    assert np.abs(w["spring.f"] - force).max() <= bound(force)


# ------------------------------------------------------------------------------------------------
# 11. the netlist is readable
def test_netlist_readability():
    net = netlist("t_smd_release", 0.1, 1e-4)
    lines = net.text.splitlines()
    subckts = [ln.split()[1] for ln in lines if ln.lower().startswith(".subckt")]
    assert sorted(subckts) == ["t_damper", "t_mass", "t_spring"]  # one per architecture used
    mass = lines[lines.index(next(ln for ln in lines if ln.startswith(".subckt t_mass"))) :]
    mass = mass[: mass.index(".ends t_mass") + 1]
    assert mass[0] == ".subckt t_mass p params: m=1 x0=0 v0=0"  # generics, with their defaults
    assert "x_weight slider t_mass m=0.5 x0=0.01 v0=0" in lines  # the bench's generic map
    assert "convabsstep" not in net.text  # an XSPICE option: mixed-signal only
    body = "\n".join(mass)
    for q in ("f", "v", "a"):  # through and free quantities are nodes
        assert re.search(rf"^b_{q}__eq {q} 0 ", body, re.M), q
        assert net.probes[f"weight.{q}"].plus == f"x_weight.{q}"
    assert (net.probes["weight.x"].plus, net.probes["weight.x"].minus) == ("slider", "0")
    equations = [k for k, ln in enumerate(lines) if re.match(r"b_\w+__eq ", ln)]
    assert len(equations) == 5
    for k in equations:
        m = re.match(r"\* (.+\.vhd):(\d+):(\d+): (.+)$", lines[k - 1])
        assert m, f"no source comment before {lines[k]!r}"
        source = Path(m.group(1)).read_text(encoding="utf-8").splitlines()[int(m.group(2)) - 1]
        assert source.strip() == m.group(4) and "==" in source
        assert len(source) - len(source.lstrip()) == int(m.group(3)) - 1
