"""The analytic two-mass model of the window regulator (thesis 3.1, Fig. 3.1), SI units.

* **Two-mass model** (thesis 3.1, Fig. 3.1): dimensionless groups, the existence condition and the
  stationary amplitude of the method of averaging (Eq. 3.11, 3.12 = 3.19), the averaged slow-variable
  system (Eq. 3.10 and 3.16-3.18) and the exact equations of motion (Eq. 3.2 and 3.13), both integrated
  with :func:`scipy.integrate.solve_ivp`.

Reconstructions of equations that the thesis prints garbled are stated where they are used
(search for "Reconstructed").

Friction cases of the two-mass model (the ``case`` argument):

``"relative"``
    Sec. 3.1.2.1: the dry friction on M_2 is ``-F_r sgn(x2' - x1')`` (Eq. 3.2b).
``"m2"``
    Sec. 3.1.2.2: the dry friction on M_2 is ``-F_r sgn(x2')`` (Eq. 3.13b).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

from wrsim.errors import WrsimError, finite, non_negative, positive

__all__ = [
    "FrictionCase",
    "FRICTION_CASES",
    "DEFAULT_V_THRESHOLD",
    "TwoMassParams",
    "TwoMassGroups",
    "dimensionless_groups",
    "existence_bound",
    "stationary_amplitude",
    "stationary_amplitude_m",
    "averaged_rates",
    "AveragedTrajectory",
    "averaged_trajectory",
    "ExactTrajectory",
    "exact_trajectory",
    "envelope_amplitude",
]

FrictionCase = Literal["relative", "m2"]
FRICTION_CASES: tuple[str, ...] = ("relative", "m2")

#: Velocity threshold [m/s] of the smoothed sign function used for the dry friction in
#: :func:`exact_trajectory`: ``sgn(v)`` is replaced by ``clip(v / v_th, -1, 1)``, i.e. the friction force
#: grows linearly with velocity below ``v_th`` -- the same regularization the thesis uses in its numerical
#: friction models (4.1.2.4: "friction torque is linearly proportional to relative rotational velocity when
#: rotational velocity is close to zero", threshold "in milli or even micro"). 1 mm/s is about 1 % of the
#: sliding-velocity amplitude of the thesis examples (about 0.1 m/s and more).
DEFAULT_V_THRESHOLD = 1.0e-3

_SQRT2 = math.sqrt(2.0)
_HALF_PI = 0.5 * math.pi
# Regularization of the amplitude in the Cartesian form of the averaged system (dimensionless); only matters
# when the relative oscillation dies out (a -> 0, dry friction sticking).
_A_EPS = 1.0e-6


def _case(value: object) -> str:
    if not isinstance(value, str) or value not in FRICTION_CASES:
        raise WrsimError(f"case must be one of {', '.join(repr(c) for c in FRICTION_CASES)}, got {value!r}")
    return value


# --------------------------------------------------------------------------------- two-mass model (3.1)


@dataclass(frozen=True)
class TwoMassParams:
    """Dimensional parameters of the two-mass model, Fig. 3.1 and Eq. 3.2 / 3.13.

    Attributes:
        M1: equivalent mass of the motor armature [kg] (Eq. 3.24), > 0.
        M2: glass mass [kg], > 0.
        c: system stiffness [N/m], > 0.
        mu: damping factor [N*s/m], >= 0.
        F_a: amplitude of the harmonic driving force ``F_a sin(omega t)`` on M1 [N], > 0.
        F_r: amplitude of the dry friction force on M2 [N], > 0.
        omega: angular frequency of the driving force [1/s], > 0.
    """

    M1: float
    M2: float
    c: float
    mu: float
    F_a: float
    F_r: float
    omega: float

    def __post_init__(self) -> None:
        for name in ("M1", "M2", "c", "F_a", "F_r", "omega"):
            object.__setattr__(self, name, positive(name, getattr(self, name)))
        object.__setattr__(self, "mu", non_negative("mu", self.mu))


@dataclass(frozen=True)
class TwoMassGroups:
    """Scales and dimensionless groups of Sec. 3.1.2.1 (defined below Eq. 3.2).

    Attributes:
        omega0: time scale ``omega_0 = sqrt(c (M1 + M2) / (2 M1 M2))`` [1/s].
        L: length scale [m].
        nu: ``omega / omega_0``.
        eps: ``epsilon = F_r / (M L omega_0^2)``, ``M = M1 + M2``.
        alpha: ``mu L omega_0 / (F_r m1 m2)``.
        beta: ``F_a / F_r``.
        delta: detuning ``Delta`` from ``nu = sqrt(2) + epsilon Delta``.
        m1: ``M1 / M``.
        m2: ``M2 / M``.
    """

    omega0: float
    L: float
    nu: float
    eps: float
    alpha: float
    beta: float
    delta: float
    m1: float
    m2: float

    @property
    def existence_bound(self) -> float:
        """``4 m1 / (pi m2)``: a stationary amplitude exists only for ``beta`` above it (after Eq. 3.11)."""
        return 4.0 * self.m1 / (math.pi * self.m2)


def _omega0(p: TwoMassParams) -> float:
    return math.sqrt(p.c * (p.M1 + p.M2) / (2.0 * p.M1 * p.M2))


def dimensionless_groups(params: TwoMassParams, L: float | None = None) -> TwoMassGroups:
    """Scales and dimensionless groups of the two-mass model exactly as defined in Sec. 3.1.2.1.

    ``omega_0^2 = c (M1 + M2) / (2 M1 M2)``, ``nu = omega / omega_0``, ``epsilon = F_r / (M L omega_0^2)``,
    ``alpha = mu L omega_0 / (F_r m1 m2)``, ``beta = F_a / F_r``, ``m_i = M_i / M``; ``Delta`` follows from
    ``nu = sqrt(2) + epsilon Delta`` (the detuning from the main resonance, before Eq. 3.9).

    The length scale defaults to the thesis's choice (3.1.2.3, after [76])
    ``L = F_a / (M1 omega_0^2 |2 - nu^2|)``, which is undefined at exact resonance ``nu^2 = 2``; pass ``L``
    explicitly there. Dimensional results (``a * L``) do not depend on the choice of ``L``.
    """
    if not isinstance(params, TwoMassParams):
        raise WrsimError(f"params must be a TwoMassParams, got {type(params).__name__}")
    p = params
    w0 = _omega0(p)
    nu = p.omega / w0
    if L is None:
        detune = abs(2.0 - nu * nu)
        if detune < 1e-12:
            raise WrsimError(
                f"omega = {p.omega:.6g} 1/s is the main resonance sqrt(2)*omega_0, where the default length "
                "scale L = F_a/(M1 omega_0^2 |2 - nu^2|) is undefined; pass L explicitly"
            )
        length = p.F_a / (p.M1 * w0 * w0 * detune)
    else:
        length = positive("L", L)
    M = p.M1 + p.M2
    m1 = p.M1 / M
    m2 = p.M2 / M
    eps = p.F_r / (M * length * w0 * w0)
    alpha = p.mu * length * w0 / (p.F_r * m1 * m2)
    beta = p.F_a / p.F_r
    delta = (nu - _SQRT2) / eps
    return TwoMassGroups(omega0=w0, L=length, nu=nu, eps=eps, alpha=alpha, beta=beta, delta=delta, m1=m1, m2=m2)


def existence_bound(m1: float) -> float:
    """Lower bound ``4 m1 / (pi m2)`` on ``beta`` for a positive stationary amplitude (text after Eq. 3.11).

    Args:
        m1: mass fraction ``M1 / (M1 + M2)``, in (0, 1); ``m2 = 1 - m1``.
    """
    x = finite("m1", m1)
    if not 0.0 < x < 1.0:
        raise WrsimError(f"m1 must be in (0, 1), got {x!r}")
    return 4.0 * x / (math.pi * (1.0 - x))


def stationary_amplitude(m1: float, alpha: float, beta: float, delta: float) -> float:
    """Dimensionless stationary amplitude ``a`` of the averaged system, Eq. 3.12 (= Eq. 3.19).

    ``a`` is the positive root of Eq. 3.11,
    ``2 m1^2 m2^2 pi^2 (alpha^2 + 4 Delta^2) a^2 + 8 sqrt(2) m1^2 m2 pi alpha a + (16 m1^2 - m2^2 pi^2 beta^2)
    = 0`` (Reconstructed: the thesis prints the first term with ``alpha^2`` where ``a^2`` is meant), i.e.
    Eq. 3.12 ``a = (-4 sqrt(2) m1 alpha + sqrt(2 [m2^2 pi^2 beta^2 (alpha^2 + 4 Delta^2) - 64 Delta^2 m1^2]))
    / (2 m1 m2 pi (alpha^2 + 4 Delta^2))``. It is evaluated in the algebraically identical rationalized form
    ``a = -2 C / (B + sqrt(B^2 - 4 A C))`` (A, B, C the coefficients above), which stays accurate near the
    existence bound and finite for ``alpha = 0``. The same value holds for both friction cases.

    Raises:
        WrsimError: if ``beta <= 4 m1/(pi m2)`` (no stationary amplitude), or if ``alpha = Delta = 0``
            (undamped exact resonance: no bounded amplitude).
    """
    bound = existence_bound(m1)
    a_ = non_negative("alpha", alpha)
    b_ = positive("beta", beta)
    d_ = finite("delta", delta)
    m1_ = float(m1)
    m2_ = 1.0 - m1_
    if b_ <= bound:
        raise WrsimError(f"no stationary amplitude: beta = {b_:.6g} <= 4 m1/(pi m2) = {bound:.6g}")
    pi2 = math.pi * math.pi
    A = 2.0 * m1_**2 * m2_**2 * pi2 * (a_**2 + 4.0 * d_**2)
    B = 8.0 * _SQRT2 * m1_**2 * m2_ * math.pi * a_
    C = 16.0 * m1_**2 - m2_**2 * pi2 * b_**2  # < 0 above the existence bound
    denom = B + math.sqrt(B * B - 4.0 * A * C)
    if denom <= 0.0:
        raise WrsimError("no bounded stationary amplitude: alpha = 0 and delta = 0 (undamped exact resonance)")
    return -2.0 * C / denom


def stationary_amplitude_m(params: TwoMassParams) -> float:
    """Dimensional stationary amplitude [m] of the relative displacement ``x2* - x1*`` (Eq. 3.12 times L).

    Valid for both friction cases (Eq. 3.12 = Eq. 3.19). The product ``a L`` is independent of the length
    scale: under ``L -> k L`` one has ``epsilon -> epsilon/k``, ``alpha -> k alpha``, ``Delta -> k Delta`` and
    Eq. 3.12 gives ``a -> a/k``.

    Raises:
        WrsimError: if ``F_a/F_r <= 4 M1/(pi M2)`` (no stationary amplitude).
    """
    if not isinstance(params, TwoMassParams):
        raise WrsimError(f"params must be a TwoMassParams, got {type(params).__name__}")
    w0 = _omega0(params)
    nu = params.omega / w0
    # any positive length works; use the thesis's scale unless it is undefined (exact resonance)
    length = None if abs(2.0 - nu * nu) >= 1e-12 else params.F_a / (params.M1 * w0 * w0)
    g = dimensionless_groups(params, length)
    return stationary_amplitude(g.m1, g.alpha, g.beta, g.delta) * g.L


def averaged_rates(
    case: FrictionCase, groups: TwoMassGroups, V: float, a: float, xi: float
) -> tuple[float, float, float]:
    """Right-hand side ``(dV/dt, da/dt, dxi/dt)`` of the averaged system in dimensionless time ``t = omega_0 t*``.

    ``case="relative"``: Eq. 3.10,
    ``V' = 0``,
    ``a' = -(eps/sqrt(2)) [2/(pi m2) + alpha a sqrt(2)/2 - beta cos(xi)/(2 m1)]``,
    ``xi' = eps Delta - eps beta sin(xi) / (2 sqrt(2) m1 a)``.

    ``case="m2"``: Eq. 3.16-3.18 with ``s = V/(m1 a sqrt(2))``:
    ``V' = -eps (2/pi) arcsin(s)`` for ``|s| <= 1`` and ``-eps sgn(V)`` otherwise;
    ``a'`` as above with the friction term ``2/(pi m2)`` multiplied by ``sqrt(1 - s^2)`` (and absent for
    ``|s| > 1``); ``xi'`` as above.

    Reconstructed: the thesis's averaging operator must read ``<...> = (1/2pi) int_0^2pi (...) dphi``; the
    forcing term of Eq. 3.10b must carry the factor 1/2 (``beta cos(xi)/(2 m1)``) that Eq. 3.17 has -- only
    then do Eq. 3.11/3.12 and the bound ``beta > 4 m1/(pi m2)`` follow; Eq. 3.8c reads
    ``phi' = theta' + sqrt(2)`` (printed ``a' + sqrt(2)``), and ``z' = -a sqrt(2) sin(phi)`` in 3.1.2.2.

    Args:
        case: ``"relative"`` (Sec. 3.1.2.1) or ``"m2"`` (Sec. 3.1.2.2).
        groups: from :func:`dimensionless_groups`.
        V: dimensionless velocity of the centre of mass.
        a: dimensionless amplitude of the relative displacement, > 0 (``xi'`` is singular at 0).
        xi: slow phase ``xi = nu t - phi`` [rad].
    """
    c = _case(case)
    if not isinstance(groups, TwoMassGroups):
        raise WrsimError(f"groups must be a TwoMassGroups, got {type(groups).__name__}")
    V_ = finite("V", V)
    a_ = positive("a", a)
    xi_ = finite("xi", xi)
    g = groups
    if c == "relative":
        dV, fric = 0.0, 1.0
    else:
        s = V_ / (g.m1 * a_ * _SQRT2)
        if abs(s) <= 1.0:
            dV, fric = -g.eps * (2.0 / math.pi) * math.asin(s), math.sqrt(1.0 - s * s)
        else:
            dV, fric = -g.eps * math.copysign(1.0, V_), 0.0
    da = -(g.eps / _SQRT2) * (
        2.0 / (math.pi * g.m2) * fric + g.alpha * a_ * _SQRT2 / 2.0 - g.beta * math.cos(xi_) / (2.0 * g.m1)
    )
    dxi = g.eps * g.delta - g.eps * g.beta * math.sin(xi_) / (2.0 * _SQRT2 * g.m1 * a_)
    return dV, da, dxi


@dataclass(frozen=True)
class AveragedTrajectory:
    """Solution of the averaged system (Eq. 3.10 or 3.16-3.18).

    Attributes:
        t: dimensional time [s].
        a: dimensionless amplitude of the relative displacement.
        xi: slow phase [rad], wrapped to (-pi, pi].
        V: dimensionless velocity of the centre of mass.
        groups: the dimensionless groups used.
    """

    t: np.ndarray
    a: np.ndarray
    xi: np.ndarray
    V: np.ndarray
    groups: TwoMassGroups

    @property
    def amplitude_m(self) -> np.ndarray:
        """Dimensional amplitude ``a * L`` of the relative displacement [m]."""
        return self.a * self.groups.L


def _check_time(t_end: object) -> float:
    return positive("t_end", t_end)


def averaged_trajectory(
    case: FrictionCase,
    params: TwoMassParams,
    a0: float,
    t_end: float,
    *,
    xi0: float = 0.0,
    V0: float = 0.0,
    L: float | None = None,
    n_points: int = 2001,
) -> AveragedTrajectory:
    """Integrate the averaged slow-variable system (Eq. 3.10, or Eq. 3.16-3.18) from ``t = 0`` to ``t_end``.

    The slow variables are integrated in the Cartesian form ``u = a cos(xi)``, ``w = a sin(xi)``:
    ``u' = -eps alpha u/2 - eps Delta w + eps beta/(2 sqrt(2) m1) - F u/a``,
    ``w' = -eps alpha w/2 + eps Delta u - F w/a``, ``F = eps sqrt(2)/(pi m2)`` times the friction factor of
    :func:`averaged_rates`. For ``a > 0`` this is algebraically identical to Eq. 3.10 / 3.17-3.18 but avoids
    the ``1/a`` singularity of ``xi'``; in the dry-friction term ``a`` is regularized as
    ``sqrt(a^2 + 1e-12)`` so the amplitude can die out (sticking) when ``beta`` is below the existence bound.

    Args:
        case: ``"relative"`` (Sec. 3.1.2.1) or ``"m2"`` (Sec. 3.1.2.2).
        params: dimensional parameters.
        a0: initial dimensionless amplitude, >= 0 (the thesis uses 0.01).
        t_end: end time [s], > 0.
        xi0: initial slow phase [rad] (thesis: 0).
        V0: initial dimensionless centre-of-mass velocity (thesis: 0).
        L: length scale [m]; default as in :func:`dimensionless_groups`.
        n_points: number of output samples, >= 2.
    """
    from scipy.integrate import solve_ivp

    c = _case(case)
    g = dimensionless_groups(params, L)
    a_start = non_negative("a0", a0)
    t_stop = _check_time(t_end)
    xi_start = finite("xi0", xi0)
    v_start = finite("V0", V0)
    if isinstance(n_points, bool) or not isinstance(n_points, int) or n_points < 2:
        raise WrsimError(f"n_points must be an integer >= 2, got {n_points!r}")

    eps, alpha, delta, m1, m2, beta = g.eps, g.alpha, g.delta, g.m1, g.m2, g.beta
    force = eps * beta / (2.0 * _SQRT2 * m1)
    k_fric = eps * _SQRT2 / (math.pi * m2)
    relative = c == "relative"

    def rhs(_tau: float, y: np.ndarray) -> list[float]:
        u, w, V = float(y[0]), float(y[1]), float(y[2])
        a_reg = math.sqrt(u * u + w * w + _A_EPS * _A_EPS)
        if relative:
            dV, fric = 0.0, 1.0
        else:
            s = V / (m1 * a_reg * _SQRT2)
            if abs(s) <= 1.0:
                dV, fric = -eps * (2.0 / math.pi) * math.asin(s), math.sqrt(1.0 - s * s)
            else:
                dV, fric = -eps * math.copysign(1.0, V), 0.0
        f = k_fric * fric / a_reg
        du = -0.5 * eps * alpha * u - eps * delta * w + force - f * u
        dw = -0.5 * eps * alpha * w + eps * delta * u - f * w
        return [du, dw, dV]

    tau_end = t_stop * g.omega0
    tau = np.linspace(0.0, tau_end, n_points)
    y0 = [a_start * math.cos(xi_start), a_start * math.sin(xi_start), v_start]
    sol = solve_ivp(rhs, (0.0, tau_end), y0, method="LSODA", t_eval=tau, rtol=1e-8, atol=1e-10)
    if not sol.success or not np.all(np.isfinite(sol.y)):
        raise WrsimError(f"averaged system ({c}) could not be integrated to t_end = {t_stop:g} s: {sol.message}")
    u, w, V = sol.y
    return AveragedTrajectory(t=sol.t / g.omega0, a=np.hypot(u, w), xi=np.arctan2(w, u), V=V, groups=g)


@dataclass(frozen=True)
class ExactTrajectory:
    """Solution of the exact two-mass equations of motion (Eq. 3.2 or 3.13).

    Attributes:
        t: time [s].
        z: relative displacement ``x2* - x1*`` [m].
        x1: displacement of M1 [m].
        x2: displacement of M2 [m].
    """

    t: np.ndarray
    z: np.ndarray
    x1: np.ndarray
    x2: np.ndarray


def exact_trajectory(
    case: FrictionCase,
    params: TwoMassParams,
    a0: float,
    t_end: float,
    *,
    xi0: float = 0.0,
    V0: float = 0.0,
    L: float | None = None,
    v_threshold: float = DEFAULT_V_THRESHOLD,
    points_per_period: int = 64,
) -> ExactTrajectory:
    """Integrate the exact dimensional two-mass model, Eq. 3.2 (``"relative"``) or Eq. 3.13 (``"m2"``).

    ``M1 x1'' + c (x1 - x2) + mu (x1' - x2') = F_a sin(omega t)``,
    ``M2 x2'' + c (x2 - x1) + mu (x2' - x1') = -F_r sgn(v)`` with ``v = x2' - x1'`` or ``v = x2'``.
    ``sgn`` is smoothed to ``clip(v / v_threshold, -1, 1)`` (see :data:`DEFAULT_V_THRESHOLD`).

    The initial state is the one the averaged system starts from (``a0, xi0, V0`` in the scaling of
    :func:`dimensionless_groups`): ``z = a0 L cos(xi0)``, ``z' = sqrt(2) a0 L omega_0 sin(xi0)``, centre-of-mass
    position 0 and velocity ``V0 L omega_0``. The thesis's runs use ``a0 = 0.01, xi0 = 0, V0 = 0``.

    Args:
        case: ``"relative"`` or ``"m2"``.
        params: dimensional parameters.
        a0: initial dimensionless amplitude, >= 0.
        t_end: end time [s], > 0.
        xi0, V0, L: see above.
        v_threshold: velocity threshold of the smoothed sign [m/s], > 0.
        points_per_period: output samples per forcing period ``2 pi / omega``, >= 8.
    """
    from scipy.integrate import solve_ivp

    c = _case(case)
    g = dimensionless_groups(params, L)
    a_start = non_negative("a0", a0)
    t_stop = _check_time(t_end)
    xi_start = finite("xi0", xi0)
    v_start = finite("V0", V0)
    vth = positive("v_threshold", v_threshold)
    if isinstance(points_per_period, bool) or not isinstance(points_per_period, int) or points_per_period < 8:
        raise WrsimError(f"points_per_period must be an integer >= 8, got {points_per_period!r}")

    p = params
    M1, M2, k, d, Fa, Fr, w = p.M1, p.M2, p.c, p.mu, p.F_a, p.F_r, p.omega
    relative = c == "relative"

    def rhs(t: float, y: np.ndarray) -> list[float]:
        x1, x2, v1, v2 = float(y[0]), float(y[1]), float(y[2]), float(y[3])
        s = ((v2 - v1) if relative else v2) / vth
        sgn = 1.0 if s > 1.0 else (-1.0 if s < -1.0 else s)
        coupling = k * (x1 - x2) + d * (v1 - v2)
        return [v1, v2, (Fa * math.sin(w * t) - coupling) / M1, (coupling - Fr * sgn) / M2]

    m1, m2 = g.m1, g.m2
    z0 = a_start * g.L * math.cos(xi_start)
    zd0 = _SQRT2 * a_start * g.L * g.omega0 * math.sin(xi_start)
    vc0 = v_start * g.L * g.omega0
    y0 = [-m2 * z0, m1 * z0, vc0 - m2 * zd0, vc0 + m1 * zd0]

    period = 2.0 * math.pi / w
    n = max(2, int(math.ceil(t_stop / period * points_per_period)) + 1)
    t_eval = np.linspace(0.0, t_stop, n)
    # absolute tolerances scaled to the problem: positions ~ L, velocities ~ L omega_0
    atol = np.array([1e-7 * g.L, 1e-7 * g.L, 1e-7 * g.L * g.omega0, 1e-7 * g.L * g.omega0])
    sol = solve_ivp(rhs, (0.0, t_stop), y0, method="LSODA", t_eval=t_eval, rtol=1e-7, atol=atol, max_step=period / 16.0)
    if not sol.success or not np.all(np.isfinite(sol.y)):
        raise WrsimError(f"exact two-mass model ({c}) could not be integrated to t_end = {t_stop:g} s: {sol.message}")
    x1, x2 = sol.y[0], sol.y[1]
    return ExactTrajectory(t=sol.t, z=x2 - x1, x1=x1, x2=x2)


def envelope_amplitude(t: np.ndarray, x: np.ndarray, t_from: float) -> float:
    """Settled oscillation amplitude of the samples ``x(t)`` with ``t >= t_from``.

    The window is cut into oscillation cycles at upward crossings (with hysteresis of a quarter of the
    window's half range, around a linear trend, so small higher harmonics or a slow drift do not create
    spurious cycles); the result is the median over the complete cycles of ``(max - min) / 2``. A constant
    signal has amplitude 0.

    Raises:
        WrsimError: if ``t``/``x`` are not matching finite 1-D arrays with increasing ``t``, if ``t_from`` is
            outside ``t``, or if the window holds less than one complete cycle.
    """
    tt = np.asarray(t, dtype=float)
    xx = np.asarray(x, dtype=float)
    if tt.ndim != 1 or tt.size < 3:
        raise WrsimError(f"t must be a 1-D array of at least 3 samples, got shape {tt.shape}")
    if xx.shape != tt.shape:
        raise WrsimError(f"x must have the same shape as t {tt.shape}, got {xx.shape}")
    if not np.all(np.isfinite(tt)) or np.any(np.diff(tt) <= 0.0):
        raise WrsimError("t must be finite and strictly increasing")
    if not np.all(np.isfinite(xx)):
        raise WrsimError("x must be finite")
    start = finite("t_from", t_from)
    if not tt[0] <= start < tt[-1]:
        raise WrsimError(f"t_from must lie in [{tt[0]:g}, {tt[-1]:g}), got {start!r}")
    sel = tt >= start
    tw, xw = tt[sel], xx[sel]
    if tw.size < 3:
        raise WrsimError(f"t_from = {start:g} leaves fewer than 3 samples")
    half_range = 0.5 * float(np.max(xw) - np.min(xw))
    if half_range == 0.0:
        return 0.0
    trend = np.polyval(np.polyfit(tw - tw[0], xw, 1), tw - tw[0])
    r = xw - trend
    h = 0.25 * 0.5 * float(np.max(r) - np.min(r))
    ups: list[int] = []
    armed = False
    for i, val in enumerate(r):
        if val < -h:
            armed = True
        elif val > h and armed:
            ups.append(i)
            armed = False
    if len(ups) < 2:
        raise WrsimError(f"t_from = {start:g}: fewer than one complete oscillation cycle after t_from")
    amps = [0.5 * float(np.max(xw[i0:i1]) - np.min(xw[i0:i1])) for i0, i1 in zip(ups[:-1], ups[1:])]
    return float(np.median(amps))
