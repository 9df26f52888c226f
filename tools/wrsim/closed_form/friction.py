"""Friction and stiffness identification helpers of the mechanism components (thesis 4.2.1, 4.2.2.1).

All quantities are SI: N, m, rad, N/m, N*m/rad. Angles are wrap angles of the cable in rad.

- Slider (4.2.1.5, Eq. 4.40, Fig. 4.56): linear fit of the cable-force difference over the load force,
  and the slider's friction F_r = F_r0 + k*F_g against its share F_g of the load.
- Pulley (4.2.1.3, Eq. 4.39): friction coefficient between pulley and shaft from the force ratio
  eta = F_b/F_a, and the inverse (eta from mu).
- Bowden cable (4.2.1.2, Eq. 4.37/4.38): capstan law F_a = F_b*exp(mu*alpha).
- System stiffness (4.2.2.1, Eq. 4.42): springs in series, 1/C = 1/C1 + 1/C2 + 1/C3.

Cable-force measurement files (docs/measurement-format.md) are read by read_slider_forces and
read_cable_forces.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim.data.measurements import read_table
from wrsim.errors import WrsimError

__all__ = [
    "SliderFit",
    "slider_friction_fit",
    "read_slider_forces",
    "pulley_mu_from_efficiency",
    "pulley_efficiency",
    "capstan_ratio",
    "bowden_mu",
    "read_cable_forces",
    "translational_stiffness",
    "resultant_stiffness",
    "system_stiffness_from_resultant",
]


@dataclass(frozen=True)
class SliderFit:
    """Result of slider_friction_fit (forces in N).

    Cable-force difference over the whole load: F_up - F_dw = slope*F_load + intercept (r_squared).
    Friction of the measured slider (Eq. 4.40, F_g = share*F_load):
    F_r = F_up - F_dw - F_g = friction_offset + friction_slope*F_g (friction_r_squared).
    """

    slope: float
    intercept: float
    r_squared: float
    share: float
    friction_offset: float
    friction_slope: float
    friction_r_squared: float


def _array(name: str, values) -> np.ndarray:
    a = np.asarray(values, dtype=float)
    if a.ndim != 1 or a.size < 2:
        raise WrsimError(f"{name}: expected a 1-D series of at least two values, got shape {a.shape}")
    return a


def slider_friction_fit(load_force, force_top, force_bottom, share: float) -> SliderFit:
    """Fit the slider friction measurement of Fig. 4.55/4.56.

    load_force: force of the load spring on the glass dummy [N]; force_top/force_bottom: cable forces
    above and below the measured slider [N]; share: part of the load carried by that slider (0.6 for
    slider B in the thesis, 60/40 split).
    """
    from scipy.stats import linregress

    load = _array("load_force", load_force)
    top, bottom = _array("force_top", force_top), _array("force_bottom", force_bottom)
    if not load.shape == top.shape == bottom.shape:
        raise WrsimError(
            f"slider fit: load_force, force_top and force_bottom differ in length "
            f"({load.size}, {top.size}, {bottom.size})"
        )
    if not 0.0 < share <= 1.0:
        raise WrsimError(f"slider fit: share must be in (0, 1], got {share:g}")
    if np.ptp(load) == 0:
        raise WrsimError("slider fit: the load force must vary")
    diff = top - bottom
    fit = linregress(load, diff)
    friction = linregress(share * load, diff - share * load)
    return SliderFit(
        float(fit.slope),
        float(fit.intercept),
        float(fit.rvalue**2),
        share,
        float(friction.intercept),
        float(friction.slope),
        float(friction.rvalue**2),
    )


def _check_pulley(wrap_angle: float, r_in: float, r_out: float) -> None:
    if not 0.0 < wrap_angle <= 2 * math.pi:
        raise WrsimError(f"pulley: wrap angle must be in (0, 2*pi] rad, got {wrap_angle:g}")
    if not 0.0 < r_in < r_out:
        raise WrsimError(f"pulley: need 0 < r_in < r_out, got r_in = {r_in:g} m, r_out = {r_out:g} m")


def pulley_mu_from_efficiency(eta: float, wrap_angle: float, r_in: float, r_out: float) -> float:
    """Friction coefficient between pulley and shaft from the measured force ratio eta = F_b/F_a
    (Eq. 4.39 solved for mu): mu = (1 - eta)*r_out / (r_in*sqrt(1 + eta**2 - 2*eta*cos(alpha)))."""
    _check_pulley(wrap_angle, r_in, r_out)
    if not 0.0 < eta <= 1.0:
        raise WrsimError(f"pulley: force ratio eta = F_b/F_a must be in (0, 1], got {eta:g}")
    normal = math.sqrt(1.0 + eta**2 - 2.0 * eta * math.cos(wrap_angle))  # F_n/F_a, Eq. 4.39c
    return (1.0 - eta) * r_out / (r_in * normal)


def pulley_efficiency(mu: float, wrap_angle: float, r_in: float, r_out: float) -> float:
    """Force ratio eta = F_b/F_a of a rotatable pulley (Eq. 4.39 solved for eta, cable moving from B
    to A): (1 - eta)**2 = k**2*(1 + eta**2 - 2*eta*cos(alpha)) with k = mu*r_in/r_out, smaller root."""
    _check_pulley(wrap_angle, r_in, r_out)
    k2 = (mu * r_in / r_out) ** 2
    if mu < 0 or k2 >= 1.0:
        raise WrsimError(f"pulley: need 0 <= mu*r_in/r_out < 1, got mu = {mu:g}")
    a = 1.0 - k2 * math.cos(wrap_angle)
    b = 1.0 - k2
    return (a - math.sqrt(a * a - b * b)) / b


def capstan_ratio(mu: float, wrap_angle: float) -> float:
    """F_a/F_b = exp(mu*alpha) of a bowden cable pulled out at A (Eq. 4.37a); 1/ratio is its
    efficiency (Eq. 4.38b)."""
    if mu < 0 or wrap_angle < 0:
        raise WrsimError(f"capstan: mu and wrap angle must be >= 0, got {mu:g}, {wrap_angle:g} rad")
    return math.exp(mu * wrap_angle)


def bowden_mu(force_a, force_b, wrap_angle: float) -> float:
    """Friction coefficient of a bowden cable from pulling force(s) F_a and held force(s) F_b
    (Eq. 4.37a solved for mu): the mean of ln(F_a/F_b) over the samples, divided by alpha."""
    fa, fb = np.atleast_1d(np.asarray(force_a, dtype=float)), np.atleast_1d(np.asarray(force_b, dtype=float))
    if fa.shape != fb.shape:
        raise WrsimError(f"bowden: force_a and force_b differ in length ({fa.size}, {fb.size})")
    if wrap_angle <= 0:
        raise WrsimError(f"bowden: wrap angle must be > 0, got {wrap_angle:g} rad")
    if np.any(fb <= 0) or np.any(fa < fb):
        k = int(np.flatnonzero((fb <= 0) | (fa < fb))[0])
        raise WrsimError(
            f"bowden: sample {k + 1}: need F_a >= F_b > 0 (pulling side first), got "
            f"F_a = {fa[k]:g} N, F_b = {fb[k]:g} N"
        )
    return float(np.mean(np.log(fa / fb)) / wrap_angle)


def translational_stiffness(rotational: float, radius: float) -> float:
    """A rotational stiffness [N*m/rad] seen as a translational one [N/m] at radius [m]: c/r**2
    (thesis 4.2.2.1: 0.8 N*m/deg at the 20 mm drum radius -> 114.591 N/mm)."""
    if radius <= 0:
        raise WrsimError(f"stiffness: radius must be > 0, got {radius:g} m")
    return rotational / radius**2


def resultant_stiffness(*stiffnesses: float) -> float:
    """Springs in series (Eq. 4.42): 1/C = sum of 1/C_k; every C_k [N/m] must be > 0."""
    if not stiffnesses or any(c <= 0 for c in stiffnesses):
        raise WrsimError(f"stiffness: need one or more stiffnesses > 0, got {list(stiffnesses)}")
    return 1.0 / sum(1.0 / c for c in stiffnesses)


def system_stiffness_from_resultant(resultant: float, gauge: float, damper: float) -> float:
    """Eq. 4.42 solved for the window-regulator stiffness C2 [N/m] from the measured resultant C,
    the force gauge C1 and the rubber damper C3 (translational, see translational_stiffness)."""
    inv = 1.0 / resultant - 1.0 / gauge - 1.0 / damper
    if resultant <= 0 or gauge <= 0 or damper <= 0 or inv <= 0:
        raise WrsimError(
            f"stiffness: a resultant of {resultant:g} N/m is not softer than gauge "
            f"({gauge:g} N/m) and damper ({damper:g} N/m) in series; no positive "
            f"system stiffness fits Eq. 4.42"
        )
    return 1.0 / inv


def read_slider_forces(path: str | Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Read a slider friction measurement (load_force, force_top, force_bottom, all forces; one row per
    load step, load_force strictly rising). Returns the three columns in N."""
    table = read_table(
        path,
        increasing="load_force",
        require_source=True,
        columns=("load_force", "force_top", "force_bottom"),
        what="a slider friction measurement (docs/measurement-format.md)",
    )
    return table.column("load_force", "N"), table.column("force_top", "N"), table.column("force_bottom", "N")


def read_cable_forces(path: str | Path) -> tuple[np.ndarray, np.ndarray]:
    """Read a cable-force pair measurement of a pulley or bowden (force_a = pulling side, force_b =
    held side, forces). Returns both columns in N."""
    table = read_table(
        path,
        require_source=True,
        columns=("force_a", "force_b"),
        what="a cable-force measurement (docs/measurement-format.md)",
    )
    return table.column("force_a", "N"), table.column("force_b", "N")
