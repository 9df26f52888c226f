"""Synthetic test-stand data: determinism, centred unit spread, exact model lines under the imperfections,
the imperfections themselves, and the files it writes."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wrsim import paths
from wrsim.closed_form.motor import drive_ramp_line, motor_ramp_line
from wrsim.data.curves import read_characteristic, read_torque_angle
from wrsim.data.params import load_params
from wrsim.errors import WrsimError
from wrsim.identify.calculator import line_fit
from wrsim.identify.synthetic import (
    DRIVE_STAND,
    MOTOR_STAND,
    Spread,
    Truth,
    damper_curves,
    draw_units,
    drive_curves,
    motor_curves,
    write_group,
)

ROOT = paths.ROOT
TRUTH = Truth.from_params(load_params(ROOT / "params" / "fpg2_12nm.txt"))
NO_SPREAD = Spread(**{name: 0.0 for name in Spread.__dataclass_fields__})


def test_truth_from_the_parameter_set():
    assert TRUTH.motor.ke == 0.0204369637 and TRUTH.motor.ra == 0.5538483046
    assert (TRUTH.ratio, TRUTH.eta, TRUTH.m_gc) == (73.0, 0.45162397, 0.3156856005)
    assert TRUTH.damper_stiffness == (57.3, 51.6, 48.7, 47.7, 51.6, 68.8)


def test_same_seed_same_data_other_seed_other_data():
    a = motor_curves(draw_units(TRUTH, seed=3), seed=3)
    b = motor_curves(draw_units(TRUTH, seed=3), seed=3)
    c = motor_curves(draw_units(TRUTH, seed=4), seed=4)
    assert len(a) == 10 and [x.name for x in a[:2]] == ["motor_u1_cw", "motor_u1_ccw"]
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x.current, y.current)
    assert not np.array_equal(a[0].current[:100], c[0].current[:100])


def test_unit_spread_is_centred_on_the_truth():
    units = draw_units(TRUTH, count=5, seed=1)
    for name in ("ke", "ra", "visc"):
        factors = np.array([getattr(u.motor, name) for u in units]) / getattr(TRUTH.motor, name)
        assert np.exp(np.mean(np.log(factors))) == pytest.approx(1.0, abs=1e-12), name
        assert np.std(np.log(factors)) > 0.3 * getattr(Spread(), "flux" if name == "ke" else name)
    for values, truth in (([u.eta for u in units], TRUTH.eta), ([u.m_gc for u in units], TRUTH.m_gc)):
        assert np.exp(np.mean(np.log(np.array(values) / truth))) == pytest.approx(1.0, abs=1e-12)
    assert all(u.ra_direction[0] * u.ra_direction[1] == pytest.approx(1.0) for u in units)
    single = draw_units(TRUTH, count=1, seed=1)[0]
    assert single.motor == TRUTH.motor and single.eta == TRUTH.eta
    with pytest.raises(WrsimError, match="at least one unit"):
        draw_units(TRUTH, count=0)


def test_clean_stand_gives_the_model_lines():
    unit = draw_units(TRUTH, 1)
    cw, ccw = motor_curves(unit, MOTOR_STAND.clean())
    assert (cw.direction, ccw.direction) == (1, -1)
    assert cw.torque[0] == MOTOR_STAND.start and np.all(np.diff(cw.time) > 0)
    np.testing.assert_allclose(np.diff(cw.torque) / np.diff(cw.time), MOTOR_STAND.torque_rate, rtol=1e-9)
    w, i = motor_ramp_line(TRUTH.motor, 13.0, MOTOR_STAND.torque_rate, cw.torque)
    np.testing.assert_allclose(cw.speed, w, rtol=1e-12)
    np.testing.assert_allclose(cw.current, i, rtol=1e-12)
    np.testing.assert_array_equal(cw.voltage, 13.0)
    # the record starts in generator mode (speed above no load) and stops near stall
    assert cw.speed[-1] / motor_ramp_line(TRUTH.motor, 13.0, MOTOR_STAND.torque_rate, [0.0])[0][0] == pytest.approx(
        MOTOR_STAND.end_speed, abs=1e-3
    )
    (dcw, _) = drive_curves(unit, TRUTH.ratio, DRIVE_STAND.clean())
    w, i = drive_ramp_line(TRUTH.motor, TRUTH.ratio, TRUTH.eta, TRUTH.m_gc, 13.0, 6.5, dcw.torque)
    np.testing.assert_allclose(dcw.speed, w, rtol=1e-12)
    np.testing.assert_allclose(dcw.current, i, rtol=1e-12)
    assert dcw.torque[-1] == pytest.approx(12.56, abs=0.01)  # 3 % of no-load speed left; stall 12.86 N*m


def test_imperfections():
    unit = draw_units(TRUTH, 1)
    cw = motor_curves(unit, MOTOR_STAND, seed=2)[0]
    ideal = motor_curves(
        unit,
        replace(
            MOTOR_STAND, noise_torque=0.0, noise_speed=0.0, noise_current=0.0, noise_voltage=0.0, ripple_torque=0.0
        ),
        seed=2,
    )[0]
    ratio = ideal.current / motor_ramp_line(TRUTH.motor, 13.0, MOTOR_STAND.torque_rate, ideal.torque)[1] - 1
    work = (ideal.torque > 0.04) & (ideal.torque < 0.30)
    # commutation ripple of 4 % in the working range, growing to 5 x that near stall (disordered curves)
    assert np.max(np.abs(ratio[work])) == pytest.approx(0.04, abs=2e-4)
    assert np.max(np.abs(ratio[ideal.torque > 0.36])) > 0.15
    # noise and ripple average out in a line fit over the working range
    slope, _ = line_fit(cw.torque[work], cw.speed[work])
    s_true, _ = line_fit(ideal.torque[work], motor_ramp_line(TRUTH.motor, 13.0, 1 / 6, ideal.torque[work])[0])
    assert slope == pytest.approx(s_true, rel=0.003)
    assert np.std(cw.voltage - 13.0) == pytest.approx(MOTOR_STAND.noise_voltage, rel=0.1)


def test_drive_overload_friction_only_above_6_nm():
    unit = draw_units(TRUTH, 1)
    stand = replace(DRIVE_STAND.clean(), overload_friction=DRIVE_STAND.overload_friction)
    cw = drive_curves(unit, TRUTH.ratio, stand)[0]
    model, _ = drive_ramp_line(TRUTH.motor, TRUTH.ratio, TRUTH.eta, TRUTH.m_gc, 13.0, 6.5, cw.torque[cw.torque < 10])
    gap = cw.speed[cw.torque < 10] - model
    below = cw.torque[cw.torque < 10] <= 6.0
    assert np.max(np.abs(gap[below])) < 1e-12
    assert np.all(gap[~below][1:] < 0)  # more friction: slower than the model above the working range


def test_damper_curves_follow_eq_4_28():
    units = draw_units(TRUTH, 2, NO_SPREAD)
    curves = damper_curves(units, TRUTH, noise_torque=0.0, noise_angle=0.0)
    assert [c.direction for c in curves] == [1, -1, 1, -1]
    c = curves[0]
    np.testing.assert_allclose(c.torque, np.interp(c.angle, TRUTH.damper_angles, TRUTH.damper_stiffness) * c.angle)
    assert c.angle[-1] == pytest.approx(np.radians(10.0))


def test_write_group_files_read_back(tmp_path):
    paths = write_group(tmp_path, TRUTH, count=2, seed=5)
    assert {k: len(v) for k, v in paths.items()} == {"motor": 4, "drive": 4, "damper": 4}
    assert paths["motor"][1].name == "motor_u1_ccw.csv"
    units = draw_units(TRUTH, 2, seed=5)
    made = motor_curves(units, seed=5)[1]
    read = read_characteristic(paths["motor"][1])
    assert read.direction == -1 and read.label == "motor_u1_ccw"
    assert read.source.startswith("synthetic motor test-stand data (wrsim.synthetic, seed 5): unit u1, ccw")
    np.testing.assert_allclose(read.speed, made.speed, atol=1e-3)  # written to 1e-3 rpm
    np.testing.assert_allclose(read.current, made.current, atol=1e-5)
    np.testing.assert_allclose(read.torque, made.torque, atol=1e-6)
    text = paths["motor"][1].read_text().splitlines()
    assert text[2] == "time[s],torque[N*m],speed[rpm],current[A],voltage[V],direction[1]"
    assert text[3].endswith(",-1.0") and float(text[3].split(",")[2]) < 0  # signed values
    damper = read_torque_angle(paths["damper"][0])
    np.testing.assert_allclose(damper.torque, damper_curves(units, TRUTH, seed=5)[0].torque, atol=1e-6)
