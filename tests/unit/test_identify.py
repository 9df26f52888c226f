"""Identification of motor and drive parameters (thesis 4.1.1.4, 4.1.4.2) and the closed-form lines."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from wrsim import paths
from wrsim.closed_form.motor import MotorParams, drive_line_summary, drive_ramp_line, motor_ramp_line
from wrsim.data.curves import (
    DamperCurve,
    RawCurve,
    read_characteristic,
    read_torque_angle,
    write_characteristic,
)
from wrsim.data.measurements import read_table, write_table
from wrsim.data.params import load_params
from wrsim.data.temperature import temperature_rules
from wrsim.errors import WrsimError
from wrsim.identify.calculator import (
    gear_efficiency_from_slopes,
    housing_friction_from_gap,
    identify_default_set,
    least_squares_motor,
    line_fit,
    motor_from_line,
    parameter_calculator,
    write_default_set,
)
from wrsim.identify.fit import (
    fit_curve,
    group_lines,
    identify_damper,
    identify_drive,
    identify_motor,
    validate,
)
from wrsim.identify.operating import identify_operating_points
from wrsim.identify.paramset import temperature_set, write_identified_set
from wrsim.identify.report import write_report
from wrsim.identify.synthetic import (
    DRIVE_STAND,
    MOTOR_STAND,
    Spread,
    Truth,
    damper_curves,
    draw_units,
    drive_curves,
    motor_curves,
)

ROOT = paths.ROOT
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
    np.testing.assert_allclose(p.ra * i + p.laa * didt + p.ke * w, U, rtol=1e-13)  # Eq. 4.1a
    np.testing.assert_allclose(p.kt * i, p.mc + p.visc * w + p.j * dwdt + m, rtol=1e-13)  # Eq. 4.1b
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
    assert details["speed_slope"] == pytest.approx(-1528.31, rel=1e-5)  # rad/s per N*m
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
    assert speed_err < 0.02 and current_err < 0.041  # the thesis's own bounds: 1.8 %, 4.03 %
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
    assert np.max(np.abs(w / fit_w - 1)) < 0.003  # measured 0.23 %; thesis 0.24 %
    assert np.max(np.abs(i / fit_i - 1)) < 0.037  # measured 1.65 %; thesis 3.63 %


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


# ------------------------------------------------------------------------------------------------
# raw files, group pipeline, temperature sets (issue 6)

FPG2 = load_params(ROOT / "params" / "fpg2_12nm.txt")
SYN = Truth.from_params(FPG2)
NO_SPREAD = Spread(**{name: 0.0 for name in Spread.__dataclass_fields__})
RAW_UNITS = {"time": "s", "torque": "N*m", "speed": "rpm", "current": "A", "voltage": "V", "direction": "1"}


def _raw(tmp_path, name="m.csv", units=RAW_UNITS, comments=("source: unit test",), **change):
    """A small valid raw motor file (a straight line), with columns replaced or removed (value None)."""
    m = np.linspace(0.0, 0.4, 41)
    cols = {
        "time": m * 6,
        "torque": m,
        "speed": 6000 - 15000 * m,
        "current": 1 + 60 * m,
        "voltage": np.full(41, 13.0),
        "direction": np.ones(41),
    }
    cols.update(change)
    cols = {k: v for k, v in cols.items() if v is not None}
    path = tmp_path / name
    write_table(path, cols, {k: units[k] for k in cols}, list(comments))
    return path


def _fig4_15_curve() -> RawCurve:
    t = read_table(MEAS / "fig4_15_motor.csv", increasing="torque", require_source=True)
    m = t.column("torque", "N*m")
    return RawCurve(
        "fig4_15_mean",
        1,
        m / RATE,
        m,
        t.column("mean_speed", "rad/s"),
        t.column("mean_current", "A"),
        np.full(m.size, U),
        t.source,
    )


def test_read_characteristic_magnitudes_and_units(tmp_path):
    m = np.linspace(0.0, 0.4, 41)
    curve = read_characteristic(
        _raw(
            tmp_path,
            torque=-m,
            speed=-(6000 - 15000 * m),
            current=-(1 + 60 * m),
            voltage=np.full(41, -13.0),
            direction=-np.ones(41),
        )
    )
    assert curve.direction == -1 and curve.label == "m" and curve.source == "unit test"
    assert curve.speed[0] == pytest.approx(6000 * np.pi / 30) and curve.torque[-1] == pytest.approx(0.4)
    assert np.all(curve.voltage == 13.0) and curve.current[-1] == pytest.approx(25.0)


@pytest.mark.parametrize(
    "change, message",
    [
        (
            {"voltage": None},
            r"m.csv: a raw characteristic measurement \(docs/measurement-format.md\) needs the columns "
            r"time, torque, speed, current, voltage, direction; missing: voltage",
        ),
        ({"time": np.r_[0.0, 0.1, 0.1, np.arange(3, 41) * 0.1]}, r"m.csv:5: column 'time': 0.1 does not increase"),
        (
            {"direction": np.r_[np.ones(20), -np.ones(21)]},
            r"column 'direction': data row 21 is -1; a file holds one direction",
        ),
        ({"direction": np.full(41, 0.5)}, r"column 'direction': data row 1 is 0.5"),
        (
            {"speed": -(6000 - 15000 * np.linspace(0, 0.4, 41))},
            r"column 'speed' is mostly of the opposite sign to direction \+1",
        ),
        (
            {"torque": np.r_[np.linspace(0, 0.4, 21), np.linspace(0.38, 0.0, 20)]},
            r"column 'torque' must rise over the measurement \(one ramp per file.*\): "
            r"data rows 25-28 average 0.29 N\*m, not more than rows 21-24 \(0.37 N\*m\)",
        ),
    ],
)
def test_read_characteristic_errors(tmp_path, change, message):
    with pytest.raises(WrsimError, match=message):
        read_characteristic(_raw(tmp_path, **change))


def test_read_characteristic_unit_and_source_errors(tmp_path):
    with pytest.raises(WrsimError, match=r"column 'speed': cannot convert 'A'"):
        read_characteristic(_raw(tmp_path, units={**RAW_UNITS, "speed": "A"}))
    with pytest.raises(WrsimError, match=r"m.csv:1: missing '# source: "):
        read_characteristic(_raw(tmp_path, comments=()))


def test_ramp_check_tolerates_ripple(tmp_path):
    m = np.linspace(0.0, 0.4, 41) + 0.02 * np.sin(np.arange(41) * 2.5)  # single samples fall
    assert np.any(np.diff(m) < 0)
    assert read_characteristic(_raw(tmp_path, torque=m)).torque.size == 41


def test_characteristic_and_torque_angle_round_trip(tmp_path):
    curve = motor_curves(draw_units(SYN, 1), seed=1)[1]
    write_characteristic(tmp_path / "c.csv", curve, ["extra comment"])
    back = read_characteristic(tmp_path / "c.csv")
    assert back.direction == -1 and back.source == curve.source
    np.testing.assert_allclose(back.time, curve.time, atol=1e-9)
    np.testing.assert_allclose(back.voltage, curve.voltage, atol=1e-4)
    damper = DamperCurve("d", -1, np.radians([0.0, 1.0, 2.0]), np.array([0.0, 1.1, 2.0]), "unit test")
    from wrsim.data.curves import write_torque_angle

    write_torque_angle(tmp_path / "d.csv", damper, [])
    assert (tmp_path / "d.csv").read_text().splitlines()[1:3] == [
        "angle[deg],torque[N*m],direction[1]",
        "-0.0,-0.0,-1.0",
    ]
    back = read_torque_angle(tmp_path / "d.csv")
    np.testing.assert_allclose(back.angle, damper.angle, atol=1e-7)
    with pytest.raises(WrsimError, match="torque-angle measurement .* missing: angle"):
        read_torque_angle(_raw(tmp_path))


def test_fit_curve_and_group_lines():
    m = np.linspace(0.0, 1.0, 101)
    curves = [
        RawCurve(f"c{k}", 1, m / 2, m, 100 - (20 + k) * m, 1 + (3 + k) * m, np.full(101, 12.0 + k)) for k in range(3)
    ]
    fits = [fit_curve(c, 0.2, 0.6) for c in curves]
    f = fits[1]
    assert (f.samples, f.speed_slope, f.current_slope) == (41, pytest.approx(-21), pytest.approx(4))
    assert (f.torque_rate, f.voltage, f.stall) == (pytest.approx(2.0), 13.0, pytest.approx(100 / 21))
    g = group_lines(fits, 0.2, 0.6, points=5)
    assert (g.lo, g.hi) == (0.2, 0.6)
    np.testing.assert_allclose(g.speed["min"], 100 - 22 * g.torque)
    np.testing.assert_allclose(g.speed["max"], 100 - 20 * g.torque)
    np.testing.assert_allclose(g.speed["middle"], g.speed["mean"])
    np.testing.assert_allclose(g.current["max"], 1 + 5 * g.torque)
    with pytest.raises(WrsimError, match=r"c0: only 0 samples within the working range 2-3 N\*m"):
        fit_curve(curves[0], 2.0, 3.0)
    flat = RawCurve("flat", 1, m, m, 100 + 0 * m, m, m)
    with pytest.raises(WrsimError, match="flat: the speed does not fall with the torque"):
        fit_curve(flat, 0.2, 0.6)


def test_validate_channel_and_table():
    m = np.linspace(0.0, 1.0, 101)
    fits = [fit_curve(RawCurve(f"c{k}", 1, m, m, 100 - (20 + k) * m, 1 + m, np.ones(101)), 0.1, 0.9) for k in range(3)]
    g = group_lines(fits, 0.2, 0.8)
    inside = validate(g, "middle", "sim", m, 100 - 21 * m, 1 + m, points=4)
    np.testing.assert_allclose(inside.torque, [0.2, 0.4, 0.6, 0.8])
    assert inside.max_speed_error == pytest.approx(0.0, abs=1e-12) and inside.speed_outside == 0.0
    outside = validate(g, "middle", "sim", m, 100 - 23 * m, 1.01 * (1 + m))
    assert outside.speed_outside == pytest.approx(0.8 / (100 - 21 * 0.8) * 100)  # 1 unit per N*m beyond min
    assert outside.current_outside == pytest.approx(1.0)
    assert outside.max_current_error == pytest.approx(1.0)
    with pytest.raises(WrsimError, match=r"sim: covers 0-0.5 N\*m, not the working range 0.2-0.8 N\*m"):
        validate(g, "middle", "sim", m[:51], m[:51], m[:51])
    with pytest.raises(WrsimError, match="group line must be min, max, mean or middle"):
        validate(g, "median", "sim", m, m, m)


def test_group_pipeline_round_trip_of_fig4_15_mean_line(identified):
    ident = identify_motor([_fig4_15_curve()])
    p, details = identified
    for name in ("ke", "kt", "ra", "visc"):
        assert getattr(ident.params, name) == pytest.approx(getattr(p, name), rel=1e-12), name
    assert ident.stall == pytest.approx(details["stall_torque"], rel=1e-12)
    assert (ident.group.lo, ident.group.hi) == (pytest.approx(0.0402166, rel=1e-5), pytest.approx(0.321733, rel=1e-5))
    assert ident.voltage == U and ident.torque_rate == pytest.approx(RATE, rel=1e-12)
    assert ident.least_squares_details["case"] == "kt=ke"


def test_identify_motor_clean_synthetic_data_is_exact():
    units = draw_units(SYN, 5, NO_SPREAD)
    ident = identify_motor(motor_curves(units, MOTOR_STAND.clean()))
    for name in ("ke", "kt", "ra", "visc"):
        assert getattr(ident.params, name) == pytest.approx(getattr(SYN.motor, name), rel=1e-9), name
    for f in ident.group.fits:  # each curve cut to 10-80 % of its own stall torque
        assert (f.lo / f.stall, f.hi / f.stall) == (pytest.approx(0.1, rel=1e-3), pytest.approx(0.8, rel=1e-3))
    with pytest.raises(WrsimError, match="method must be 'calculator' or 'least-squares'"):
        identify_motor(motor_curves(units), method="guess")
    with pytest.raises(WrsimError, match="identify motor: no measurement files"):
        identify_motor([])


@pytest.fixture(scope="module")
def seeds_identified():
    """Identification of ten synthetic groups (seeds 0-9): 5 units x 2 directions, spread, ripple, noise."""
    out = []
    for seed in range(10):
        units = draw_units(SYN, 5, seed=seed)
        mot = identify_motor(motor_curves(units, seed=seed))
        drv = identify_drive(drive_curves(units, SYN.ratio, seed=seed), mot.params, SYN.ratio)
        dmp = identify_damper(damper_curves(units, SYN, seed=seed))
        out.append((mot, drv, dmp))
    return out


def test_identification_recovers_synthetic_groups_within_2_percent(seeds_identified):
    worst = {}
    for mot, drv, dmp in seeds_identified:
        errors = {name: getattr(mot.params, name) / getattr(SYN.motor, name) - 1 for name in ("ke", "kt", "ra")}
        errors |= {
            f"lsq {name}": getattr(mot.least_squares, name) / getattr(SYN.motor, name) - 1 for name in ("ke", "ra")
        }
        errors["eta"] = drv.eta / SYN.eta - 1
        table = np.interp(SYN.damper_angles, dmp.angles, dmp.stiffness)
        errors["damper"] = np.max(np.abs(table / SYN.damper_stiffness - 1))
        for k, v in errors.items():
            worst[k] = max(worst.get(k, 0.0), abs(v))
    assert all(v < 0.02 for v in worst.values()), worst
    # measured over seeds 0-9: ke 1.23 %, kt 0.96 %, ra 1.53 %, eta 1.53 %; the middle of the boundaries of five
    # units is not their centre, which is what limits the recovery (without spread it is better than 0.2 %)
    assert worst["ra"] == pytest.approx(0.0153, abs=5e-4) and worst["eta"] == pytest.approx(0.0153, abs=5e-4)


def test_housing_friction_is_sensitive_to_the_motor_set(seeds_identified):
    m_gc = np.array([drv.m_gc / SYN.m_gc - 1 for _, drv, _ in seeds_identified])
    # the gap is a fraction of a rpm at the gear: m_gc inherits the motor set's error many times over
    assert m_gc.min() == pytest.approx(-0.107, abs=0.01) and m_gc.max() == pytest.approx(0.385, abs=0.01)
    for _, drv, _ in seeds_identified:  # yet the identified drive line is the mean drive line
        w, _ = drv.model_line(drv.group.torque)
        assert np.max(np.abs(w / drv.group.speed["mean"] - 1)) < 1e-3


def test_identify_drive_clean_is_exact_and_checks_inputs():
    units = draw_units(SYN, 3, NO_SPREAD)
    curves = drive_curves(units, SYN.ratio, DRIVE_STAND.clean())
    drv = identify_drive(curves, SYN.motor, SYN.ratio)
    assert drv.eta == pytest.approx(SYN.eta, rel=1e-9) and drv.m_gc == pytest.approx(SYN.m_gc, rel=1e-7)
    assert (drv.group.lo, drv.group.hi, drv.reference) == (1.0, 6.0, "mean")
    with pytest.raises(WrsimError, match=r"efficiency from the slopes is 2\.\d+, outside \(0, 1\]"):
        identify_drive(curves, SYN.motor, 30.0)
    with pytest.raises(WrsimError, match="drive line lies above the motor model's"):
        identify_drive(curves, replace(SYN.motor, ke=SYN.motor.ke * 1.05), SYN.ratio)


def test_drive_from_fig4_44_fit_line(identified):
    t = read_table(MEAS / "fig4_44_drive.csv", increasing="torque", require_source=True)
    m = t.column("torque", "N*m")
    curve = RawCurve(
        "fig4_44",
        1,
        m / DRIVE_RATE,
        m,
        t.column("fit_speed", "rad/s"),
        t.column("fit_current", "A"),
        np.full(m.size, U),
    )
    drv = identify_drive([curve], identified[0], RATIO, working_range=(1.0, 5.0169))
    assert drv.eta == pytest.approx(0.45585, abs=5e-5)  # = findings['eta_our_slopes'], not the printed 0.4516
    assert drv.m_gc == pytest.approx(0.3460, abs=1e-4)  # with that eta; the thesis's own set: 0.4097
    v = validate(drv.group, "mean", "model", drv.group.torque, *drv.model_line(drv.group.torque), points=5)
    assert v.max_speed_error < 1e-9 and v.max_current_error == pytest.approx(3.20, abs=0.01)  # thesis: 3.63 %


def test_identify_damper():
    units = draw_units(SYN, 2, NO_SPREAD)
    clean = identify_damper(damper_curves(units, SYN, noise_torque=0.0, noise_angle=0.0))
    np.testing.assert_allclose(clean.angles, SYN.damper_angles, rtol=1e-12)
    np.testing.assert_allclose(clean.stiffness, SYN.damper_stiffness, rtol=1e-9)
    assert clean.rms < 1e-12
    short = damper_curves(units, SYN, max_angle=np.radians(1.5), noise_torque=0.0, noise_angle=0.0)
    with pytest.raises(WrsimError, match="the curves reach only 1.5 deg; the table needs at least one step of 2 deg"):
        identify_damper(short)


def test_identified_set_with_base_keeps_the_other_sections(tmp_path):
    ident = identify_motor([_fig4_15_curve()])
    out = tmp_path / "m.txt"
    write_identified_set(out, ident, ROOT / "params" / "fpg2_12nm.txt")
    pset = load_params(out)
    assert list(pset.sections) == ["dcpm_motor", "worm_gear", "drive", "rubber_damper"]
    assert pset.value_in("worm_gear", "eta", "1") == 0.45162397
    text = out.read_text()
    assert "eta = 0.45162397 1  # fpg2_12nm.txt: 4.1.4.2: published efficiency" in text
    assert "#   Generated by wrsim.identify.write_default_set from params/measurements/; do not edit." in text
    assert "ke = 0.0204369637 V*s/rad" in text and "middle line of 1 curve, 10-80 % of stall" in text


def test_report_files(tmp_path):
    ident = identify_motor(motor_curves(draw_units(SYN, 2, seed=1), seed=1))
    v = validate(ident.group, "middle", "model", ident.group.torque, *ident.model_line(ident.group.torque))
    index = write_report(tmp_path / "rep", ident, [v])
    assert sorted(p.name for p in (tmp_path / "rep").iterdir()) == ["channel.png", "curves.png", "index.html"]
    page = index.read_text()
    assert "<h3>model vs middle line</h3>" in page and "inside the channel" in page
    assert page.count("<tr>") == 1 + 7 + 1 + 7 + 1 + 4  # parameters, validation table, curves
    assert (tmp_path / "rep" / "channel.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    write_report(tmp_path / "rep", identify_damper(damper_curves(draw_units(SYN, 1), SYN)))  # replaces it whole
    assert sorted(p.name for p in (tmp_path / "rep").iterdir()) == ["index.html", "stiffness.png"]
    assert [p.name for p in tmp_path.iterdir() if not p.name.startswith(".")] == ["rep"]


@pytest.mark.parametrize(
    "celsius, flux, resistance, grease, seal, damper, bowden",
    [
        (-40.0, 1.2, 6.0 / 7.0, 2.0, 2.0, 2.0, 0.20),  # bowden held at its -30 degC measurement below it
        (-30.0, 7.0 / 6.0, 1.0 - 1.0 / 7.0 * 5.0 / 6.0, 2.0 ** (5.0 / 6.0), 1.0 + 5.0 / 6.0, 1.0 + 5.0 / 6.0, 0.20),
        (20.0, 1.0, 1.0, 1.0, 1.0, 1.0, None),
        (80.0, 0.8, 8.0 / 7.0, 0.5, 1.0 - 0.2 * 60.0 / 65.0, 1.0 - 0.1 * 60.0 / 65.0, None),
        (85.0, 1.0 - 0.2 * 65.0 / 60.0, 1.0 + 1.0 / 7.0 * 65.0 / 60.0, 2.0 ** (-65.0 / 60.0), 0.8, 0.9, None),
    ],
)
def test_temperature_rules_are_their_closed_forms(celsius, flux, resistance, grease, seal, damper, bowden):
    # drive: no-load speed x1.25 and maximal torque x0.70 at 80 degC on an ideal motor (5.3.1), linear in T;
    # grease doubles the housing friction every 60 K colder; seals x2 at -40, x0.8 at 85 degC; damper x2 / x0.9
    rules, mu, mu20 = temperature_rules(load_params(paths.PARAMS / "rail_wr_8p5nm.txt"), celsius, "test")
    factor = {k: f for k, (f, _) in rules.items()}
    assert factor[("dcpm_motor", "ke")] == factor[("dcpm_motor", "kt")] == pytest.approx(flux, rel=1e-12)
    assert factor[("dcpm_motor", "ra")] == pytest.approx(resistance, rel=1e-12)
    assert factor[("drive", "m_gc")] == pytest.approx(grease, rel=1e-12)
    assert factor[("seal_friction", "forces")] == factor[("top_frame_seal", "frictions")] == pytest.approx(seal)
    assert factor[("rubber_damper", "stiffness")] == pytest.approx(damper, rel=1e-12)
    assert mu20 == 0.08 and (mu == pytest.approx(bowden) if bowden is not None else mu is None)


def test_temperature_sets_are_generated_and_meet_5_3_1_at_80_degc(tmp_path):
    for base, temperatures in (("fpg2_12nm", (80.0, -30.0)), ("rail_wr_8p5nm", (85.0, 80.0, -30.0, -40.0))):
        for celsius in temperatures:
            name = f"{base}_{'m' if celsius < 0 else ''}{abs(celsius):.0f}c"
            out = tmp_path / f"{name}.txt"
            temperature_set(ROOT / "params" / f"{base}.txt", celsius, out)
            assert out.read_text() == (ROOT / "params" / f"{name}.txt").read_text(), name
    hot = temperature_set(ROOT / "params" / "rail_wr_8p5nm.txt", 80.0, tmp_path / "h.txt")["change"]
    cold = temperature_set(ROOT / "params" / "rail_wr_8p5nm.txt", -40.0, tmp_path / "c.txt")["change"]
    # thesis 5.3.1 at 80 degC: steeper, no-load speed +20 .. 30 %, maximal torque about -30 % (the system's drive
    # with its friction and the grease rule: +25.2 %, -29.4 %); at -40 degC a flat line
    assert hot["slope_rpm"] > 0.5 and 0.20 <= hot["no_load_rpm"] <= 0.30
    assert hot["no_load_rpm"] == pytest.approx(0.252, abs=0.001) and hot["stall"] == pytest.approx(-0.294, abs=0.001)
    assert cold["slope_rpm"] < -0.3 and cold["stall"] == pytest.approx(0.382, abs=0.001)
    hot_set = load_params(ROOT / "params" / "rail_wr_8p5nm_80c.txt")
    assert hot_set.value_in("seal_friction", "forces", "N") == pytest.approx([15.0 * 0.8154, 65.0 * 0.8154], rel=1e-3)
    assert hot_set.value_in("bowden", "mu", "1") == 0.08  # Fig. 4.50: unchanged over 20 .. 80 degC
    mid = tmp_path / "m5.txt"
    temperature_set(ROOT / "params" / "fpg2_12nm.txt", -5.0, mid)
    assert load_params(mid).value_in("bowden", "mu", "1") == pytest.approx(0.08 + 0.12 * 25 / 50)
    with pytest.raises(WrsimError, match="-41 degC is outside -40 .. 85 degC"):
        temperature_set(ROOT / "params" / "fpg2_12nm.txt", -41.0, tmp_path / "x.txt")


def test_drive_line_summary_is_the_closed_form():
    s = drive_line_summary(SYN.motor, SYN.ratio, SYN.eta, SYN.m_gc, U)
    w, _ = drive_ramp_line(SYN.motor, SYN.ratio, SYN.eta, SYN.m_gc, U, 0.0, [0.0, s["stall"] * 0.999])
    assert w[0] * 30 / np.pi == pytest.approx(s["no_load_rpm"], rel=1e-12)
    assert w[1] == pytest.approx(0.0, abs=1e-3 * w[0])
    assert (s["no_load_rpm"], s["stall"]) == (pytest.approx(77.99, abs=0.01), pytest.approx(12.86, abs=0.01))


def test_least_squares_method_and_its_limits():
    physical = Truth(
        replace(SYN.motor, kt=SYN.motor.ke, visc=1.5e-5, mc=0.004),
        SYN.ratio,
        SYN.eta,
        SYN.m_gc,
        SYN.damper_angles,
        SYN.damper_stiffness,
    )
    curves = motor_curves(draw_units(physical, 2, NO_SPREAD), MOTOR_STAND.clean())
    ident = identify_motor(curves, method="least-squares")
    assert ident.method == "least-squares" and ident.least_squares_details["case"] == "kt=ke"
    for name in ("ke", "kt", "ra", "visc", "mc"):
        assert getattr(ident.params, name) == pytest.approx(getattr(physical.motor, name), rel=1e-6), name
    # the thesis's set has kt = 0.83 ke (Coulomb friction folded in by the calculator): with kt = ke imposed at one
    # voltage the least-squares fit needs a negative visc, which the model rejects
    with pytest.raises(
        WrsimError,
        match=r"identify motor \(least-squares\): visc = -\d.*the motor model needs both "
        r">= 0 \(kt = ke imposed",
    ):
        identify_motor(motor_curves(draw_units(SYN, 2, NO_SPREAD), MOTOR_STAND.clean()), method="least-squares")


def test_group_needs_one_supply_voltage():
    units = draw_units(SYN, 1)
    curves = motor_curves(units, MOTOR_STAND.clean()) + motor_curves(units, replace(MOTOR_STAND.clean(), voltage=12.0))
    with pytest.raises(
        WrsimError,
        match=r"identify motor: the curves were measured at different supply voltages "
        r"\(12 .. 13 V\); identify one voltage at a time",
    ):
        identify_motor(curves)


# ------------------------------------------------------------------------------------------------
# the drive of a built system from its operating points (thesis 5.3.1, identify.operating)
FIG_5_8 = paths.MEASUREMENTS / "fig5_7_5_8_stroke.csv"
FAMILY = paths.PARAMS / "fpg2_12nm.txt"


def _points(tmp_path, drive: MotorParams, eta: float, m_gc: float, torques=(1.0, 2.0, 3.0)):
    """Operating points of a known drive (closed form of Eq. 4.30/4.31 at 13 V) as a measurement file."""
    m = np.array(torques)
    w, i = drive_ramp_line(drive, 73.0, eta, m_gc, 13.0, 0.0, m)
    path = tmp_path / "points.csv"
    cols = {"drum_torque": m, "drive_speed": w * 60.0 / (2.0 * np.pi), "drive_current": i}
    write_table(path, cols, {"drum_torque": "N*m", "drive_speed": "rpm", "drive_current": "A"}, ["source: test"])
    return path


def test_operating_points_recover_a_drive_inside_the_bounds(tmp_path):
    # a drive with kt = ke and a self-locking gear: the fit returns its parameters and no bound is active
    m_gc = load_params(FAMILY).number_in("drive", "m_gc", "N*m")
    truth = MotorParams(ke=0.021, kt=0.021, ra=0.7, laa=9e-5, j=9.85e-6, visc=1.2e-5, mc=0.0)
    ident = identify_operating_points(_points(tmp_path, truth, 0.46, m_gc), FAMILY, 13.0)
    assert ident.at_bound == ()
    assert (ident.motor.ke, ident.motor.ra, ident.motor.visc, ident.eta) == pytest.approx(
        (truth.ke, truth.ra, truth.visc, 0.46), rel=1e-6
    )
    dw, di = ident.residuals()
    assert np.max(np.abs(dw)) < 1e-6 and np.max(np.abs(di)) < 1e-6
    # the lines through the points imply kt*eta/ke = eta for kt = ke (up to the viscous term of the slope)
    assert ident.implied["kt_eta_over_ke"] == pytest.approx(0.46, rel=0.02)


def test_fig_5_8_drive_sits_on_the_self_locking_bound_and_is_the_published_set(tmp_path):
    ident = identify_operating_points(FIG_5_8, FAMILY, 13.0)
    # the points need kt*eta/ke = 0.514: beyond a self-locking gear on a motor with kt <= ke
    assert ident.implied["kt_eta_over_ke"] == pytest.approx(0.5139, abs=1e-4)
    assert ident.at_bound == ("eta",) and ident.eta == pytest.approx(0.5)
    dw, di = ident.residuals()
    assert np.max(np.abs(dw)) < 0.3 and np.max(np.abs(di)) < 0.3  # [%]
    s = ident.summary()
    assert s["no_load_rpm"] == pytest.approx(82.99, abs=0.01) and s["stall"] == pytest.approx(10.418, abs=1e-3)
    # params/drive_8p5nm.txt is this identification, written by `wrsim identify operating-points`
    write_identified_set(tmp_path / "d.txt", ident)
    again, published = load_params(tmp_path / "d.txt"), load_params(paths.PARAMS / "drive_8p5nm.txt")
    assert again.sections.keys() == published.sections.keys()
    for entity, keys in published.sections.items():
        for key, p in keys.items():
            assert again.sections[entity][key].value == pytest.approx(p.value, rel=1e-9), (entity, key)


def test_operating_points_errors(tmp_path):
    one = tmp_path / "one.csv"
    one.write_text("# source: test\ndrum_torque[N*m],drive_speed[rpm],drive_current[A]\n1.4,72,2.5\n")
    with pytest.raises(WrsimError, match="needs two or more points with different drum torques"):
        identify_operating_points(one, FAMILY, 13.0)
    bad = tmp_path / "bad.csv"
    bad.write_text("# source: test\ndrum_torque[N*m],drive_speed[rpm],drive_current[A]\n1.4,72,2.5\n2.5,-63,4\n")
    with pytest.raises(WrsimError, match="speeds and currents > 0"):
        identify_operating_points(bad, FAMILY, 13.0)
