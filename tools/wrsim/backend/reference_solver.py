"""The reference solver: a bench's analog equations, generated from the IR, integrated by SUNDIALS IDAS (a compiled
variable-order BDF solver for index-1 DAEs) through CasADi. `wrsim bench` runs it beside ngspice and reports the
ratio, the measure of what the lowering and ngspice cost over the equations themselves (docs/performance.md).
It is a reference, not a second engine: the digital units are not run -- the digital signals that equations read
are replayed from the ngspice run's event record, IDAS restarting at each change --, no 'above time points (a
condition switches where IDAS's step control finds it), the unknowns at given output times only.

The system, flattened over every instance, is the one the netlist gives ngspice: an equation per free or through
quantity (its residual), Kirchhoff's current law at every terminal node, `q'dot` as an algebraic unknown whose
quantity becomes a differential state, `q'integ` as a state. The quiescent point (time <= 0, every 'dot 0) is
solved first by Newton (with least-norm steps where it leaves unknowns free), then IDAS integrates from it."""

from __future__ import annotations

import contextlib
import math
import os
import sys
import tempfile
import time as clock
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT, ArchModel, Design, generic_values, instances, numbers
from wrsim.elab.eliminate import eliminated
from wrsim.errors import WrsimError

__all__ = ["System", "ReferenceRun", "flatten", "integrate"]


@dataclass
class System:
    """The flattened equations of a design, in netlist-wide node names (lower case, `x_label.` prefixes)."""

    residuals: list[sy.S] = field(default_factory=list)  # = 0, one per free/through quantity
    kcl: dict[str, list[tuple[str, float]]] = field(default_factory=dict)  # terminal -> (through node, +-1)
    derivatives: dict[str, sy.S] = field(default_factory=dict)  # 'dot unknown -> the quantity it derives
    integrals: dict[str, sy.S] = field(default_factory=dict)  # 'integ node -> its integrand
    defined: dict[str, sy.S] = field(default_factory=dict)  # guard and level nodes -> their expression
    inputs: dict[str, str] = field(default_factory=dict)  # D->A level node -> the digital node it reads
    unknowns: list[str] = field(default_factory=list)  # free and through quantity nodes


@dataclass
class ReferenceRun:
    """One integration: the wall time of IDAS alone and of the whole (build, quiescent point, IDAS), IDAS's steps,
    and every unknown and state at the output times (netlist-wide node names)."""

    seconds: float
    total: float
    steps: int
    values: dict[str, np.ndarray]


def flatten(design: Design) -> System:
    """The equations of every instance of `design` (after the elimination pass) with generics as numbers, in the
    netlist's node names (elab.design.instances), so that a replayed event record matches."""
    sysm = System()
    top = eliminated(design).top
    values = generic_values(top)
    driven: dict[str, str] = {}  # digital node an A->D element drives -> its 0/1 level node

    def visit(m: ArchModel, node: Callable[[str], str], path: str) -> None:
        if m.holds or m.elements:
            raise WrsimError(
                f"the reference solver cannot integrate {m.entity.name}: it has values that change at "
                f"events (processes, break lists, 'zoh, 'ztf, 'delayed, 'slew, 'ramp)"
            )

        def num(s: sy.S) -> sy.S:
            return numbers(s, values[path], node)

        sysm.unknowns += [node(u) for u in m.unknowns]
        sysm.residuals += [num(eq.residual) for eq in m.equations]
        for b in m.branches:
            for terminal, sign in ((node(b.plus), 1.0), (node(b.minus), -1.0)):
                if terminal != "0":
                    sysm.kcl.setdefault(terminal, []).append((node(b.through), sign))
        for d in m.derivatives.values():
            sysm.derivatives[node(d.element)] = num(d.source)
        for it in m.integrals.values():
            sysm.integrals[node(it.node)] = num(it.source)
        for x in m.crossings:
            sysm.defined[node(x.node)] = num(x.guard)
        for a in m.adcs:
            sysm.defined[node(a.level)] = sy.cond(num(a.cond), sy.const(1.0), sy.const(0.0))
            driven[node(a.node)] = node(a.level)
        for digital, level in m.dacs.items():
            if digital not in m.recorded:  # (a recorded level no equation reads)
                sysm.inputs[node(level)] = node(digital)

    instances(top, visit)
    for level, digital in list(sysm.inputs.items()):
        if digital in driven:  # a signal of the analog side itself: its level, not a replay
            sysm.defined[level] = sy.Node(driven[digital])
            del sysm.inputs[level]
    return sysm


_CASADI: dict[str, Callable[..., ca.SX]] = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": lambda a, b: a / b,
    "**": lambda a, b: a**b,
    "neg": lambda a: -a,
    "abs": ca.fabs,
    "<": lambda a, b: a < b,
    "<=": lambda a, b: a <= b,
    ">": lambda a, b: a > b,
    ">=": lambda a, b: a >= b,
    "==": lambda a, b: a == b,
    "!=": lambda a, b: a != b,
    "and": ca.logic_and,
    "or": ca.logic_or,
    "not": ca.logic_not,
    "sin": ca.sin,
    "cos": ca.cos,
    "tan": ca.tan,
    "atan": ca.atan,
    "sqrt": ca.sqrt,
    "exp": ca.exp,
    "ln": ca.log,
    "sinh": ca.sinh,
    "cosh": ca.cosh,
    "tanh": ca.tanh,
    "asin": ca.asin,
    "acos": ca.acos,
    "floor": ca.floor,
    "ceil": ca.ceil,
    "sgn": ca.sign,
    "min": ca.fmin,
    "max": ca.fmax,
}


class _Builder:
    """S -> CasADi SX, with every node a symbol or a defined expression and each sub-expression built once."""

    def __init__(self, symbols: dict[str, ca.SX], defined: dict[str, sy.S], t: ca.SX, quiescent: bool):
        self.symbols, self.defined, self.t, self.quiescent = symbols, defined, t, quiescent
        self.memo: dict[sy.S, ca.SX] = {}

    def node(self, name: str) -> ca.SX:
        if name == "0":
            return ca.SX(0)
        if name not in self.symbols:
            if name not in self.defined:
                raise WrsimError(f"the reference solver cannot integrate this design: node {name} has no equation")
            self.symbols[name] = self(self.defined[name])
        return self.symbols[name]

    def __call__(self, s: sy.S) -> ca.SX:
        hit = self.memo.get(s)
        if hit is not None:
            return hit
        if s == QUIESCENT:  # time <= 0: true at the quiescent point only
            out = ca.SX(1.0 if self.quiescent else 0.0)
        elif isinstance(s, sy.Const):
            out = ca.SX(s.value)
        elif isinstance(s, sy.Node):
            out = self.node(s.name)
        elif isinstance(s, sy.Diff):
            out = self.node(s.plus) - self.node(s.minus)
        elif isinstance(s, sy.Branch):
            out = self.node(s.name)
        elif isinstance(s, sy.Time):
            out = self.t
        elif isinstance(s, sy.Cond):
            out = ca.if_else(self(s.test), self(s.then), self(s.other))
        elif isinstance(s, (sy.Op, sy.Fn)) and s.name in _CASADI:
            out = _CASADI[s.name](*(self(a) for a in s.args))
        else:
            raise WrsimError(f"the reference solver cannot integrate {s!r}")
        self.memo[s] = out
        return out


def _state_of(source: sy.S) -> str:
    """The node that a 'dot's quantity makes a differential state: v(n) or v(n) - v(0)."""
    if isinstance(source, sy.Node):
        return source.name
    if isinstance(source, sy.Diff) and source.minus == "0":
        return source.plus
    raise WrsimError(
        f"the reference solver cannot integrate the 'dot of {source!r} (only of a node against the reference)"
    )


def integrate(
    system: System,
    times: list[float],
    reltol: float,
    max_step: float,
    replay: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
) -> ReferenceRun:
    """Integrate `system` from its quiescent point at t = 0 through the output `times` (increasing, > 0). `replay`
    gives each digital node that an equation reads as (change times, 0/1 levels), the first at t = 0 (an ngspice
    event record, backend.ngspice.raw.read_events)."""
    try:
        return _integrate(system, times, reltol, max_step, replay or {})
    except RuntimeError as e:  # CasADi's own errors (a structurally singular system, ...)
        raise WrsimError(f"the reference solver failed: {str(e).splitlines()[-1]}") from None


def _integrate(
    system: System, times: list[float], reltol: float, max_step: float, replay: dict[str, tuple[np.ndarray, np.ndarray]]
) -> ReferenceRun:
    t0 = clock.perf_counter()
    states = {n: _state_of(src) for n, src in system.derivatives.items()}  # 'dot unknown -> state node
    if len(set(states.values())) < len(states):
        raise WrsimError("the reference solver cannot integrate a quantity whose 'dot is taken in two places")
    state_nodes = list(states.values()) + list(system.integrals)
    algebraic = [
        n for n in dict.fromkeys(system.unknowns + list(system.kcl) + list(system.derivatives)) if n not in state_nodes
    ]
    if len(algebraic) != len(system.residuals) + len(system.kcl):
        raise WrsimError(
            f"the reference solver's system is not square: {len(algebraic)} algebraic unknowns, "
            f"{len(system.residuals) + len(system.kcl)} equations"
        )
    levels = sorted(system.inputs)
    missing = [system.inputs[n] for n in levels if system.inputs[n] not in replay]
    if missing:
        raise WrsimError(f"the reference solver needs a record of the digital signals {', '.join(missing)}")
    x, z, t = ca.SX.sym("x", len(state_nodes)), ca.SX.sym("z", len(algebraic)), ca.SX.sym("t")
    p = ca.SX.sym("p", len(levels))
    names = {
        **{n: x[k] for k, n in enumerate(state_nodes)},
        **{n: z[k] for k, n in enumerate(algebraic)},
        **{n: p[k] for k, n in enumerate(levels)},
    }

    def equations(quiescent: bool) -> tuple[ca.SX, ca.SX]:
        b = _Builder(dict(names), system.defined, t, quiescent)
        alg = [b(r) for r in system.residuals]
        alg += [sum((sign * b.node(th) for th, sign in terms), ca.SX(0)) for terms in system.kcl.values()]
        ode = [b.node(d) for d in states] + [b(src) for src in system.integrals.values()]
        return ca.vertcat(*ode), ca.vertcat(*alg)

    # The quiescent point: every 'dot 0, the integrals 0, the algebraic equations at time 0 in the quiescent domain.
    ode_q, alg_q = equations(True)
    w = ca.vertcat(x, z)
    held = ca.vertcat(*(ode_q[k] for k in range(len(states))), *(x[k] for k in range(len(states), len(state_nodes))))
    g = ca.vertcat(alg_q, held)
    segments = _segments([system.inputs[n] for n in levels], replay, times)
    from_here = np.full(w.shape[0], 1e-3)  # not 0: sqrt, |x| have no slope there
    try:
        root = ca.rootfinder(
            "quiescent",
            "newton",
            ca.Function("g", [w, p, t], [g]),
            {"abstol": 1e-10, "max_iter": 200, "error_on_fail": False},
        )
        w0 = np.asarray(root(from_here, segments[0][1], 0.0)).ravel()
    except RuntimeError:  # structurally singular: unknowns the quiescent point leaves free
        w0 = _least_change_root(ca.Function("g", [w, p, t], [g, ca.jacobian(g, w)]), from_here, segments[0][1])
    if not np.all(np.isfinite(w0)):
        raise WrsimError("the reference solver found no quiescent point")
    ode, alg = equations(False)
    if not state_nodes:  # IDAS needs a differential state: a constant one
        x, ode, w0 = ca.SX.sym("x", 1), ca.SX(0), np.concatenate([[0.0], w0])
    dae = {"x": x, "z": z, "p": p, "t": t, "ode": ode, "alg": alg}
    # IDAS's error test on the differential states only (suppress_algebraic), as ngspice's truncation error is
    # taken on its reactive elements only; with the algebraic unknowns in it, the stroke bench took 7x the steps.
    options = {
        "reltol": reltol,
        "abstol": 1e-6,
        "max_step_size": max_step,
        "calc_ic": True,
        "suppress_algebraic": True,
        "max_num_steps": 10_000_000,
    }
    # After a replayed change the algebraic unknowns jump: Newton from the last values finds them before IDAS
    # (whose own consistent-start search fails at some relay switchings of the closed loop).
    consistent = None
    if len(segments) > 1:
        try:
            consistent = ca.rootfinder(
                "consistent",
                "newton",
                ca.Function("c", [z, x, p, t], [alg]),
                {"abstol": 1e-9, "max_iter": 100, "error_on_fail": False},
            )
        except RuntimeError:  # structurally singular in z alone: IDAS's own search only
            pass
    xk, zk = w0[: x.shape[0]], w0[x.shape[0] :]
    columns: list[np.ndarray] = []
    seconds, steps = 0.0, 0
    for k, (start, level, grid) in enumerate(segments):
        end = segments[k + 1][0] if k + 1 < len(segments) else times[-1]
        said: list[str] = []
        try:
            with _c_stderr_into(said):
                f = ca.integrator(
                    "reference", "idas", dae, start, grid if grid and grid[-1] == end else [*grid, end], options
                )
                if k and consistent is not None:
                    guess = np.asarray(consistent(zk, xk, level, start)).ravel()
                    zk = guess if np.all(np.isfinite(guess)) else zk
                s0 = clock.perf_counter()  # IDAS alone: not building its functions, not the restart
                out = f(x0=xk, z0=zk, p=level)
                seconds += clock.perf_counter() - s0
        except RuntimeError as e:
            reason = next((ln.strip() for ln in reversed(said) if ln.strip()), str(e).splitlines()[-1].strip())
            raise WrsimError(f"IDAS stopped between {start:g} s and {end:g} s: {reason}") from None
        steps += int(f.stats().get("nsteps", 0))
        xs, zs = np.asarray(out["xf"]), np.asarray(out["zf"])
        columns += [np.concatenate([xs[:, j], zs[:, j]]) for j in range(len(grid))]
        xk, zk = xs[:, -1], zs[:, -1]
    table = np.array(columns).T
    values = dict(zip(state_nodes + algebraic, table[x.shape[0] - len(state_nodes) :]))
    return ReferenceRun(seconds, clock.perf_counter() - t0, steps, values)


def _least_change_root(g: ca.Function, w: np.ndarray, p: list[float], tol: float = 1e-10) -> np.ndarray:
    """A root of g(w, p, 0) (g returns the residuals and their Jacobian) by Newton with the least-squares step of
    least norm, for a quiescent system that leaves unknowns free (1076.1's `'dot == 0` can: the worm-gear benches'
    load deformation and motor angle): they keep their start, much as ngspice's gmin ties a floating node to the
    reference. CasADi's Newton, which solves the regular systems, refuses such a system. NaN where no root is
    found."""
    for _ in range(200):
        r, jac = (np.asarray(v, dtype=float) for v in g(w, p, 0.0))
        r = r.ravel()
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):
            break
        if np.max(np.abs(r), initial=0.0) <= tol:
            return w
        w = w + np.linalg.lstsq(jac, -r, rcond=None)[0]
    return np.full_like(w, np.nan)


@contextlib.contextmanager
def _c_stderr_into(said: list[str]) -> Iterator[None]:
    """SUNDIALS prints its errors on the C library's stderr: collect them into `said` (for the one error line the
    caller raises) instead of letting them interleave with the command's output."""
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            said += tmp.read().decode("utf-8", "replace").splitlines()


def _segments(
    signals: list[str], replay: dict[str, tuple[np.ndarray, np.ndarray]], times: list[float]
) -> list[tuple[float, list[float], list[float]]]:
    """(start, the replayed levels from then on, the output times up to the next start) per interval between changes
    of any replayed signal before the last output time."""
    starts = sorted({0.0, *(float(tc) for n in signals for tc in replay[n][0] if 0.0 < tc < times[-1])})
    out = []
    for k, start in enumerate(starts):
        end = starts[k + 1] if k + 1 < len(starts) else math.inf
        level = [float(replay[n][1][np.searchsorted(replay[n][0], start, side="right") - 1]) for n in signals]
        out.append((start, level, [tc for tc in times if start < tc <= end]))
    return out
