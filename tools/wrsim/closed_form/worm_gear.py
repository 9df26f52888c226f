"""Worm-gear efficiency and ratio in closed form (thesis 4.1.2.4-4.1.2.5), SI units, angles in rad: driving-mode
efficiency of the 2D architecture (Eq. 4.19e / 4.20b) and of the 3D architecture (Eq. 4.26b), the gear-to-worm
("self-locking mode") power ratios (Eq. 4.22b, 4.27b), the kinematic ratio (Eq. 4.14e), the inverses that
parametrize the 2D/3D architectures to a target efficiency and ratio, and the equivalent armature mass seen
through the gear and drum (Eq. 3.24)."""

from __future__ import annotations

import math

from wrsim.errors import WrsimError, finite, non_negative, positive

__all__ = [
    "eta_2d",
    "eta_2d_self_locking",
    "eta_3d",
    "eta_3d_self_locking",
    "ratio_2d",
    "mu_for_eta_2d",
    "mu_for_eta_3d",
    "lead_angle_for_ratio",
    "equivalent_mass",
]

_HALF_PI = 0.5 * math.pi


def _angle(name: str, value: object, *, allow_zero: bool = False) -> float:
    x = finite(name, value)
    low_ok = x >= 0.0 if allow_zero else x > 0.0
    if not (low_ok and x < _HALF_PI):
        interval = "[0, pi/2)" if allow_zero else "(0, pi/2)"
        raise WrsimError(f"{name} must be an angle in {interval} rad, got {x!r}")
    return x


def _efficiency(name: str, value: object, *, allow_one: bool = False) -> float:
    x = finite(name, value)
    high_ok = x <= 1.0 if allow_one else x < 1.0
    if not (x > 0.0 and high_ok):
        interval = "(0, 1]" if allow_one else "(0, 1)"
        raise WrsimError(f"{name} must be in {interval}, got {x!r}")
    return x


# ------------------------------------------------------------------------------------ worm gear (4.1.2.4-5)


def eta_2d(lead_angle: float, mu_c: float) -> float:
    """Driving-mode (worm drives gear) power efficiency of the 2D architecture, Eq. 4.19e.

    ``eta = (1 - mu_c tan(phi_l)) tan(phi_l) / (tan(phi_l) + mu_c)``, which equals
    ``tan(phi_l) / tan(phi_l + phi_f)`` with the friction angle ``phi_f = arctan(mu_c)`` (Eq. 4.20b).
    Reconstructed: the thesis prints Eq. 4.20a as ``mu_c = tan(phi_l)``; it must read ``mu_c = tan(phi_f)``.
    Bearing friction is not included. A result <= 0 (``phi_l + phi_f >= pi/2``) means the worm cannot drive
    the gear at all; the value is returned as the equation gives it.

    Args:
        lead_angle: lead angle ``phi_l`` at the pitch circle [rad], in (0, pi/2).
        mu_c: Coulomb friction coefficient at the contacting face, >= 0.
    """
    lam = _angle("lead_angle", lead_angle)
    mu = non_negative("mu_c", mu_c)
    t = math.tan(lam)
    return (1.0 - mu * t) * t / (t + mu)


def eta_2d_self_locking(lead_angle: float, mu_c: float) -> float:
    """Gear-to-worm power ratio ``P_w / P_g`` of the 2D architecture in self-locking mode, Eq. 4.22b.

    ``P_w/P_g = (tan(phi_l) - mu_c) / ((1 + mu_c tan(phi_l)) tan(phi_l)) = tan(phi_l - phi_f) / tan(phi_l)``.
    Zero when the friction angle equals the lead angle, negative (self-locking) when it is larger.

    Note: Table 4.6 of the thesis lists ``tan(phi_l - phi_f)`` -- the *force* ratio of Eq. 4.22a -- rather
    than this power ratio (0.349 % vs 3.32 % for phi_l = 6 deg, phi_f = 5.8 deg).
    """
    lam = _angle("lead_angle", lead_angle)
    mu = non_negative("mu_c", mu_c)
    t = math.tan(lam)
    return (t - mu) / ((1.0 + mu * t) * t)


def eta_3d(lead_angle: float, mu_c: float, press_angle: float) -> float:
    """Driving-mode power efficiency of the 3D architecture, Eq. 4.26b.

    ``eta = (cos(phi_p) - mu_c tan(phi_l)) tan(phi_l) / (cos(phi_p) tan(phi_l) + mu_c)``, i.e. the 2D
    result (Eq. 4.19e) with ``mu_c`` replaced by ``mu_c / cos(phi_p)``. ``press_angle = 0`` gives the 2D
    architecture exactly, as the thesis states.

    Args:
        lead_angle: lead angle ``phi_l`` [rad], in (0, pi/2).
        mu_c: Coulomb friction coefficient at the contacting face, >= 0.
        press_angle: pressure angle ``phi_p`` [rad], in [0, pi/2).
    """
    lam = _angle("lead_angle", lead_angle)
    mu = non_negative("mu_c", mu_c)
    cp = math.cos(_angle("press_angle", press_angle, allow_zero=True))
    t = math.tan(lam)
    return (cp - mu * t) * t / (cp * t + mu)


def eta_3d_self_locking(lead_angle: float, mu_c: float, press_angle: float) -> float:
    """Gear-to-worm power ratio of the 3D architecture in self-locking mode, Eq. 4.27b.

    ``(cos(phi_p) tan(phi_l) - mu_c) / ((cos(phi_p) + mu_c tan(phi_l)) tan(phi_l))`` -- Eq. 4.22b with
    ``mu_c / cos(phi_p)``. (The thesis labels it ``P_gear/P_worm``; from Eq. 4.27a and the kinematics it is
    the worm-to-gear power ratio ``P_worm/P_gear`` of power flowing from gear to worm, as in Eq. 4.22b.)
    """
    lam = _angle("lead_angle", lead_angle)
    mu = non_negative("mu_c", mu_c)
    cp = math.cos(_angle("press_angle", press_angle, allow_zero=True))
    t = math.tan(lam)
    return (cp * t - mu) / ((cp + mu * t) * t)


def ratio_2d(r_worm: float, r_gear: float, lead_angle: float) -> float:
    """Gear ratio ``i = omega_worm / omega_gear = r_gear / (r_worm tan(phi_l))``, Eq. 4.14e.

    Args:
        r_worm: pitch radius of the worm [m], > 0.
        r_gear: pitch radius of the gear wheel [m], > 0.
        lead_angle: lead angle [rad], in (0, pi/2).
    """
    rw = positive("r_worm", r_worm)
    rg = positive("r_gear", r_gear)
    lam = _angle("lead_angle", lead_angle)
    return rg / (rw * math.tan(lam))


def mu_for_eta_2d(lead_angle: float, eta: float) -> float:
    """Contact friction coefficient giving the driving-mode efficiency ``eta`` (inverse of Eq. 4.19e).

    Solving Eq. 4.19e for ``mu_c``: ``mu_c = tan(phi_l) (1 - eta) / (eta + tan(phi_l)^2)``, equivalently
    ``phi_f = arctan(tan(phi_l) / eta) - phi_l`` from Eq. 4.20b.

    Args:
        lead_angle: lead angle [rad], in (0, pi/2).
        eta: target efficiency, in (0, 1).
    """
    lam = _angle("lead_angle", lead_angle)
    e = _efficiency("eta", eta)
    t = math.tan(lam)
    return t * (1.0 - e) / (e + t * t)


def mu_for_eta_3d(lead_angle: float, eta: float, press_angle: float) -> float:
    """Contact friction coefficient giving the driving-mode efficiency ``eta`` of Eq. 4.26b.

    Since Eq. 4.26b is Eq. 4.19e with ``mu_c / cos(phi_p)``, the result is
    ``cos(phi_p) * mu_for_eta_2d(lead_angle, eta)``.
    """
    cp = math.cos(_angle("press_angle", press_angle, allow_zero=True))
    return cp * mu_for_eta_2d(lead_angle, eta)


def lead_angle_for_ratio(r_worm: float, r_gear: float, ratio: float) -> float:
    """Lead angle [rad] that gives the gear ratio ``ratio`` with the given pitch radii (inverse of Eq. 4.14e).

    ``phi_l = arctan(r_gear / (r_worm * i))``.
    """
    rw = positive("r_worm", r_worm)
    rg = positive("r_gear", r_gear)
    i = positive("ratio", ratio)
    return math.atan(rg / (rw * i))


# ------------------------------------------------------------------------------------ equivalent mass (3.2)


def equivalent_mass(j: float, ratio: float, eta: float, r_drum: float) -> float:
    """Equivalent translational mass of the armature inertia, Eq. 3.24: ``M1 = eta i^2 J_a / r_cd^2`` [kg].

    Args:
        j: armature moment of inertia ``J_a`` [kg*m^2], > 0.
        ratio: worm-gear reduction ratio ``i``, > 0.
        eta: worm-gear power efficiency ``eta_w``, in (0, 1] (1 = lossless).
        r_drum: cable-drum radius ``r_cd`` [m], > 0.
    """
    ja = positive("j", j)
    i = positive("ratio", ratio)
    e = _efficiency("eta", eta, allow_one=True)
    r = positive("r_drum", r_drum)
    return e * i * i * ja / (r * r)
