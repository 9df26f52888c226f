"""The thesis's identification of the FPG2 12Nm drive (4.1.1.3-4.1.1.4, 4.1.4.2): the parameter calculator
(Eq. 4.2-4.8), the least-squares variant, the worm-gear efficiency from the slopes (Eq. 4.35b), the housing
friction from the speed gap (Fig. 4.42/4.43), and the default parameter set from the transcribed thesis data."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.closed_form.motor import (
    MotorParams,
    drive_ramp_line,
    line_coefficients,
    motor_ramp_line,
)
from wrsim.data.measurements import read_table
from wrsim.data.params import save_params
from wrsim.data.units import convert
from wrsim.errors import WrsimError

__all__ = [
    "parameter_calculator",
    "line_fit",
    "motor_from_line",
    "least_squares_motor",
    "gear_efficiency_from_slopes",
    "housing_friction_from_gap",
    "identify_default_set",
    "write_default_set",
    "significant",
    "THESIS_LAA",
    "THESIS_J",
    "THESIS_VOLTAGE",
]

# Conditions of the thesis's FPG2 12Nm identification.
THESIS_VOLTAGE = 13.0  # V, rated supply of both characteristic-line measurements
THESIS_LAA = 0.09e-3  # H, Appendix A generic default (supplier-specification type, Tab. 4.4)
THESIS_J = 9.85e-6  # kg*m**2, Appendix A generic default (supplier-specification type)
_MOTOR_RATE = 0.5 / 3.0  # N*m/s, servo ramp 0 -> 0.5 N*m in 3 s (4.1.1.4)
_FRACTIONS = (0.1, 0.5)  # points at 10 % and 50 % of stall torque, the standard (4.1.1.3)
_RATIO = 73.0  # worm gear ratio of the FPG2 12Nm (4.1.4.2)
_ETA = 0.45162397  # published worm-gear efficiency (4.1.4.2)
_DRIVE_RATE = 13.0 / 2.0  # N*m/s at the gear: one measurement ~2 s up to stall ~13 N*m (4.1.4.2)
_PRINTED_S_A = -14639.24  # rpm/(N*m), motor slope printed in 4.1.4.2
_PRINTED_S_D = -6.00  # rpm/(N*m), drive slope printed in 4.1.4.2
_THESIS_M_GC = 0.4097  # N*m, the thesis's housing friction (Fig. 4.43)
_DAMPER_ANGLES_DEG = [0.0, 2.0, 4.0, 6.0, 8.0, 10.0]
_DAMPER_STIFFNESS = [57.3, 51.6, 48.7, 47.7, 51.6, 68.8]  # N*m/rad
_COND_LIMIT = 1e6  # max cond of the column-scaled [i, w, 1] for a free (kt, visc, mc) fit


def parameter_calculator(
    m1: float, w1: float, i1: float, m2: float, w2: float, i2: float, u: float, laa: float, j: float, torque_rate: float
) -> MotorParams:
    """The thesis's parameter calculator, Eq. 4.2-4.8, from two points (M_n, w_n, i_n) of one
    characteristic line measured under a torque ramp dM/dt = torque_rate.

    di/dt (Eq. 4.4c) and dw/dt (Eq. 4.7c) are the line slopes times dM/dt. Eq. 4.7b is Eq. 4.7a
    solved with M_coul = 0, so Eq. 4.8a returns 0 by construction: M_c is not identified by the
    calculator; Coulomb friction of the real motor ends up in visc and kt.
    """
    if i2 == i1 or m2 == m1:
        raise WrsimError(
            f"parameter calculator: the two points must differ in torque and current "
            f"(M = {m1:g}, {m2:g} N*m; i = {i1:g}, {i2:g} A)"
        )
    m1, w1, i1, m2, w2, i2 = (float(v) for v in (m1, w1, i1, m2, w2, i2))
    di, dw, dm = i2 - i1, w2 - w1, m2 - m1
    omega_idle = (w1 - w2) / di * i1 + w1  # Eq. 4.3
    didt = di / dm * torque_rate  # Eq. 4.4c
    ke = (u - laa * didt) / omega_idle  # Eq. 4.4b
    ra = ke * (w1 - w2) / di  # Eq. 4.5b
    dwdt = dw / dm * torque_rate  # Eq. 4.7c
    visc = (i1 * dm / di - j * dwdt - m1) / (w1 + (w1 - w2) / di * i1)  # Eq. 4.7b
    kt = (visc * dw + dm) / di  # Eq. 4.6b
    mc = 0.0  # Eq. 4.8a, i1*kt - m1 - j*dwdt - visc*w1, is identically 0 after Eq. 4.7b
    return MotorParams(ke=ke, kt=kt, ra=ra, laa=laa, j=j, visc=visc, mc=mc)


def line_fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares straight line y = slope*x + intercept; returns (slope, intercept)."""
    from scipy.stats import linregress

    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if x.shape != y.shape or x.size < 2 or np.ptp(x) == 0:
        raise WrsimError(
            f"line fit needs at least two distinct x values and as many y values (got {x.size} x, {y.size} y)"
        )
    fit = linregress(x, y)
    return float(fit.slope), float(fit.intercept)


def motor_from_line(
    torque: np.ndarray,
    speed: np.ndarray,
    current: np.ndarray,
    u: float,
    laa: float,
    j: float,
    torque_rate: float,
    fractions: tuple[float, float] = _FRACTIONS,
) -> tuple[MotorParams, dict]:
    """Identify the motor from one measured characteristic line (thesis procedure 4.1.1.4).

    Fits speed and current over torque with straight lines, takes the stall torque where the fitted
    speed is 0, evaluates both lines at `fractions` of it and runs parameter_calculator.
    """
    s_w, w0 = line_fit(torque, speed)
    s_i, i0 = line_fit(torque, current)
    if s_w >= 0:
        raise WrsimError(
            f"speed does not fall with torque (slope {s_w:g} rad/s/(N*m)); not a motor characteristic line"
        )
    stall = -w0 / s_w
    m = np.array(fractions, dtype=float) * stall
    w, i = w0 + s_w * m, i0 + s_i * m
    params = parameter_calculator(m[0], w[0], i[0], m[1], w[1], i[1], u, laa, j, torque_rate)
    details = {
        "stall_torque": stall,
        "points": {"torque": m.tolist(), "speed": w.tolist(), "current": i.tolist()},
        "speed_slope": s_w,
        "speed_intercept": w0,
        "current_slope": s_i,
        "current_intercept": i0,
    }
    return params, details


def _per_voltage_rate(torque: np.ndarray, values: np.ndarray, groups: np.ndarray, torque_rate: float) -> np.ndarray:
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
        raise WrsimError(
            f"least squares: {name} must be one number or one value per sample "
            f"({n} samples), got shape {np.shape(value)}"
        ) from None


def _scaled_cond(x: np.ndarray) -> float:
    return float(np.linalg.cond(x / np.linalg.norm(x, axis=0)))


def least_squares_motor(
    torque: np.ndarray,
    speed: np.ndarray,
    current: np.ndarray,
    u: float | np.ndarray,
    laa: float,
    j: float,
    torque_rate: float,
    didt: float | np.ndarray | None = None,
    dwdt: float | np.ndarray | None = None,
) -> tuple[MotorParams, dict]:
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
        raise WrsimError(
            f"least squares: torque, speed and current must be 1-D of one length (got {m.shape}, {w.shape}, {i.shape})"
        )
    uu = _per_sample(u, m.size, "u")
    voltages = np.unique(uu)
    groups = np.searchsorted(voltages, uu)
    didt_v = _per_voltage_rate(m, i, groups, torque_rate) if didt is None else _per_sample(didt, m.size, "didt")
    dwdt_v = _per_voltage_rate(m, w, groups, torque_rate) if dwdt is None else _per_sample(dwdt, m.size, "dwdt")

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
        reason = (
            f"only one supply voltage ({voltages[0]:g} V)"
            if voltages.size < 2
            else f"regressor [i, w, 1] ill-conditioned (cond {cond_me:.3g} >= {_COND_LIMIT:g})"
        )
        constraint = (
            f"kt = ke imposed (SI energy balance): {reason}, so kt, visc and mc are not separately identifiable"
        )
    params = MotorParams(ke=float(ke), kt=float(kt), ra=float(ra), laa=laa, j=j, visc=float(visc), mc=float(mc))
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


def gear_efficiency_from_slopes(s_motor: float, s_drive: float, ratio: float) -> float:
    """Eq. 4.35b: eta = s_a/(s_d*i**2), slopes of speed over torque in the same units for both."""
    return s_motor / (s_drive * ratio**2)


def housing_friction_from_gap(
    p: MotorParams,
    ratio: float,
    eta: float,
    u: float,
    torque_rate: float,
    gear_torque: np.ndarray,
    fitted_gear_speed: np.ndarray,
) -> float:
    """Gear-side housing friction M_gc [N*m] that makes the mean of drive_ramp_line's gear speed
    minus `fitted_gear_speed` [rad/s] zero over `gear_torque`. Closed form: the gear speed is
    affine in M_gc with slope s_w/(ratio**2*eta)."""
    omega, _ = drive_ramp_line(p, ratio, eta, 0.0, u, torque_rate, gear_torque)
    gap = float(np.mean(omega - np.asarray(fitted_gear_speed, dtype=float)))
    s_w = line_coefficients(p, u, torque_rate / (ratio * eta))[1]
    return float(-gap / (s_w / (ratio**2 * eta)))


def _max_rel_error_pct(model: np.ndarray, reference: np.ndarray) -> float:
    return float(np.max(np.abs(model / reference - 1.0)) * 100.0)


def identify_default_set(root: Path = paths.ROOT) -> dict:
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
    motor, details = motor_from_line(torque, speed, current, THESIS_VOLTAGE, THESIS_LAA, THESIS_J, _MOTOR_RATE)
    omega, amps = motor_ramp_line(motor, THESIS_VOLTAGE, _MOTOR_RATE, torque)

    drv = read_table(mdir / "fig4_44_drive.csv", increasing="torque", require_source=True)
    gear_torque = drv.column("torque", "N*m")
    fit_speed, fit_current = drv.column("fit_speed", "rad/s"), drv.column("fit_current", "A")
    m_gc = housing_friction_from_gap(motor, _RATIO, _ETA, THESIS_VOLTAGE, _DRIVE_RATE, gear_torque, fit_speed)
    gear_omega, drive_amps = drive_ramp_line(motor, _RATIO, _ETA, m_gc, THESIS_VOLTAGE, _DRIVE_RATE, gear_torque)

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


def significant(x: float) -> float:
    """Round to 10 significant digits so the committed file does not depend on the last float bit."""
    return float(f"{x:.10g}")


def write_default_set(root: Path = paths.ROOT, out_path: Path = paths.PARAMS / f"{paths.DEFAULT_PARAMS}.txt") -> dict:
    """Run identify_default_set and write the parameter set (params/fpg2_12nm.txt); returns the
    identification dict."""
    r = identify_default_set(root)
    p, d, v, f = r["motor"], r["motor_details"], r["validation"], r["findings"]
    m_gc = r["drive"]["m_gc"]
    calc = "parameter calculator on the Fig. 4.15 mean line"
    header = [
        "wrsim parameter set: Bosch FPG2 12Nm window-regulator drive (motor, worm gear, damper).",
        "Generated by wrsim.identify.write_default_set from params/measurements/; do not edit.",
        f"Conditions: {THESIS_VOLTAGE:g} V; motor ramp 0 -> 0.5 N*m in 3 s (4.1.1.4);",
        "  drive ramp 0 -> 13 N*m in 2 s at the gear (4.1.4.2).",
        "Motor: Eq. 4.2-4.8 on the linear fit of the Fig. 4.15 mean line, points at 10 % and",
        f"  50 % of the fitted stall torque {d['stall_torque']:.4f} N*m. Ramp line vs that mean line:",
        f"  max speed error {v['motor_speed_pct']:.2f} %, current {v['motor_current_pct']:.2f} % "
        f"(thesis's simulation: {v['thesis_motor_speed_pct']:.2f} %, "
        f"{v['thesis_motor_current_pct']:.2f} %).",
        "  mc = 0 by construction: Eq. 4.7b is Eq. 4.7a solved with M_coul = 0, so the",
        "  motor's Coulomb friction is folded into visc and kt.",
        f"Efficiency: Eq. 4.35b with the printed slopes s_a = {_PRINTED_S_A}, s_d = {_PRINTED_S_D:.2f} rpm/(N*m)",
        f"  gives eta = {f['eta_printed_slopes']:.4f}, not the printed {_ETA}, which needs "
        f"s_d = {f['s_d_for_printed_eta']:.4f}.",
        f"  The printed s_a is the slope of the thesis's SIMULATED Fig. 4.15 speed ({f['s_a_thesis_sim_rpm']:.2f}),",
        f"  not of its mean line ({f['s_a_mean_rpm']:.2f}); mean line and Fig. 4.44 fit slope ({f['s_d_fit_rpm']:.4f})",
        f"  give eta = {f['eta_our_slopes']:.4f}. This set keeps the published eta.",
        "Housing friction m_gc acts at the gear shaft; it closes the mean speed gap to the",
        f"  Fig. 4.44 fit (1-5 N*m): {m_gc:.4f} N*m with this motor set (the thesis's {_THESIS_M_GC} N*m",
        "  belongs to its own middle-line motor set). Drive line vs Fig. 4.44 fit:",
        f"  max speed error {v['drive_speed_pct']:.2f} %, current {v['drive_current_pct']:.2f} %.",
    ]
    rubber = (
        "estimated from the text of 4.1.4.1 (1 N*m ~ 1 deg, 5 N*m ~ 6 deg at room temperature); "
        "Fig. 4.32's data is not in the text"
    )
    sections = {
        "dcpm_motor": [
            ("ke", significant(p.ke), "V*s/rad", f"Eq. 4.4b, {calc}"),
            ("kt", significant(p.kt), "N*m/A", f"Eq. 4.6b, {calc}"),
            ("ra", significant(p.ra), "Ohm", f"Eq. 4.5b, {calc}"),
            ("laa", THESIS_LAA, "H", "Appendix A default (supplier specification, Tab. 4.4)"),
            ("j", THESIS_J, "kg*m**2", "Appendix A default (supplier specification, Tab. 4.4)"),
            ("visc", significant(p.visc), "N*m*s/rad", f"Eq. 4.7b, {calc}"),
            ("mc", significant(p.mc), "N*m", "Eq. 4.8a: 0 by construction of the calculator (see header)"),
        ],
        "worm_gear": [
            ("ratio", _RATIO, "1", "4.1.4.2: worm gear ratio of the FPG2 12Nm"),
            ("eta", _ETA, "1", "4.1.4.2: published efficiency (Eq. 4.35b; see header)"),
        ],
        "drive": [
            ("m_gc", significant(m_gc), "N*m", "gear-side housing friction, speed gap to Fig. 4.44 fit"),
        ],
        "rubber_damper": [
            ("angles", r["rubber_damper"]["angles"], "rad", "0, 2, ..., 10 deg: grid of the estimate"),
            ("stiffness", r["rubber_damper"]["stiffness"], "N*m/rad", f"secant (Eq. 4.28), {rubber}"),
        ],
    }
    save_params(out_path, header, sections)
    return r
