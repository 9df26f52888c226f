"""Closed-form DCPM motor and worm-gear drive under a torque ramp (thesis Eq. 4.1, 4.30/4.31).

All quantities are SI: rad/s, N*m, A, V, s. The motor model is Eq. 4.1::

    U = ra*i + laa*di/dt + ke*w                    (4.1a)
    kt*i = mc + visc*w + j*dw/dt + M_load          (4.1b)   (mc acts against w > 0)

Under a load ramp M_load = r*t, w and i are affine in the load torque and both derivatives are constant
(Eq. 4.4c, 4.7c): these are the reference lines the lowered models and the identification are checked against.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from wrsim.data.params import ParamSet
from wrsim.data.units import convert
from wrsim.errors import WrsimError

__all__ = [
    "MotorParams",
    "line_coefficients",
    "motor_ramp_line",
    "drive_ramp_line",
    "drive_line_summary",
    "motor_from_set",
]


@dataclass(frozen=True)
class MotorParams:
    """DCPM motor parameters (generics of entity dcpm_motor), SI units."""

    ke: float  # V*s/rad, back-EMF constant
    kt: float  # N*m/A, torque constant
    ra: float  # Ohm, effective resistance
    laa: float  # H, effective inductance
    j: float  # kg*m**2, rotor inertia
    visc: float  # N*m*s/rad, viscous friction
    mc: float  # N*m, Coulomb friction


def line_coefficients(p: MotorParams, u: float, torque_rate: float) -> tuple[float, float, float, float]:
    """Affine particular solution of Eq. 4.1 under M_load = torque_rate*t, as functions of the load:
    w = w0 + s_w*M, i = i0 + s_i*M (so dw/dt = s_w*torque_rate, di/dt = s_i*torque_rate)."""
    # Terms in t: ra*s_i + ke*s_w = 0 and kt*s_i = visc*s_w + 1.
    s_w = -p.ra / (p.ra * p.visc + p.kt * p.ke)
    s_i = p.ke / (p.ra * p.visc + p.kt * p.ke)
    # Constant terms: ra*i0 + ke*w0 = u - laa*di/dt and kt*i0 - visc*w0 = mc + j*dw/dt.
    i0, w0 = np.linalg.solve(
        [[p.ra, p.ke], [p.kt, -p.visc]], [u - p.laa * s_i * torque_rate, p.mc + p.j * s_w * torque_rate]
    )
    return float(w0), s_w, float(i0), s_i


def motor_ramp_line(p: MotorParams, u: float, torque_rate: float, torque: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Exact quasi-steady (affine particular) solution of Eq. 4.1 for the load ramp
    M_load = torque_rate*t, evaluated at the given load torques (t = torque/torque_rate).

    Returns (omega [rad/s], current [A]). mc acts against positive w, so the line holds only
    below stall; a torque at or beyond stall raises WrsimError.
    """
    w0, s_w, i0, s_i = line_coefficients(p, u, torque_rate)
    m = np.asarray(torque, dtype=float)
    omega, current = w0 + s_w * m, i0 + s_i * m
    if np.any(omega <= 0):
        raise WrsimError(
            f"motor line: load torque {np.max(m):g} N*m reaches stall "
            f"({-w0 / s_w:g} N*m at {u:g} V); the ramp line needs w > 0"
        )
    return omega, current


def drive_ramp_line(
    p: MotorParams, ratio: float, eta: float, m_gc: float, u: float, torque_rate: float, gear_torque: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Drive characteristic line (Eq. 4.30/4.31) under a gear-side load ramp dM_g/dt = torque_rate.

    The housing friction m_gc [N*m] acts at the GEAR shaft, so the motor sees the load
    (M_g + m_gc)/(ratio*eta) rising at torque_rate/(ratio*eta). Returns (gear omega [rad/s],
    current [A]) with gear omega = motor omega/ratio.
    """
    k = ratio * eta
    motor_load = (np.asarray(gear_torque, dtype=float) + m_gc) / k
    omega, current = motor_ramp_line(p, u, torque_rate / k, motor_load)
    return omega / ratio, current


def drive_line_summary(motor: MotorParams, ratio: float, eta: float, m_gc: float, u: float) -> dict:
    """Steady-state drive characteristic (Eq. 4.30/4.31, closed form) at supply u [V]: no-load gear speed
    [rpm], stall torque at the gear [N*m] and slope [rpm/(N*m)]; the same for the bare motor."""
    w0, s_w, _, _ = line_coefficients(motor, u, 0.0)
    k = ratio * eta
    rpm = convert(1.0, "rad/s", "rpm")
    return {
        "no_load_rpm": (w0 + s_w * m_gc / k) / ratio * rpm,
        "stall": -w0 / s_w * k - m_gc,
        "slope_rpm": s_w / (ratio * k) * rpm,
        "motor_no_load_rpm": w0 * rpm,
        "motor_stall": -w0 / s_w,
    }


def motor_from_set(pset: ParamSet) -> MotorParams:
    """The [dcpm_motor] section of a parameter set as MotorParams (SI units)."""
    units = {"ke": "V*s/rad", "kt": "N*m/A", "ra": "Ohm", "laa": "H", "j": "kg*m**2", "visc": "N*m*s/rad", "mc": "N*m"}
    return MotorParams(**{k: pset.number_in("dcpm_motor", k, u) for k, u in units.items()})
