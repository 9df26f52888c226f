"""The VHDL-AMS corpus (tests/corpus/): small IEEE 1076.1 models, one testbench entity per file, each simulated
with `wrsim run`, once with behavioural sources and once with compiled models (`--compile`, OSDI), and compared
with a closed form or a SciPy reference (solve_ivp, rtol 1e-10).

A waveform passes when its largest error over the simulated time points is at most 1e-3 of the larger of the
reference's largest magnitude and the check's floor; points within 1e-3 of the stop time of a discontinuity of
the reference (a reset, a sample instant) are not compared there, the timing of such events is checked on its
own: the time at which a column crosses a level must match the closed form within 1e-3 relative. `wrsim run`
writes its table on 2001 uniform points (benches.core.resampled), so a crossing is known to lie between two
rows: the closed-form time must be within 1e-3 relative of that interval (stop times are chosen so that an
interval is about 1e-3 of the event's time or less).

The models of tests/corpus/analysis run an analysis instead of a transient (a DC sweep, AC, noise: `Case.analysis`)
and are judged the same way over the table's first column (the swept generic, the frequency); a noise density,
which spans decades, within 1e-3 of the reference at each point. AC and noise run the compiled equations only:
with behavioural sources they are one error."""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from conftest import table
from wrsim import paths
from wrsim.cli import main

CORPUS = paths.ROOT / "tests" / "corpus"
RTOL = 1e-3

Ref = Callable[[np.ndarray], np.ndarray]


@dataclass(frozen=True)
class Wave:
    """`column` (a quantity's name as the waveform table heads it, without the '_<top>[unit]' suffix) against
    `ref`(t) (t: the table's first column, the frequency of an AC or noise analysis, the swept generic of a DC
    sweep); `floor`: the smallest scale of the tolerance; `jumps`: times of discontinuities of the reference."""

    column: str
    ref: Ref
    floor: float = 1e-9
    jumps: Sequence[float] = ()
    pointwise: bool = False  # the tolerance is 1e-3 of |ref| at each point (densities over decades)


@dataclass(frozen=True)
class Event:
    """The `nth` (from 0) crossing of `level` by `column` in `direction` (+1 rising, -1 falling) happens at `at`."""

    column: str
    level: float
    at: float
    direction: int = 1
    nth: int = 0


@dataclass(frozen=True)
class Case:
    file: str  # relative to tests/corpus
    top: str
    stop: float
    max_step: float
    checks: Sequence[Wave | Event] = field(default_factory=tuple)
    analysis: tuple[str, ...] = ()  # instead of a transient to `stop`: wrsim run's --dc, --ac or --noise options
    table: str = "waveforms.csv"  # ... and the table it writes


# ---------------------------------------------------------------------------------------------------------------
# closed forms and references


def _exp_rise(scale: float, tau: float, t0: float = 0.0) -> Ref:
    return lambda t: np.where(t >= t0, scale * (1.0 - np.exp(-(t - t0) / tau)), 0.0)


def _exp_decay(scale: float, tau: float) -> Ref:
    return lambda t: scale * np.exp(-t / tau)


def _second_order_step(w0: float, sigma: float, scale: float = 1.0) -> Ref:
    """scale*(1 - exp(-sigma*t)*(cos(wd*t) + sigma/wd*sin(wd*t))), wd = sqrt(w0**2 - sigma**2)."""
    wd = np.sqrt(w0**2 - sigma**2)
    return lambda t: scale * (1.0 - np.exp(-sigma * t) * (np.cos(wd * t) + sigma / wd * np.sin(wd * t)))


def _second_order_impulse(w0: float, sigma: float, scale: float = 1.0) -> Ref:
    """scale*(w0**2/wd)*exp(-sigma*t)*sin(wd*t): the derivative of _second_order_step."""
    wd = np.sqrt(w0**2 - sigma**2)
    return lambda t: scale * w0**2 / wd * np.exp(-sigma * t) * np.sin(wd * t)


def _ivp(rhs: Callable, y0: Sequence[float], stop: float, method: str = "DOP853"):
    """Dense solution of y' = rhs(t, y) from y0 on [0, stop]."""
    sol = solve_ivp(rhs, (0.0, stop), list(y0), method=method, rtol=1e-10, atol=1e-12, dense_output=True)
    assert sol.success, sol.message
    return sol.sol


def _state(solution: Callable[[], Callable], index: int, scale: float = 1.0) -> Ref:
    return lambda t: scale * solution()(t)[index]


@functools.cache
def _ladder():
    r, c = 1e3, 1e-6

    def rhs(t, x):
        x0 = 1.0
        return [
            ((x0 - x[0]) - (x[0] - x[1])) / (r * c),
            ((x[0] - x[1]) - (x[1] - x[2])) / (r * c),
            (x[1] - x[2]) / (r * c),
        ]

    return _ivp(rhs, [0.0, 0.0, 0.0], 10e-3)


@functools.cache
def _rectifier():
    amp, f, i_s, nvt, rl, c = 5.0, 1e3, 1e-14, 0.02585, 1e3, 10e-6

    def rhs(t, y):
        vd = amp * np.sin(2 * np.pi * f * t) - y[0]
        return [(i_s * np.expm1(min(vd / nvt, 80.0)) - y[0] / rl) / c]  # trial steps of Radau may overshoot

    return _ivp(rhs, [0.0], 3e-3, method="Radau")


@functools.cache
def _two_mass():
    f, m1, m2, k1, k2, d1, d2 = 2.0, 1.0, 0.5, 100.0, 50.0, 1.0, 3.0

    def rhs(t, y):
        x1, v1, x2, v2 = y
        return [v1, (f - d1 * v1 - k1 * (x1 - x2)) / m1, v2, (k1 * (x1 - x2) - k2 * x2 - d2 * v2) / m2]

    return _ivp(rhs, [0.0] * 4, 3.0)


@functools.cache
def _pendulum():
    g, length, c = 9.81, 1.0, 0.5
    return _ivp(lambda t, y: [y[1], -(g / length) * np.sin(y[0]) - c * y[1]], [1.0, 0.0], 5.0)


@functools.cache
def _motor():
    u, ra, la, km, j, b = 12.0, 1.0, 1e-3, 0.05, 1e-4, 1e-5
    return _ivp(
        lambda t, y: [(u - ra * y[0] - km * y[1]) / la, (km * y[0] - b * y[1]) / j], [0.0, 0.0], 0.1, method="Radau"
    )


@functools.cache
def _thermal_two_node():
    p, cj, rjc, cc, rca = 5.0, 1.0, 1.0, 10.0, 2.0
    return _ivp(
        lambda t, y: [(p - (y[0] - y[1]) / rjc) / cj, ((y[0] - y[1]) / rjc - y[1] / rca) / cc], [0.0, 0.0], 60.0
    )


@functools.cache
def _thermal_local():
    p, c1, r12, c2, r2a = 20.0, 2.0, 0.5, 40.0, 1.5
    return _ivp(
        lambda t, y: [(p - (y[0] - y[1]) / r12) / c1, ((y[0] - y[1]) / r12 - y[1] / r2a) / c2], [0.0, 0.0], 200.0
    )


@functools.cache
def _self_heating():
    u, r0, alpha, rth, cth = 10.0, 10.0, 0.004, 5.0, 2.0
    return _ivp(lambda t, y: [(u**2 / (r0 * (1 + alpha * y[0])) - y[0] / rth) / cth], [0.0], 50.0)


def _clipper(t: np.ndarray) -> np.ndarray:
    r, r_on, g_off, knee = 1e3, 10.0, 1e-9, 0.7
    vs = 5.0 * np.sin(2 * np.pi * 1e3 * t)
    below = vs / (1 + r * g_off)
    above = (vs / r + knee / r_on) / (1 / r + g_off + 1 / r_on)
    return np.where(below > knee, above, below)


_T1 = 10e-3 * np.log(2.0)  # the comparator's switching time (comparator_tb, process_threshold_tb)
_G, _E = 9.81, 0.8
_V1 = np.sqrt(2 * _G * 1.0)
_IMPACTS = np.cumsum([np.sqrt(2 * 1.0 / _G)] + [2 * _E**n * _V1 / _G for n in range(1, 8)])


def _ball(t: np.ndarray) -> np.ndarray:
    """Height of the ball dropped from 1 m (restitution 0.8)."""
    t = np.asarray(t, dtype=float)
    x = 1.0 - 0.5 * _G * t**2
    for n, ti in enumerate(_IMPACTS, start=1):
        dt = t - ti
        x = np.where(dt >= 0, _E**n * _V1 * dt - 0.5 * _G * dt**2, x)
    return x


def _staircase(t: np.ndarray, edges: np.ndarray, step: float) -> np.ndarray:
    return step * np.sum(np.asarray(t)[:, None] >= edges[None, :], axis=1)


_EDGES = 0.5e-3 + 1e-3 * np.arange(10)  # clock_counter_tb's rising edges


def _lagged_staircase(t: np.ndarray) -> np.ndarray:
    dt = np.asarray(t)[:, None] - _EDGES[None, :]
    return np.sum(np.where(dt >= 0, 0.5 * (1.0 - np.exp(-np.maximum(dt, 0) / 1e-3)), 0.0), axis=1)


_LEVEL_EDGES = np.sort(np.concatenate([(1 / 12 + np.arange(2)) / 500, (5 / 12 + np.arange(2)) / 500])) + 1e-4


def _delayed_level(t: np.ndarray) -> np.ndarray:
    """inertial_delay_tb's level: 2.0 from 0.1 ms after x = sin(2*pi*500*t) rises through 0.5 until 0.1 ms after it
    falls through it again, -1.0 otherwise."""
    x = np.sin(2 * np.pi * 500 * (np.asarray(t) - 1e-4))
    return np.where((t >= 1e-4) & (x > 0.5), 2.0, -1.0)


_PULSES = 0.5e-3 + 0.25e-3 * np.arange(6)  # transport_delay_tb: p rises here, for 0.1 ms


def _pulses(t: np.ndarray) -> np.ndarray:
    t = np.asarray(t)
    return np.any((t[:, None] >= _PULSES[None, :]) & (t[:, None] < _PULSES[None, :] + 1e-4), axis=1).astype(float)


_LOOP_EDGES = tuple(sorted([*(3e-3 * np.arange(1, 4)), *(1e-3 + 3e-3 * np.arange(4))]))  # loop_pulse_tb's p

_TICKS = 1e-3 * np.arange(1, 5)  # time_literals_tb: the clock process's runs after the one at initialisation


def _square_lag(t: np.ndarray, low: float = 0.0, high: float = 1.0) -> np.ndarray:
    """The lag (tau = 1 ms) of a square wave that is `low` on even and `high` on odd milliseconds, from `low` at 0:
    time_literals_tb's y (0/1), concurrent_assign_tb's z (-1/3)."""
    t = np.asarray(t)
    k = np.floor(t / 1e-3 + 1e-9).astype(int)
    start = np.full(k.max() + 1, low)
    for j in range(1, len(start)):  # the lag at the start of [j, j+1) ms
        q = high if (j - 1) % 2 else low
        start[j] = q + (start[j - 1] - q) * np.exp(-1.0)
    q = np.where(k % 2 == 1, high, low)
    return q + (start[k] - q) * np.exp(-(t - k * 1e-3) / 1e-3)


def _gate(t: np.ndarray) -> np.ndarray:
    """concurrent_assign_tb's gate: 3 while clk = '1' ([1, 2), [3, 4) ms), -1 otherwise."""
    return np.where(np.floor(np.asarray(t) / 1e-3 + 1e-9) % 2 == 1, 3.0, -1.0)


_A = np.round(1e-3 * np.arange(1, 7), 9)  # simultaneous_events_tb: a changes every 1 ms, b every 1.5 ms
_B = np.round(1.5e-3 * np.arange(1, 5), 9)
_TOGETHER, _ALONE, _INSTANTS = np.intersect1d(_A, _B), np.setxor1d(_A, _B), np.union1d(_A, _B)

_STEPS = np.array([1e-3, 2e-3, 2.5e-3, 3e-3])  # process_all_tb: y steps here
_LEVELS = np.array([1.0, 21.0, 121.0, 123.0])  # ... to these values, from 0


def _steps(t: np.ndarray) -> np.ndarray:
    return np.sum(np.where(np.asarray(t)[:, None] >= _STEPS[None, :], np.diff(_LEVELS, prepend=0.0), 0.0), axis=1)


def _steps_lag(t: np.ndarray) -> np.ndarray:
    """The lag (tau = 1 ms) of _steps, from 0: a sum of exponential rises, one per step."""
    dt = np.asarray(t)[:, None] - _STEPS[None, :]
    return np.sum(np.where(dt >= 0, np.diff(_LEVELS, prepend=0.0) * -np.expm1(-np.maximum(dt, 0) / 1e-3), 0.0), axis=1)


def _piecewise(edges: list[float], levels: list[float]) -> Ref:
    """levels[0] before edges[0], levels[k] on [edges[k-1], edges[k]), ..."""
    return lambda t: np.asarray(levels)[np.searchsorted(edges, np.asarray(t), side="right")]


_Z_EDGES = [1.5e-3, 2e-3, 2.5e-3, 2.7e-3, 3e-3, 3.5e-3]  # reject_waveform_tb's z and w change here
_W_EDGES = [1.1e-3, 1.2e-3, 1.6e-3, 1.8e-3, 1.9e-3, 2.1e-3]

_T2 = 1e-3 * np.log(2) + 2e-3  # wait_sequence_tb: the source steps to 0 here
_SEQUENCE = np.array([1e-3 * np.log(2), _T2, _T2 + 1e-3 * np.log((1 - np.exp(-_T2 / 1e-3)) / 0.25)])


def _rc_sequence(t: np.ndarray) -> np.ndarray:
    t = np.asarray(t)
    return np.where(t < _T2, 1 - np.exp(-t / 1e-3), (1 - np.exp(-_T2 / 1e-3)) * np.exp(-(t - _T2) / 1e-3))


def _slew(t: np.ndarray) -> np.ndarray:
    return np.interp(t, [0, 1e-3, 2e-3, 3e-3, 5e-3, 1.0], [0, 0, 1, 1, 0, 0])


def _ramp(t: np.ndarray) -> np.ndarray:
    return np.interp(t, [0, 1e-3, 2e-3, 4e-3, 6e-3, 1.0], [0, 0, 2, 2, 0, 0])


def _ztf(t: np.ndarray) -> np.ndarray:
    n = np.floor((np.asarray(t) - 0.5e-3) / 1e-3)
    return np.where(n >= 0, 1.0 - 0.5 ** (n + 1), 0.0)


def _horner(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    x = 1e3 * np.asarray(t)
    return 1 - 2 * x + 0.5 * x**2 + 0.25 * x**3, -2 + x + 0.75 * x**2


# ---------------------------------------------------------------------------------------------------------------
# the corpus

_W0_RLC, _A_RLC = 1e4, 1000.0  # rlc_series_tb
_W0_PAR, _A_PAR = 1e4, 5000.0  # rlc_parallel_proposed_tb
_WLC = 1 / np.sqrt(1e-3 * 1e-6)  # lc_tank_tb

CASES: list[Case] = [
    # electrical
    Case(
        "electrical/rc_charge_tb.vhd",
        "rc_charge_tb",
        5e-3,
        5e-6,
        (Wave("vc", _exp_rise(1.0, 1e-3)), Wave("ic", _exp_decay(1e-3, 1e-3), jumps=(0.0,))),
    ),
    Case(
        "electrical/rl_step_tb.vhd",
        "rl_step_tb",
        5e-3,
        5e-6,
        (Wave("il", _exp_rise(0.1, 1e-3)), Wave("vl", _exp_decay(1.0, 1e-3), jumps=(0.0,))),
    ),
    Case(
        "electrical/rlc_series_tb.vhd",
        "rlc_series_tb",
        5e-3,
        1e-6,
        (Wave("vc", _second_order_step(_W0_RLC, _A_RLC)), Wave("il", _second_order_impulse(_W0_RLC, _A_RLC, 1e-6))),
    ),
    Case(
        "electrical/lc_tank_tb.vhd",
        "lc_tank_tb",
        1e-3,
        1e-7,
        (Wave("vc", lambda t: np.cos(_WLC * t)), Wave("il", lambda t: 1e-6 * _WLC * np.sin(_WLC * t))),
    ),
    Case(
        "electrical/clipper_tb.vhd",
        "clipper_tb",
        2e-3,
        1e-6,
        (Wave("vd", _clipper), Wave("ir", lambda t: (5.0 * np.sin(2 * np.pi * 1e3 * t) - _clipper(t)) / 1e3)),
    ),
    Case("electrical/mode_case_tb.vhd", "mode_case_tb", 5e-3, 5e-6, (Wave("vc", _exp_rise(2.0, 1e-3)),)),
    Case(
        "electrical/comparator_tb.vhd",
        "comparator_tb",
        14e-3,
        1.4e-5,
        (Wave("v1", _exp_rise(1.0, 10e-3)), Wave("v2", _exp_rise(2.0, 5e-3, _T1)), Event("vs2", 1.0, _T1)),
    ),
    Case("electrical/divider_pkg_tb.vhd", "divider_pkg_tb", 6e-3, 6e-6, (Wave("vb", _exp_rise(0.4, 1.2e-3)),)),
    Case(
        "electrical/table_pkg_tb.vhd",
        "table_pkg_tb",
        2e-3,
        2e-6,
        (Wave("inl", lambda t: np.interp(1e3 * t, [0.0, 0.5, 1.0, 2.0], [0.0, 1e-3, 1.5e-3, 4e-3])),),
    ),
    Case(
        "electrical/rc_component_tb.vhd",
        "rc_component_tb",
        5e-3,
        5e-6,
        (Wave("c1.v", _exp_rise(2.0, 1e-3)), Wave("r1.i", _exp_decay(1e-3, 1e-3), jumps=(0.0,))),
    ),
    Case("electrical/divider_arch_tb.vhd", "divider_arch_tb", 4e-3, 4e-6, (Wave("vm", _exp_rise(3.0, 0.75e-3)),)),
    Case("electrical/config_spec_tb.vhd", "config_spec_tb", 10e-3, 1e-5, (Wave("vc", _exp_rise(1.0, 2e-3)),)),
    Case("electrical/rc_ladder_gen_tb.vhd", "rc_ladder_gen_tb", 10e-3, 1e-5, (Wave("vout", _state(_ladder, 2)),)),
    Case("electrical/if_gen_tb.vhd", "if_gen_tb", 4e-3, 4e-6, (Wave("vl", _exp_rise(8.0, 0.8e-3)),)),
    Case(
        "electrical/case_gen_tb.vhd",
        "case_gen_tb",
        5e-3,
        5e-6,
        (
            Wave("vl", _exp_rise(5.0, 1e-3)),
            Wave("case_src__iri", lambda t: (10.0 - _exp_rise(5.0, 1e-3)(t)) / 4e3 * (t > 0), jumps=(0.0,)),
        ),
    ),
    Case(
        "electrical/vector_rc_tb.vhd",
        "vector_rc_tb",
        10e-3,
        1e-5,
        tuple(Wave(f"vc({k})", _exp_rise(1.0, k * 1e-3)) for k in (1, 2, 3)),
    ),
    Case(
        "electrical/parallel_rc_tb.vhd",
        "parallel_rc_tb",
        5e-3,
        5e-6,
        (Wave("v", _exp_rise(1.0, 1e-3)), Wave("icap", _exp_decay(1e-3, 1e-3), jumps=(0.0,))),
    ),
    Case("electrical/noise_rc_tb.vhd", "noise_rc_tb", 5e-3, 5e-6, (Wave("vc", _exp_rise(1.0, 1e-3)),)),
    Case(
        "electrical/rc_proposed_tb.vhd",
        "rc_proposed_tb",
        5e-3,
        5e-6,
        (Wave("vc", _exp_decay(3.0, 1e-3)), Wave("ir", _exp_decay(6e-3, 1e-3))),
    ),
    Case(
        "electrical/rlc_parallel_proposed_tb.vhd",
        "rlc_parallel_proposed_tb",
        2e-3,
        1e-6,
        (
            Wave("il", _second_order_step(_W0_PAR, _A_PAR, 10e-3)),
            Wave("v", _second_order_impulse(_W0_PAR, _A_PAR, 10e-3 * 10e-3)),
        ),
    ),
    Case("electrical/diode_rectifier_tb.vhd", "diode_rectifier_tb", 3e-3, 1e-6, (Wave("vb", _state(_rectifier, 0)),)),
    # mechanical
    Case(
        "mechanical/msd_velocity_tb.vhd",
        "msd_velocity_tb",
        1.0,
        1e-4,
        (Wave("vm", _second_order_impulse(20.0, 4.0, 0.01)), Wave("fk", _second_order_step(20.0, 4.0, 4.0))),
    ),
    Case(
        "mechanical/msd_position_tb.vhd",
        "msd_position_tb",
        2.0,
        1e-4,
        (Wave("x", lambda t: 0.01 * (1.0 - _second_order_step(20.0, 2.0)(t))),),
    ),
    Case(
        "mechanical/inertia_damper_tb.vhd",
        "inertia_damper_tb",
        0.5,
        5e-4,
        (Wave("w", _exp_rise(10.0, 0.1)), Wave("tb", _exp_rise(1.0, 0.1))),
    ),
    Case(
        "mechanical/torsion_pendulum_tb.vhd",
        "torsion_pendulum_tb",
        2.0,
        1e-4,
        (Wave("theta", lambda t: 0.1 * np.cos(10.0 * t)), Wave("tk", lambda t: 0.1 * np.cos(10.0 * t))),
    ),
    Case(
        "mechanical/two_mass_tb.vhd",
        "two_mass_tb",
        3.0,
        5e-4,
        (Wave("v1", _state(_two_mass, 1)), Wave("v2", _state(_two_mass, 3))),
    ),
    Case(
        "mechanical/shaft_alias_tb.vhd",
        "shaft_alias_tb",
        1.0,
        1e-3,
        (Wave("w", _exp_decay(50.0, 0.2)), Wave("tb", _exp_decay(5.0, 0.2))),
    ),
    Case(
        "mechanical/bouncing_ball_tb.vhd",
        "bouncing_ball_tb",
        2.0,
        1e-3,
        (
            Wave("x", _ball, floor=1.0, jumps=tuple(_IMPACTS[:3])),
            *(Event("v", 0.0, _IMPACTS[n], +1, n) for n in range(3)),
        ),
    ),
    Case(
        "mechanical/msd_proposed_tb.vhd",
        "msd_proposed_tb",
        2.0,
        1e-3,
        (Wave("v", _exp_decay(3.0, 0.5)), Wave("fd", _exp_decay(12.0, 0.5))),
    ),
    Case("mechanical/pendulum_tb.vhd", "pendulum_tb", 5.0, 1e-3, (Wave("theta", _state(_pendulum, 0)),)),
    Case(
        "mechanical/dc_motor_tb.vhd",
        "dc_motor_tb",
        0.1,
        1e-5,
        (Wave("w", _state(_motor, 1)), Wave("ia", _state(_motor, 0))),
    ),
    # thermal
    Case(
        "thermal/thermal_rc_tb.vhd",
        "thermal_rc_tb",
        50.0,
        0.05,
        (Wave("temp", _exp_rise(20.0, 10.0)), Wave("q_r", _exp_rise(10.0, 10.0))),
    ),
    Case(
        "thermal/thermal_two_node_tb.vhd",
        "thermal_two_node_tb",
        60.0,
        0.05,
        (Wave("tj", _state(_thermal_two_node, 0)), Wave("tc", _state(_thermal_two_node, 1))),
    ),
    Case(
        "thermal/thermal_local_tb.vhd",
        "thermal_local_tb",
        200.0,
        0.2,
        (Wave("t_die", _state(_thermal_local, 0)), Wave("t_sink", _state(_thermal_local, 1))),
    ),
    Case("thermal/thermal_proposed_tb.vhd", "thermal_proposed_tb", 10.0, 0.01, (Wave("temp", _exp_decay(60.0, 2.0)),)),
    Case(
        "thermal/self_heating_tb.vhd",
        "self_heating_tb",
        50.0,
        0.05,
        (
            Wave("temp", _state(_self_heating, 0)),
            Wave("i", lambda t: 10.0 / (10.0 * (1 + 0.004 * _self_heating()(t)[0]))),
        ),
    ),
    # signal: attributes, processes, procedurals
    Case(
        "signal/integ_oscillator_tb.vhd",
        "integ_oscillator_tb",
        20e-3,
        1e-5,
        (Wave("a", lambda t: np.cos(1e3 * t)), Wave("b", lambda t: np.sin(1e3 * t))),
    ),
    Case("signal/dotdot_step_tb.vhd", "dotdot_step_tb", 0.2, 1e-4, (Wave("x", _second_order_step(100.0, 30.0)),)),
    Case(
        "signal/break_decay_tb.vhd",
        "break_decay_tb",
        5e-3,
        5e-6,
        (Wave("y", _exp_decay(2.0, 1e-3)), Wave("z", _exp_decay(4.0, 0.5e-3))),
    ),
    Case(
        "signal/sawtooth_tb.vhd",
        "sawtooth_tb",
        4.5e-3,
        1e-6,
        (
            Wave("x", lambda t: 1e3 * np.mod(t, 1e-3), jumps=(1e-3, 2e-3, 3e-3, 4e-3)),
            *(Event("x", 0.5, 0.5e-3 + n * 1e-3, +1, n) for n in range(4)),
        ),
    ),
    Case("signal/ltf_lowpass_tb.vhd", "ltf_lowpass_tb", 5e-3, 5e-6, (Wave("y", _exp_rise(1.0, 1e-3)),)),
    Case(
        "signal/ltf_second_order_tb.vhd",
        "ltf_second_order_tb",
        10e-3,
        1e-5,
        (Wave("vout", _second_order_step(1e3, 500.0)),),
    ),
    Case(
        "signal/ztf_tb.vhd",
        "ztf_tb",
        3e-3,
        1e-6,
        (Wave("y", _ztf, jumps=tuple(0.5e-3 + 1e-3 * np.arange(3))), Event("y", 0.25, 0.5e-3)),
    ),
    Case(
        "signal/zoh_tb.vhd",
        "zoh_tb",
        10e-3,
        1e-6,
        (
            Wave(
                "y",
                lambda t: np.sin(2 * np.pi * 100 * np.floor(t / 0.5e-3) * 0.5e-3),
                jumps=tuple(0.5e-3 * np.arange(1, 21)),
            ),
        ),
    ),
    Case(
        "signal/delayed_tb.vhd",
        "delayed_tb",
        10e-3,
        1e-5,
        (Wave("y", lambda t: np.where(t >= 1e-3, np.sin(2 * np.pi * 200 * (t - 1e-3)), 0.0)),),
    ),
    Case(
        "signal/slew_tb.vhd",
        "slew_tb",
        6e-3,
        1e-6,
        (Wave("y", _slew), Wave("u", lambda t: np.where((t >= 1e-3) & (t < 3e-3), 1.0, 0.0), jumps=(1e-3, 3e-3))),
    ),
    Case("signal/ramp_tb.vhd", "ramp_tb", 7e-3, 1e-6, (Wave("q", _ramp),)),
    Case(
        "signal/process_threshold_tb.vhd",
        "process_threshold_tb",
        14e-3,
        1.4e-5,
        (Wave("v2", _exp_rise(2.0, 5e-3, _T1)), Event("vs2", 1.0, _T1)),
    ),
    Case(
        "signal/clock_counter_tb.vhd",
        "clock_counter_tb",
        4.2e-3,
        1e-6,
        (
            Wave("q", lambda t: _staircase(t, _EDGES, 0.5), jumps=tuple(_EDGES[:4])),
            Wave("y", _lagged_staircase),
            Event("q", 0.25, 0.5e-3),
            Event("q", 1.25, 2.5e-3, +1, 0),
        ),
    ),
    Case(
        "signal/time_literals_tb.vhd",
        "time_literals_tb",
        4.5e-3,
        1e-5,
        (
            Wave("q", lambda t: np.floor(t / 1e-3 + 1e-9) % 2, jumps=tuple(_TICKS)),
            Wave("z", lambda t: np.floor(t / 1e-3 + 1e-9) * 1e-3, jumps=tuple(_TICKS)),
            Wave("y", _square_lag),
            Event("q", 0.5, 1e-3),
            Event("q", 0.5, 2e-3, -1),
        ),
    ),
    Case(
        "signal/sequential_case_tb.vhd",
        "sequential_case_tb",
        4.5e-3,
        1e-5,
        tuple(
            Wave(name, lambda t, v=values: np.select([t < 1e-3, t < 2e-3, t < 3e-3], v[:3], v[3]), jumps=_TICKS[:3])
            for name, values in (
                ("y", (1.0, 2.0, 4.0, -1.0)),
                ("w", (1.0, 2.0, 40.0, -10.0)),
                ("s", (0.25, 0.5, 2.5, 1.5)),
            )
        ),
    ),
    Case(
        "signal/concurrent_assign_tb.vhd",
        "concurrent_assign_tb",
        4.5e-3,
        1e-5,
        (
            Wave("g", _gate, jumps=tuple(_TICKS)),
            Wave("y", lambda t: np.select([t < 1e-3, t < 3e-3], [1.0, 2.0], 0.5), jumps=(1e-3, 3e-3)),
            Wave("z", lambda t: _square_lag(t, -1.0, 3.0)),
            Event("g", 1.0, 1e-3),
            Event("g", 1.0, 2e-3, -1),
            Event("y", 1.0, 3e-3, -1),
        ),
    ),
    Case(
        "signal/process_all_tb.vhd",
        "process_all_tb",
        4.5e-3,
        1e-5,
        (
            Wave("w", _steps, jumps=tuple(_STEPS)),
            Wave("yl", _steps_lag),
            Event("w", 10.0, 2e-3),
            Event("w", 100.0, 2.5e-3),
        ),
    ),
    Case(
        "signal/stable_tb.vhd",
        "stable_tb",
        4.5e-3,
        1e-5,
        (  # clk changes every 1 ms, d at 1.5 and 3.5 ms
            Wave("qc", lambda t: _staircase(t, 1e-3 * np.arange(1, 5), 1.0), jumps=tuple(1e-3 * np.arange(1, 5))),
            Wave("qd", lambda t: 1.0 + _staircase(t, np.array([1.5e-3, 3.5e-3]), 1.0), jumps=(1.5e-3, 3.5e-3)),
            Event("qc", 0.5, 1e-3),
            Event("qd", 1.5, 1.5e-3),
        ),
    ),
    Case(
        "signal/break_dot_tb.vhd",
        "break_dot_tb",
        2.0,
        1e-3,
        (
            Wave("x", lambda t: 1.0 - 0.25 * np.exp(-2.0 * t)),
            Wave("v", lambda t: 0.5 * np.exp(-2.0 * t)),
        ),
    ),
    Case(
        "signal/break_dotdot_tb.vhd",
        "break_dotdot_tb",
        3.0,
        1e-3,
        (
            Wave("x", lambda t: np.cos(2.0 * t) - np.sin(2.0 * t)),
            Wave("v", lambda t: -2.0 * (np.sin(2.0 * t) + np.cos(2.0 * t))),
        ),
    ),
    Case(
        "signal/loop_pulse_tb.vhd",
        "loop_pulse_tb",
        10e-3,
        1e-4,
        (
            Wave("p", lambda t: (np.mod(np.asarray(t) + 1e-12, 3e-3) < 1e-3).astype(float), jumps=_LOOP_EDGES),
            Wave("f", lambda t: np.full_like(t, 120.0)),
            Wave("r", lambda t: np.full_like(t, np.sqrt(2.0))),
            Wave("s", lambda t: np.full_like(t, 25.0)),
        ),
    ),
    Case(
        "signal/real_subtype_signal_tb.vhd",
        "real_subtype_signal_tb",
        2e-3,
        1e-4,
        (
            Wave("v", lambda t: np.where(np.asarray(t) < 1e-3, 1.0, 5.0), jumps=(1e-3,)),
            Wave("i", lambda t: np.where(np.asarray(t) < 1e-3, 1.0 / 200.0, 5.0 / 300.0), jumps=(1e-3,)),
        ),
    ),
    Case(
        "signal/constrained_vector_tb.vhd",
        "constrained_vector_tb",
        1e-3,
        1e-5,
        tuple(
            Wave(q, (lambda v: lambda t: np.full_like(t, v))(v))
            for q, v in (("a", 61.0), ("b", 6.0), ("s", 14.0), ("y", 10.0))
        ),
    ),
    Case(
        "signal/async_reset_counter_tb.vhd",
        "async_reset_counter_tb",
        4.2e-3,
        1e-6,
        (  # the reset falls at
            Wave("qn", lambda t: _staircase(t, _EDGES[2:], 1.0), jumps=tuple(_EDGES[2:4])),  # 1.7 ms, clk '1':
            Wave("qm", lambda t: _staircase(t, _EDGES[2:], 1.0), jumps=tuple(_EDGES[2:4])),  # no edge of clk then
            Event("qn", 0.5, 2.5e-3),
            Event("qm", 1.5, 3.5e-3),
        ),
    ),
    Case(
        "signal/inertial_delay_tb.vhd",
        "inertial_delay_tb",
        4e-3,
        1e-6,
        (  # the 0.1 ms pulse is swallowed
            Wave("qq", lambda t: ((t >= 2.2e-3) & (t < 2.7e-3)).astype(float), jumps=(2.2e-3, 2.7e-3)),
            Wave("lv", _delayed_level, jumps=tuple(_LEVEL_EDGES)),
            Event("qq", 0.5, 2.2e-3),
            Event("qq", 0.5, 2.7e-3, -1),
            Event("lv", 0.5, _LEVEL_EDGES[0]),
            Event("lv", 0.5, _LEVEL_EDGES[1], -1),
        ),
    ),
    Case(
        "signal/transport_delay_tb.vhd",
        "transport_delay_tb",
        2.6e-3,
        1e-5,
        (  # pulses shorter than the delay
            Wave("qq", lambda t: _pulses(t - 3e-4), jumps=tuple(np.concatenate([_PULSES, _PULSES + 1e-4]) + 3e-4)),
            Wave("qr", lambda t: 0.0 * t),
            Event("qq", 0.5, _PULSES[0] + 3e-4),
            Event("qq", 0.5, _PULSES[5] + 4e-4, -1, 5),
        ),
    ),
    Case(
        "signal/reject_waveform_tb.vhd",
        "reject_waveform_tb",
        4e-3,
        1e-5,
        (  # inertial, reject, transport, waveforms of two elements
            Wave("qu", lambda t: 0.0 * t),
            Wave("qy", _piecewise([2e-3, 3e-3], [0.0, 1.0, 0.0]), jumps=(2e-3, 3e-3)),
            Wave("qz", _piecewise(_Z_EDGES, [0.0, 5.0, 1.0, 0.0, 1.0, 0.0, 5.0]), jumps=tuple(_Z_EDGES)),
            Wave("qw", _piecewise(_W_EDGES, [0.0, 1.0, 2.0, 0.0, 1.0, 2.0, 0.0]), jumps=tuple(_W_EDGES)),
            Wave("qq", _piecewise([1.5e-3], [0.0, 1.0]), jumps=(1.5e-3,)),
            Event("qy", 0.5, 2e-3),
            Event("qz", 0.5, 2.7e-3, +1, 1),
            Event("qw", 1.5, 1.9e-3, +1, 1),
        ),
    ),
    Case(
        "signal/wait_sequence_tb.vhd",
        "wait_sequence_tb",
        6e-3,
        1e-5,
        (  # waits of three kinds in turn
            Wave("v", _rc_sequence),
            Wave("ph", lambda t: _staircase(t, _SEQUENCE, 1.0), jumps=tuple(_SEQUENCE)),
            Event("ph", 0.5, _SEQUENCE[0]),
            Event("ph", 1.5, _SEQUENCE[1]),
            Event("ph", 2.5, _SEQUENCE[2]),
        ),
    ),
    Case(
        "signal/time_generic_tb.vhd",
        "time_generic_tb",
        2e-3,
        1e-6,
        (
            Wave("v", lambda t: np.sin(2 * np.pi * t / 1e-3)),
            Wave("q", lambda t: np.mod(np.floor(t / 0.25e-3), 2.0), jumps=tuple(0.25e-3 * np.arange(1, 9))),
            Event("q", 0.5, 0.25e-3),
            Event("q", 0.5, 0.5e-3, -1),
        ),
    ),
    Case(
        "signal/procedural_sat_tb.vhd",
        "procedural_sat_tb",
        40e-3,
        2e-6,
        (  # the clipping corners
            Wave("y", lambda t: np.clip(2.0 * np.sin(2 * np.pi * 50 * t), -1.0, 1.0)),
        ),
    ),
    Case(
        "signal/procedural_horner_tb.vhd",
        "procedural_horner_tb",
        2e-3,
        2e-6,
        (Wave("p", lambda t: _horner(t)[0]), Wave("dp", lambda t: _horner(t)[1])),
    ),
    Case(
        "signal/array_quantity_tb.vhd",
        "array_quantity_tb",
        10e-3,
        1e-5,
        (
            Wave("q(1)", lambda t: 1 - np.exp(-t / 1e-3)),
            Wave("q(2)", lambda t: 1 - np.exp(-t / 1e-3) * (1 + t / 1e-3)),
            Wave("q(3)", lambda t: 1 - np.exp(-t / 1e-3) * (1 + t / 1e-3 + (t / 1e-3) ** 2 / 2)),
        ),
    ),
    Case("signal/limit_spec_tb.vhd", "limit_spec_tb", 5e-3, 5e-6, (Wave("y", _exp_rise(1.0, 1e-3)),)),
    Case(
        "signal/attribute_spec_tb.vhd",
        "attribute_spec_tb",
        5e-3,
        5e-6,
        (Wave("vin", _exp_rise(1.0, 1e-3)), Wave("vout", _exp_rise(3.0, 1e-3))),
    ),
    Case(
        "signal/simultaneous_events_tb.vhd",
        "simultaneous_events_tb",
        6.5e-3,
        1e-5,
        (  # one run per instant, 'event true for each signal that changed there (a and b together at 3 and 6 ms)
            Wave(
                "qn",
                lambda t: _staircase(t, _TOGETHER, 10.0) + _staircase(t, _ALONE, 1.0),
                jumps=tuple(_INSTANTS),
            ),
            Wave("qc", lambda t: 1.0 + _staircase(t, _INSTANTS, 1.0), jumps=tuple(_INSTANTS)),
            Wave("qs", lambda t: 1.0 + _staircase(t, np.setdiff1d(_B, _A), 1.0), jumps=tuple(_B)),
            Wave("qe", lambda t: _staircase(t, np.intersect1d(_A[::2], _B[1::2]), 1.0), jumps=(3e-3,)),
            Wave("qx", lambda t: _staircase(t, _A, 2.0), jumps=tuple(_A)),  # d <= a: a delta cycle after a
            Event("qn", 7.5, 3e-3),
            Event("qn", 20.0, 6e-3),
            Event("qc", 8.5, 6e-3),
        ),
    ),
]


def _db(h: Callable[[np.ndarray], np.ndarray]) -> Ref:
    return lambda f: 20.0 * np.log10(np.abs(h(2j * np.pi * f)))


def _deg(h: Callable[[np.ndarray], np.ndarray]) -> Ref:
    return lambda f: np.degrees(np.angle(h(2j * np.pi * f)))


_LAG = lambda s: 1.0 / (1.0 + s * 1e-3)  # noqa: E731 - filters_ac_tb's transfer functions
_LOW = lambda s: 1e6 / (s**2 + 1e3 * s + 1e6)  # noqa: E731
_INT = lambda s: 1000.0 / s  # noqa: E731
_RLC = lambda s: 1.0 / (1.0 + s * 10.0 * 10e-6 + s**2 * 10e-3 * 10e-6)  # noqa: E731


def _integrator_gain(f: np.ndarray) -> np.ndarray:
    """integrator_noise_tb's G = 1/(Y + (1 + Y)/A), Y = j*w*R*C."""
    y = 2j * np.pi * f * 10e3 * 100e-9
    return 1.0 / (y + (1.0 + y) / 1e6)


def _integrator_noise(f: np.ndarray) -> np.ndarray:
    g = _integrator_gain(f)
    y = 2j * np.pi * f * 10e3 * 100e-9
    return np.sqrt(np.abs((1.0 + y) * g) ** 2 * 1e-16 + np.abs(g) ** 2 * 4 * 1.380649e-23 * 300 * 10e3)


# The analyses (tests/corpus/analysis): a DC sweep against Lambert's W, small-signal responses of an RC-free lag,
# an 'ltf, an 'integ and an RLC network, an op-amp integrator's output noise and its input-referred noise.
ANALYSES: list[Case] = [
    Case(
        "analysis/diode_dc_tb.vhd",
        "diode_dc_tb",
        0.0,
        0.0,
        (Wave("v", lambda u: _diode_v(u), floor=1e-3), Wave("i", lambda u: 1e-12 * (np.exp(_diode_v(u) / 0.025) - 1))),
        ("--dc", "u", "0", "1", "0.0625"),
        "dc.csv",
    ),
    Case(
        "analysis/filters_ac_tb.vhd",
        "filters_ac_tb",
        0.0,
        0.0,
        tuple(
            check
            for name, h in (("lag", _LAG), ("low", _LOW), ("int", _INT), ("vc", _RLC))
            for check in (Wave(f"|{name}|", _db(h)), Wave(f"{name} phase", _deg(h)))
        ),
        ("--ac", "1", "1e5", "20"),
        "ac.csv",
    ),
    Case(
        "analysis/integrator_noise_tb.vhd",
        "integrator_noise_tb",
        0.0,
        0.0,
        (
            Wave("vo noise", _integrator_noise, pointwise=True),
            Wave(
                "vo noise referred to u", lambda f: _integrator_noise(f) / np.abs(_integrator_gain(f)), pointwise=True
            ),
        ),
        ("--noise", "vo", "1", "1e5", "10", "--noise-input", "u"),
        "noise.csv",
    ),
]


def _diode_v(u: np.ndarray) -> np.ndarray:
    """diode_dc_tb's diode voltage: u = v + R*Is*(exp(v/Vt) - 1) by Lambert's W."""
    from scipy.special import lambertw

    r, i_s, vt = 100.0, 1e-12, 0.025
    u = np.asarray(u, dtype=float)
    return u + r * i_s - vt * np.real(lambertw(r * i_s / vt * np.exp((u + r * i_s) / vt)))


# ---------------------------------------------------------------------------------------------------------------
# running and judging


GRID = 2001  # the checks read the waveforms on a uniform grid of this many points (crossings between its points)


def _column(header: list[str], data: np.ndarray, name: str, top: str) -> np.ndarray:
    """The column of quantity `name` (a hierarchical name such as 'c1.v') of bench `top`: headed '<name>[<unit>]'."""
    want = name.lower()
    for k, head in enumerate(header):
        if head.split("[", 1)[0].lower() == want:
            return data[:, k]
    raise AssertionError(f"no column {want!r} in {header}")


def _crossing(t: np.ndarray, y: np.ndarray, level: float, direction: int, nth: int) -> tuple[float, float]:
    """The table's interval (t_k, t_k+1) holding the nth crossing of `level` in `direction`."""
    s = direction * (y - level)
    found = np.nonzero((s[:-1] < 0) & (s[1:] >= 0))[0]
    assert len(found) > nth, f"only {len(found)} crossings of {level}"
    k = found[nth]
    return float(t[k]), float(t[k + 1])


def _judge(case: Case, header: list[str], data: np.ndarray) -> list[str]:
    t = data[:, 0]
    failures = []
    for check in case.checks:
        y = _column(header, data, check.column, case.top)
        if isinstance(check, Wave):
            ref = np.asarray(check.ref(t), dtype=float)
            keep = np.ones_like(t, dtype=bool)
            for jump in check.jumps:
                keep &= np.abs(t - jump) > RTOL * case.stop
            scale = np.maximum(np.abs(ref), check.floor) if check.pointwise else max(np.max(np.abs(ref)), check.floor)
            err = (np.abs(y - ref) / scale)[keep]
            worst = int(np.argmax(err))
            if err[worst] > RTOL:
                failures.append(
                    f"{check.column}: max error {err[worst]:.2g} of the scale at {header[0]} = {t[keep][worst]:.6g}"
                )
        else:
            before, after = _crossing(t, y, check.level, check.direction, check.nth)
            off = max(before - check.at, check.at - after, 0.0)  # 0 when the crossing interval holds `at`
            if off > RTOL * abs(check.at):
                failures.append(
                    f"{check.column} crossing {check.level} #{check.nth}: between {before:.7g} and "
                    f"{after:.7g} s, expected {check.at:.7g} s ({off / check.at:.2g} relative)"
                )
    return failures


def test_the_corpus_is_complete():
    files = {p.relative_to(CORPUS).as_posix() for p in CORPUS.rglob("*.vhd")}
    assert files == {c.file for c in CASES + ANALYSES}
    assert len(CASES) >= 44
    for case in CASES + ANALYSES:
        path = CORPUS / case.file
        assert path.stem == case.top and path.read_text().startswith("--")


@pytest.mark.parametrize("compiled", [False, True], ids=["behavioural", "compiled"])
@pytest.mark.parametrize("case", CASES + ANALYSES, ids=[c.top for c in CASES + ANALYSES])
def test_corpus_model(case: Case, compiled: bool, tmp_path: Path, capsys: pytest.CaptureFixture[str]):
    how = case.analysis or ("--stop", repr(case.stop), "--max-step", repr(case.max_step), "--resample", str(GRID))
    run = ["run", "--compile" if compiled else "--no-compile", str(CORPUS / case.file), "--top", case.top, *how]
    status = main([*run, "--results", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip()
    if not compiled and case.analysis[:1] in (
        ("--ac",),
        ("--noise",),
    ):  # 1076.1's linearisation is the compiled device's
        assert status == 2 and "drop --no-compile" in err, err
        return
    assert status == 0, f"wrsim run {case.file}: {err}"
    header, data = table(tmp_path / "out" / "run" / case.top / case.table)
    failures = _judge(case, header, data)
    assert not failures, f"{case.file}: " + "; ".join(failures)
