"""Identification of a group of units from raw curves (thesis 4.1.1.3-4.1.1.4, 4.1.4.2, 4.1.3): each curve cut
to its working range (motor 10-80 % of its stall torque, drive 1-6 N*m) and fitted with lines (averaging out the
commutation ripple, Fig. 4.9), group lines min/max/mean/middle of the boundaries (Fig. 4.11-4.13, 4.38-4.40),
the parameter calculator on the middle line (least squares as variant), the worm-gear efficiency and housing
friction, the rubber-damper stiffness table (Eq. 4.28), and the validation of a model line against the group."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from wrsim.closed_form.motor import (
    MotorParams,
    drive_ramp_line,
    line_coefficients,
    motor_ramp_line,
)
from wrsim.data.curves import MIN_SAMPLES, DamperCurve, RawCurve
from wrsim.errors import WrsimError
from wrsim.identify.calculator import (
    THESIS_J,
    THESIS_LAA,
    gear_efficiency_from_slopes,
    housing_friction_from_gap,
    least_squares_motor,
    line_fit,
    motor_from_line,
)

__all__ = [
    "CurveFit",
    "fit_curve",
    "GroupLines",
    "group_lines",
    "Validation",
    "validate",
    "MotorIdentification",
    "identify_motor",
    "DriveIdentification",
    "identify_drive",
    "DamperIdentification",
    "identify_damper",
]

_MOTOR_FRACTIONS = (0.1, 0.8)  # motor working range, fractions of the stall torque (4.1.1.4)
_DRIVE_RANGE = (1.0, 6.0)  # N*m, drive working range at the gear (4.1.4.2)
_DAMPER_STEP = math.radians(2.0)  # rad, grid of the identified stiffness table


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
    if n < MIN_SAMPLES:
        raise WrsimError(
            f"{curve.name}: only {n} samples within the working range {lo:.4g}-{hi:.4g} N*m "
            f"(need {MIN_SAMPLES}); the file covers {curve.torque.min():.4g}-"
            f"{curve.torque.max():.4g} N*m"
        )
    m = curve.torque[sel]
    s_w, w0 = line_fit(m, curve.speed[sel])
    if s_w >= 0:
        raise WrsimError(
            f"{curve.name}: the speed does not fall with the torque within {lo:.4g}-{hi:.4g} "
            f"N*m (slope {s_w:.4g} rad/s per N*m); not a characteristic curve"
        )
    s_i, i0 = line_fit(m, curve.current[sel])
    rate = line_fit(curve.time[sel], m)[0]
    return CurveFit(curve.name, curve.direction, lo, hi, n, s_w, w0, s_i, i0, rate, float(np.mean(curve.voltage[sel])))


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
    return GroupLines(
        list(fits), m, _four(np.array([f.speed(m) for f in fits])), _four(np.array([f.current(m) for f in fits]))
    )


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


def validate(group: GroupLines, reference: str, label: str, torque, speed, current, points: int = 7) -> Validation:
    """Compare a simulated line (speed [rad/s], current [A] over rising torque [N*m]) with the group's
    `reference` line; the table has `points` torques spread evenly over the working range."""
    reference = _line_choice(reference)
    torque = np.asarray(torque, dtype=float)
    if torque.min() > group.lo or torque.max() < group.hi:
        raise WrsimError(
            f"{label}: covers {torque.min():.4g}-{torque.max():.4g} N*m, not the working range "
            f"{group.lo:.4g}-{group.hi:.4g} N*m"
        )
    gw, gi = np.interp(group.torque, torque, speed), np.interp(group.torque, torque, current)
    ref_w, ref_i = group.speed[reference], group.current[reference]
    at = np.linspace(group.lo, group.hi, points)
    return Validation(
        label,
        reference,
        at,
        np.interp(at, torque, speed),
        np.interp(at, group.torque, ref_w),
        np.interp(at, torque, current),
        np.interp(at, group.torque, ref_i),
        float(np.max(np.abs(gw / ref_w - 1.0)) * 100.0),
        float(np.max(np.abs(gi / ref_i - 1.0)) * 100.0),
        _outside_pct(gw, group.speed, ref_w),
        _outside_pct(gi, group.current, ref_i),
        gw,
        gi,
    )


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
        raise WrsimError(
            f"identify {what}: the curves were measured at different supply voltages "
            f"({min(volts):.4g} .. {max(volts):.4g} V); identify one voltage at a time"
        )
    return float(np.mean(volts)), float(np.mean([f.torque_rate for f in fits]))


def identify_motor(
    curves: list[RawCurve],
    laa: float = THESIS_LAA,
    j: float = THESIS_J,
    fractions: tuple[float, float] = _MOTOR_FRACTIONS,
    method: str = "calculator",
) -> MotorIdentification:
    """Identify a group of motors (thesis 4.1.1.4 b): cut every curve to `fractions` of its stall torque,
    fit lines, form the group lines over `fractions` of the middle line's stall torque, and run the
    parameter calculator on the middle line (motor_from_line: points at 10 % and 50 % of its stall).
    The least-squares variant (least_squares_motor) runs on the cut raw samples of all curves;
    `method` ('calculator' or 'least-squares') chooses which set is `params`. laa [H], j [kg*m**2]:
    supplier values (Tab. 4.4)."""
    from scipy.optimize import brentq

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
    calc, calc_details = motor_from_line(group.torque, group.speed["middle"], group.current["middle"], u, laa, j, rate)
    cut = [(c, (c.torque >= f.lo) & (c.torque <= f.hi)) for c, f in zip(curves, fits)]
    torque, speed, current = (
        np.concatenate([getattr(c, name)[sel] for c, sel in cut]) for name in ("torque", "speed", "current")
    )
    lsq, lsq_details = least_squares_motor(torque, speed, current, u, laa, j, rate)
    chosen = calc if method == "calculator" else lsq
    if chosen.visc < 0 or chosen.mc < 0:
        raise WrsimError(
            f"identify motor ({method}): visc = {chosen.visc:.4g} N*m*s/rad, mc = {chosen.mc:.4g} N*m; "
            f"the motor model needs both >= 0"
            + (f" ({lsq_details['constraint']})" if method == "least-squares" and lsq_details["constraint"] else "")
        )
    return MotorIdentification(
        chosen, method, calc, calc_details, lsq, lsq_details, group, list(curves), u, rate, float(stall), fractions
    )


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
        return drive_ramp_line(self.motor, self.ratio, self.eta, self.m_gc, self.voltage, self.torque_rate, torque)


def identify_drive(
    curves: list[RawCurve],
    motor: MotorParams,
    ratio: float,
    working_range: tuple[float, float] = _DRIVE_RANGE,
    line: str = "mean",
) -> DriveIdentification:
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
    s_a = line_coefficients(motor, u, 0.0)[1]
    s_d = line_fit(group.torque, group.speed[line])[0]
    eta = gear_efficiency_from_slopes(s_a, s_d, ratio)
    if not 0.0 < eta <= 1.0:
        raise WrsimError(
            f"identify drive: efficiency from the slopes is {eta:.4g}, outside (0, 1]: do motor "
            f"set and drive files belong together, is the ratio {ratio:g} right?"
        )
    m_gc = housing_friction_from_gap(motor, ratio, eta, u, rate, group.torque, group.speed[line])
    if m_gc < 0:
        raise WrsimError(
            f"identify drive: the drive line lies above the motor model's (housing friction "
            f"{m_gc:.4g} N*m < 0): check the motor set, the ratio and the supply voltage"
        )
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
        raise WrsimError(
            f"identify damper: the curves reach only {math.degrees(top):.3g} deg; the table needs at "
            f"least one step of {math.degrees(step):.3g} deg"
        )
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
        raise WrsimError(
            f"identify damper: the fitted stiffness is not positive everywhere "
            f"({', '.join(f'{c:.3g}' for c in stiffness)} N*m/rad)"
        )
    rms = float(np.sqrt(np.mean((design @ stiffness - torque) ** 2)))
    return DamperIdentification(grid, stiffness, list(curves), rms)
