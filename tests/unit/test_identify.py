"""Identification of motor and drive parameters (thesis 4.1.1.4, 4.1.4.2) and the closed-form lines."""
from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from wrsim.errors import WrsimError
from wrsim.identify import (MotorParams, drive_ramp_line, gear_efficiency_from_slopes,
                            housing_friction_from_gap, identify_default_set, least_squares_motor,
                            line_fit, motor_from_line, motor_ramp_line, parameter_calculator,
                            write_default_set)
from wrsim.measurements import read_table
from wrsim.params import load_params

ROOT = Path(__file__).resolve().parents[2]
MEAS = ROOT / "params" / "measurements"
U, LAA, J, RATE = 13.0, 0.09e-3, 9.85e-6, 0.5 / 3
RATIO, ETA, DRIVE_RATE = 73.0, 0.45162397, 13.0 / 2
TRUE = MotorParams(ke=0.0205, kt=0.0172, ra=0.556, laa=LAA, j=J, visc=2.7e-5, mc=0.0)


@pytest.fixture(scope="module")
def fig4_15():
    t = read_table(MEAS / "fig4_15_motor.csv", increasing="torque", require_source=True)
    return t.column("torque", "N*m"), t.column("mean_speed", "rad/s"), t.column("mean_current", "A")


@pytest.fixture(scope="module")
def identified(fig4_15):
    return motor_from_line(*fig4_15, U, LAA, J, RATE)


def test_ramp_line_solves_eq_4_1_with_ramp_terms():
    p = replace(TRUE, mc=0.004)
    m = np.array([0.05, 0.25])
    w, i = motor_ramp_line(p, U, RATE, m)
    dwdt, didt = (w[1] - w[0]) / (m[1] - m[0]) * RATE, (i[1] - i[0]) / (m[1] - m[0]) * RATE
    np.testing.assert_allclose(p.ra * i + p.laa * didt + p.ke * w, U, rtol=1e-13)           # Eq. 4.1a
    np.testing.assert_allclose(p.kt * i, p.mc + p.visc * w + p.j * dwdt + m, rtol=1e-13)    # Eq. 4.1b
    w_s, i_s = motor_ramp_line(p, U, 0.0, m)  # torque_rate 0: the steady-state line
    np.testing.assert_allclose(p.ra * i_s + p.ke * w_s, U, rtol=1e-13)
    np.testing.assert_allclose(p.kt * i_s, p.mc + p.visc * w_s + m, rtol=1e-13)
    assert np.all(w > w_s)  # while decelerating, the rotor's inertia helps carry the load


def test_ramp_line_stops_at_stall():
    with pytest.raises(WrsimError, match=r"load torque 1 N\*m reaches stall \(0\.4\d+ N\*m at 13 V\)"):
        motor_ramp_line(TRUE, U, RATE, [0.1, 1.0])


def test_calculator_reproduces_itself():
    m1, m2 = 0.04, 0.2
    w, i = motor_ramp_line(TRUE, U, RATE, [m1, m2])
    p = parameter_calculator(m1, w[0], i[0], m2, w[1], i[1], U, LAA, J, RATE)
    for name in ("ke", "kt", "ra", "visc"):
        assert getattr(p, name) == pytest.approx(getattr(TRUE, name), rel=1e-9), name
    assert p.mc == 0.0
    dwdt = (w[1] - w[0]) / (m2 - m1) * RATE
    assert i[0] * p.kt - m1 - J * dwdt - p.visc * w[0] == pytest.approx(0.0, abs=1e-15)  # Eq. 4.8a


def test_calculator_puts_coulomb_friction_into_visc():
    true = replace(TRUE, mc=0.004)
    w, i = motor_ramp_line(true, U, RATE, [0.04, 0.2])
    p = parameter_calculator(0.04, w[0], i[0], 0.2, w[1], i[1], U, LAA, J, RATE)
    omega_idle = (w[0] - w[1]) / (i[1] - i[0]) * i[0] + w[0]
    assert p.ke == pytest.approx(true.ke, rel=1e-9) and p.ra == pytest.approx(true.ra, rel=1e-9)
    assert p.visc == pytest.approx(true.visc + true.mc / omega_idle, rel=1e-9)
    assert p.mc == 0.0
    with pytest.raises(WrsimError, match="must differ in torque and current"):
        parameter_calculator(0.1, 500, 3, 0.1, 400, 3, U, LAA, J, RATE)


def test_line_fit():
    assert line_fit([0, 1, 2], [1, 3, 5]) == pytest.approx((2.0, 1.0))
    with pytest.raises(WrsimError, match="at least two distinct x"):
        line_fit([1.0, 1.0], [2.0, 3.0])


def test_motor_from_fig4_15_mean_line(identified):
    p, details = identified
    assert details["stall_torque"] == pytest.approx(0.402166, rel=1e-5)
    assert details["points"]["torque"] == pytest.approx([0.0402166, 0.201083], rel=1e-5)
    assert details["speed_slope"] == pytest.approx(-1528.31, rel=1e-5)   # rad/s per N*m
    assert p.ke == pytest.approx(0.0204370, rel=1e-5)
    assert p.kt == pytest.approx(0.0170280, rel=1e-5)
    assert p.ra == pytest.approx(0.553848, rel=1e-5)
    assert p.visc == pytest.approx(2.59835e-5, rel=1e-5)
    assert (p.laa, p.j, p.mc) == (LAA, J, 0.0)


def test_identified_motor_matches_fig4_15_in_working_range(fig4_15, identified):
    p, details = identified
    torque, speed, current = fig4_15
    sel = (torque >= 0.1 * details["stall_torque"]) & (torque <= 0.8 * details["stall_torque"])
    assert sel.sum() == 7
    w, i = motor_ramp_line(p, U, RATE, torque[sel])
    speed_err = np.max(np.abs(w / speed[sel] - 1))
    current_err = np.max(np.abs(i / current[sel] - 1))
    assert speed_err < 0.02 and current_err < 0.041       # the thesis's own bounds: 1.8 %, 4.03 %
    assert speed_err == pytest.approx(0.00111, abs=1e-5)  # measured: 0.11 %
    assert current_err == pytest.approx(0.00985, abs=1e-5)  # measured: 0.98 % (at 0.043 N*m)


def test_gear_efficiency_eq_4_35b():
    assert gear_efficiency_from_slopes(-14639.24, -6.0827, 73) == pytest.approx(0.4516, abs=5e-5)
    assert gear_efficiency_from_slopes(-14639.24, -6.00, 73) == pytest.approx(0.45785, abs=5e-5)


def test_drive_line_is_motor_line_through_the_gear():
    g = np.array([1.0, 3.0, 5.0])
    wg, ig = drive_ramp_line(TRUE, RATIO, ETA, 0.4, U, DRIVE_RATE, g)
    wa, ia = motor_ramp_line(TRUE, U, DRIVE_RATE / (RATIO * ETA), (g + 0.4) / (RATIO * ETA))
    np.testing.assert_allclose(wg, wa / RATIO, rtol=1e-14)
    np.testing.assert_allclose(ig, ia, rtol=1e-14)


def test_housing_friction_recovers_known_value():
    g = np.linspace(1, 5, 9)
    fitted, _ = drive_ramp_line(TRUE, RATIO, ETA, 0.37, U, DRIVE_RATE, g)
    assert housing_friction_from_gap(TRUE, RATIO, ETA, U, DRIVE_RATE, g, fitted) == pytest.approx(0.37, rel=1e-10)


def test_drive_with_identified_housing_friction_matches_fig4_44(identified):
    p, _ = identified
    t = read_table(MEAS / "fig4_44_drive.csv", increasing="torque", require_source=True)
    g = t.column("torque", "N*m")
    fit_w, fit_i = t.column("fit_speed", "rad/s"), t.column("fit_current", "A")
    m_gc = housing_friction_from_gap(p, RATIO, ETA, U, DRIVE_RATE, g, fit_w)
    assert m_gc == pytest.approx(0.31569, abs=1e-4)
    w, i = drive_ramp_line(p, RATIO, ETA, m_gc, U, DRIVE_RATE, g)
    assert np.mean(w - fit_w) == pytest.approx(0.0, abs=1e-12)
    assert np.max(np.abs(w / fit_w - 1)) < 0.003     # measured 0.23 %; thesis 0.24 %
    assert np.max(np.abs(i / fit_i - 1)) < 0.037     # measured 1.65 %; thesis 3.63 %


def _two_voltage_samples(p: MotorParams, voltages=(12.0, 13.0)):
    m = np.linspace(0.04, 0.32, 15)
    parts = [(m, *motor_ramp_line(p, u, RATE, m), np.full_like(m, u)) for u in voltages]
    return [np.concatenate(col) for col in zip(*parts)]


def test_least_squares_two_voltages_identifies_coulomb_and_viscous_friction():
    true = replace(TRUE, kt=0.0181, visc=1.5e-5, mc=0.004)
    torque, speed, current, u = _two_voltage_samples(true)
    p, details = least_squares_motor(torque, speed, current, u, LAA, J, RATE)
    assert details["case"] == "free" and details["constraint"] is None
    assert details["voltages"] == [12.0, 13.0] and details["samples"] == 30
    assert details["cond_mechanical"] < 1e3
    for name in ("ke", "kt", "ra", "visc", "mc"):
        assert getattr(p, name) == pytest.approx(getattr(true, name), rel=1e-8), name


def test_least_squares_single_voltage_imposes_kt_equals_ke():
    true = replace(TRUE, kt=TRUE.ke, visc=1.5e-5, mc=0.004)
    m = np.linspace(0.04, 0.32, 15)
    speed, current = motor_ramp_line(true, U, RATE, m)
    p, details = least_squares_motor(m, speed, current, U, LAA, J, RATE)
    assert details["case"] == "kt=ke"
    assert details["constraint"].startswith("kt = ke imposed (SI energy balance): only one supply voltage (13 V)")
    assert details["cond_mechanical"] > 1e12  # i, w, 1 collinear along one line
    assert p.kt == p.ke
    for name in ("ke", "ra", "visc", "mc"):  # exact when the true motor has kt = ke
        assert getattr(p, name) == pytest.approx(getattr(true, name), rel=1e-8), name


def test_least_squares_nearly_equal_voltages_fall_back_to_constraint():
    torque, speed, current, u = _two_voltage_samples(TRUE, voltages=(13.0, 13.0 + 1e-9))
    p, details = least_squares_motor(torque, speed, current, u, LAA, J, RATE)
    assert details["case"] == "kt=ke" and "ill-conditioned" in details["constraint"]
    assert p.kt == p.ke


def test_default_set_round_trip(tmp_path):
    out = tmp_path / "fpg2_12nm.txt"
    result = write_default_set(ROOT, out)
    assert out.read_text() == (ROOT / "params" / "fpg2_12nm.txt").read_text()
    pset = load_params(out)
    for name in ("ke", "kt", "ra", "visc"):
        unit = {"ke": "V*s/rad", "kt": "N*m/A", "ra": "Ohm", "visc": "N*m*s/rad"}[name]
        assert pset.value_in("dcpm_motor", name, unit) == pytest.approx(getattr(result["motor"], name), rel=1e-9)
    assert pset.value_in("drive", "m_gc", "N*m") == pytest.approx(result["drive"]["m_gc"], rel=1e-9)


def test_default_set_findings():
    r = identify_default_set(ROOT)
    f, v = r["findings"], r["validation"]
    assert f["eta_printed_slopes"] == pytest.approx(0.45785, abs=5e-5)
    assert f["s_d_for_printed_eta"] == pytest.approx(-6.0827, abs=5e-5)
    assert f["s_a_thesis_sim_rpm"] == pytest.approx(-14639.24, rel=2e-5)  # printed s_a = simulated slope
    assert f["s_a_mean_rpm"] == pytest.approx(-14594.33, abs=0.01)
    assert f["eta_our_slopes"] == pytest.approx(0.45585, abs=5e-5)
    assert r["drive"]["m_gc"] == pytest.approx(0.3157, abs=1e-4)
    assert v["thesis_motor_speed_pct"] == pytest.approx(1.84, abs=0.01)
    assert v["thesis_motor_current_pct"] == pytest.approx(4.03, abs=0.01)
    assert v["drive_speed_pct"] < 0.3 and v["drive_current_pct"] < 3.7
