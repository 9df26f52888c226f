"""Two-mass analytical model (thesis 3.1): the exact VHDL-AMS simulation next to the method of averaging
(Fig. 3.2/3.3), and the averaging summary behind `wrsim averaging`.

The thesis's claim is that the exact relative displacement settles at the stationary amplitude of the averaged
system (Eq. 3.12 = 3.19). With its own parameters it does not, within 10 %: the averaging assumes the
perturbation to be O(eps), but there the forcing term eps*beta/m1 = |2 - nu**2| = 0.59, the damping eps*alpha
= 0.38 and the detuning eps*Delta = 0.19 are not small. The exact model (VHDL-AMS, confirmed by SciPy) settles
14.3 % (friction on the relative velocity) and 21.4 % (friction on M_2's velocity) below Eq. 3.12, so the bench
asserts that honest bound (THESIS_BOUND_PCT). A second run keeps alpha, beta and Delta (nearly) but shrinks eps
tenfold -- damping mu and detuning omega - sqrt(2)*omega_0 scaled by 0.1 -- and there the exact amplitude is
within 10 % of Eq. 3.12 in both cases (-1.9 %, -5.2 %).
"""

from __future__ import annotations

import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim.benches.core import (
    Bench,
    Judgement,
    Run,
    Session,
    Simulated,
    instance,
    metric,
)
from wrsim.closed_form.two_mass import (
    AveragedTrajectory,
    ExactTrajectory,
    FrictionCase,
    TwoMassGroups,
    TwoMassParams,
    averaged_trajectory,
    dimensionless_groups,
    envelope_amplitude,
    exact_trajectory,
    stationary_amplitude,
)
from wrsim.data.atomic import write_bytes_atomic
from wrsim.data.measurements import Table
from wrsim.errors import WrsimError
from wrsim.results import Metric, Plot, Signal

__all__ = ["CASES", "THESIS", "SMALL_EPS_SCALE", "CaseSummary", "summarize", "describe", "averaging_figure", "BENCHES"]

CASES: dict[FrictionCase, str] = {"relative": "case1", "m2": "case2"}  # friction case -> instance label in tb_two_mass
THESIS = {  # thesis 3.1.2.3
    "relative": TwoMassParams(M1=45.0, M2=5.0, c=2e4, mu=80.0, F_a=200.0, F_r=10.0, omega=75.8),
    "m2": TwoMassParams(M1=45.0, M2=5.0, c=2e4, mu=80.0, F_a=1800.0, F_r=90.0, omega=75.8),
}
A0 = 0.01  # thesis initial condition a(0) = 0.01, xi(0) = 0, V(0) = 0
THESIS_BOUND_PCT = {"relative": 15.0, "m2": 22.5}  # |exact/averaged - 1| with the thesis's parameters (measured
#                                                  -14.3 % and -21.4 %); the thesis's claim of agreement needs 10 %
SMALL_EPS_SCALE = 0.1  # damping and detuning factor of the run where averaging is valid
SETTLED_FROM = 3.5  # [s] amplitudes are measured from here to the end of the run


def _small_eps(p: TwoMassParams) -> tuple[float, float]:
    """(mu, omega) with damping and detuning from the main resonance sqrt(2)*omega_0 scaled by SMALL_EPS_SCALE:
    eps shrinks by that factor while alpha, beta and Delta stay nearly the same."""
    w_res = math.sqrt(2.0) * dimensionless_groups(p).omega0
    return p.mu * SMALL_EPS_SCALE, w_res + SMALL_EPS_SCALE * (p.omega - w_res)


# ------------------------------------------------------------------------------------------------
# the averaging summary (also `wrsim averaging`)
@dataclass(frozen=True)
class CaseSummary:
    """Everything the method of averaging says about one friction case, plus the exact and averaged runs."""

    case: FrictionCase
    params: TwoMassParams
    groups: TwoMassGroups
    amplitude: float | None  # dimensionless stationary amplitude a (Eq. 3.12), None if none exists
    amplitude_m: float | None  # [m] a*L
    no_amplitude: str  # why there is none ("" if there is one)
    averaged: AveragedTrajectory
    exact: ExactTrajectory | None


def summarize(case: FrictionCase, params: TwoMassParams, t_end: float, exact: bool = True) -> CaseSummary:
    """Groups, existence bound, stationary amplitude and the averaged (and optionally exact) trajectories
    from the thesis's initial condition. Below the existence bound the amplitude is None with the reason."""
    g = dimensionless_groups(params)
    try:
        a = stationary_amplitude(g.m1, g.alpha, g.beta, g.delta)
        reason = ""
    except WrsimError as e:
        if not str(e).startswith("no "):
            raise
        a, reason = None, str(e)
    averaged = averaged_trajectory(case, params, A0, t_end)
    ex = exact_trajectory(case, params, A0, t_end) if exact else None
    return CaseSummary(case, params, g, a, None if a is None else a * g.L, reason, averaged, ex)


def describe(s: CaseSummary) -> list[str]:
    """Text lines: groups, existence condition, stationary amplitude, averaged and exact settled amplitudes."""
    g, p = s.groups, s.params
    title = "friction on x2' - x1' (Eq. 3.2)" if s.case == "relative" else "friction on x2' (Eq. 3.13)"
    out = [
        f"{s.case}: {title}; M1 = {p.M1:g} kg, M2 = {p.M2:g} kg, c = {p.c:g} N/m, mu = {p.mu:g} N*s/m, "
        f"omega = {p.omega:g} 1/s, F_a = {p.F_a:g} N, F_r = {p.F_r:g} N",
        f"  groups: omega_0 = {g.omega0:.5g} 1/s, nu = {g.nu:.5g}, L = {g.L:.5g} m, eps = {g.eps:.5g}, "
        f"alpha = {g.alpha:.5g}, beta = {g.beta:.5g}, Delta = {g.delta:.5g}, m1 = {g.m1:.4g}, m2 = {g.m2:.4g}",
        f"  existence: beta = {g.beta:.5g} {'>' if g.beta > g.existence_bound else '<='} 4 m1/(pi m2) = "
        f"{g.existence_bound:.5g}",
    ]
    t_end = s.averaged.t[-1]
    if s.amplitude is None:
        out.append(
            f"  stationary amplitude: none ({s.no_amplitude}); averaged a*L at {t_end:g} s = "
            f"{s.averaged.amplitude_m[-1]:.4g} m"
        )
    else:
        out.append(
            f"  stationary amplitude (Eq. 3.12): a = {s.amplitude:.5g}, a*L = {s.amplitude_m:.5g} m; "
            f"averaged system at {t_end:g} s: {s.averaged.amplitude_m[-1]:.5g} m"
        )
    if s.exact is not None:
        amp = envelope_amplitude(s.exact.t, s.exact.z, 0.75 * t_end)
        vs = f" ({(amp / s.amplitude_m - 1) * 100:+.1f} % vs Eq. 3.12)" if s.amplitude_m else ""
        out.append(f"  exact system, settled amplitude over the last quarter: {amp:.5g} m{vs}")
    return out


def averaging_figure(path: Path, summaries: list[CaseSummary]) -> Path:
    """Fig. 3.2/3.3: exact relative displacement and the averaged amplitude envelope, one panel per case."""
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 3.2 * len(summaries)), layout="constrained")
    for k, s in enumerate(summaries):
        ax = fig.add_subplot(len(summaries), 1, k + 1)
        if s.exact is not None:
            ax.plot(s.exact.t, s.exact.z * 1e3, lw=0.6, label="exact x2* - x1*")
        env = s.averaged.amplitude_m * 1e3
        ax.plot(s.averaged.t, env, "C1", label="averaged a*L")
        ax.plot(s.averaged.t, -env, "C1")
        if s.amplitude_m is not None:
            ax.axhline(s.amplitude_m * 1e3, color="C2", ls="--", label=f"Eq. 3.12: {s.amplitude_m * 1e3:.3g} mm")
        ax.set_title(
            f"friction on {'x2* - x1*' if s.case == 'relative' else 'x2*'}: F_a = {s.params.F_a:g} N, "
            f"F_r = {s.params.F_r:g} N"
        )
        ax.set_xlabel("time [s]")
        ax.set_ylabel("relative displacement [mm]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="lower right")
    png = io.BytesIO()
    fig.savefig(png, format="png", dpi=100)
    write_bytes_atomic(path, png.getvalue())
    return path


# ------------------------------------------------------------------------------------------------
# the bench
def _params_of(s: Simulated, label: str) -> TwoMassParams:
    g = instance(s.design.tree, label).generics
    return TwoMassParams(g["m1"], g["m2"], g["c"], g["mu"], g["f_a"], g["f_r"], g["omega"])


def _judge(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    metrics: list[Metric] = []
    plots: list[Plot] = []
    t = np.linspace(0.0, bench.stop, 6001)
    signals = [Signal("time", "s", t)]
    for s in sims:
        run = s.run.label
        for case, label in CASES.items():
            p = _params_of(s, label)
            ref = summarize(case, p, bench.stop, exact=True)
            z = s.waves[f"{label}.z"]
            amp = envelope_amplitude(s.waves.time, z, SETTLED_FROM)
            if ref.amplitude_m is None or ref.exact is None:
                raise WrsimError(f"{run} {label}: no stationary amplitude ({ref.no_amplitude})")
            amp_scipy = envelope_amplitude(ref.exact.t, ref.exact.z, SETTLED_FROM)
            dev = (amp / ref.amplitude_m - 1.0) * 100.0
            g = ref.groups
            metrics.append(
                metric(
                    f"{run} {label}: exact amplitude, VHDL-AMS vs SciPy",
                    (amp / amp_scipy - 1) * 100,
                    0.0,
                    1.0,
                    "%",
                    f"{amp:.5g} m vs {amp_scipy:.5g} m (LSODA, same equations)",
                )
            )
            metrics.append(
                metric(
                    f"{run} {label}: averaged system settles to Eq. 3.12",
                    (ref.averaged.amplitude_m[-1] / ref.amplitude_m - 1) * 100,
                    0.0,
                    0.1,
                    "%",
                    f"a = {ref.amplitude:.4g}, a*L = {ref.amplitude_m:.4g} m",
                )
            )
            bound = THESIS_BOUND_PCT[case] if run == "thesis" else 10.0
            note = f"eps = {g.eps:.3g}, alpha = {g.alpha:.3g}, beta = {g.beta:.3g}, Delta = {g.delta:.3g}; " + (
                "honest bound: the thesis's parameters do not make the perturbation small (|2 - nu^2| = "
                f"{abs(2 - g.nu**2):.2f}); the thesis's 10 % agreement holds in run eps01"
                if run == "thesis"
                else "eps small: the method of averaging applies"
            )
            metrics.append(metric(f"{run} {label}: exact vs averaged stationary amplitude", dev, 0.0, bound, "%", note))
            z_grid = np.interp(t, s.waves.time, z)
            env = np.interp(t, ref.averaged.t, ref.averaged.amplitude_m)
            signals += [Signal(f"z_{label}_{run}", "m", z_grid), Signal(f"averaged_{label}_{run}", "m", env)]
            plots.append(
                Plot(
                    f"{bench.name} {run}: {label} (friction on {'x2-x1' if case == 'relative' else 'x2'}),"
                    f" Eq. 3.12 = {ref.amplitude_m:.3g} m, exact {amp:.3g} m",
                    signals[0],
                    [
                        Signal("x2-x1 exact (VHDL-AMS)", "m", z_grid),
                        Signal("averaged +-a*L", "m", env),
                        Signal("averaged +-a*L", "m", -env),
                    ],
                    [],
                    [],
                    f"{run}_{label}.png",
                )
            )
    return Judgement(metrics=metrics, plots=plots, waveforms=signals)


_MU_S, _OMEGA_S = _small_eps(THESIS["relative"])

BENCHES = [
    Bench(
        name="two-mass",
        entity="tb_two_mass",
        description="Two-mass model, exact (VHDL-AMS) vs method of averaging, friction on x2'-x1' (F_a 200 N, F_r "
        "10 N) and "
        "on x2' (1800 N, 90 N); thesis parameters and eps/10 (thesis 3.1.2.3, Fig. 3.2/3.3)",
        stop=5.0,
        max_step=2.5e-4,
        runs=(Run("thesis", {}), Run("eps01", {"mu": _MU_S, "omega": _OMEGA_S})),
        judge=_judge,
    ),
]
