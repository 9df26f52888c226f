"""ngspice as a shared library (libngspice), for netlists with `q'above(e)` guards: after every accepted time
point the guards' last values predict the next zero crossing, and a breakpoint there makes it a time point, so
an 'above event (an A->D edge, a switch of equations) lands on its crossing within `resolution` whatever the
step size (IEEE 1076.1 puts an analog solution point at every 'above event). ngspice itself has no such
mechanism for behavioural sources; its shared-library interface offers the two callbacks this needs: the values
of every accepted point (SendData) and the step about to be taken, which the caller may shorten (GetSyncData).

Run as `python -m wrsim.backend.ngspice.shared --max-step H --stop T [--resolution R] NETLIST GUARD...` in the
netlist's folder (a process of its own, as `ngspice -b`: a crash of the simulator or of a co-simulated
digital unit ends only that process). It sources the netlist, whose .control section runs the analysis and
writes the raw file and the event record; ngspice's messages go to stdout; the exit status is 1 when ngspice
asks to quit with an error."""
from __future__ import annotations

import argparse
import ctypes
import ctypes.util
import math
import sys
from dataclasses import dataclass, field

__all__ = ["CrossingGuards", "predict_crossing", "library_path"]


def library_path() -> str | None:
    """The libngspice shared object to load, or None when it is not installed."""
    return ctypes.util.find_library("ngspice")


def predict_crossing(history: list[tuple[float, float]]) -> float | None:
    """The time after the last point of `history` ((t, g) pairs, oldest first, 2 or 3 of them) at which g
    reaches 0 if it keeps its course: the root of the parabola through three points, else of the secant; None
    when g moves away from 0 or stands still."""
    (t1, g1), (t2, g2) = history[-2], history[-1]
    if t2 <= t1 or g2 == g1 or g2 == 0.0:
        return None
    d1 = (g2 - g1) / (t2 - t1)
    if (g2 > 0.0) == (d1 > 0.0):
        return None
    if len(history) >= 3 and history[-3][0] < t1:
        t0, g0 = history[-3]
        a = (d1 - (g1 - g0) / (t1 - t0)) / (t2 - t0)   # g ~ g2 + s*(t - t2) + a*(t - t2)**2
        s = d1 + a * (t2 - t1)
        if a != 0.0 and s * s - 4.0 * a * g2 >= 0.0:
            roots = [t2 + (-s + sign * math.sqrt(s * s - 4.0 * a * g2)) / (2.0 * a) for sign in (1.0, -1.0)]
            ahead = [r for r in roots if r > t2]
            if ahead:
                return min(ahead)
        if s != 0.0 and (g2 > 0.0) != (s > 0.0):
            return t2 - g2 / s
    return t2 - g2 / d1


@dataclass
class CrossingGuards:
    """Step policy for a set of guards. `observe(t, values)` takes every accepted point and predicts each
    guard's next zero crossing; `step(t, delta)`, called before every step with the step ngspice proposes,
    shortens it so that the step ends on the earliest target within it. A crossing within `APPROACH`
    resolutions is targeted `resolution`/2 past its predicted time (the point falls just past it); a farther
    one at 90 % of the way first (an extrapolation over a whole step can be off by microseconds; from 10 % of
    the distance its error is a thousand times smaller). The step is shortened, not cut by a breakpoint:
    ngspice cuts the step after a breakpoint to a tenth and doubles it back step by step."""

    APPROACH = 50.0

    count: int
    window: float
    resolution: float = 1e-6
    _history: list[list[tuple[float, float]]] = field(default_factory=list)
    _targets: list[float] = field(default_factory=list)
    landings: list[int] = field(default_factory=list)      # shortened steps per guard
    points: int = 0                                         # accepted points observed

    def __post_init__(self) -> None:
        self._history = [[] for _ in range(self.count)]
        self._targets = [math.inf] * self.count
        self.landings = [0] * self.count

    def observe(self, t: float, values: list[float]) -> None:
        self.points += 1
        for k, g in enumerate(values):
            h = self._history[k]
            if h and t <= h[-1][0]:
                h.clear()                      # the analysis restarted (or went back): forget the course
            h.append((t, g))
            del h[:-3]
            self._targets[k] = math.inf
            tc = predict_crossing(h) if len(h) >= 2 else None
            if tc is not None and t < tc <= t + self.window:
                far = tc - t > self.APPROACH * self.resolution
                self._targets[k] = t + 0.9 * (tc - t) if far else tc + 0.5 * self.resolution

    def step(self, t: float, delta: float) -> float:
        """The step to take from the accepted time t instead of ngspice's proposal `delta`."""
        k = min(range(self.count), key=self._targets.__getitem__, default=None)
        if k is None or not t < self._targets[k] < t + delta:
            return delta
        self.landings[k] += 1
        return self._targets[k] - t


class _VecValues(ctypes.Structure):
    _fields_ = [("name", ctypes.c_char_p), ("creal", ctypes.c_double), ("cimag", ctypes.c_double),
                ("is_scale", ctypes.c_bool), ("is_complex", ctypes.c_bool)]


class _VecValuesAll(ctypes.Structure):
    _fields_ = [("veccount", ctypes.c_int), ("vecindex", ctypes.c_int),
                ("vecsa", ctypes.POINTER(ctypes.POINTER(_VecValues)))]


_SendChar = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_void_p)
_SendStat = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_void_p)
_ControlledExit = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_int, ctypes.c_bool, ctypes.c_bool, ctypes.c_int,
                                   ctypes.c_void_p)
_SendData = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(_VecValuesAll), ctypes.c_int, ctypes.c_int,
                             ctypes.c_void_p)
_SendInitData = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_int, ctypes.c_void_p)
_BGThreadRunning = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_bool, ctypes.c_int, ctypes.c_void_p)
_GetSyncData = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_double, ctypes.POINTER(ctypes.c_double), ctypes.c_double,
                                ctypes.c_int, ctypes.c_int, ctypes.c_int, ctypes.c_void_p)


def _to_stop(t: float, delta: float, stop: float, max_step: float) -> float:
    """`delta`, or the step that ends on `stop` without passing it when `delta` reaches past half of the rest:
    with a step callback, ngspice pulls a step that would pass the final time back below it and then halves
    its way towards it until the step is zero ("timestep too small")."""
    if t + 2.0 * delta < stop:
        return delta
    if stop - t > max_step:
        return 0.5 * (stop - t)               # two equal steps to the end
    delta = stop - t
    while t + delta > stop:
        delta = math.nextafter(delta, 0.0)
    return delta


def _run(netlist: str, guards: list[str], max_step: float, stop: float, resolution: float) -> int:
    path = library_path()
    if path is None:
        print("error: libngspice not found (install libngspice0: make setup)")
        return 2
    lib = ctypes.CDLL(path)
    policy = CrossingGuards(len(guards), 2.0 * max_step, resolution)
    wanted = [g.lower() for g in guards]
    index: list[int] = []
    status = [0]

    def send_char(text: bytes, ident: int, user: object) -> int:
        line = text.decode("utf-8", "replace")
        print(line.split(" ", 1)[1] if line.startswith(("stdout ", "stderr ")) else line, flush=False)
        return 0

    def controlled_exit(code: int, unload: bool, quit_: bool, ident: int, user: object) -> int:
        status[0] = code
        return 0

    def send_data(values: ctypes._Pointer, count: int, ident: int, user: object) -> int:
        v = values.contents
        if not index:
            names = {v.vecsa[k].contents.name.decode().lower(): k for k in range(v.veccount)}
            missing = [g for g in wanted if g not in names and f"v({g})" not in names]
            if missing:
                print(f"error: 'above guard {missing[0]} is not among the saved vectors")
                return 0
            index.extend(names.get(g, names.get(f"v({g})", 0)) for g in wanted)
            index.append(names["time"])
        policy.observe(v.vecsa[index[-1]].contents.creal, [v.vecsa[k].contents.creal for k in index[:-1]])
        return 0

    def get_sync(time: float, delta: ctypes._Pointer, old_delta: float, redo: int, ident: int, location: int,
                 user: object) -> int:
        if location == 0 and not redo:        # before a step, after ngspice's own breakpoints have cut it
            delta[0] = _to_stop(time, policy.step(time, delta[0]), stop, max_step)
        return 0

    callbacks = (_SendChar(send_char), _SendStat(lambda text, ident, user: 0), _ControlledExit(controlled_exit),
                 _SendData(send_data), _SendInitData(lambda data, ident, user: 0),
                 _BGThreadRunning(lambda running, ident, user: 0))
    lib.ngSpice_Init(*callbacks, None)
    sync, ident = _GetSyncData(get_sync), ctypes.c_int(0)
    lib.ngSpice_Init_Sync(None, None, sync, ctypes.byref(ident), None)
    lib.ngSpice_Command(f"source {netlist}".encode())
    print(f"wrsim crossings: {policy.points} accepted points; steps shortened per guard: "
          + ", ".join(f"{g} {n}" for g, n in zip(guards, policy.landings)))
    sys.stdout.flush()
    return 1 if status[0] else 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m wrsim.backend.ngspice.shared", description=__doc__)
    parser.add_argument("--max-step", type=float, required=True, help="the analysis's largest step [s]")
    parser.add_argument("--stop", type=float, required=True, help="the analysis's final time [s]")
    parser.add_argument("--resolution", type=float, default=1e-6, help="crossing resolution [s]")
    parser.add_argument("netlist")
    parser.add_argument("guards", nargs="*", help="guard node names (raw, lower case)")
    args = parser.parse_args(argv)
    return _run(args.netlist, args.guards, args.max_step, args.stop, args.resolution)


if __name__ == "__main__":
    sys.exit(main())
