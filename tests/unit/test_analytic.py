"""Tests for wrsim.closed_form.two_mass and wrsim.closed_form.worm_gear: thesis chapter 3 (two-mass model,
equivalent mass) and 4.1.2.4-5 (worm gear)."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from wrsim.closed_form.two_mass import (
    DEFAULT_V_THRESHOLD,
    FRICTION_CASES,
    TwoMassGroups,
    TwoMassParams,
    averaged_rates,
    averaged_trajectory,
    dimensionless_groups,
    envelope_amplitude,
    exact_trajectory,
    existence_bound,
    stationary_amplitude,
    stationary_amplitude_m,
)
from wrsim.closed_form.worm_gear import (
    equivalent_mass,
    eta_2d,
    eta_2d_self_locking,
    eta_3d,
    eta_3d_self_locking,
    lead_angle_for_ratio,
    mu_for_eta_2d,
    mu_for_eta_3d,
    ratio_2d,
)
from wrsim.errors import WrsimError

deg = math.radians

# Thesis 3.1.2.3: M1 = 45 kg, M2 = 5 kg, c = 2e4 N/m, mu = 80 N*s/m, omega = 75.8 1/s
CASE1 = TwoMassParams(M1=45.0, M2=5.0, c=2e4, mu=80.0, F_a=200.0, F_r=10.0, omega=75.8)  # "internal" friction
CASE2 = TwoMassParams(M1=45.0, M2=5.0, c=2e4, mu=80.0, F_a=1800.0, F_r=90.0, omega=75.8)  # "external" friction
THESIS = {"relative": CASE1, "m2": CASE2}


# ----------------------------------------------------------------------------------------- worm gear


def test_eta_2d_thesis_example_lead_and_friction_angle_6_deg():
    # 4.1.2.4: "lead angle and friction angle ... 6 deg ... about 49.4476 %"; mu = tan(6 deg) = 0.1051
    mu = math.tan(deg(6.0))
    assert mu == pytest.approx(0.1051, abs=5e-5)
    eta = eta_2d(deg(6.0), mu)
    assert eta == pytest.approx(0.4944765499, abs=1e-10)  # exact value; the thesis truncates to 49.4476 %
    assert eta == pytest.approx(0.494476, abs=1e-6)


@pytest.mark.parametrize("lead", [1.0, 6.0, 20.0, 45.0, 70.0])
@pytest.mark.parametrize("fric", [0.0, 3.0, 6.0, 15.0])
def test_eta_2d_equals_friction_angle_form_4_20b(lead, fric):
    expected = math.tan(deg(lead)) / math.tan(deg(lead + fric))
    assert eta_2d(deg(lead), math.tan(deg(fric))) == pytest.approx(expected, rel=1e-12, abs=1e-15)


def test_eta_2d_frictionless_is_one_and_jammed_is_not_positive():
    assert eta_2d(deg(6.0), 0.0) == pytest.approx(1.0, rel=1e-15)
    # lead + friction angle >= 90 deg: worm cannot drive (value returned as Eq. 4.19e gives it, finite)
    assert eta_2d(deg(60.0), math.tan(deg(30.0))) == pytest.approx(0.0, abs=1e-12)
    assert eta_2d(deg(60.0), math.tan(deg(40.0))) < 0.0


def test_self_locking_2d_table_4_6():
    lead = deg(6.0)
    t = math.tan(lead)
    values = [eta_2d_self_locking(lead, math.tan(deg(f))) for f in (5.8, 6.0, 6.2)]
    # What Eq. 4.22b (power ratio P_w/P_g) really gives: +-3.3212 %, 0
    assert values[0] == pytest.approx(0.0332115321, abs=1e-10)
    assert values[1] == pytest.approx(0.0, abs=1e-15)
    assert values[2] == pytest.approx(-0.0332115321, abs=1e-10)
    # Table 4.6 (0.349 %, 0 %, -0.349 %) is tan(phi_l - phi_f), the force ratio of Eq. 4.22a = 4.22b * tan(phi_l)
    table = [0.00349, 0.0, -0.00349]
    for v, tab in zip(values, table):
        assert v * t == pytest.approx(tab, abs=5e-6)
    for v, f in zip(values, (5.8, 6.0, 6.2)):
        assert v == pytest.approx(math.tan(lead - deg(f)) / t, rel=1e-12, abs=1e-15)


def test_eta_3d_press_angle_11_5_deg_vs_2d():
    lead, mu, press = deg(6.0), math.tan(deg(6.0)), deg(11.5)
    assert math.cos(press) == pytest.approx(0.9799, abs=5e-5)
    e2, e3 = eta_2d(lead, mu), eta_3d(lead, mu, press)
    assert e3 == pytest.approx(0.4893508334, abs=1e-9)
    assert e3 - e2 == pytest.approx(-0.0051257164, abs=1e-9)  # -0.51 percentage points: "insignificant"
    assert e3 == pytest.approx(eta_2d(lead, mu / math.cos(press)), rel=1e-12)


def test_eta_3d_zero_press_angle_reduces_to_2d():
    for lead in (2.0, 6.0, 30.0):
        for f in (0.0, 5.8, 6.2):
            mu = math.tan(deg(f))
            assert eta_3d(deg(lead), mu, 0.0) == pytest.approx(eta_2d(deg(lead), mu), rel=1e-13, abs=1e-15)
            assert eta_3d_self_locking(deg(lead), mu, 0.0) == pytest.approx(
                eta_2d_self_locking(deg(lead), mu), rel=1e-13, abs=1e-15
            )


def test_eta_3d_self_locking_value():
    # 3D at friction angle = lead angle = 6 deg is already self-locking: (cos p - 1)/(cos p + tan^2 6 deg)
    lead, mu, press = deg(6.0), math.tan(deg(6.0)), deg(11.5)
    v = eta_3d_self_locking(lead, mu, press)
    assert v == pytest.approx(-0.0202581944, abs=1e-9)
    assert v == pytest.approx(eta_2d_self_locking(lead, mu / math.cos(press)), rel=1e-12)


def test_ratio_2d_and_inverse():
    assert ratio_2d(5e-3, 20e-3, deg(45.0)) == pytest.approx(4.0, rel=1e-12)
    lam = lead_angle_for_ratio(5e-3, 20e-3, 73.0)
    assert math.degrees(lam) == pytest.approx(3.1363583683, abs=1e-9)
    assert ratio_2d(5e-3, 20e-3, lam) == pytest.approx(73.0, rel=1e-12)


@pytest.mark.parametrize("eta", [0.05, 0.3, 0.42, 0.494, 0.9])
@pytest.mark.parametrize("lead", [2.0, 6.0, 30.0])
def test_mu_for_eta_round_trips(eta, lead):
    mu2 = mu_for_eta_2d(deg(lead), eta)
    assert mu2 >= 0.0
    assert eta_2d(deg(lead), mu2) == pytest.approx(eta, rel=1e-12)
    mu3 = mu_for_eta_3d(deg(lead), eta, deg(11.5))
    assert eta_3d(deg(lead), mu3, deg(11.5)) == pytest.approx(eta, rel=1e-12)


def test_parametrize_2d_and_3d_to_thesis_drive():
    # i = 73, eta = 0.42 (Sec. 3.2) with pitch radii 5 mm / 20 mm
    lam = lead_angle_for_ratio(5e-3, 20e-3, 73.0)
    mu2 = mu_for_eta_2d(lam, 0.42)
    mu3 = mu_for_eta_3d(lam, 0.42, deg(11.5))
    assert mu2 == pytest.approx(0.0751315334, abs=1e-9)
    assert mu3 == pytest.approx(0.0736232457, abs=1e-9)
    assert mu_for_eta_2d(deg(6.0), eta_2d(deg(6.0), math.tan(deg(6.0)))) == pytest.approx(math.tan(deg(6.0)))


@pytest.mark.parametrize(
    "call, name",
    [
        (lambda: eta_2d(0.0, 0.1), "lead_angle"),
        (lambda: eta_2d(math.pi / 2, 0.1), "lead_angle"),
        (lambda: eta_2d(-0.1, 0.1), "lead_angle"),
        (lambda: eta_2d(float("nan"), 0.1), "lead_angle"),
        (lambda: eta_2d(True, 0.1), "lead_angle"),
        (lambda: eta_2d("0.1", 0.1), "lead_angle"),
        (lambda: eta_2d(0.1, -0.01), "mu_c"),
        (lambda: eta_2d(0.1, float("inf")), "mu_c"),
        (lambda: eta_2d_self_locking(2.0, 0.1), "lead_angle"),
        (lambda: eta_2d_self_locking(0.1, -1.0), "mu_c"),
        (lambda: eta_3d(0.1, 0.1, math.pi / 2), "press_angle"),
        (lambda: eta_3d(0.1, 0.1, -0.1), "press_angle"),
        (lambda: eta_3d_self_locking(0.1, -0.1, 0.2), "mu_c"),
        (lambda: ratio_2d(0.0, 0.02, 0.1), "r_worm"),
        (lambda: ratio_2d(0.005, -0.02, 0.1), "r_gear"),
        (lambda: ratio_2d(0.005, 0.02, 0.0), "lead_angle"),
        (lambda: mu_for_eta_2d(0.1, 0.0), "eta"),
        (lambda: mu_for_eta_2d(0.1, 1.0), "eta"),
        (lambda: mu_for_eta_2d(0.1, 1.5), "eta"),
        (lambda: mu_for_eta_2d(1.6, 0.5), "lead_angle"),
        (lambda: mu_for_eta_3d(0.1, 0.5, 1.6), "press_angle"),
        (lambda: lead_angle_for_ratio(0.005, 0.02, 0.0), "ratio"),
        (lambda: lead_angle_for_ratio(-0.005, 0.02, 73.0), "r_worm"),
        (lambda: lead_angle_for_ratio(0.005, 0.0, 73.0), "r_gear"),
    ],
)
def test_worm_gear_validation_names_argument(call, name):
    with pytest.raises(WrsimError, match=rf"^{name} "):
        call()


# ------------------------------------------------------------------------------------ equivalent mass


def test_equivalent_mass_thesis_example():
    # Sec. 3.2: J = 8e-6 kg m^2, i = 73, eta = 0.42, r = 0.02 m -> "about 45 kg"; exactly 44.7636 kg
    m = equivalent_mass(8e-6, 73.0, 0.42, 0.02)
    assert m == pytest.approx(44.7636, rel=1e-12)
    assert m == pytest.approx(45.0, abs=0.5)
    assert equivalent_mass(8e-6, 73.0, 1.0, 0.02) == pytest.approx(106.58, rel=1e-12)  # lossless allowed


@pytest.mark.parametrize(
    "args, name",
    [
        ((0.0, 73.0, 0.42, 0.02), "j"),
        ((8e-6, -73.0, 0.42, 0.02), "ratio"),
        ((8e-6, 73.0, 0.0, 0.02), "eta"),
        ((8e-6, 73.0, 1.01, 0.02), "eta"),
        ((8e-6, 73.0, 0.42, 0.0), "r_drum"),
        ((8e-6, 73.0, float("nan"), 0.02), "eta"),
    ],
)
def test_equivalent_mass_validation(args, name):
    with pytest.raises(WrsimError, match=rf"^{name} "):
        equivalent_mass(*args)


# ------------------------------------------------------------------------------ two-mass model groups


def test_groups_case1_vs_thesis():
    g = dimensionless_groups(CASE1)
    assert g.omega0 == pytest.approx(47.1, abs=0.05)  # thesis 47.1 1/s
    assert g.omega0 == pytest.approx(47.14045208, rel=1e-9)
    assert g.beta == pytest.approx(20.0, rel=1e-12)  # thesis 20
    assert g.m1 == pytest.approx(0.9) and g.m2 == pytest.approx(0.1)
    assert g.existence_bound == pytest.approx(11.4591559, rel=1e-8)  # thesis 11.5
    assert existence_bound(0.9) == pytest.approx(g.existence_bound, rel=1e-14)
    # What the thesis's own definitions give (thesis values in comments -- not reproducible, see report):
    assert g.nu == pytest.approx(1.6079608, rel=1e-7)
    assert g.L == pytest.approx(3.4156622e-3, rel=1e-7)  # thesis 3.3e-3 m
    assert g.eps == pytest.approx(0.02634921, rel=1e-6)  # thesis 0.05
    assert g.alpha == pytest.approx(14.312521, rel=1e-6)  # thesis 14.9
    assert g.delta == pytest.approx(7.353058, rel=1e-6)  # thesis 4


def test_groups_case2_same_dimensionless_values_larger_length():
    g1, g2 = dimensionless_groups(CASE1), dimensionless_groups(CASE2)
    assert g2.L == pytest.approx(9.0 * g1.L, rel=1e-12)
    assert g2.L == pytest.approx(3.074096e-2, rel=1e-6)  # thesis 3e-2 m
    for name in ("eps", "alpha", "beta", "delta", "nu", "m1", "m2"):
        assert getattr(g2, name) == pytest.approx(getattr(g1, name), rel=1e-12)


def test_groups_reproduce_dimensionless_equations_3_3():
    # coefficients of Eq. 3.3a/b must equal the dimensional ones
    p = CASE1
    g = dimensionless_groups(p)
    assert g.m2 * g.eps * g.alpha == pytest.approx(p.mu / (p.M1 * g.omega0), rel=1e-12)
    assert g.m1 * g.eps * g.alpha == pytest.approx(p.mu / (p.M2 * g.omega0), rel=1e-12)
    assert g.eps * g.beta / g.m1 == pytest.approx(p.F_a / (p.M1 * g.L * g.omega0**2), rel=1e-12)
    assert g.eps / g.m2 == pytest.approx(p.F_r / (p.M2 * g.L * g.omega0**2), rel=1e-12)
    assert 2 * g.m2 == pytest.approx(p.c / (p.M1 * g.omega0**2), rel=1e-12)
    assert g.nu == pytest.approx(math.sqrt(2) + g.eps * g.delta, rel=1e-12)


def test_stationary_amplitude_thesis_dimensionless_values():
    # with the dimensionless values the thesis prints (m1 = 0.9, alpha = 14.9, beta = 20, Delta = 4)
    a = stationary_amplitude(0.9, 14.9, 20.0, 4.0)
    assert a == pytest.approx(0.43, abs=0.005)  # thesis 0.43
    assert a == pytest.approx(0.42533434, rel=1e-7)
    # times the length scales the thesis's formula gives: 1.45e-3 m and 1.31e-2 m (thesis 1.4e-3, 1.3e-2)
    assert a * dimensionless_groups(CASE1).L == pytest.approx(1.452798e-3, rel=1e-6)
    assert a * dimensionless_groups(CASE2).L == pytest.approx(1.307519e-2, rel=1e-6)


def test_stationary_amplitude_is_root_of_3_11_and_matches_3_12_as_printed():
    m1, al, be, de = 0.9, 14.9, 20.0, 4.0
    m2 = 1 - m1
    a = stationary_amplitude(m1, al, be, de)
    pi = math.pi
    residual = (
        2 * m1**2 * m2**2 * pi**2 * (al**2 + 4 * de**2) * a**2
        + 8 * math.sqrt(2) * m1**2 * m2 * pi * al * a
        + (16 * m1**2 - m2**2 * pi**2 * be**2)
    )
    assert residual == pytest.approx(0.0, abs=1e-9)
    root = math.sqrt(2 * (m2**2 * pi**2 * be**2 * (al**2 + 4 * de**2) - 64 * de**2 * m1**2))
    printed = (-4 * math.sqrt(2) * m1 * al + root) / (2 * m1 * m2 * pi * (al**2 + 4 * de**2))
    assert a == pytest.approx(printed, rel=1e-12)


def test_stationary_amplitude_from_thesis_parameters():
    g = dimensionless_groups(CASE1)
    a = stationary_amplitude(g.m1, g.alpha, g.beta, g.delta)
    assert a == pytest.approx(0.39220631, rel=1e-7)  # thesis 0.43 (with its eps = 0.05, alpha = 14.9, Delta = 4)
    assert stationary_amplitude_m(CASE1) == pytest.approx(1.3396443e-3, rel=1e-7)  # thesis 1.4e-3 m
    assert stationary_amplitude_m(CASE2) == pytest.approx(1.2056798e-2, rel=1e-7)  # thesis 1.3e-2 m


def test_dimensional_amplitude_independent_of_length_scale():
    g0 = dimensionless_groups(CASE1)
    ref = stationary_amplitude(g0.m1, g0.alpha, g0.beta, g0.delta) * g0.L
    for L in (1e-4, 1e-3, 0.1, 2.0):
        g = dimensionless_groups(CASE1, L=L)
        assert stationary_amplitude(g.m1, g.alpha, g.beta, g.delta) * g.L == pytest.approx(ref, rel=1e-10)


def test_no_stationary_amplitude_below_existence_bound():
    with pytest.raises(WrsimError, match=r"^no stationary amplitude: beta = 10 <= 4 m1/\(pi m2\) = 11\.4592$"):
        stationary_amplitude(0.9, 14.9, 10.0, 4.0)
    weak = TwoMassParams(45.0, 5.0, 2e4, 80.0, 100.0, 10.0, 75.8)
    with pytest.raises(WrsimError, match=r"no stationary amplitude: beta = 10 <= 4 m1/\(pi m2\) = 11\.4592"):
        stationary_amplitude_m(weak)
    with pytest.raises(WrsimError, match=r"no stationary amplitude"):
        stationary_amplitude(0.9, 14.9, existence_bound(0.9), 4.0)


def test_stationary_amplitude_edge_cases_are_finite_or_errors():
    # alpha = 0 (no damping) but detuned: finite
    a = stationary_amplitude(0.9, 0.0, 20.0, 4.0)
    assert math.isfinite(a) and a > 0
    with pytest.raises(WrsimError, match="alpha = 0 and delta = 0"):
        stationary_amplitude(0.9, 0.0, 20.0, 0.0)
    # just above the bound: tiny positive, no cancellation to a negative number
    a = stationary_amplitude(0.9, 14.9, existence_bound(0.9) * (1 + 1e-12), 4.0)
    assert 0.0 < a < 1e-10


def test_resonance_needs_explicit_length_scale():
    w0 = dimensionless_groups(CASE1).omega0
    p = TwoMassParams(45.0, 5.0, 2e4, 80.0, 200.0, 10.0, math.sqrt(2) * w0)
    with pytest.raises(WrsimError, match=r"^omega = .*pass L explicitly"):
        dimensionless_groups(p)
    g = dimensionless_groups(p, L=1e-3)
    assert g.delta == pytest.approx(0.0, abs=1e-9)
    assert math.isfinite(stationary_amplitude_m(p))


@pytest.mark.parametrize(
    "field, value",
    [("M1", 0.0), ("M2", -5.0), ("c", float("nan")), ("mu", -1.0), ("F_a", 0.0), ("F_r", 0.0), ("omega", -75.8)],
)
def test_two_mass_params_validation(field, value):
    kwargs = dict(M1=45.0, M2=5.0, c=2e4, mu=80.0, F_a=200.0, F_r=10.0, omega=75.8)
    kwargs[field] = value
    with pytest.raises(WrsimError, match=rf"^{field} "):
        TwoMassParams(**kwargs)


def test_other_two_mass_argument_errors():
    with pytest.raises(WrsimError, match=r"^case "):
        averaged_trajectory("internal", CASE1, 0.01, 1.0)
    with pytest.raises(WrsimError, match=r"^case "):
        exact_trajectory(1, CASE1, 0.01, 1.0)
    with pytest.raises(WrsimError, match=r"^a0 "):
        averaged_trajectory("relative", CASE1, -0.01, 1.0)
    with pytest.raises(WrsimError, match=r"^t_end "):
        exact_trajectory("m2", CASE2, 0.01, 0.0)
    with pytest.raises(WrsimError, match=r"^v_threshold "):
        exact_trajectory("m2", CASE2, 0.01, 1.0, v_threshold=0.0)
    with pytest.raises(WrsimError, match=r"^L "):
        dimensionless_groups(CASE1, L=-1.0)
    with pytest.raises(WrsimError, match=r"^params "):
        dimensionless_groups({"M1": 45.0})
    with pytest.raises(WrsimError, match=r"^a "):
        averaged_rates("relative", dimensionless_groups(CASE1), 0.0, 0.0, 0.0)
    with pytest.raises(WrsimError, match=r"^m1 "):
        existence_bound(1.0)


# ---------------------------------------------------------------------------------- averaged system


def _stationary_phase(g: TwoMassGroups, a: float) -> float:
    cos_xi = 2 * g.m1 / g.beta * (2 / (math.pi * g.m2) + g.alpha * a / math.sqrt(2))
    sin_xi = 2 * g.m1 / g.beta * math.sqrt(2) * a * g.delta
    assert cos_xi**2 + sin_xi**2 == pytest.approx(1.0, rel=1e-10)
    return math.atan2(sin_xi, cos_xi)


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_averaged_rates_vanish_at_stationary_point(case):
    g = dimensionless_groups(THESIS[case])
    a = stationary_amplitude(g.m1, g.alpha, g.beta, g.delta)
    xi = _stationary_phase(g, a)
    dV, da, dxi = averaged_rates(case, g, 0.0, a, xi)
    assert (dV, da, dxi) == pytest.approx((0.0, 0.0, 0.0), abs=1e-14)


def test_averaged_rates_m2_outside_sliding_band():
    g = dimensionless_groups(CASE2)
    a = 0.1
    V = 2 * g.m1 * a * math.sqrt(2)  # |V| > m1 a sqrt(2): friction does not act on a (Eq. 3.16/3.17)
    dV, da, _ = averaged_rates("m2", g, V, a, 0.3)
    assert dV == pytest.approx(-g.eps)
    expected = -(g.eps / math.sqrt(2)) * (g.alpha * a / math.sqrt(2) - g.beta * math.cos(0.3) / (2 * g.m1))
    assert da == pytest.approx(expected)
    dV, _, _ = averaged_rates("m2", g, -V, a, 0.3)
    assert dV == pytest.approx(g.eps)


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_averaged_trajectory_settles_to_eq_3_12(case):
    p = THESIS[case]
    tr = averaged_trajectory(case, p, 0.01, 6.0, V0=0.3 if case == "m2" else 0.0)
    g = tr.groups
    a_st = stationary_amplitude(g.m1, g.alpha, g.beta, g.delta)
    assert tr.a[0] == pytest.approx(0.01)
    assert tr.t[-1] == pytest.approx(6.0)
    assert tr.a[-1] == pytest.approx(a_st, rel=1e-6)
    assert tr.amplitude_m[-1] == pytest.approx(stationary_amplitude_m(p), rel=1e-6)
    assert tr.xi[-1] == pytest.approx(_stationary_phase(g, a_st), abs=1e-5)
    if case == "m2":
        assert abs(tr.V[-1]) < 1e-4  # Eq. 3.16 drives V to 0
    else:
        assert np.all(tr.V == 0.0)  # Eq. 3.10a
    assert np.all(np.isfinite(tr.a)) and np.all(np.isfinite(tr.xi))


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_cartesian_integration_matches_polar_equations(case):
    # the integrator uses u = a cos xi, w = a sin xi; check against Eq. 3.10 / 3.16-3.18 in polar form
    p = THESIS[case]
    g = dimensionless_groups(p)
    y0 = [0.1, 0.2, 0.5]  # V, a, xi
    tr = averaged_trajectory(case, p, y0[1], 2.0, V0=y0[0], xi0=y0[2], n_points=51)
    ref = solve_ivp(
        lambda _t, y: averaged_rates(case, g, y[0], y[1], y[2]),
        (0.0, 2.0 * g.omega0),
        y0,
        t_eval=tr.t * g.omega0,
        rtol=1e-10,
        atol=1e-12,
    )
    assert ref.success
    assert tr.V == pytest.approx(ref.y[0], abs=1e-6)
    assert tr.a == pytest.approx(ref.y[1], abs=1e-6)
    dxi = np.angle(np.exp(1j * (tr.xi - ref.y[2])))
    assert np.max(np.abs(dxi)) < 1e-5


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_averaged_amplitude_dies_out_below_bound(case):
    weak = TwoMassParams(45.0, 5.0, 2e4, 80.0, 100.0, 10.0, 75.8)  # beta = 10 < 11.46
    tr = averaged_trajectory(case, weak, 0.3, 4.0)
    assert np.all(np.isfinite(tr.a))
    assert tr.a[-1] < 1e-5


# ------------------------------------------------------------------------------------- exact system


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_exact_trajectory_initial_state(case):
    p = THESIS[case]
    tr = exact_trajectory(case, p, 0.01, 0.05)
    g = dimensionless_groups(p)
    assert tr.z[0] == pytest.approx(0.01 * g.L, rel=1e-12)
    assert tr.t[0] == 0.0 and tr.t[-1] == pytest.approx(0.05)
    assert np.allclose(tr.z, tr.x2 - tr.x1)
    # centre of mass starts at rest in 0
    assert g.m1 * tr.x1[0] + g.m2 * tr.x2[0] == pytest.approx(0.0, abs=1e-15)


# With the thesis's parameters the exact model does NOT settle within 10 % of the averaged amplitude:
# the perturbation the averaging assumes to be O(eps) is not small there (forcing term eps*beta/m1 =
# |2 - nu^2| = 0.59, damping eps*alpha = 0.38, detuning eps*Delta = 0.19). These are the honest values.
EXACT_THESIS = {"relative": (1.1476e-3, 1.3396e-3), "m2": (9.471e-3, 1.2057e-2)}


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_exact_vs_averaged_with_thesis_parameters(case):
    p = THESIS[case]
    tr = exact_trajectory(case, p, 0.01, 4.0)
    amp = envelope_amplitude(tr.t, tr.z, 3.0)
    exact_ref, averaged_ref = EXACT_THESIS[case]
    assert stationary_amplitude_m(p) == pytest.approx(averaged_ref, rel=1e-4)
    assert amp == pytest.approx(exact_ref, rel=0.01)
    # settled: same amplitude one second earlier
    assert envelope_amplitude(tr.t[tr.t < 3.0], tr.z[tr.t < 3.0], 2.0) == pytest.approx(amp, rel=0.005)
    # deviation: -14 % ("relative"), -21 % ("m2")
    assert amp / stationary_amplitude_m(p) - 1 == pytest.approx(-0.143 if case == "relative" else -0.214, abs=0.01)


def _scaled(p: TwoMassParams, s: float) -> TwoMassParams:
    """Thesis parameters with damping and detuning from sqrt(2) omega_0 scaled by s: eps -> ~s*eps while
    alpha, beta, Delta stay ~the same (so a is ~unchanged and only the validity of averaging improves)."""
    w_res = math.sqrt(2) * dimensionless_groups(p).omega0
    return TwoMassParams(p.M1, p.M2, p.c, p.mu * s, p.F_a, p.F_r, w_res + s * (p.omega - w_res))


@pytest.mark.parametrize("case", FRICTION_CASES)
def test_exact_settles_within_10_percent_of_averaged_when_eps_small(case):
    p = _scaled(THESIS[case], 0.1)
    g = dimensionless_groups(p)
    assert g.eps == pytest.approx(0.00248, rel=0.01)
    assert 2 - g.nu**2 == pytest.approx(-0.05518, rel=0.01)  # forcing term now small too
    t_end = 40.0
    tr = exact_trajectory(case, p, 0.01, t_end)
    amp = envelope_amplitude(tr.t, tr.z, 30.0)
    averaged = averaged_trajectory(case, p, 0.01, t_end).amplitude_m[-1]
    assert averaged == pytest.approx(stationary_amplitude_m(p), rel=1e-5)
    rel = amp / averaged - 1
    assert abs(rel) < 0.10
    # actual deviations: -1.6 % ("relative"), -5.0 % ("m2"); at s = 1 they are -14 % and -21 %
    assert rel == pytest.approx(-0.016 if case == "relative" else -0.050, abs=0.005)


def test_smoothing_threshold_is_immaterial():
    base = exact_trajectory("relative", CASE1, 0.01, 4.0)
    fine = exact_trajectory("relative", CASE1, 0.01, 4.0, v_threshold=DEFAULT_V_THRESHOLD / 10)
    a0 = envelope_amplitude(base.t, base.z, 3.0)
    a1 = envelope_amplitude(fine.t, fine.z, 3.0)
    assert a1 == pytest.approx(a0, rel=0.01)


# ------------------------------------------------------------------------------------------ envelope


def test_envelope_amplitude_sine_with_offset_and_drift():
    t = np.linspace(0.0, 10.0, 20001)
    x = 0.3 + 0.002 * t + 2.0 * np.sin(5.0 * t)
    assert envelope_amplitude(t, x, 4.0) == pytest.approx(2.0, rel=2e-3)
    assert envelope_amplitude(t, np.full_like(t, 1.5), 4.0) == 0.0


def test_envelope_amplitude_errors():
    t = np.linspace(0.0, 1.0, 101)
    x = np.sin(2 * np.pi * 0.5 * t)  # half a cycle only
    with pytest.raises(WrsimError, match=r"^t_from = .*fewer than one complete oscillation cycle"):
        envelope_amplitude(t, x, 0.0)
    with pytest.raises(WrsimError, match=r"^t_from "):
        envelope_amplitude(t, x, 2.0)
    with pytest.raises(WrsimError, match=r"^x "):
        envelope_amplitude(t, x[:-1], 0.0)
    with pytest.raises(WrsimError, match=r"^t "):
        envelope_amplitude(t[::-1], x, 0.0)
    with pytest.raises(WrsimError, match=r"^x "):
        envelope_amplitude(t, np.where(t > 0.5, np.nan, x), 0.0)
