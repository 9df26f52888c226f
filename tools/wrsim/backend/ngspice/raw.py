"""ngspice's binary raw file and its value change dump of digital nodes, and the waveforms read from them by
hierarchical VHDL-AMS name."""

from __future__ import annotations

from dataclasses import astuple, dataclass, field
from pathlib import Path

import numpy as np
import vcd.reader

from wrsim.backend.ngspice.netlist import Probe
from wrsim.elab import symbolic as sy
from wrsim.errors import WrsimError

__all__ = ["Waveforms", "NotSaved", "check_finite", "SolverStatistics", "read_raw", "read_events", "sample_events"]


@dataclass(frozen=True)
class SolverStatistics:
    """What a simulation's log says about the solver (summed over runs with `+`): ngspice's accepted and rejected
    time points, Newton iterations and analysis time of the transient (`rusage all`), the wall time inside the
    digital units' steps (the GHDL glue), the steps shortened to land on an 'above crossing and the crossings seen
    more than the resolution after they happened (the crossing driver)."""

    points: int = 0
    rejected: int = 0
    iterations: int = 0
    analysis: float = 0.0  # [s] ngspice's CPU time in the transient
    ghdl: float = 0.0  # [s]
    landed: int = 0
    late: int = 0

    def __add__(self, other: SolverStatistics) -> SolverStatistics:
        return SolverStatistics(*(a + b for a, b in zip(astuple(self), astuple(other))))


def check_finite(name: str, values: np.ndarray, time: np.ndarray) -> None:
    """One error naming quantity `name` if `values` (over `time`) is not a finite number somewhere (NaN, infinity:
    a square root or logarithm of a negative value, a division by zero at run time): the run has no result."""
    bad = ~np.isfinite(values)
    if bad.any():
        k = int(np.argmax(bad))
        raise WrsimError(
            f"{name} is not a finite number ({values[k]}) from t = {time[k]:.6g} s on: its equation has no real value "
            "there (a square root or logarithm of a negative value, a division by zero, an overflow); the run has no "
            "result"
        )


class NotSaved(WrsimError):
    """A quantity of the design whose vectors the run did not save (a bench's save list leaves it out)."""


@dataclass
class Waveforms:
    """Simulated quantities by hierarchical VHDL-AMS name (instance labels joined by dots), with the simulator's
    log, its wall time [s] and the solver statistics from the log."""

    time: np.ndarray
    vectors: dict[str, np.ndarray]
    probes: dict[str, Probe]
    log: str = ""
    seconds: float = 0.0
    statistics: SolverStatistics = field(default_factory=SolverStatistics)
    _evaluated: dict[str, np.ndarray] = field(default_factory=dict, repr=False)  # eliminated quantities read so far

    def __contains__(self, name: str) -> bool:
        return name in self.probes

    def __getitem__(self, name: str) -> np.ndarray:
        p = self.probes.get(name)
        if p is None:
            raise WrsimError(f"no quantity '{name}' in the simulation (quantities: {', '.join(sorted(self.probes))})")
        try:
            if p.expr is not None:
                if name not in self._evaluated:
                    got = np.broadcast_to(self._evaluate(p.expr), self.time.shape).astype(float)
                    check_finite(name, got, self.time)
                    self._evaluated[name] = got
                return self._evaluated[name].copy()
            if p.branch is not None:
                return self.vectors[f"i({p.branch})"]
            if p.bits is not None:
                bits = [self._v(b) > 0.5 for b in p.bits]
                value: np.ndarray = np.zeros_like(self.time)
                for k, b in enumerate(bits):
                    value = value + b.astype(float) * 2.0**k
                if p.signed and len(bits) > 1:
                    value -= bits[-1] * 2.0 ** len(bits)
                return value
            return self._v(p.plus) - self._v(p.minus)
        except KeyError as e:
            raise NotSaved(
                f"quantity '{name}' was not saved (no vector {e.args[0]}): add it to the bench's save list"
            ) from None

    def unit(self, name: str) -> str:
        self[name]
        return self.probes[name].unit

    def _evaluate(self, s: sy.S) -> np.ndarray:
        """The value of an expression over the raw vectors (an eliminated quantity, `Probe.expr`)."""
        if isinstance(s, sy.Const):
            return np.asarray(s.value)
        if isinstance(s, sy.Node):
            return self._v(s.name)
        if isinstance(s, sy.Diff):
            return self._v(s.plus) - self._v(s.minus)
        if isinstance(s, sy.Time):
            return self.time
        if isinstance(s, sy.Cond):
            return np.where(self._evaluate(s.test) != 0, self._evaluate(s.then), self._evaluate(s.other))
        if isinstance(s, (sy.Op, sy.Fn)) and s.name in _NUMPY:
            with np.errstate(all="ignore"):
                return np.asarray(_NUMPY[s.name](*(self._evaluate(a) for a in s.args)), dtype=float)
        raise WrsimError(f"internal: cannot evaluate {s!r} from the waveforms")

    def _v(self, node: str | None) -> np.ndarray:
        if node in (None, "0"):
            return np.zeros_like(self.time)
        return self.vectors[f"v({node})"]


_NUMPY = {
    "+": np.add,
    "-": np.subtract,
    "*": np.multiply,
    "/": np.divide,
    "**": np.power,
    "neg": np.negative,
    "abs": np.abs,
    "<": np.less,
    "<=": np.less_equal,
    ">": np.greater,
    ">=": np.greater_equal,
    "==": np.equal,
    "!=": np.not_equal,
    "and": np.logical_and,
    "or": np.logical_or,
    "not": np.logical_not,
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "atan": np.arctan,
    "sqrt": np.sqrt,
    "exp": np.exp,
    "ln": np.log,
    "sinh": np.sinh,
    "cosh": np.cosh,
    "tanh": np.tanh,
    "asin": np.arcsin,
    "acos": np.arccos,
    "floor": np.floor,
    "ceil": np.ceil,
    "sgn": np.sign,
    "min": np.minimum,
    "max": np.maximum,
}


def read_raw(path: Path) -> dict[str, np.ndarray]:
    """Read an ngspice binary raw file into {vector name (lower case): values}; complex data (a small-signal
    analysis) as complex values."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise WrsimError(f"{path}: cannot read raw file: {e}") from None
    marker = data.find(b"Binary:\n")
    if marker < 0:
        raise WrsimError(f"{path}: not an ngspice binary raw file")
    header = data[:marker].decode("latin-1").splitlines()
    nvars = npts = 0
    names: list[str] = []
    width = 1  # doubles per value: 2 for complex data
    try:
        for k, line in enumerate(header):
            if line.startswith("No. Variables:"):
                nvars = int(line.split(":")[1])
            elif line.startswith("No. Points:"):
                npts = int(line.split(":")[1])
            elif line.startswith("Flags:") and "complex" in line:
                width = 2
            elif line.startswith("Variables:"):
                names = [header[k + 1 + j].split()[1].lower() for j in range(nvars)]
    except (ValueError, IndexError):
        raise WrsimError(f"{path}: malformed raw file header (line {k + 1}: {line!r})") from None
    if not names or len(names) != nvars:
        raise WrsimError(f"{path}: malformed raw file header ({nvars} variables declared, {len(names)} listed)")
    if nvars < 1 or npts < 0:
        raise WrsimError(f"{path}: malformed raw file header ({nvars} variables, {npts} points)")
    size = 8 * width * nvars * npts
    payload = data[marker + 8 : marker + 8 + size]
    if len(payload) != size:
        raise WrsimError(f"{path}: truncated raw file ({len(payload) // (8 * width * nvars)} of {npts} points)")
    arr = np.frombuffer(payload, dtype="<f8" if width == 1 else "<c16").reshape(npts, nvars)
    return {n: arr[:, j].copy() for j, n in enumerate(names)}


_LEVEL = {"0": 0.0, "1": 1.0}  # any other state ('x', 'z', 'u') is 0.5, as the D->A bridges give it


def read_events(path: Path) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Read ngspice's value change dump (`eprvcd`) of 1-bit digital nodes into {node (lower case): (times [s],
    levels 0 / 1, 0.5 unknown)}; the first entry is the value at t = 0."""
    times: dict[str, list[float]] = {}
    levels: dict[str, list[float]] = {}
    names: dict[str, str] = {}
    scale, now = 1.0, 0.0
    try:
        with path.open("rb") as f:
            for tok in vcd.reader.tokenize(f):
                if tok.kind is vcd.reader.TokenKind.TIMESCALE:
                    ts = tok.timescale
                    scale = int(ts.magnitude) * _SECONDS[ts.unit.value]
                elif tok.kind is vcd.reader.TokenKind.VAR:
                    names[tok.var.id_code] = tok.var.reference.lower()
                elif tok.kind is vcd.reader.TokenKind.CHANGE_TIME:
                    now = tok.time_change * scale
                elif tok.kind is vcd.reader.TokenKind.CHANGE_SCALAR:
                    name = names[tok.scalar_change.id_code]
                    times.setdefault(name, []).append(now)
                    levels.setdefault(name, []).append(_LEVEL.get(tok.scalar_change.value, 0.5))
    except OSError as e:
        raise WrsimError(f"{path}: cannot read the digital event record: {e}") from None
    except (vcd.reader.VCDParseError, KeyError) as e:
        raise WrsimError(f"{path}: malformed value change dump: {e}") from None
    return {n: (np.array(times[n]), np.array(levels[n])) for n in times}


_SECONDS = {"s": 1.0, "ms": 1e-3, "us": 1e-6, "ns": 1e-9, "ps": 1e-12, "fs": 1e-15}


def sample_events(events: tuple[np.ndarray, np.ndarray], time: np.ndarray) -> np.ndarray:
    """The level of a recorded digital node at each of `time`: its last change at or before that time."""
    t, level = events
    k = np.searchsorted(t, time, side="right") - 1
    return np.where(k >= 0, level[np.clip(k, 0, None)], level[0] if level.size else 0.0)
