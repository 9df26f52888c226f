"""Synthetic test-stand data from known parameters, deterministic with a seed.

The thesis ships no raw measurement files, so the identification pipeline (wrsim.identify) is proven on
data made here from a known parameter set (the "truth"):

- a group of units (default 5) whose parameters spread around the truth (Spread); the spread factors are
  centred (geometric mean 1 over the group), so the truth is the group's centre, the set a group
  identification should recover;
- per unit and direction (cw = +1, ccw = -1) one characteristic curve of the bare motor (4.1.1.4: starts
  slightly in generator mode, load ramp 0.5 N*m in 3 s, stops near stall) and one of the drive (4.1.4.2: from
  no load, load ramp 13 N*m in 2 s at the gear, stops near stall), sampled by a Stand;
- per unit and direction one torque-angle curve of the rubber damper (4.1.3, 0 .. 10 deg).

The lines themselves are the model's exact ramp solutions (identify.motor_ramp_line / drive_ramp_line);
on top come the imperfections the thesis describes: commutation ripple (Fig. 4.9, `segments` periods per
armature revolution), growing disorder near stall (Fig. 4.10/4.11: above 80 % of the stall torque),
non-periodic vibration and extra friction at high load for drives (4.1.4.2: poor linearity, additional
friction above 6 N*m), sensor noise and, between the directions, a brush-position difference in ra and a
housing-friction difference (irregular gaps between cw and ccw). Within the working ranges the
measurements are the model plus zero-mean ripple and noise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from wrsim.closed_form.motor import MotorParams, motor_from_set, motor_ramp_line
from wrsim.data.curves import (
    DamperCurve,
    RawCurve,
    write_characteristic,
    write_torque_angle,
)
from wrsim.data.params import ParamSet
from wrsim.errors import WrsimError

__all__ = [
    "Truth",
    "Spread",
    "Stand",
    "MOTOR_STAND",
    "DRIVE_STAND",
    "Unit",
    "draw_units",
    "motor_curves",
    "drive_curves",
    "damper_curves",
    "write_group",
]


@dataclass(frozen=True)
class Truth:
    """The known parameters: motor, worm gear (ratio, eta), gear-side housing friction m_gc [N*m] and the
    rubber-damper table (angles [rad], stiffness [N*m/rad])."""

    motor: MotorParams
    ratio: float
    eta: float
    m_gc: float
    damper_angles: tuple[float, ...]
    damper_stiffness: tuple[float, ...]

    @classmethod
    def from_params(cls, pset: ParamSet) -> Truth:
        """The truth from a parameter set with [dcpm_motor], [worm_gear], [drive] and [rubber_damper]."""
        return cls(
            motor_from_set(pset),
            pset.number_in("worm_gear", "ratio", "1"),
            pset.number_in("worm_gear", "eta", "1"),
            pset.number_in("drive", "m_gc", "N*m"),
            tuple(pset.vector_in("rubber_damper", "angles", "rad")),
            tuple(pset.vector_in("rubber_damper", "stiffness", "N*m/rad")),
        )


@dataclass(frozen=True)
class Spread:
    """Unit-to-unit spread: relative standard deviations of per-unit factors (log-normal, centred over the
    group). flux scales ke and kt together (one magnet); kt adds its own small part. direction_ra and
    direction_m_gc split a unit's cw and ccw curves (brush position, gear mesh)."""

    flux: float = 0.015
    kt: float = 0.005
    ra: float = 0.03
    visc: float = 0.10
    eta: float = 0.02
    m_gc: float = 0.15
    damper: float = 0.05
    direction_ra: float = 0.01
    direction_m_gc: float = 0.10


@dataclass(frozen=True)
class Stand:
    """A characteristic-curve test stand and its imperfections. Torques [N*m] are at the measured shaft
    (armature for a motor stand, gear wheel for a drive stand); speeds are the measured shaft's."""

    voltage: float  # [V] supply
    torque_rate: float  # [N*m/s] load ramp
    start: float  # [N*m] torque at the first sample (< 0: generator mode)
    end_speed: float  # [1] the record stops when the speed falls to this fraction of its no-load value
    sample_rate: float  # [Hz]
    segments: int  # [1] commutator segments: ripple periods per armature revolution
    ripple_current: float  # [1] commutation ripple amplitude, relative to the current
    ripple_speed: float  # [1] commutation ripple amplitude, relative to the speed
    ripple_torque: float  # [N*m] commutation ripple amplitude of the torque sensor
    noise_torque: float  # [N*m] standard deviation of the sensor noise
    noise_speed: float  # [rad/s]
    noise_current: float  # [A]
    noise_voltage: float  # [V]
    wobble: float = 0.0  # [1] non-periodic vibration amplitude (speed; twice that on the current)
    overload_from: float = math.inf  # [N*m] torque above which extra friction grows (drive, 4.1.4.2)
    overload_friction: float = 0.0  # [1/(N*m)] extra gear-side friction k*(M - overload_from)**2

    def clean(self) -> Stand:
        """The same stand without ripple, disorder, vibration, overload friction and noise."""
        return replace(
            self,
            ripple_current=0.0,
            ripple_speed=0.0,
            ripple_torque=0.0,
            noise_torque=0.0,
            noise_speed=0.0,
            noise_current=0.0,
            noise_voltage=0.0,
            wobble=0.0,
            overload_friction=0.0,
        )


# Motor stand of 4.1.1.4 (Fig. 4.8): 13 V, servo load ramp 0.5 N*m in 3 s, the record starts just in generator
# mode and ends near stall. Drive stand of 4.1.4.2 (Fig. 4.37): 13 V, from no load, about 13 N*m in 2 s.
# Ripple, noise and vibration amplitudes are assumptions of the order the thesis's figures suggest.
MOTOR_STAND = Stand(
    voltage=13.0,
    torque_rate=0.5 / 3.0,
    start=-0.02,
    end_speed=0.03,
    sample_rate=1000.0,
    segments=10,
    ripple_current=0.04,
    ripple_speed=0.005,
    ripple_torque=0.002,
    noise_torque=0.001,
    noise_speed=0.5,
    noise_current=0.03,
    noise_voltage=0.01,
)
DRIVE_STAND = Stand(
    voltage=13.0,
    torque_rate=6.5,
    start=0.0,
    end_speed=0.03,
    sample_rate=1000.0,
    segments=10,
    ripple_current=0.04,
    ripple_speed=0.005,
    ripple_torque=0.05,
    noise_torque=0.02,
    noise_speed=0.02,
    noise_current=0.03,
    noise_voltage=0.01,
    wobble=0.005,
    overload_from=6.0,
    overload_friction=0.012,
)


@dataclass(frozen=True)
class Unit:
    """One unit of the group: its motor, gear efficiency, housing friction, damper stiffness factor and the
    cw/ccw factors on ra and m_gc."""

    name: str
    motor: MotorParams
    eta: float
    m_gc: float
    damper_factor: float
    ra_direction: tuple[float, float]
    m_gc_direction: tuple[float, float]


def _centred(rng: np.random.Generator, sigma: float, n: int) -> np.ndarray:
    """n log-normal factors with relative spread sigma and geometric mean exactly 1."""
    z = rng.standard_normal(n)
    return np.exp(sigma * (z - z.mean()))


def draw_units(truth: Truth, count: int = 5, spread: Spread = Spread(), seed: int = 0) -> list[Unit]:
    """The group: `count` units spread around the truth (centred, see Spread)."""
    if count < 1:
        raise WrsimError(f"synthetic group: need at least one unit, got {count}")
    rng = np.random.default_rng(seed)
    f = {
        name: _centred(rng, getattr(spread, name), count) if count > 1 else np.ones(1)
        for name in ("flux", "kt", "ra", "visc", "eta", "m_gc", "damper", "direction_ra", "direction_m_gc")
    }
    units = []
    for k in range(count):
        m = truth.motor
        motor = replace(
            m,
            ke=m.ke * f["flux"][k],
            kt=m.kt * f["flux"][k] * f["kt"][k],
            ra=m.ra * f["ra"][k],
            visc=m.visc * f["visc"][k],
        )
        units.append(
            Unit(
                f"u{k + 1}",
                motor,
                truth.eta * f["eta"][k],
                truth.m_gc * f["m_gc"][k],
                float(f["damper"][k]),
                (float(f["direction_ra"][k]), float(1 / f["direction_ra"][k])),
                (float(f["direction_m_gc"][k]), float(1 / f["direction_m_gc"][k])),
            )
        )
    return units


def _affine(line, at: float) -> tuple[float, float]:
    """(value at 0, slope) of an affine line given as a function of the torque (evaluated at 0 and `at`)."""
    w = line(np.array([0.0, at]))
    return float(w[0]), float((w[1] - w[0]) / at)


def _vibration(rng: np.random.Generator, t: np.ndarray) -> np.ndarray:
    """A non-periodic vibration of unit peak amplitude: three sines of incommensurate frequencies."""
    f, phase, a = rng.uniform(0.5, 4.0, 3), rng.uniform(0, 2 * math.pi, 3), rng.uniform(0.5, 1.0, 3)
    return (a[:, None] * np.sin(2 * math.pi * f[:, None] * t + phase[:, None])).sum(axis=0) / a.sum()


def _measure(
    rng: np.random.Generator,
    stand: Stand,
    t: np.ndarray,
    torque: np.ndarray,
    speed: np.ndarray,
    current: np.ndarray,
    armature_speed: np.ndarray,
) -> tuple[np.ndarray, ...]:
    """Add commutation ripple (amplitude growing near stall), vibration and noise to the true lines."""
    from scipy.integrate import cumulative_trapezoid

    theta = cumulative_trapezoid(armature_speed, t, initial=0.0) + rng.uniform(0, 2 * math.pi)
    ripple = np.sin(stand.segments * theta)
    slow = np.clip((0.2 - armature_speed / armature_speed[0]) / 0.2, 0.0, 1.0)  # above ~80 % of stall
    amplitude = 1.0 + 4.0 * slow
    n = t.size
    speed_m = speed * (1 + stand.ripple_speed * amplitude * ripple + stand.wobble * _vibration(rng, t))
    current_m = current * (
        1
        + stand.ripple_current * amplitude * np.sin(stand.segments * theta + 0.7)
        + 2 * stand.wobble * _vibration(rng, t)
    )
    torque_m = torque + stand.ripple_torque * amplitude * np.sin(stand.segments * theta + 1.9)
    return (
        torque_m + stand.noise_torque * rng.standard_normal(n),
        speed_m + stand.noise_speed * rng.standard_normal(n),
        current_m + stand.noise_current * rng.standard_normal(n),
        stand.voltage + stand.noise_voltage * rng.standard_normal(n),
    )


def _ramp(stand: Stand, end: float) -> tuple[np.ndarray, np.ndarray]:
    duration = (end - stand.start) / stand.torque_rate
    t = np.arange(int(math.floor(duration * stand.sample_rate)) + 1) / stand.sample_rate
    return t, stand.start + stand.torque_rate * t


def _source(kind: str, unit: Unit, direction: int, seed: int) -> str:
    return (
        f"synthetic {kind} test-stand data (wrsim.synthetic, seed {seed}): unit {unit.name}, "
        f"{'cw' if direction > 0 else 'ccw'}; not a measurement"
    )


def motor_curves(units: list[Unit], stand: Stand = MOTOR_STAND, seed: int = 0) -> list[RawCurve]:
    """One motor characteristic per unit and direction (cw, ccw), as read_characteristic returns them."""
    rng = np.random.default_rng(seed)
    out = []
    for unit in units:
        for k, d in enumerate((1, -1)):
            p = replace(unit.motor, ra=unit.motor.ra * unit.ra_direction[k])

            def line(m, p=p):
                return motor_ramp_line(p, stand.voltage, stand.torque_rate, m)[0]

            w0, s_w = _affine(line, 1e-3)
            t, torque = _ramp(stand, (stand.end_speed * w0 - w0) / s_w)
            speed, current = motor_ramp_line(p, stand.voltage, stand.torque_rate, torque)
            m, w, i, u = _measure(rng, stand, t, torque, speed, current, speed)
            out.append(
                RawCurve(
                    f"motor_{unit.name}_{'cw' if d > 0 else 'ccw'}", d, t, m, w, i, u, _source("motor", unit, d, seed)
                )
            )
    return out


def drive_curves(units: list[Unit], ratio: float, stand: Stand = DRIVE_STAND, seed: int = 0) -> list[RawCurve]:
    """One drive characteristic per unit and direction (gear-wheel torque and speed), as read_characteristic
    returns them. Above stand.overload_from the housing friction grows (not part of the model; there the
    ramp terms of the line keep the nominal load rate, an approximation outside the working range)."""
    from scipy.optimize import brentq

    rng = np.random.default_rng(seed)
    out = []
    for unit in units:
        for k, d in enumerate((1, -1)):
            p = replace(unit.motor, ra=unit.motor.ra * unit.ra_direction[k])
            m_gc, gain = unit.m_gc * unit.m_gc_direction[k], ratio * unit.eta

            def friction(g):
                return m_gc + stand.overload_friction * np.maximum(0.0, g - stand.overload_from) ** 2

            def armature(load):  # motor under the armature-side load, ramp rate seen by the motor
                return motor_ramp_line(p, stand.voltage, stand.torque_rate / gain, load)

            w0, s_w = _affine(lambda load: armature(load)[0], 1e-3)
            load_end = (stand.end_speed * (w0 + s_w * m_gc / gain) - w0) / s_w
            end = brentq(lambda g: (g + friction(g)) / gain - load_end, 0.0, load_end * gain)
            t, torque = _ramp(stand, end)
            omega, current = armature((torque + friction(torque)) / gain)
            m, w, i, u = _measure(rng, stand, t, torque, omega / ratio, current, omega)
            out.append(
                RawCurve(
                    f"drive_{unit.name}_{'cw' if d > 0 else 'ccw'}", d, t, m, w, i, u, _source("drive", unit, d, seed)
                )
            )
    return out


def damper_curves(
    units: list[Unit],
    truth: Truth,
    seed: int = 0,
    max_angle: float = math.radians(10.0),
    samples: int = 201,
    noise_torque: float = 0.02,
    noise_angle: float = math.radians(0.02),
) -> list[DamperCurve]:
    """One torque-angle curve per unit and direction: the gear wheel held, a torque wrench turned from 0 to
    max_angle [rad]; torque = c(angle)*angle (Eq. 4.28, the truth's table times the unit's factor) + noise."""
    rng = np.random.default_rng(seed)
    out = []
    for unit in units:
        for d in (1, -1):
            angle = np.linspace(0.0, max_angle, samples)
            torque = np.interp(angle, truth.damper_angles, truth.damper_stiffness) * unit.damper_factor * angle
            out.append(
                DamperCurve(
                    f"damper_{unit.name}_{'cw' if d > 0 else 'ccw'}",
                    d,
                    angle + noise_angle * rng.standard_normal(samples),
                    torque + noise_torque * rng.standard_normal(samples),
                    _source("rubber-damper", unit, d, seed),
                )
            )
    return out


def write_group(
    directory: str | Path, truth: Truth, count: int = 5, seed: int = 0, spread: Spread = Spread()
) -> dict[str, list[Path]]:
    """Write the synthetic group into `directory`: motor_*.csv, drive_*.csv, damper_*.csv (one file per unit
    and direction, docs/measurement-format.md). Returns the paths by kind ('motor', 'drive', 'damper')."""
    directory = Path(directory)
    units = draw_units(truth, count, spread, seed)
    groups: dict[str, Sequence[RawCurve | DamperCurve]] = {
        "motor": motor_curves(units, MOTOR_STAND, seed),
        "drive": drive_curves(units, truth.ratio, DRIVE_STAND, seed),
        "damper": damper_curves(units, truth, seed),
    }
    out: dict[str, list[Path]] = {}
    for kind, curves in groups.items():
        out[kind] = []
        for c in curves:
            path = directory / f"{c.name}.csv"
            if isinstance(c, DamperCurve):
                write_torque_angle(path, c, [])
            else:
                stand = MOTOR_STAND if kind == "motor" else DRIVE_STAND
                write_characteristic(
                    path,
                    c,
                    [f"stand: {stand.voltage:g} V, load ramp {stand.torque_rate:g} N*m/s, {stand.sample_rate:g} Hz"],
                )
            out[kind].append(path)
    return out
