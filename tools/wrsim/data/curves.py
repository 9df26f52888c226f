"""Raw test-stand measurement files (docs/measurement-format.md): characteristic curves (torque ramp: time,
torque, speed, current, voltage, direction) and torque-angle curves of the rubber damper."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim.data.measurements import Table, read_table, write_table
from wrsim.data.units import convert
from wrsim.errors import WrsimError

__all__ = [
    "RawCurve",
    "DamperCurve",
    "read_characteristic",
    "write_characteristic",
    "read_torque_angle",
    "write_torque_angle",
]

_CHARACTERISTIC = ("time", "torque", "speed", "current", "voltage", "direction")
_TORQUE_ANGLE = ("angle", "torque", "direction")
MIN_SAMPLES = 5  # fewest samples a curve must have inside its working range
_RAMP_SEGMENTS = 10  # the ramp check compares the means of this many consecutive row segments
# Resolution the writers round to (far below any test stand's): decimals per written unit.
_DECIMALS = {"time": 6, "torque": 6, "speed": 3, "current": 5, "voltage": 4, "direction": 0, "angle": 5}


@dataclass(frozen=True, eq=False)
class RawCurve:
    """One raw characteristic-curve measurement: one unit, one direction (docs/measurement-format.md).

    Values are magnitudes in SI units (the file's signed values times its direction): time [s], torque
    [N*m] (armature torque for a motor, gear-wheel torque for a drive), speed [rad/s] of the same shaft,
    current [A], voltage [V]. `name` is the file path (or a label for data made in memory).
    """

    name: str
    direction: int
    time: np.ndarray
    torque: np.ndarray
    speed: np.ndarray
    current: np.ndarray
    voltage: np.ndarray
    source: str = ""

    @property
    def label(self) -> str:
        return Path(self.name).stem


@dataclass(frozen=True, eq=False)
class DamperCurve:
    """One torque-angle measurement of a rubber damper in one direction: magnitudes, angle [rad] and
    torque [N*m] (docs/measurement-format.md)."""

    name: str
    direction: int
    angle: np.ndarray
    torque: np.ndarray
    source: str = ""

    @property
    def label(self) -> str:
        return Path(self.name).stem


def _direction(table: Table) -> int:
    d = table.column("direction", "1")
    bad = np.flatnonzero((d != d[0]) | (np.abs(d) != 1.0))
    if bad.size:
        k = int(bad[0])
        raise WrsimError(
            f"{table.path}: column 'direction': data row {k + 1} is {d[k]:g}; a file holds one "
            f"direction, +1 or -1 in every row"
        )
    return int(d[0])


def _check_sign(table: Table, name: str, values: np.ndarray, direction: int) -> None:
    if np.median(values) <= 0:
        raise WrsimError(
            f"{table.path}: column '{name}' is mostly of the opposite sign to direction "
            f"{direction:+d}; values are recorded signed and direction gives the sense of rotation"
        )


def _check_ramp(table: Table, name: str, values: np.ndarray, unit: str) -> None:
    """The ramp column must rise over the file. Ripple and noise make single samples fall, so the means of
    consecutive row segments (about a tenth of the rows each) are compared; falling, repeated or reversed
    ramps fail."""
    edges = np.linspace(0, values.size, min(_RAMP_SEGMENTS, values.size) + 1).astype(int)
    means = [float(np.mean(values[a:b])) for a, b in zip(edges[:-1], edges[1:])]
    for k in range(1, len(means)):
        if means[k] <= means[k - 1]:
            raise WrsimError(
                f"{table.path}: column '{name}' must rise over the measurement (one ramp per file, counted in "
                f"the file's direction): data rows {edges[k] + 1}-{edges[k + 1]} average {means[k]:.6g} {unit}, "
                f"not more than rows {edges[k - 1] + 1}-{edges[k]} ({means[k - 1]:.6g} {unit})"
            )


def read_characteristic(path: str | Path) -> RawCurve:
    """Read a raw characteristic-curve file of a motor or a drive (one unit, one direction)."""
    table = read_table(
        path,
        increasing="time",
        require_source=True,
        columns=_CHARACTERISTIC,
        what="a raw characteristic measurement (docs/measurement-format.md)",
    )
    d = _direction(table)
    torque, speed = d * table.column("torque", "N*m"), d * table.column("speed", "rad/s")
    current, voltage = d * table.column("current", "A"), d * table.column("voltage", "V")
    for name, values in (("speed", speed), ("current", current), ("voltage", voltage)):
        _check_sign(table, name, values, d)
    _check_ramp(table, "torque", torque, "N*m")
    return RawCurve(str(path), d, table.column("time", "s"), torque, speed, current, voltage, table.source)


def read_torque_angle(path: str | Path) -> DamperCurve:
    """Read a rubber-damper torque-angle file (one gear wheel, one direction)."""
    table = read_table(
        path, require_source=True, columns=_TORQUE_ANGLE, what="a torque-angle measurement (docs/measurement-format.md)"
    )
    d = _direction(table)
    angle, torque = d * table.column("angle", "rad"), d * table.column("torque", "N*m")
    for name, values in (("angle", angle), ("torque", torque)):
        _check_sign(table, name, values, d)
    _check_ramp(table, "angle", angle, "rad")
    return DamperCurve(str(path), d, angle, torque, table.source)


def _rounded(columns: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    return {name: np.round(values, _DECIMALS[name]) for name, values in columns.items()}


def write_characteristic(path: str | Path, curve: RawCurve, comments: list[str]) -> None:
    """Write `curve` as a raw characteristic file (signed values, speed in rpm), `# source:` first."""
    d = float(curve.direction)
    columns = {
        "time": curve.time,
        "torque": d * curve.torque,
        "speed": d * convert(curve.speed, "rad/s", "rpm"),
        "current": d * curve.current,
        "voltage": d * curve.voltage,
        "direction": np.full(curve.time.size, d),
    }
    units = {"time": "s", "torque": "N*m", "speed": "rpm", "current": "A", "voltage": "V", "direction": "1"}
    write_table(path, _rounded(columns), units, [f"source: {curve.source}", *comments])


def write_torque_angle(path: str | Path, curve: DamperCurve, comments: list[str]) -> None:
    """Write `curve` as a torque-angle file (signed values, angle in deg), `# source:` first."""
    d = float(curve.direction)
    columns = {
        "angle": d * convert(curve.angle, "rad", "deg"),
        "torque": d * curve.torque,
        "direction": np.full(curve.angle.size, d),
    }
    write_table(
        path,
        _rounded(columns),
        {"angle": "deg", "torque": "N*m", "direction": "1"},
        [f"source: {curve.source}", *comments],
    )
