"""The drive of a built window regulator from its operating points (thesis 5.3.1): the load torque at the drum
(Fig. 5.7, measured with a torque handle) and the drive's speed and current while it lifts the glass (Fig. 5.8),
at one supply voltage. The family's set (4.1) gives the structure and every value the points leave free.

Steady state of the drive (Eq. 4.1 with Eq. 4.29-4.31), gear load M at the drum, gear speed w, current i::

    U = ra*i + ke*r*w              kt*i = mc + visc*r*w + (M + m_gc)/(r*eta)

Two points (M, w, i) fix four numbers: no-load speed, speed slope, no-load current and current slope. The fit
takes four parameters for them: ke and ra (the voltage equation), eta (with kt the current slope) and visc
(with the family's m_gc and mc the no-load current). The others are held:

* kt = ke: the SI identity of a DC motor's constants; kt > ke would deliver more shaft power than the
  back-EMF takes (the thesis's calculator gives kt < ke because it folds Coulomb friction into kt, 4.1.1.3;
  here that friction is m_gc and visc);
* eta within the industrial range 0.40 .. 0.50 of window-lift worm gears (4.1.2.7; above 0.50 the gear does
  not self-lock);
* ratio, laa, j, mc, m_gc: the family's.

Where the points ask for more than these bounds allow (an efficiency beyond a self-locking gear), the fit
stops at the bound and the residuals say by how much; `implied` gives what the points alone would need."""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from wrsim.closed_form.motor import MotorParams, drive_line_summary, line_coefficients, motor_from_set
from wrsim.data.measurements import read_table
from wrsim.data.params import load_params
from wrsim.data.units import convert
from wrsim.errors import WrsimError

__all__ = ["ETA_RANGE", "OperatingPointIdentification", "identify_operating_points"]

ETA_RANGE = (0.40, 0.50)  # worm-gear efficiency of window-lift drives in industry (thesis 4.1.2.7)


@dataclass(frozen=True, eq=False)
class OperatingPointIdentification:
    """Result of identify_operating_points: the drive (motor, ratio, eta, m_gc) and its fit to the points
    (SI units: N*m at the drum, rad/s at the gear, A)."""

    motor: MotorParams
    ratio: float
    eta: float
    m_gc: float
    voltage: float
    torque: np.ndarray
    speed: np.ndarray
    current: np.ndarray
    source: Path
    family: Path
    at_bound: tuple[str, ...]  # parameters the fit left on a bound
    implied: dict[str, float]  # what the points alone need: kt*eta/ke, no-load speed [rpm], stall [N*m]

    kind = "operating-points"

    def model_points(self) -> tuple[np.ndarray, np.ndarray]:
        """The identified drive's steady state at the measured torques: (gear speed [rad/s], current [A])."""
        return _steady(self.motor, self.ratio, self.eta, self.m_gc, self.voltage, self.torque)

    def residuals(self) -> tuple[np.ndarray, np.ndarray]:
        """Relative deviations [%] of the model from the points: (speed, current)."""
        w, i = self.model_points()
        return (w / self.speed - 1.0) * 100.0, (i / self.current - 1.0) * 100.0

    def summary(self) -> dict:
        """No-load speed [rpm], stall torque [N*m] and slope [rpm/(N*m)] at the gear, at the fit's voltage."""
        return drive_line_summary(self.motor, self.ratio, self.eta, self.m_gc, self.voltage)


def _steady(
    motor: MotorParams, ratio: float, eta: float, m_gc: float, u: float, torque: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Steady state of the drive under the gear loads `torque`: (gear speed [rad/s], current [A])."""
    w0, s_w, i0, s_i = line_coefficients(motor, u, 0.0)
    load = (torque + m_gc) / (ratio * eta)
    return (w0 + s_w * load) / ratio, i0 + s_i * load


def _implied(torque: np.ndarray, speed: np.ndarray, current: np.ndarray, u: float, ratio: float) -> dict[str, float]:
    """The straight lines through the points (least squares for more than two) and the drive they imply."""
    s_i, i0 = np.polyfit(torque, current, 1)
    s_w, w0 = np.polyfit(torque, speed, 1)
    # voltage equation over the points: U = ra*i + (ke*r)*w
    (ra, ker), *_ = np.linalg.lstsq(np.column_stack([current, speed]), np.full(len(torque), u), rcond=None)
    values = {
        "kt_eta_over_ke": 1.0 / (s_i * ker),
        "no_load_rpm": convert(w0, "rad/s", "rpm"),
        "stall": -w0 / s_w,
        "no_load_current": i0,
        "current_slope": s_i,
        "ra": ra,
        "ke": ker / ratio,
    }
    return {k: float(v) for k, v in values.items()}


def identify_operating_points(
    points: Path, family: Path, voltage: float, eta_range: tuple[float, float] = ETA_RANGE
) -> OperatingPointIdentification:
    """Identify the drive from the operating points in `points` (CSV with drum_torque, drive_speed and
    drive_current, docs/measurement-format.md) at `voltage` [V], on the structure and held values of the
    family set `family` ([dcpm_motor], [worm_gear] ratio, [drive] m_gc)."""
    from scipy.optimize import least_squares

    table = read_table(points, require_source=True)
    torque = table.column("drum_torque", "N*m")
    speed = table.column("drive_speed", "rad/s")
    current = table.column("drive_current", "A")
    where = f"identify operating-points: {points}"
    if len(torque) < 2 or np.ptp(torque) <= 0.0:
        raise WrsimError(f"{where}: needs two or more points with different drum torques")
    if np.any(speed <= 0) or np.any(current <= 0) or np.any(torque < 0):
        raise WrsimError(f"{where}: torques must be >= 0, speeds and currents > 0 (a lifting drive)")
    if voltage <= 0:
        raise WrsimError(f"{where}: the supply voltage must be > 0, got {voltage:g} V")
    pset = load_params(family)
    base = motor_from_set(pset)
    ratio = pset.number_in("worm_gear", "ratio", "1")
    m_gc = pset.number_in("drive", "m_gc", "N*m")
    implied = _implied(torque, speed, current, voltage, ratio)

    def drive(x: np.ndarray) -> MotorParams:
        return replace(base, ke=float(x[0]), kt=float(x[0]), ra=float(x[1]), visc=float(x[2]))

    def residual(x: np.ndarray) -> np.ndarray:
        w, i = _steady(drive(x), ratio, x[3], m_gc, voltage, torque)
        return np.concatenate([w / speed - 1.0, i / current - 1.0])

    lo = np.array([1e-6, 1e-6, 0.0, eta_range[0]])
    hi = np.array([np.inf, np.inf, np.inf, eta_range[1]])
    x0 = np.clip([base.ke, base.ra, base.visc, pset.number_in("worm_gear", "eta", "1")], lo, np.minimum(hi, 1e9))
    fit = least_squares(residual, x0, bounds=(lo, hi), x_scale=np.abs(x0) + [0, 0, 1e-6, 0], xtol=1e-12)
    names = ("ke", "ra", "visc", "eta")
    at_bound = tuple(n for n, v, a, b in zip(names, fit.x, lo, hi) if np.isclose(v, a) or np.isclose(v, b))
    x = [float(v) for v in fit.x]
    return OperatingPointIdentification(
        drive(np.array(x)),
        ratio,
        x[3],
        m_gc,
        voltage,
        torque,
        speed,
        current,
        Path(points),
        Path(family),
        at_bound,
        implied,
    )
