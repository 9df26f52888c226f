"""Parameter identification of the DCPM motor and the worm-gear drive (thesis 4.1.1.3-4.1.1.4, 4.1.4.2).

All quantities are SI inside: rad/s, N*m, A, V, s. The motor model is Eq. 4.1::

    U = ra*i + laa*di/dt + ke*w                    (4.1a)
    kt*i = mc + visc*w + j*dw/dt + M_load          (4.1b)   (mc acts against w > 0)

The characteristic-line measurements load the motor with a torque ramp M_load = r*t, so along a line
w and i are affine in the load torque and both derivatives are constant (Eq. 4.4c, 4.7c).

Group pipeline over raw test-stand files (docs/measurement-format.md; `wrsim identify motor|drive|damper`):
read -> cut to the working range (motor 10-80 % of the curve's stall torque, drive 1-6 N*m) -> linear fit
per curve (averages out the commutation ripple, Fig. 4.9) -> group lines min/max/mean/middle of the
boundaries (Fig. 4.11-4.13, 4.38-4.40) -> parameter calculator on the middle line (Eq. 4.2-4.8; least
squares as variant) / worm-gear eta from the slopes (Eq. 4.35b) and M_gc from the speed gap (Fig. 4.42) /
rubber-damper stiffness table (Eq. 4.28) -> parameter set and validation report (Fig. 4.15/4.44).
Temperature sets (-30 degC, 80 degC) are derived from the 20 degC set by physical scaling (temperature_set).
"""
from __future__ import annotations

import html
import math
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from matplotlib.figure import Figure
from scipy.optimize import brentq
from scipy.stats import linregress

from wrsim.errors import WrsimError
from wrsim.measurements import Table, read_table, write_table
from wrsim.params import ParamSet, load_params, save_params
from wrsim.report import publish_directory
from wrsim.units import convert

__all__ = [
    "MotorParams", "parameter_calculator", "line_fit", "motor_from_line", "least_squares_motor",
    "motor_ramp_line", "drive_ramp_line", "gear_efficiency_from_slopes",
    "housing_friction_from_gap", "identify_default_set", "write_default_set",
    "RawCurve", "DamperCurve", "read_characteristic", "write_characteristic", "read_torque_angle",
    "write_torque_angle", "CurveFit", "fit_curve", "GroupLines", "group_lines", "Validation", "validate",
    "MotorIdentification", "identify_motor", "DriveIdentification", "identify_drive",
    "DamperIdentification", "identify_damper", "write_identified_set",
    "write_report", "motor_from_set", "drive_line_summary", "temperature_set", "identify_files",
]

# Conditions of the thesis's FPG2 12Nm identification.
_U = 13.0                      # V, rated supply of both characteristic-line measurements
_LAA = 0.09e-3                 # H, Appendix A generic default (supplier-specification type, Tab. 4.4)
_J = 9.85e-6                   # kg*m**2, Appendix A generic default (supplier-specification type)
_MOTOR_RATE = 0.5 / 3.0        # N*m/s, servo ramp 0 -> 0.5 N*m in 3 s (4.1.1.4)
_FRACTIONS = (0.1, 0.5)        # points at 10 % and 50 % of stall torque, the standard (4.1.1.3)
_RATIO = 73.0                  # worm gear ratio of the FPG2 12Nm (4.1.4.2)
_ETA = 0.45162397              # published worm-gear efficiency (4.1.4.2)
_DRIVE_RATE = 13.0 / 2.0       # N*m/s at the gear: one measurement ~2 s up to stall ~13 N*m (4.1.4.2)
_PRINTED_S_A = -14639.24       # rpm/(N*m), motor slope printed in 4.1.4.2
_PRINTED_S_D = -6.00           # rpm/(N*m), drive slope printed in 4.1.4.2
_THESIS_M_GC = 0.4097          # N*m, the thesis's housing friction (Fig. 4.43)
_DAMPER_ANGLES_DEG = [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
_DAMPER_STIFFNESS = [57.3, 51.6, 48.7, 47.7, 51.6, 68.8]  # N*m/rad
_COND_LIMIT = 1e6              # max cond of the column-scaled [i, w, 1] for a free (kt, visc, mc) fit


@dataclass(frozen=True)
class MotorParams:
    """DCPM motor parameters (generics of entity dcpm_motor), SI units."""

    ke: float    # V*s/rad, back-EMF constant
    kt: float    # N*m/A, torque constant
    ra: float    # Ohm, effective resistance
    laa: float   # H, effective inductance
    j: float     # kg*m**2, rotor inertia
    visc: float  # N*m*s/rad, viscous friction
    mc: float    # N*m, Coulomb friction


def parameter_calculator(m1: float, w1: float, i1: float, m2: float, w2: float, i2: float,
                         u: float, laa: float, j: float, torque_rate: float) -> MotorParams:
    """The thesis's parameter calculator, Eq. 4.2-4.8, from two points (M_n, w_n, i_n) of one
    characteristic line measured under a torque ramp dM/dt = torque_rate.

    di/dt (Eq. 4.4c) and dw/dt (Eq. 4.7c) are the line slopes times dM/dt. Eq. 4.7b is Eq. 4.7a
    solved with M_coul = 0, so Eq. 4.8a returns 0 by construction: M_c is not identified by the
    calculator; Coulomb friction of the real motor ends up in visc and kt.
    """
    if i2 == i1 or m2 == m1:
        raise WrsimError(f"parameter calculator: the two points must differ in torque and current "
                         f"(M = {m1:g}, {m2:g} N*m; i = {i1:g}, {i2:g} A)")
    m1, w1, i1, m2, w2, i2 = (float(v) for v in (m1, w1, i1, m2, w2, i2))
    di, dw, dm = i2 - i1, w2 - w1, m2 - m1
    omega_idle = (w1 - w2) / di * i1 + w1                        # Eq. 4.3
    didt = di / dm * torque_rate                                 # Eq. 4.4c
    ke = (u - laa * didt) / omega_idle                           # Eq. 4.4b
    ra = ke * (w1 - w2) / di                                     # Eq. 4.5b
    dwdt = dw / dm * torque_rate                                 # Eq. 4.7c
    visc = (i1 * dm / di - j * dwdt - m1) / (w1 + (w1 - w2) / di * i1)  # Eq. 4.7b
    kt = (visc * dw + dm) / di                                   # Eq. 4.6b
    mc = 0.0  # Eq. 4.8a, i1*kt - m1 - j*dwdt - visc*w1, is identically 0 after Eq. 4.7b
    return MotorParams(ke=ke, kt=kt, ra=ra, laa=laa, j=j, visc=visc, mc=mc)


def line_fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares straight line y = slope*x + intercept; returns (slope, intercept)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.shape != y.shape or x.size < 2 or np.ptp(x) == 0:
        raise WrsimError(f"line fit needs at least two distinct x values and as many y values "
                         f"(got {x.size} x, {y.size} y)")
    fit = linregress(x, y)
    return float(fit.slope), float(fit.intercept)


def motor_from_line(torque: np.ndarray, speed: np.ndarray, current: np.ndarray, u: float,
                    laa: float, j: float, torque_rate: float,
                    fractions: tuple[float, float] = _FRACTIONS) -> tuple[MotorParams, dict]:
    """Identify the motor from one measured characteristic line (thesis procedure 4.1.1.4).

    Fits speed and current over torque with straight lines, takes the stall torque where the fitted
    speed is 0, evaluates both lines at `fractions` of it and runs parameter_calculator.
    """
    s_w, w0 = line_fit(torque, speed)
    s_i, i0 = line_fit(torque, current)
    if s_w >= 0:
        raise WrsimError(f"speed does not fall with torque (slope {s_w:g} rad/s/(N*m)); "
                         f"not a motor characteristic line")
    stall = -w0 / s_w
    m = np.array(fractions, dtype=float) * stall
    w, i = w0 + s_w * m, i0 + s_i * m
    params = parameter_calculator(m[0], w[0], i[0], m[1], w[1], i[1], u, laa, j, torque_rate)
    details = {
        "stall_torque": stall,
        "points": {"torque": m.tolist(), "speed": w.tolist(), "current": i.tolist()},
        "speed_slope": s_w, "speed_intercept": w0,
        "current_slope": s_i, "current_intercept": i0,
    }
    return params, details


def _per_voltage_rate(torque: np.ndarray, values: np.ndarray, groups: np.ndarray,
                      torque_rate: float) -> np.ndarray:
    """d(values)/dt per sample: the line slope over torque of its voltage group times dM/dt."""
    rate = np.empty_like(values)
    for g in np.unique(groups):
        sel = groups == g
        rate[sel] = line_fit(torque[sel], values[sel])[0] * torque_rate
    return rate


def _per_sample(value: float | np.ndarray, n: int, name: str) -> np.ndarray:
    try:
        return np.broadcast_to(np.asarray(value, dtype=float), (n,))
    except ValueError:
        raise WrsimError(f"least squares: {name} must be one number or one value per sample "
                         f"({n} samples), got shape {np.shape(value)}") from None


def _scaled_cond(x: np.ndarray) -> float:
    return float(np.linalg.cond(x / np.linalg.norm(x, axis=0)))


def least_squares_motor(torque: np.ndarray, speed: np.ndarray, current: np.ndarray,
                        u: float | np.ndarray, laa: float, j: float, torque_rate: float,
                        didt: float | np.ndarray | None = None,
                        dwdt: float | np.ndarray | None = None) -> tuple[MotorParams, dict]:
    """Least-squares identification over all given samples (pass only working-range samples).

    Electrical: U - laa*di/dt = ra*i + ke*w, fitted for (ra, ke).
    Mechanical: kt*i = mc + visc*w + j*dw/dt + M, fitted for (kt, visc, mc).

    Identifiability: along ONE characteristic line at constant U, w and i are affine in each other
    (Eq. 4.1a), so the regressors i, w, 1 are collinear and only two combinations of (kt, visc, mc)
    are determined (kt + visc*ra/ke and mc + visc*w at i = 0). With samples from two or more supply
    voltages (`u` an array, one value per sample) the lines are offset and (kt, visc, mc) are
    fitted freely. With one voltage, or when the column-scaled mechanical regressor is still
    ill-conditioned (cond >= 1e6), kt = ke is imposed (energy balance in SI units) and only
    (visc, mc) are fitted; details['constraint'] says so.

    didt/dwdt default to the slope over torque of each voltage's line times torque_rate.
    details: case ('free' or 'kt=ke'), constraint (None or its reason), voltages, cond_electrical,
    cond_mechanical, rms residuals (V, N*m), samples.
    """
    m = np.asarray(torque, dtype=float)
    w, i = np.asarray(speed, dtype=float), np.asarray(current, dtype=float)
    if not m.shape == w.shape == i.shape or m.ndim != 1:
        raise WrsimError(f"least squares: torque, speed and current must be 1-D of one length "
                         f"(got {m.shape}, {w.shape}, {i.shape})")
    uu = _per_sample(u, m.size, "u")
    voltages = np.unique(uu)
    groups = np.searchsorted(voltages, uu)
    didt_v = (_per_voltage_rate(m, i, groups, torque_rate) if didt is None
              else _per_sample(didt, m.size, "didt"))
    dwdt_v = (_per_voltage_rate(m, w, groups, torque_rate) if dwdt is None
              else _per_sample(dwdt, m.size, "dwdt"))

    x_el = np.column_stack([i, w])
    y_el = uu - laa * didt_v
    (ra, ke), *_ = np.linalg.lstsq(x_el, y_el, rcond=None)

    x_me = np.column_stack([i, -w, -np.ones_like(m)])
    y_me = j * dwdt_v + m
    cond_me = _scaled_cond(x_me)
    if voltages.size >= 2 and cond_me < _COND_LIMIT:
        (kt, visc, mc), *_ = np.linalg.lstsq(x_me, y_me, rcond=None)
        case, constraint = "free", None
    else:
        kt = ke
        (visc, mc), *_ = np.linalg.lstsq(x_me[:, 1:], y_me - kt * i, rcond=None)
        case = "kt=ke"
        reason = (f"only one supply voltage ({voltages[0]:g} V)" if voltages.size < 2 else
                  f"regressor [i, w, 1] ill-conditioned (cond {cond_me:.3g} >= {_COND_LIMIT:g})")
        constraint = (f"kt = ke imposed (SI energy balance): {reason}, so kt, visc and mc are not "
                      f"separately identifiable")
    params = MotorParams(ke=float(ke), kt=float(kt), ra=float(ra), laa=laa, j=j,
                         visc=float(visc), mc=float(mc))
    details = {
        "case": case,
        "constraint": constraint,
        "voltages": voltages.tolist(),
        "cond_electrical": _scaled_cond(x_el),
        "cond_mechanical": cond_me,
        "rms_electrical": float(np.sqrt(np.mean((x_el @ [ra, ke] - y_el) ** 2))),
        "rms_mechanical": float(np.sqrt(np.mean((kt * i - mc - visc * w - y_me) ** 2))),
        "samples": int(m.size),
    }
    return params, details


def _line_coefficients(p: MotorParams, u: float,
                       torque_rate: float) -> tuple[float, float, float, float]:
    """Affine particular solution of Eq. 4.1 under M_load = torque_rate*t, as functions of the load:
    w = w0 + s_w*M, i = i0 + s_i*M (so dw/dt = s_w*torque_rate, di/dt = s_i*torque_rate)."""
    # Terms in t: ra*s_i + ke*s_w = 0 and kt*s_i = visc*s_w + 1.
    s_w = -p.ra / (p.ra * p.visc + p.kt * p.ke)
    s_i = p.ke / (p.ra * p.visc + p.kt * p.ke)
    # Constant terms: ra*i0 + ke*w0 = u - laa*di/dt and kt*i0 - visc*w0 = mc + j*dw/dt.
    i0, w0 = np.linalg.solve([[p.ra, p.ke], [p.kt, -p.visc]],
                             [u - p.laa * s_i * torque_rate, p.mc + p.j * s_w * torque_rate])
    return float(w0), s_w, float(i0), s_i


def motor_ramp_line(p: MotorParams, u: float, torque_rate: float,
                    torque: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact quasi-steady (affine particular) solution of Eq. 4.1 for the load ramp
    M_load = torque_rate*t, evaluated at the given load torques (t = torque/torque_rate).

    Returns (omega [rad/s], current [A]). mc acts against positive w, so the line holds only
    below stall; a torque at or beyond stall raises WrsimError.
    """
    w0, s_w, i0, s_i = _line_coefficients(p, u, torque_rate)
    m = np.asarray(torque, dtype=float)
    omega, current = w0 + s_w * m, i0 + s_i * m
    if np.any(omega <= 0):
        raise WrsimError(f"motor line: load torque {np.max(m):g} N*m reaches stall "
                         f"({-w0 / s_w:g} N*m at {u:g} V); the ramp line needs w > 0")
    return omega, current


def drive_ramp_line(p: MotorParams, ratio: float, eta: float, m_gc: float, u: float,
                    torque_rate: float, gear_torque: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drive characteristic line (Eq. 4.30/4.31) under a gear-side load ramp dM_g/dt = torque_rate.

    The housing friction m_gc [N*m] acts at the GEAR shaft, so the motor sees the load
    (M_g + m_gc)/(ratio*eta) rising at torque_rate/(ratio*eta). Returns (gear omega [rad/s],
    current [A]) with gear omega = motor omega/ratio.
    """
    k = ratio * eta
    motor_load = (np.asarray(gear_torque, dtype=float) + m_gc) / k
    omega, current = motor_ramp_line(p, u, torque_rate / k, motor_load)
    return omega / ratio, current


def gear_efficiency_from_slopes(s_motor: float, s_drive: float, ratio: float) -> float:
    """Eq. 4.35b: eta = s_a/(s_d*i**2), slopes of speed over torque in the same units for both."""
    return s_motor / (s_drive * ratio**2)


def housing_friction_from_gap(p: MotorParams, ratio: float, eta: float, u: float,
                              torque_rate: float, gear_torque: np.ndarray,
                              fitted_gear_speed: np.ndarray) -> float:
    """Gear-side housing friction M_gc [N*m] that makes the mean of drive_ramp_line's gear speed
    minus `fitted_gear_speed` [rad/s] zero over `gear_torque`. Closed form: the gear speed is
    affine in M_gc with slope s_w/(ratio**2*eta)."""
    omega, _ = drive_ramp_line(p, ratio, eta, 0.0, u, torque_rate, gear_torque)
    gap = float(np.mean(omega - np.asarray(fitted_gear_speed, dtype=float)))
    s_w = _line_coefficients(p, u, torque_rate / (ratio * eta))[1]
    return float(-gap / (s_w / (ratio**2 * eta)))


def _max_rel_error_pct(model: np.ndarray, reference: np.ndarray) -> float:
    return float(np.max(np.abs(model / reference - 1.0)) * 100.0)


def identify_default_set(root: Path) -> dict:
    """Identify the FPG2 12Nm parameter set from the transcribed thesis data under `root`/params.

    Motor: calculator on the linear fit of the Fig. 4.15 mean line (13 V, ramp 0->0.5 N*m in 3 s,
    Appendix A laa and j, points at 10 %/50 % of stall). Worm gear: ratio 73 and the published
    eta = 0.45162397. Drive: gear-side M_gc from the speed gap to the Fig. 4.44 fit line (ramp
    0->13 N*m in 2 s). Returns a dict with keys motor, motor_details, worm_gear, drive,
    rubber_damper, validation (max errors in %) and findings (efficiency cross-checks).
    """
    mdir = Path(root) / "params" / "measurements"
    mot = read_table(mdir / "fig4_15_motor.csv", increasing="torque", require_source=True)
    torque = mot.column("torque", "N*m")
    speed, current = mot.column("mean_speed", "rad/s"), mot.column("mean_current", "A")
    motor, details = motor_from_line(torque, speed, current, _U, _LAA, _J, _MOTOR_RATE)
    omega, amps = motor_ramp_line(motor, _U, _MOTOR_RATE, torque)

    drv = read_table(mdir / "fig4_44_drive.csv", increasing="torque", require_source=True)
    gear_torque = drv.column("torque", "N*m")
    fit_speed, fit_current = drv.column("fit_speed", "rad/s"), drv.column("fit_current", "A")
    m_gc = housing_friction_from_gap(motor, _RATIO, _ETA, _U, _DRIVE_RATE, gear_torque, fit_speed)
    gear_omega, drive_amps = drive_ramp_line(motor, _RATIO, _ETA, m_gc, _U, _DRIVE_RATE,
                                             gear_torque)

    rad_s_to_rpm = convert(1.0, "rad/s", "rpm")
    s_a = details["speed_slope"] * rad_s_to_rpm
    s_d = line_fit(gear_torque, fit_speed)[0] * rad_s_to_rpm
    return {
        "motor": motor,
        "motor_details": details,
        "worm_gear": {"ratio": _RATIO, "eta": _ETA},
        "drive": {"m_gc": m_gc},
        "rubber_damper": {
            "angles": [convert(a, "deg", "rad") for a in _DAMPER_ANGLES_DEG],
            "stiffness": list(_DAMPER_STIFFNESS),
        },
        "validation": {
            "motor_speed_pct": _max_rel_error_pct(omega, speed),
            "motor_current_pct": _max_rel_error_pct(amps, current),
            "thesis_motor_speed_pct": _max_rel_error_pct(mot.column("sim_speed", "rad/s"), speed),
            "thesis_motor_current_pct": _max_rel_error_pct(mot.column("sim_current", "A"), current),
            "drive_speed_pct": _max_rel_error_pct(gear_omega, fit_speed),
            "drive_current_pct": _max_rel_error_pct(drive_amps, fit_current),
        },
        "findings": {
            "eta_printed_slopes": gear_efficiency_from_slopes(_PRINTED_S_A, _PRINTED_S_D, _RATIO),
            "s_d_for_printed_eta": _PRINTED_S_A / (_ETA * _RATIO**2),
            "s_a_thesis_sim_rpm": line_fit(torque, mot.column("sim_speed", "rpm"))[0],
            "s_a_mean_rpm": s_a,
            "s_d_fit_rpm": s_d,
            "eta_our_slopes": gear_efficiency_from_slopes(s_a, s_d, _RATIO),
        },
    }


def _sig(x: float) -> float:
    """Round to 10 significant digits so the committed file does not depend on the last float bit."""
    return float(f"{x:.10g}")


def write_default_set(root: Path, out_path: Path) -> dict:
    """Run identify_default_set and write the parameter set (params/fpg2_12nm.txt); returns the
    identification dict."""
    r = identify_default_set(root)
    p, d, v, f = r["motor"], r["motor_details"], r["validation"], r["findings"]
    m_gc = r["drive"]["m_gc"]
    calc = "parameter calculator on the Fig. 4.15 mean line"
    header = [
        "wrsim parameter set: Bosch FPG2 12Nm window-regulator drive (motor, worm gear, damper).",
        "Generated by wrsim.identify.write_default_set from params/measurements/; do not edit.",
        f"Conditions: {_U:g} V; motor ramp 0 -> 0.5 N*m in 3 s (4.1.1.4);",
        "  drive ramp 0 -> 13 N*m in 2 s at the gear (4.1.4.2).",
        "Motor: Eq. 4.2-4.8 on the linear fit of the Fig. 4.15 mean line, points at 10 % and",
        f"  50 % of the fitted stall torque {d['stall_torque']:.4f} N*m. Ramp line vs that mean line:",
        f"  max speed error {v['motor_speed_pct']:.2f} %, current {v['motor_current_pct']:.2f} % "
        f"(thesis's simulation: {v['thesis_motor_speed_pct']:.2f} %, "
        f"{v['thesis_motor_current_pct']:.2f} %).",
        "  mc = 0 by construction: Eq. 4.7b is Eq. 4.7a solved with M_coul = 0, so the",
        "  motor's Coulomb friction is folded into visc and kt.",
        f"Efficiency: Eq. 4.35b with the printed slopes s_a = {_PRINTED_S_A}, "
        f"s_d = {_PRINTED_S_D:.2f} rpm/(N*m)",
        f"  gives eta = {f['eta_printed_slopes']:.4f}, not the printed {_ETA}, which needs "
        f"s_d = {f['s_d_for_printed_eta']:.4f}.",
        f"  The printed s_a is the slope of the thesis's SIMULATED Fig. 4.15 speed "
        f"({f['s_a_thesis_sim_rpm']:.2f}),",
        f"  not of its mean line ({f['s_a_mean_rpm']:.2f}); mean line and Fig. 4.44 fit slope "
        f"({f['s_d_fit_rpm']:.4f})",
        f"  give eta = {f['eta_our_slopes']:.4f}. This set keeps the published eta.",
        "Housing friction m_gc acts at the gear shaft; it closes the mean speed gap to the",
        f"  Fig. 4.44 fit (1-5 N*m): {m_gc:.4f} N*m with this motor set (the thesis's "
        f"{_THESIS_M_GC} N*m",
        "  belongs to its own middle-line motor set). Drive line vs Fig. 4.44 fit:",
        f"  max speed error {v['drive_speed_pct']:.2f} %, current {v['drive_current_pct']:.2f} %.",
    ]
    rubber = ("estimated from the text of 4.1.4.1 (1 N*m ~ 1 deg, 5 N*m ~ 6 deg at room temperature); "
              "Fig. 4.32's data is not in the text")
    sections = {
        "dcpm_motor": [
            ("ke", _sig(p.ke), "V*s/rad", f"Eq. 4.4b, {calc}"),
            ("kt", _sig(p.kt), "N*m/A", f"Eq. 4.6b, {calc}"),
            ("ra", _sig(p.ra), "Ohm", f"Eq. 4.5b, {calc}"),
            ("laa", _LAA, "H", "Appendix A default (supplier specification, Tab. 4.4)"),
            ("j", _J, "kg*m**2", "Appendix A default (supplier specification, Tab. 4.4)"),
            ("visc", _sig(p.visc), "N*m*s/rad", f"Eq. 4.7b, {calc}"),
            ("mc", _sig(p.mc), "N*m", "Eq. 4.8a: 0 by construction of the calculator (see header)"),
        ],
        "worm_gear": [
            ("ratio", _RATIO, "1", "4.1.4.2: worm gear ratio of the FPG2 12Nm"),
            ("eta", _ETA, "1", "4.1.4.2: published efficiency (Eq. 4.35b; see header)"),
        ],
        "drive": [
            ("m_gc", _sig(m_gc), "N*m", "gear-side housing friction, speed gap to Fig. 4.44 fit"),
        ],
        "rubber_damper": [
            ("angles", r["rubber_damper"]["angles"], "rad", "0, 2, ..., 10 deg: grid of the estimate"),
            ("stiffness", r["rubber_damper"]["stiffness"], "N*m/rad", f"secant (Eq. 4.28), {rubber}"),
        ],
    }
    save_params(out_path, header, sections)
    return r


# ================================================================================================
# raw test-stand files (docs/measurement-format.md)

_CHARACTERISTIC = ("time", "torque", "speed", "current", "voltage", "direction")
_TORQUE_ANGLE = ("angle", "torque", "direction")
_MIN_SAMPLES = 5          # fewest samples a curve must have inside its working range
_RAMP_SEGMENTS = 10       # the ramp check compares the means of this many consecutive row segments
_MOTOR_FRACTIONS = (0.1, 0.8)   # motor working range, fractions of the stall torque (4.1.1.4)
_DRIVE_RANGE = (1.0, 6.0)       # N*m, drive working range at the gear (4.1.4.2)
_DAMPER_STEP = math.radians(2.0)  # rad, grid of the identified stiffness table
# Resolution the writers round to (far below any test stand's): decimals per written unit.
_DECIMALS = {"time": 6, "torque": 6, "speed": 3, "current": 5, "voltage": 4, "direction": 0, "angle": 5}


@dataclass(frozen=True, eq=False)
class RawCurve:
    """One raw characteristic-curve measurement: one unit, one direction (docs/measurement-format.md).

    Values are magnitudes in SI units (the file's signed values times its direction): time [s], torque
    [N*m] (armature torque for a motor, gear-wheel torque for a drive), speed [rad/s] of the same shaft,
    current [A], voltage [V]. `name` is the file path (or a label for data made in memory).
    """

    name: str
    direction: int
    time: np.ndarray
    torque: np.ndarray
    speed: np.ndarray
    current: np.ndarray
    voltage: np.ndarray
    source: str = ""

    @property
    def label(self) -> str:
        return Path(self.name).stem


@dataclass(frozen=True, eq=False)
class DamperCurve:
    """One torque-angle measurement of a rubber damper in one direction: magnitudes, angle [rad] and
    torque [N*m] (docs/measurement-format.md)."""

    name: str
    direction: int
    angle: np.ndarray
    torque: np.ndarray
    source: str = ""

    @property
    def label(self) -> str:
        return Path(self.name).stem


def _direction(table: Table) -> int:
    d = table.column("direction", "1")
    bad = np.flatnonzero((d != d[0]) | (np.abs(d) != 1.0))
    if bad.size:
        k = int(bad[0])
        raise WrsimError(f"{table.path}: column 'direction': data row {k + 1} is {d[k]:g}; a file holds one "
                         f"direction, +1 or -1 in every row")
    return int(d[0])


def _check_sign(table: Table, name: str, values: np.ndarray, direction: int) -> None:
    if np.median(values) <= 0:
        raise WrsimError(f"{table.path}: column '{name}' is mostly of the opposite sign to direction "
                         f"{direction:+d}; values are recorded signed and direction gives the sense of rotation")


def _check_ramp(table: Table, name: str, values: np.ndarray, unit: str) -> None:
    """The ramp column must rise over the file. Ripple and noise make single samples fall, so the means of
    consecutive row segments (about a tenth of the rows each) are compared; falling, repeated or reversed
    ramps fail."""
    edges = np.linspace(0, values.size, min(_RAMP_SEGMENTS, values.size) + 1).astype(int)
    means = [float(np.mean(values[a:b])) for a, b in zip(edges[:-1], edges[1:])]
    for k in range(1, len(means)):
        if means[k] <= means[k - 1]:
            raise WrsimError(
                f"{table.path}: column '{name}' must rise over the measurement (one ramp per file, counted in "
                f"the file's direction): data rows {edges[k] + 1}-{edges[k + 1]} average {means[k]:.6g} {unit}, "
                f"not more than rows {edges[k - 1] + 1}-{edges[k]} ({means[k - 1]:.6g} {unit})")


def read_characteristic(path: str | Path) -> RawCurve:
    """Read a raw characteristic-curve file of a motor or a drive (one unit, one direction)."""
    table = read_table(path, increasing="time", require_source=True, columns=_CHARACTERISTIC,
                       what="a raw characteristic measurement (docs/measurement-format.md)")
    d = _direction(table)
    torque, speed = d * table.column("torque", "N*m"), d * table.column("speed", "rad/s")
    current, voltage = d * table.column("current", "A"), d * table.column("voltage", "V")
    for name, values in (("speed", speed), ("current", current), ("voltage", voltage)):
        _check_sign(table, name, values, d)
    _check_ramp(table, "torque", torque, "N*m")
    return RawCurve(str(path), d, table.column("time", "s"), torque, speed, current, voltage, table.source)


def read_torque_angle(path: str | Path) -> DamperCurve:
    """Read a rubber-damper torque-angle file (one gear wheel, one direction)."""
    table = read_table(path, require_source=True, columns=_TORQUE_ANGLE,
                       what="a torque-angle measurement (docs/measurement-format.md)")
    d = _direction(table)
    angle, torque = d * table.column("angle", "rad"), d * table.column("torque", "N*m")
    for name, values in (("angle", angle), ("torque", torque)):
        _check_sign(table, name, values, d)
    _check_ramp(table, "angle", angle, "rad")
    return DamperCurve(str(path), d, angle, torque, table.source)


def _rounded(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {name: np.round(values, _DECIMALS[name]) for name, values in columns.items()}


def write_characteristic(path: str | Path, curve: RawCurve, comments: list[str]) -> None:
    """Write `curve` as a raw characteristic file (signed values, speed in rpm), `# source:` first."""
    d = float(curve.direction)
    columns = {"time": curve.time, "torque": d * curve.torque, "speed": d * convert(curve.speed, "rad/s", "rpm"),
               "current": d * curve.current, "voltage": d * curve.voltage,
               "direction": np.full(curve.time.size, d)}
    units = {"time": "s", "torque": "N*m", "speed": "rpm", "current": "A", "voltage": "V", "direction": "1"}
    write_table(path, _rounded(columns), units, [f"source: {curve.source}", *comments])


def write_torque_angle(path: str | Path, curve: DamperCurve, comments: list[str]) -> None:
    """Write `curve` as a torque-angle file (signed values, angle in deg), `# source:` first."""
    d = float(curve.direction)
    columns = {"angle": d * convert(curve.angle, "rad", "deg"), "torque": d * curve.torque,
               "direction": np.full(curve.angle.size, d)}
    write_table(path, _rounded(columns), {"angle": "deg", "torque": "N*m", "direction": "1"},
                [f"source: {curve.source}", *comments])


# ================================================================================================
# cutting, fitting, group lines

@dataclass(frozen=True)
class CurveFit:
    """Straight lines through one curve over its working range lo..hi [N*m]: speed [rad/s] and current [A]
    over torque, the torque ramp rate [N*m/s] and the mean supply voltage [V] there."""

    name: str
    direction: int
    lo: float
    hi: float
    samples: int
    speed_slope: float
    speed_intercept: float
    current_slope: float
    current_intercept: float
    torque_rate: float
    voltage: float

    @property
    def stall(self) -> float:
        """Torque [N*m] where the fitted speed is 0."""
        return -self.speed_intercept / self.speed_slope

    def speed(self, torque) -> np.ndarray:
        return self.speed_intercept + self.speed_slope * np.asarray(torque, dtype=float)

    def current(self, torque) -> np.ndarray:
        return self.current_intercept + self.current_slope * np.asarray(torque, dtype=float)


def fit_curve(curve: RawCurve, lo: float, hi: float) -> CurveFit:
    """Cut `curve` to lo <= torque <= hi [N*m] and fit speed, current and torque-over-time with lines."""
    sel = (curve.torque >= lo) & (curve.torque <= hi)
    n = int(sel.sum())
    if n < _MIN_SAMPLES:
        raise WrsimError(f"{curve.name}: only {n} samples within the working range {lo:.4g}-{hi:.4g} N*m "
                         f"(need {_MIN_SAMPLES}); the file covers {curve.torque.min():.4g}-"
                         f"{curve.torque.max():.4g} N*m")
    m = curve.torque[sel]
    s_w, w0 = line_fit(m, curve.speed[sel])
    if s_w >= 0:
        raise WrsimError(f"{curve.name}: the speed does not fall with the torque within {lo:.4g}-{hi:.4g} "
                         f"N*m (slope {s_w:.4g} rad/s per N*m); not a characteristic curve")
    s_i, i0 = line_fit(m, curve.current[sel])
    rate = line_fit(curve.time[sel], m)[0]
    return CurveFit(curve.name, curve.direction, lo, hi, n, s_w, w0, s_i, i0, rate,
                    float(np.mean(curve.voltage[sel])))


def _motor_fit(curve: RawCurve, fractions: tuple[float, float]) -> CurveFit:
    """Cut to fractions of the curve's own stall torque: start from a line through all samples, then refit
    over the range of the last stall estimate until the selected samples no longer change."""
    s_w, w0 = line_fit(curve.torque, curve.speed)
    if s_w >= 0:
        raise WrsimError(f"{curve.name}: the speed does not fall with the torque; not a characteristic curve")
    stall = -w0 / s_w
    for _ in range(50):
        fit = fit_curve(curve, fractions[0] * stall, fractions[1] * stall)
        if fit.stall == stall:
            break
        stall = fit.stall
    return fit


@dataclass(frozen=True, eq=False)
class GroupLines:
    """The fitted lines of a group of curves on a torque grid over the working range (Fig. 4.13/4.40):
    speed [rad/s] and current [A] as dicts with 'min', 'max' (boundaries), 'mean' and 'middle'
    (middle of the boundaries)."""

    fits: list[CurveFit]
    torque: np.ndarray
    speed: dict[str, np.ndarray]
    current: dict[str, np.ndarray]

    @property
    def lo(self) -> float:
        return float(self.torque[0])

    @property
    def hi(self) -> float:
        return float(self.torque[-1])


def _four(values: np.ndarray) -> dict[str, np.ndarray]:
    lo, hi = values.min(axis=0), values.max(axis=0)
    return {"min": lo, "max": hi, "mean": values.mean(axis=0), "middle": 0.5 * (lo + hi)}


def group_lines(fits: list[CurveFit], lo: float, hi: float, points: int = 61) -> GroupLines:
    """Min, max, mean and middle lines of `fits` on `points` torques from lo to hi [N*m]."""
    if not fits:
        raise WrsimError("group lines: no curves")
    m = np.linspace(lo, hi, points)
    return GroupLines(list(fits), m, _four(np.array([f.speed(m) for f in fits])),
                      _four(np.array([f.current(m) for f in fits])))


def _line_choice(line: str) -> str:
    if line not in ("min", "max", "mean", "middle"):
        raise WrsimError(f"group line must be min, max, mean or middle, not '{line}'")
    return line


# ================================================================================================
# validation: a simulated (or closed-form) line against the group

@dataclass(frozen=True, eq=False)
class Validation:
    """A simulated line against a group: the quantitative table (Fig. 4.15/4.44) at `torque` [N*m] and,
    over the whole working-range grid, the largest errors [%] against the reference line and the largest
    distance outside the measured channel (min..max of the fits) [% of the reference; 0 = inside]."""

    label: str
    reference: str
    torque: np.ndarray
    speed: np.ndarray
    ref_speed: np.ndarray
    current: np.ndarray
    ref_current: np.ndarray
    max_speed_error: float
    max_current_error: float
    speed_outside: float
    current_outside: float
    grid_speed: np.ndarray
    grid_current: np.ndarray

    @property
    def speed_error(self) -> np.ndarray:
        return np.abs(self.speed / self.ref_speed - 1.0) * 100.0

    @property
    def current_error(self) -> np.ndarray:
        return np.abs(self.current / self.ref_current - 1.0) * 100.0


def _outside_pct(values: np.ndarray, lines: dict[str, np.ndarray], reference: np.ndarray) -> float:
    """Largest distance of `values` outside min..max [% of the reference]; rounding-level gaps count as 0."""
    gap = np.maximum(lines["min"] - values, values - lines["max"]) / np.abs(reference)
    worst = float(np.max(gap))
    return worst * 100.0 if worst > 1e-9 else 0.0


def validate(group: GroupLines, reference: str, label: str, torque, speed, current,
             points: int = 7) -> Validation:
    """Compare a simulated line (speed [rad/s], current [A] over rising torque [N*m]) with the group's
    `reference` line; the table has `points` torques spread evenly over the working range."""
    reference = _line_choice(reference)
    torque = np.asarray(torque, dtype=float)
    if torque.min() > group.lo or torque.max() < group.hi:
        raise WrsimError(f"{label}: covers {torque.min():.4g}-{torque.max():.4g} N*m, not the working range "
                         f"{group.lo:.4g}-{group.hi:.4g} N*m")
    gw, gi = np.interp(group.torque, torque, speed), np.interp(group.torque, torque, current)
    ref_w, ref_i = group.speed[reference], group.current[reference]
    at = np.linspace(group.lo, group.hi, points)
    return Validation(
        label, reference, at, np.interp(at, torque, speed), np.interp(at, group.torque, ref_w),
        np.interp(at, torque, current), np.interp(at, group.torque, ref_i),
        float(np.max(np.abs(gw / ref_w - 1.0)) * 100.0), float(np.max(np.abs(gi / ref_i - 1.0)) * 100.0),
        _outside_pct(gw, group.speed, ref_w), _outside_pct(gi, group.current, ref_i), gw, gi)


# ================================================================================================
# identification of a group

@dataclass(frozen=True, eq=False)
class MotorIdentification:
    """Result of identify_motor. `params` is the chosen method's set; voltage [V] and torque_rate [N*m/s]
    are the group's mean test conditions; stall [N*m] is where the middle line's speed is 0."""

    params: MotorParams
    method: str
    calculator: MotorParams
    calculator_details: dict
    least_squares: MotorParams
    least_squares_details: dict
    group: GroupLines
    curves: list[RawCurve]
    voltage: float
    torque_rate: float
    stall: float
    fractions: tuple[float, float]

    kind = "motor"
    reference = "middle"

    def model_line(self, torque) -> tuple[np.ndarray, np.ndarray]:
        """Closed-form ramp line of the identified motor (speed [rad/s], current [A])."""
        return motor_ramp_line(self.params, self.voltage, self.torque_rate, torque)


def _check_curves(curves: list, what: str) -> None:
    if not curves:
        raise WrsimError(f"identify {what}: no measurement files")


def _conditions(fits: list[CurveFit], what: str) -> tuple[float, float]:
    """Mean supply voltage [V] and load ramp [N*m/s] of a group; the group lines need one supply voltage."""
    volts = [f.voltage for f in fits]
    if max(volts) > 1.02 * min(volts):
        raise WrsimError(f"identify {what}: the curves were measured at different supply voltages "
                         f"({min(volts):.4g} .. {max(volts):.4g} V); identify one voltage at a time")
    return float(np.mean(volts)), float(np.mean([f.torque_rate for f in fits]))


def identify_motor(curves: list[RawCurve], laa: float = _LAA, j: float = _J,
                   fractions: tuple[float, float] = _MOTOR_FRACTIONS,
                   method: str = "calculator") -> MotorIdentification:
    """Identify a group of motors (thesis 4.1.1.4 b): cut every curve to `fractions` of its stall torque,
    fit lines, form the group lines over `fractions` of the middle line's stall torque, and run the
    parameter calculator on the middle line (motor_from_line: points at 10 % and 50 % of its stall).
    The least-squares variant (least_squares_motor) runs on the cut raw samples of all curves;
    `method` ('calculator' or 'least-squares') chooses which set is `params`. laa [H], j [kg*m**2]:
    supplier values (Tab. 4.4)."""
    _check_curves(curves, "motor")
    if method not in ("calculator", "least-squares"):
        raise WrsimError(f"identify motor: method must be 'calculator' or 'least-squares', not '{method}'")
    fits = [_motor_fit(c, fractions) for c in curves]

    def middle_speed(m: float) -> float:
        w = [f.speed(m) for f in fits]
        return 0.5 * (min(w) + max(w))

    stall = brentq(middle_speed, 0.0, 2.0 * max(f.stall for f in fits))
    group = group_lines(fits, fractions[0] * stall, fractions[1] * stall)
    u, rate = _conditions(fits, "motor")
    calc, calc_details = motor_from_line(group.torque, group.speed["middle"], group.current["middle"],
                                         u, laa, j, rate)
    cut = [(c, (c.torque >= f.lo) & (c.torque <= f.hi)) for c, f in zip(curves, fits)]
    lsq, lsq_details = least_squares_motor(*(np.concatenate([getattr(c, name)[sel] for c, sel in cut])
                                             for name in ("torque", "speed", "current")), u, laa, j, rate)
    chosen = calc if method == "calculator" else lsq
    if chosen.visc < 0 or chosen.mc < 0:
        raise WrsimError(f"identify motor ({method}): visc = {chosen.visc:.4g} N*m*s/rad, mc = {chosen.mc:.4g} N*m; "
                         f"the motor model needs both >= 0"
                         + (f" ({lsq_details['constraint']})" if method == "least-squares" and lsq_details["constraint"]
                            else ""))
    return MotorIdentification(chosen, method, calc, calc_details, lsq, lsq_details, group, list(curves), u, rate,
                               float(stall), fractions)


@dataclass(frozen=True, eq=False)
class DriveIdentification:
    """Result of identify_drive: worm-gear efficiency eta (Eq. 4.35b) and gear-side housing friction m_gc
    [N*m] for the given motor and ratio; slopes of speed over torque in rad/s per N*m (s_a of the motor
    model at steady state, s_d of the group line)."""

    motor: MotorParams
    ratio: float
    eta: float
    m_gc: float
    group: GroupLines
    curves: list[RawCurve]
    voltage: float
    torque_rate: float
    reference: str
    motor_slope: float
    drive_slope: float

    kind = "drive"

    def model_line(self, torque) -> tuple[np.ndarray, np.ndarray]:
        """Closed-form ramp line of the identified drive (gear speed [rad/s], current [A])."""
        return drive_ramp_line(self.motor, self.ratio, self.eta, self.m_gc, self.voltage, self.torque_rate,
                               torque)


def identify_drive(curves: list[RawCurve], motor: MotorParams, ratio: float,
                   working_range: tuple[float, float] = _DRIVE_RANGE, line: str = "mean") -> DriveIdentification:
    """Identify worm gear and housing of a group of drives (thesis 4.1.4.2): cut every curve to the working
    range [N*m at the gear], fit lines, take the group's `line` (the thesis uses the mean), then
    eta = s_a/(s_d*i**2) with s_a the motor model's slope (Eq. 4.35b) and m_gc from the speed gap between
    the drive model and that line (Fig. 4.42/4.43)."""
    _check_curves(curves, "drive")
    line = _line_choice(line)
    if ratio <= 0:
        raise WrsimError(f"identify drive: gear ratio must be > 0, got {ratio:g}")
    fits = [fit_curve(c, *working_range) for c in curves]
    group = group_lines(fits, *working_range)
    u, rate = _conditions(fits, "drive")
    s_a = _line_coefficients(motor, u, 0.0)[1]
    s_d = line_fit(group.torque, group.speed[line])[0]
    eta = gear_efficiency_from_slopes(s_a, s_d, ratio)
    if not 0.0 < eta <= 1.0:
        raise WrsimError(f"identify drive: efficiency from the slopes is {eta:.4g}, outside (0, 1]: do motor "
                         f"set and drive files belong together, is the ratio {ratio:g} right?")
    m_gc = housing_friction_from_gap(motor, ratio, eta, u, rate, group.torque, group.speed[line])
    if m_gc < 0:
        raise WrsimError(f"identify drive: the drive line lies above the motor model's (housing friction "
                         f"{m_gc:.4g} N*m < 0): check the motor set, the ratio and the supply voltage")
    return DriveIdentification(motor, ratio, eta, m_gc, group, list(curves), u, rate, line, s_a, s_d)


@dataclass(frozen=True, eq=False)
class DamperIdentification:
    """Result of identify_damper: the secant stiffness table of Eq. 4.28, angles [rad] and stiffness
    [N*m/rad], and the rms torque residual [N*m] of the table model over the samples used."""

    angles: np.ndarray
    stiffness: np.ndarray
    curves: list[DamperCurve]
    rms: float

    kind = "damper"


def identify_damper(curves: list[DamperCurve], step: float = _DAMPER_STEP) -> DamperIdentification:
    """Stiffness table c(dphi) of the rubber damper (thesis 4.1.3) on the grid 0, step, ... [rad] up to the
    smallest largest angle of the curves (5 % of a step beyond it at most). The table is fitted by least
    squares to the torques with the model's own form, M = c(|dphi|)*dphi with c piecewise linear and constant
    beyond the ends (rubber_damper, table_lookup), over the samples of both directions of all curves."""
    _check_curves(curves, "damper")
    top = min(float(c.angle.max()) for c in curves)
    n = int(math.floor(top / step + 0.05))  # the last grid angle may lie 5 % of a step beyond the data
    if step <= 0 or n < 1:
        raise WrsimError(f"identify damper: the curves reach only {math.degrees(top):.3g} deg; the table needs at "
                         f"least one step of {math.degrees(step):.3g} deg")
    grid = step * np.arange(n + 1)
    top = max(top, grid[-1])
    phi = np.concatenate([c.angle[c.angle <= top] for c in curves])
    torque = np.concatenate([c.torque[c.angle <= top] for c in curves])
    hats = np.column_stack([np.interp(phi, grid, np.eye(n + 1)[k]) for k in range(n + 1)])
    design = phi[:, None] * hats
    if np.any(np.abs(design).sum(axis=0) == 0):
        raise WrsimError("identify damper: some table angles have no samples around them")
    stiffness, *_ = np.linalg.lstsq(design, torque, rcond=None)
    if np.any(stiffness <= 0):
        raise WrsimError(f"identify damper: the fitted stiffness is not positive everywhere "
                         f"({', '.join(f'{c:.3g}' for c in stiffness)} N*m/rad)")
    rms = float(np.sqrt(np.mean((design @ stiffness - torque) ** 2)))
    return DamperIdentification(grid, stiffness, list(curves), rms)


# ================================================================================================
# parameter sets

Section = list[tuple[str, float | list[float], str, str]]


def _curves(n: int) -> str:
    return f"{n} curve{'' if n == 1 else 's'}"


def _files(curves: list) -> str:
    names = [c.label for c in curves]
    return ", ".join(names) if len(names) <= 4 else f"{names[0]} .. {names[-1]} ({len(names)} files)"


def _sections(ident) -> tuple[list[str], dict[str, Section]]:
    """Header lines and parameter sections ([entity] -> (key, value, unit, source)) of an identification."""
    rpm = convert(1.0, "rad/s", "rpm")
    if isinstance(ident, MotorIdentification):
        p, d, lsq = ident.params, ident.calculator_details, ident.least_squares_details
        lo, hi = ident.fractions
        n = _curves(len(ident.curves))
        how = (f"parameter calculator on the middle line of {n}" if ident.method == "calculator"
               else f"least squares over the cut samples of {n} ({lsq['case']})")
        header = [
            f"Motor identified by `wrsim identify motor` from {_files(ident.curves)}.",
            f"Conditions (group means over the working ranges): {ident.voltage:.4g} V, "
            f"load ramp {ident.torque_rate:.4g} N*m/s.",
            f"Each curve cut to {lo:.0%}-{hi:.0%} of its own stall torque and fitted with lines; middle line of "
            f"the boundaries over {ident.group.lo:.4f}-{ident.group.hi:.4f} N*m (stall {ident.stall:.4f} N*m).",
            f"Parameter calculator (Eq. 4.2-4.8) at {d['points']['torque'][0]:.4f} and "
            f"{d['points']['torque'][1]:.4f} N*m of the middle line's fit: ke {ident.calculator.ke:.6g}, "
            f"kt {ident.calculator.kt:.6g}, ra {ident.calculator.ra:.6g}, visc {ident.calculator.visc:.4g}.",
            f"Least squares ({lsq['case']}): ke {ident.least_squares.ke:.6g}, kt {ident.least_squares.kt:.6g}, "
            f"ra {ident.least_squares.ra:.6g}, visc {ident.least_squares.visc:.4g}, mc {ident.least_squares.mc:.4g}"
            + (f"; {lsq['constraint']}." if lsq["constraint"] else "."),
            f"This set: {ident.method}.",
        ]
        src = f"{how}, 10-80 % of stall"
        mc_src = ("Eq. 4.8a: 0 by construction of the calculator (Coulomb friction folded into visc and kt)"
                  if ident.method == "calculator" else src)
        return header, {"dcpm_motor": [
            ("ke", _sig(p.ke), "V*s/rad", f"{'Eq. 4.4b, ' if ident.method == 'calculator' else ''}{src}"),
            ("kt", _sig(p.kt), "N*m/A", f"{'Eq. 4.6b, ' if ident.method == 'calculator' else ''}{src}"),
            ("ra", _sig(p.ra), "Ohm", f"{'Eq. 4.5b, ' if ident.method == 'calculator' else ''}{src}"),
            ("laa", p.laa, "H", "supplier value (Tab. 4.4), input of the identification"),
            ("j", p.j, "kg*m**2", "supplier value (Tab. 4.4), input of the identification"),
            ("visc", _sig(p.visc), "N*m*s/rad", f"{'Eq. 4.7b, ' if ident.method == 'calculator' else ''}{src}"),
            ("mc", _sig(p.mc), "N*m", mc_src),
        ]}
    if isinstance(ident, DriveIdentification):
        header = [
            f"Worm gear and housing identified by `wrsim identify drive` from {_files(ident.curves)}.",
            f"Conditions (group means over {ident.group.lo:g}-{ident.group.hi:g} N*m): {ident.voltage:.4g} V, "
            f"load ramp {ident.torque_rate:.4g} N*m/s at the gear.",
            f"Eq. 4.35b: s_a = {ident.motor_slope * rpm:.2f} rpm/(N*m) (motor set, steady state), "
            f"s_d = {ident.drive_slope * rpm:.4f} rpm/(N*m) ({ident.reference} line of the drive fits), "
            f"ratio {ident.ratio:g} -> eta = {ident.eta:.6f}.",
            f"m_gc closes the mean speed gap between the drive model and that line: {ident.m_gc:.4f} N*m.",
        ]
        return header, {
            "worm_gear": [("ratio", ident.ratio, "1", "gear ratio, input of the identification (design)"),
                          ("eta", _sig(ident.eta), "1", f"Eq. 4.35b, slopes of motor set and {ident.reference} "
                                                         f"drive line")],
            "drive": [("m_gc", _sig(ident.m_gc), "N*m", f"gear-side housing friction, speed gap to the "
                                                        f"{ident.reference} drive line")],
        }
    header = [
        f"Rubber damper identified by `wrsim identify damper` from {_files(ident.curves)}.",
        f"Stiffness table fitted by least squares to the torques with M = c(|dphi|)*dphi (Eq. 4.28, "
        f"piecewise linear c); rms residual {ident.rms:.4g} N*m.",
    ]
    return header, {"rubber_damper": [
        ("angles", [_sig(a) for a in ident.angles], "rad", f"table grid, {math.degrees(ident.angles[1]):g} deg steps"),
        ("stiffness", [_sig(c) for c in ident.stiffness], "N*m/rad", "secant stiffness (Eq. 4.28), least squares"),
    ]}


def _base_sections(base: Path) -> dict[str, Section]:
    """The sections of parameter set `base`, each line's source kept and prefixed by the file name."""
    pset = load_params(base)
    lines = Path(base).read_text(encoding="utf-8").splitlines()
    out: dict[str, Section] = {}
    for entity, keys in pset.sections.items():
        out[entity] = []
        for key, p in keys.items():
            comment = lines[p.line - 1].partition("#")[2].strip()
            out[entity].append((key, p.value, p.unit, f"{Path(base).name}: {comment}" if comment
                                else f"{Path(base).name}:{p.line}"))
    return out


def write_identified_set(out: str | Path, ident, base: str | Path | None = None) -> None:
    """Write the identified sections as a parameter set; with `base`, its other sections are carried over
    (identified sections replace the base's)."""
    header, sections = _sections(ident)
    merged = _base_sections(Path(base)) if base else {}
    merged.update(sections)
    lines = ["wrsim parameter set generated by wrsim.identify; do not edit.", *header]
    if base:
        text = Path(base).read_text(encoding="utf-8").splitlines()
        head = [line[1:].strip() for line in text[:next((k for k, t in enumerate(text) if not t.startswith("#")),
                                                          len(text))]]
        lines += [f"Other sections carried over from {base}, whose header reads:", *(f"  {h}" for h in head)]
    save_params(out, lines, merged)


def motor_from_set(pset: ParamSet) -> MotorParams:
    """The [dcpm_motor] section of a parameter set as MotorParams (SI units)."""
    units = {"ke": "V*s/rad", "kt": "N*m/A", "ra": "Ohm", "laa": "H", "j": "kg*m**2", "visc": "N*m*s/rad",
             "mc": "N*m"}
    return MotorParams(**{k: float(pset.value_in("dcpm_motor", k, u)) for k, u in units.items()})


# ================================================================================================
# validation report (HTML + PNGs)

def _working_range(ax, lo: float, hi: float) -> None:
    for x in (lo, hi):
        ax.axvline(x, color="0.4", linestyle=":", linewidth=1.2, label="working range" if x == lo else None)


def _curves_figure(ident, speed_name: str) -> Figure:
    """Raw curves and their fitted lines over the working range (Fig. 4.11/4.12, 4.38/4.39)."""
    rpm = convert(1.0, "rad/s", "rpm")
    fig = Figure(figsize=(9, 7))
    ax_w, ax_i = fig.subplots(2, 1, sharex=True)
    for k, (c, f) in enumerate(zip(ident.curves, ident.group.fits)):
        color = f"C{k % 10}"
        ax_w.plot(c.torque, c.speed * rpm, color=color, linewidth=0.5, alpha=0.35)
        ax_i.plot(c.torque, c.current, color=color, linewidth=0.5, alpha=0.35)
        m = np.array([f.lo, f.hi])
        ax_w.plot(m, f.speed(m) * rpm, color=color, linewidth=2, label=f"{c.label} fit")
        ax_i.plot(m, f.current(m), color=color, linewidth=2)
    for ax in (ax_w, ax_i):
        _working_range(ax, ident.group.lo, ident.group.hi)
        ax.grid(True, alpha=0.3)
    ax_w.set_ylabel(f"{speed_name} [rpm]")
    ax_i.set_ylabel("current [A]")
    ax_i.set_xlabel("torque [N*m]")
    ax_w.set_title(f"{ident.kind}: raw curves (thin) and linear fits over each curve's working range")
    ax_w.legend(loc="best", fontsize="small", ncol=2)
    return fig


def _channel_figure(ident, validations: list[Validation], speed_name: str) -> Figure:
    """Boundaries, mean and middle line of the fits with the simulated lines (Fig. 4.13/4.14, 4.40/4.45)."""
    rpm = convert(1.0, "rad/s", "rpm")
    g = ident.group
    fig = Figure(figsize=(9, 7))
    axes = fig.subplots(2, 1, sharex=True)
    for ax, lines, scale, grid_of in ((axes[0], g.speed, rpm, "grid_speed"), (axes[1], g.current, 1.0, "grid_current")):
        ax.fill_between(g.torque, lines["min"] * scale, lines["max"] * scale, color="0.85", label="channel (min..max)")
        ax.plot(g.torque, lines["min"] * scale, "k--", linewidth=1, label="min / max")
        ax.plot(g.torque, lines["max"] * scale, "k--", linewidth=1)
        ax.plot(g.torque, lines["mean"] * scale, color="C0", label="mean")
        ax.plot(g.torque, lines["middle"] * scale, color="C2", label="middle of boundaries")
        for k, v in enumerate(validations):
            ax.plot(g.torque, getattr(v, grid_of) * scale, color=f"C{3 + k}", linewidth=2.2, alpha=0.8,
                    label=v.label)
        _working_range(ax, g.lo, g.hi)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel(f"{speed_name} [rpm]")
    axes[1].set_ylabel("current [A]")
    axes[1].set_xlabel("torque [N*m]")
    axes[0].set_title(f"{ident.kind}: simulated lines in the channel of the measured fits")
    axes[0].legend(loc="best", fontsize="small")
    return fig


def _damper_figure(ident: DamperIdentification) -> Figure:
    """Secant stiffness of the samples and the identified table (Fig. 4.32), in deg and N*m/deg."""
    per_deg = math.radians(1.0)
    fig = Figure(figsize=(8, 5), layout="constrained")
    ax = fig.add_subplot()
    for k, c in enumerate(ident.curves):
        keep = c.angle > ident.angles[1] / 4
        ax.plot(np.degrees(c.angle[keep]), c.torque[keep] / c.angle[keep] * per_deg, ".", markersize=2,
                color=f"C{k % 10}", alpha=0.4, label=f"{c.label} M/angle")
    ax.plot(np.degrees(ident.angles), ident.stiffness * per_deg, "ko-", linewidth=2, label="identified table")
    ax.set_xlabel("angle change [deg]")
    ax.set_ylabel("stiffness [N*m/deg]")
    ax.set_title("rubber damper: secant stiffness of the samples and the identified table")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="x-small", ncol=2)
    return fig


def _table(header: list[str], rows: list[list[str]]) -> str:
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _validation_html(v: Validation) -> str:
    rpm = convert(1.0, "rad/s", "rpm")
    rows = [[f"{m:.5g}", f"{w * rpm:.5g}", f"{rw * rpm:.5g}", f"{ew:.3f}", f"{i:.5g}", f"{ri:.5g}", f"{ei:.3f}"]
            for m, w, rw, ew, i, ri, ei in zip(v.torque, v.speed, v.ref_speed, v.speed_error, v.current,
                                               v.ref_current, v.current_error)]
    inside = ("inside the channel" if v.speed_outside == 0 and v.current_outside == 0 else
              f"OUTSIDE the channel by up to {v.speed_outside:.3g} % (speed), {v.current_outside:.3g} % (current)")
    return (f"<h3>{html.escape(v.label)} vs {v.reference} line</h3>"
            + _table(["torque [N*m]", "sim speed [rpm]", f"{v.reference} speed [rpm]", "difference [%]",
                      "sim current [A]", f"{v.reference} current [A]", "difference [%]"], rows)
            + f"<p>Over the working range: max speed difference {v.max_speed_error:.3f} %, max current "
              f"difference {v.max_current_error:.3f} %; {inside}.</p>")


def _fits_html(ident) -> str:
    rpm = convert(1.0, "rad/s", "rpm")
    rows = [[Path(f.name).stem, f"{f.direction:+d}", str(f.samples), f"{f.lo:.4g}-{f.hi:.4g}", f"{f.stall:.4g}",
             f"{f.speed_intercept * rpm:.5g}", f"{f.speed_slope * rpm:.5g}", f"{f.current_intercept:.4g}",
             f"{f.current_slope:.4g}", f"{f.torque_rate:.4g}", f"{f.voltage:.4g}"] for f in ident.group.fits]
    return _table(["curve", "dir", "samples", "cut [N*m]", "stall [N*m]", "speed at 0 [rpm]",
                   "speed slope [rpm/(N*m)]", "current at 0 [A]", "current slope [A/(N*m)]",
                   "ramp [N*m/s]", "voltage [V]"], rows)


def write_report(directory: str | Path, ident, validations: list[Validation] | None = None) -> Path:
    """Write the validation report of an identification into `directory` (index.html and PNGs), replacing
    the directory as a whole. `validations` are the simulated lines to judge (motor, drive)."""
    directory = Path(directory)
    header, sections = _sections(ident)
    rows = [[f"[{entity}] {key}", repr(value) if not isinstance(value, list) else ", ".join(f"{x:.6g}" for x in value),
             unit, comment] for entity, entries in sections.items() for key, value, unit, comment in entries]
    parts = [f"<h1>wrsim identification: {ident.kind}</h1>",
             "".join(f"<p>{html.escape(line)}</p>" for line in header),
             "<h2>Parameters</h2>", _table(["parameter", "value", "unit", "source"], rows)]
    figures: dict[str, Figure] = {}
    if isinstance(ident, DamperIdentification):
        figures["stiffness.png"] = _damper_figure(ident)
        grid = [[f"{math.degrees(a):.4g}", f"{a:.6g}", f"{c:.5g}", f"{c * math.radians(1.0):.5g}"]
                for a, c in zip(ident.angles, ident.stiffness)]
        parts += ["<h2>Stiffness table</h2>",
                  _table(["angle [deg]", "angle [rad]", "stiffness [N*m/rad]", "stiffness [N*m/deg]"], grid)]
    else:
        speed_name = "armature speed" if ident.kind == "motor" else "gear speed"
        figures["curves.png"] = _curves_figure(ident, speed_name)
        figures["channel.png"] = _channel_figure(ident, validations or [], speed_name)
        parts += ["<h2>Validation (working range marked in the plots)</h2>",
                  *(_validation_html(v) for v in validations or [])]
        parts += ["<h2>Curves</h2>", _fits_html(ident)]
    parts += [f'<p><img src="{name}" alt="{name}"></p>' for name in figures]
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>wrsim identification</title>"
            "<style>body{font-family:sans-serif} table{border-collapse:collapse}"
            "td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}</style></head><body>\n"
            + "\n".join(parts) + "\n</body></html>\n")
    with publish_directory(directory.parent, directory.name) as tmp:
        for name, fig in figures.items():
            fig.savefig(tmp / name, format="png", dpi=100)
        (tmp / "index.html").write_text(page, encoding="utf-8")
    return directory / "index.html"


# ================================================================================================
# temperature parameter sets (thesis 4.1.1.4, 4.1.3, 5.3.1, chapter 6)

_T_REF = 20.0                 # degC, temperature of the identified set (room temperature, 4.1.1.4)
_ALPHA_CU = 3.93e-3           # 1/K, resistance of annealed copper at 20 degC (IEC 60028)
_ALPHA_BR = -2.0e-3           # 1/K, remanence of hard ferrite magnets (typically -0.18 .. -0.20 %/K)
# Assumed rubber-damper stiffness factors: Fig. 4.33 shows the damper "quite stiff" at -40 degC and "softer,
# but not much" at 80 degC; its data is not in the text.
_DAMPER_FACTORS = ((-30.0, 2.0), (20.0, 1.0), (80.0, 0.9))
# Bowden friction coefficient (thesis 4.2.1.2, Fig. 4.50, thesis numbers): 0.20 at -30 degC, 0.08 from 20 to
# 80 degC; between -30 and 20 degC linear (assumption).
_BOWDEN_MU = ((-30.0, 0.20), (20.0, 0.08))


def drive_line_summary(motor: MotorParams, ratio: float, eta: float, m_gc: float, u: float) -> dict:
    """Steady-state drive characteristic (Eq. 4.30/4.31, closed form) at supply u [V]: no-load gear speed
    [rpm], stall torque at the gear [N*m] and slope [rpm/(N*m)]; the same for the bare motor."""
    w0, s_w, _, _ = _line_coefficients(motor, u, 0.0)
    k = ratio * eta
    rpm = convert(1.0, "rad/s", "rpm")
    return {"no_load_rpm": (w0 + s_w * m_gc / k) / ratio * rpm, "stall": -w0 / s_w * k - m_gc,
            "slope_rpm": s_w / (ratio * k) * rpm, "motor_no_load_rpm": w0 * rpm, "motor_stall": -w0 / s_w}


def _damper_factor(celsius: float) -> float:
    ts, fs = zip(*_DAMPER_FACTORS)
    return float(np.interp(celsius, ts, fs))


def temperature_set(base: str | Path, celsius: float, out: str | Path, u: float = _U) -> dict:
    """Derive the parameter set at `celsius` from the 20 degC set `base` and write it to `out`.

    Physical assumptions (not thesis numbers): ra*(1 + alpha_Cu*dT) (copper winding), ke and kt*(1 +
    alpha_Br*dT) (ferrite magnet flux), rubber-damper stiffness times an assumed factor (2.0 at -30 degC,
    0.9 at 80 degC, linear in between). Thesis numbers: below 20 degC [bowden] mu rises to 0.20 at -30 degC
    (Fig. 4.50; from the base's value or 0.08 at 20 degC, linear in between). Every other value unchanged.
    The header compares the resulting
    drive characteristic at `u` with the thesis's statements (5.3.1). Returns the summaries at 20 degC
    and at `celsius` and the relative changes."""
    if not _DAMPER_FACTORS[0][0] <= celsius <= _DAMPER_FACTORS[-1][0]:
        raise WrsimError(f"temperature set: {celsius:g} degC is outside {_DAMPER_FACTORS[0][0]:g} .. "
                         f"{_DAMPER_FACTORS[-1][0]:g} degC, the range the scaling is documented for")
    base = Path(base)
    pset = load_params(base)
    sections = _base_sections(base)
    dt = celsius - _T_REF
    f_r, f_k, f_c = 1.0 + _ALPHA_CU * dt, 1.0 + _ALPHA_BR * dt, _damper_factor(celsius)
    rules = {("dcpm_motor", "ra"): (f_r, f"copper: x(1 + {_ALPHA_CU:g}/K*({dt:+g} K)) = x{f_r:.4f}"),
             ("dcpm_motor", "ke"): (f_k, f"ferrite flux: x(1 {_ALPHA_BR:+g}/K*({dt:+g} K)) = x{f_k:.4f}"),
             ("dcpm_motor", "kt"): (f_k, f"ferrite flux: x(1 {_ALPHA_BR:+g}/K*({dt:+g} K)) = x{f_k:.4f}"),
             ("rubber_damper", "stiffness"): (f_c, f"assumed x{f_c:g} (Fig. 4.33 qualitative, no data)")}
    for entity, entries in sections.items():
        for n, (key, value, unit, comment) in enumerate(entries):
            factor, why = rules.get((entity, key), (None, None))
            if factor is None:
                entries[n] = (key, value, unit, f"unchanged from 20 degC ({comment})")
            else:
                scaled = [_sig(v * factor) for v in value] if isinstance(value, list) else _sig(value * factor)
                entries[n] = (key, scaled, unit, f"{why}; 20 degC: {comment}")
    if celsius < _T_REF:
        known = "mu" in pset.sections.get("bowden", {})
        mu20 = pset.value_in("bowden", "mu", "1") if known else _BOWDEN_MU[1][1]
        mu = float(np.interp(celsius, [_BOWDEN_MU[0][0], _T_REF], [_BOWDEN_MU[0][1], mu20]))
        bowden = [e for e in sections.get("bowden", []) if e[0] != "mu"]
        sections["bowden"] = bowden + [("mu", _sig(mu), "1", "thesis 4.2.1.2, Fig. 4.50: 0.20 at -30 degC, "
                                        f"{mu20:g} at 20 degC{'' if celsius == _BOWDEN_MU[0][0] else ', linear'}")]
    motor20 = motor_from_set(pset)
    motor = replace(motor20, ke=motor20.ke * f_k, kt=motor20.kt * f_k, ra=motor20.ra * f_r)
    gear = (pset.value_in("worm_gear", "ratio", "1"), pset.value_in("worm_gear", "eta", "1"),
            pset.value_in("drive", "m_gc", "N*m"))
    s20, st = drive_line_summary(motor20, *gear, u), drive_line_summary(motor, *gear, u)
    change = {k: st[k] / s20[k] - 1.0 for k in s20}
    thesis = {80.0: "thesis 5.3.1 at 80 degC: steeper, no-load speed +20..30 %, max torque about -30 %",
              -30.0: "thesis 5.3.1 at -40 degC: flat curve (Fig. 5.5, no numbers)"}
    header = [
        f"wrsim parameter set: Bosch FPG2 12Nm drive at {celsius:g} degC, derived from {base.name} "
        f"({_T_REF:g} degC)",
        f"by wrsim.identify.temperature_set (`wrsim identify temperature --celsius {celsius:g}`); do not edit.",
        "Scaling = physical assumptions, not thesis numbers (chapter 6: resistance and ke/kt vary with",
        "temperature; the thesis gives no coefficients):",
        f"  ra x(1 + alpha_Cu*dT), alpha_Cu = {_ALPHA_CU:g} 1/K (copper winding; brush share of ra neglected)",
        f"  ke, kt x(1 + alpha_Br*dT), alpha_Br = {_ALPHA_BR:g} 1/K (ferrite magnet remanence)",
        f"  rubber damper stiffness x{f_c:g}: assumed; Fig. 4.33 shows it much stiffer at -40 degC and a",
        "  little softer at 80 degC, its data is not in the text",
        "  unchanged: laa, j, visc, mc, eta, m_gc, ratio (no thesis data; grease friction would rise in the",
        "  cold and fall in the heat, which this set does not model)",
        f"Check at {u:g} V, steady state (closed form of Eq. 4.30/4.31), against {_T_REF:g} degC:",
        f"  drive no-load speed {s20['no_load_rpm']:.2f} -> {st['no_load_rpm']:.2f} rpm "
        f"({change['no_load_rpm']:+.1%}), stall torque {s20['stall']:.2f} -> {st['stall']:.2f} N*m "
        f"({change['stall']:+.1%}),",
        f"  slope {s20['slope_rpm']:.3f} -> {st['slope_rpm']:.3f} rpm/(N*m) "
        f"(x{st['slope_rpm'] / s20['slope_rpm']:.2f}, "
        f"{'steeper' if change['slope_rpm'] > 0 else 'flatter'}).",
        f"  {thesis.get(celsius, 'thesis: no statement for this temperature')}.",
    ]
    if celsius == 80.0:
        def no_load_rise(f: float) -> float:
            m = replace(motor, ke=motor20.ke * f, kt=motor20.kt * f)
            return drive_line_summary(m, *gear, u)["no_load_rpm"] / s20["no_load_rpm"] - 1.0

        need = [brentq(lambda f: no_load_rise(f) - rise, 0.5, 1.0) for rise in (0.2, 0.3)]
        stall = drive_line_summary(replace(motor, ke=motor20.ke * need[0], kt=motor20.kt * need[0]), *gear, u)["stall"]
        header += [f"  Not reached: +20 .. +30 % no-load speed would need ke, kt x{need[0]:.3f} .. "
                   f"x{need[1]:.3f}, i.e. alpha_Br = {(need[0] - 1) / dt:.2%} .. {(need[1] - 1) / dt:.2%}/K,",
                   f"  beyond ferrite magnets, and the stall torque would then fall by {1 - stall / s20['stall']:.0%} "
                   f"already at +20 %; or far less friction."]
    if celsius < _T_REF:
        header += [f"[bowden] mu = {mu:.3g}: thesis number (4.2.1.2, Fig. 4.50: 0.08 at 20 .. 80 degC, 0.20 at "
                   f"-30 degC); it sets",
                   "  every bowden instance whose generic map does not set mu (the entity also models fixed pulleys).",
                   "Not in this set: seal friction rises greatly as the rubber hardens (5.3.1, no number)."]
    save_params(out, header, sections)
    return {"at_20": s20, "at_t": st, "change": change}


# ================================================================================================
# command line (`wrsim identify motor|drive|damper|temperature`)

def identify_files(what: str, files: list[Path], out: Path | None, base: Path | None = None,
                   report: Path | None = None, ratio: float | None = None, method: str = "calculator",
                   celsius: float | None = None) -> list[str]:
    """Run one identification from files, write the parameter set `out` (and the report directory) and
    return the lines to print."""
    if out is None:
        raise WrsimError(f"identify {what}: give --out FILE for the parameter set")
    if what == "temperature":
        if base is None or celsius is None or files:
            raise WrsimError("identify temperature: give --base PARAMS --celsius T (and no files)")
        r = temperature_set(base, celsius, out)
        c = r["change"]
        return [f"drive at {celsius:g} degC vs 20 degC: no-load speed {c['no_load_rpm']:+.1%}, stall torque "
                f"{c['stall']:+.1%}, slope {c['slope_rpm']:+.1%}", f"wrote {out}"]
    if not files:
        raise WrsimError(f"identify {what}: give one or more measurement files")
    pset = load_params(base) if base else None
    rpm = convert(1.0, "rad/s", "rpm")
    if what == "motor":
        known = pset.sections.get("dcpm_motor", {}) if pset else {}
        laa = pset.value_in("dcpm_motor", "laa", "H") if "laa" in known else _LAA
        j = pset.value_in("dcpm_motor", "j", "kg*m**2") if "j" in known else _J
        ident = identify_motor([read_characteristic(f) for f in files], laa, j, method=method)
        p = ident.params
        lines = [f"motor ({ident.method}): ke={p.ke:.6g} V*s/rad kt={p.kt:.6g} N*m/A ra={p.ra:.6g} Ohm "
                 f"visc={p.visc:.6g} N*m*s/rad mc={p.mc:.3g} N*m"]
    elif what == "drive":
        if pset is None or "dcpm_motor" not in pset.sections:
            raise WrsimError("identify drive: needs the motor set: give --base PARAMS with a [dcpm_motor] section "
                             "(e.g. the output of `wrsim identify motor`)")
        if ratio is None:
            if "ratio" not in pset.sections.get("worm_gear", {}):
                raise WrsimError(f"identify drive: give --ratio (no [worm_gear] ratio in {base})")
            ratio = pset.value_in("worm_gear", "ratio", "1")
        ident = identify_drive([read_characteristic(f) for f in files], motor_from_set(pset), ratio)
        lines = [f"drive: ratio={ident.ratio:g} eta={ident.eta:.6g} m_gc={ident.m_gc:.6g} N*m "
                 f"(s_a={ident.motor_slope * rpm:.2f}, s_d={ident.drive_slope * rpm:.4f} rpm/(N*m))"]
    elif what == "damper":
        ident = identify_damper([read_torque_angle(f) for f in files])
        lines = ["damper: stiffness " + ", ".join(f"{c:.4g}" for c in ident.stiffness) + " N*m/rad at "
                 + ", ".join(f"{math.degrees(a):g}" for a in ident.angles) + f" deg (rms {ident.rms:.3g} N*m)"]
    else:
        raise WrsimError(f"identify: unknown kind '{what}' (motor, drive, damper, temperature, default)")
    write_identified_set(out, ident, base)
    lines.append(f"wrote {out}")
    if report:
        validations = []
        if not isinstance(ident, DamperIdentification):
            g = ident.group
            validations.append(validate(g, ident.reference, "model (closed form)", g.torque,
                                        *ident.model_line(g.torque), points=7 if what == "motor" else 6))
            v = validations[0]
            lines.insert(-1, f"model vs {v.reference} line: max speed difference {v.max_speed_error:.3f} %, current "
                             f"{v.max_current_error:.3f} %; outside the channel: speed {v.speed_outside:.3g} %, "
                             f"current {v.current_outside:.3g} %")
        lines.append(f"report: {write_report(report, ident, validations)}")
    return lines
