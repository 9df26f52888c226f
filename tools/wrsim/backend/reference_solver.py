"""The reference solver: a bench's analog equations, generated from the IR, integrated by SUNDIALS IDAS (a compiled
variable-order BDF solver for index-1 DAEs) with event location. `wrsim bench` runs it beside ngspice and reports
the ratio, the measure of what the lowering and ngspice cost over the equations themselves (docs/performance.md).
It is a reference, not a second engine: the digital units are not run -- the digital signals that equations read
are replayed from the ngspice run's event record, IDAS restarting at each change --, the unknowns at given output
times and the 'above crossings only.

The system, flattened over every instance, is the one the netlist gives ngspice: an equation per free or through
quantity (its residual), Kirchhoff's current law at every terminal node, `q'dot` as an algebraic unknown whose
quantity becomes a differential state, `q'integ` as a state. The quiescent point (time <= 0, every 'dot 0) is
solved first by Newton (with least-norm steps where it leaves unknowns free). Then every condition that the states
depend on (relations, abs, min, max, sign, floor in the states' rows and in the algebraic rows they read) becomes a
mode, so that IDAS integrates smooth equations between events, and tools/cosim/reference_idas.c locates each mode's
change and each 'above crossing with IDAS's root finding and restarts IDAS at each change. The conditions of rows
that only follow the states (a Hall sensor's pole signals) are evaluated as they stand. CasADi generates the
equations and their Jacobian as C into that program (gcc, cached in the build tree by the digest of the C)."""

from __future__ import annotations

import time as clock
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

import casadi as ca
import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import maximum_bipartite_matching

from wrsim import paths
from wrsim.backend.native import CC, compile_c, digest, run_child, staging
from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT, ArchModel, Design, generic_values, instances, numbers
from wrsim.elab.eliminate import eliminated
from wrsim.errors import WrsimError

__all__ = ["System", "ReferenceRun", "Integration", "flatten", "integrate", "prepare"]


@dataclass
class System:
    """The flattened equations of a design, in netlist-wide node names (lower case, `x_label.` prefixes)."""

    residuals: list[sy.S] = field(default_factory=list)  # = 0, one per free/through quantity
    kcl: dict[str, list[tuple[str, float]]] = field(default_factory=dict)  # terminal -> (through node, +-1)
    derivatives: dict[str, sy.S] = field(default_factory=dict)  # 'dot unknown -> the quantity it derives
    integrals: dict[str, sy.S] = field(default_factory=dict)  # 'integ node -> its integrand
    defined: dict[str, sy.S] = field(default_factory=dict)  # guard and level nodes -> their expression
    guards: list[str] = field(default_factory=list)  # the 'above guard nodes (defined), whose crossings are located
    inputs: dict[str, str] = field(default_factory=dict)  # D->A level node -> the digital node it reads
    unknowns: list[str] = field(default_factory=list)  # free and through quantity nodes


@dataclass
class ReferenceRun:
    """One integration: the wall time of IDAS alone (with its restarts) and of the whole (generation, build,
    quiescent point, IDAS), IDAS's steps, the mode changes located, every unknown and state at the output times
    (netlist-wide node names) and the times at which each 'above guard crossed zero."""

    seconds: float
    total: float
    steps: int
    values: dict[str, np.ndarray]
    events: int = 0
    crossings: dict[str, np.ndarray] = field(default_factory=dict)


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
            sysm.guards.append(node(x.node))
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


_MODED = {">", ">=", "<", "<=", "abs", "sgn", "min", "max", "floor", "ceil"}  # the conditions that become modes


class _Builder:
    """S -> CasADi SX, with every node a symbol or a defined expression and each sub-expression built once. With
    `sites` (a list, filled here) every condition is a mode instead: a symbol of `modes()` standing for which side of
    its argument's zero (0/1) or which integer interval (floor) the argument is in, and `sites` gets (kind, argument)
    for the program that locates the changes (1 for a floor, 0 otherwise)."""

    def __init__(
        self,
        symbols: dict[str, ca.SX],
        defined: dict[str, sy.S],
        t: ca.SX,
        quiescent: bool,
        sites: list[tuple[int, ca.SX]] | None = None,
    ):
        self.symbols, self.defined, self.t, self.quiescent, self.sites = symbols, defined, t, quiescent, sites
        self.memo: dict[sy.S, ca.SX] = {}
        self.mode_symbols: list[ca.SX] = []

    def modes(self) -> ca.SX:
        return ca.vertcat(*self.mode_symbols) if self.mode_symbols else ca.SX(0, 1)

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
        elif self.sites is not None and isinstance(s, (sy.Op, sy.Fn)) and s.name in _MODED:
            out = self._moded(s)
        elif isinstance(s, (sy.Op, sy.Fn)) and s.name in _CASADI:
            out = _CASADI[s.name](*(self(a) for a in s.args))
        else:
            raise WrsimError(f"the reference solver cannot integrate {s!r}")
        self.memo[s] = out
        return out

    def _mode(self, kind: int, argument: ca.SX) -> ca.SX:
        assert self.sites is not None
        self.sites.append((kind, argument))
        self.mode_symbols.append(ca.SX.sym(f"m{len(self.sites)}"))
        return self.mode_symbols[-1]

    def _moded(self, s: sy.Op | sy.Fn) -> ca.SX:
        """A condition as its mode (the memo makes each distinct condition one site)."""
        a = [self(x) for x in s.args]
        if s.name in (">", ">="):
            out = self._mode(0, a[0] - a[1])
        elif s.name in ("<", "<="):
            out = 1 - self._mode(0, a[0] - a[1])
        elif s.name == "abs":
            out = (2 * self._mode(0, a[0]) - 1) * a[0]
        elif s.name == "sgn":
            out = 2 * self._mode(0, a[0]) - 1
        elif s.name in ("max", "min"):
            m = self._mode(0, a[0] - a[1])
            out = ca.if_else(m > 0.5, a[0], a[1]) if s.name == "max" else ca.if_else(m > 0.5, a[1], a[0])
        elif s.name == "floor":
            out = self._mode(1, a[0])
        else:  # ceil
            out = -self._mode(1, -a[0])
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
    return prepare(system, times, reltol, max_step, replay).run()


def prepare(
    system: System,
    times: list[float],
    reltol: float,
    max_step: float,
    replay: dict[str, tuple[np.ndarray, np.ndarray]] | None = None,
) -> Integration:
    """What `integrate` runs, built (the equations generated and compiled, the quiescent point solved): several of
    them may then run at once (`Integration.run` only runs the program)."""
    try:
        return _prepare(system, times, reltol, max_step, replay or {})
    except RuntimeError as e:  # CasADi's own errors (a structurally singular system, ...)
        raise WrsimError(f"the reference solver failed: {str(e).splitlines()[-1]}") from None


@dataclass(frozen=True)
class Integration:
    """A built integration (`prepare`): the program, its input and how to read its output."""

    program: Path
    text: str
    unknowns: list[str]
    guards: list[str]
    points: int  # output times
    started: float  # perf_counter at the start of `prepare`

    def run(self) -> ReferenceRun:
        """Run the program: the unknowns at the output times, the guards' crossings, IDAS's statistics."""
        proc = run_child([str(self.program)], input=self.text, capture_output=True, text=True, timeout=3600)
        rows: list[list[float]] = []
        crossed: dict[str, list[float]] = {g: [] for g in self.guards}
        said: dict[str, float] = {}
        for line in proc.stdout.splitlines():
            word, _, rest = line.partition(" ")
            if word == "error":
                raise WrsimError(f"IDAS: {rest}")
            if word == "y":
                rows.append([float(v) for v in rest.split()[1:]])
            elif word == "cross":
                k, when, _ = rest.split()
                crossed[self.guards[int(k)]].append(float(when))
            elif word in ("steps", "events", "seconds"):
                said[word] = float(rest)
        if proc.returncode != 0 or len(rows) != self.points:
            raise WrsimError(f"the reference solver's program failed (exit {proc.returncode}): {proc.stderr.strip()}")
        table = np.array(rows).T
        return ReferenceRun(
            said["seconds"],
            clock.perf_counter() - self.started,
            int(said["steps"]),
            {n: table[k] for k, n in enumerate(self.unknowns) if n != "(constant)"},
            int(said["events"]),
            {g: np.array(v) for g, v in crossed.items()},
        )


def _prepare(
    system: System, times: list[float], reltol: float, max_step: float, replay: dict[str, tuple[np.ndarray, np.ndarray]]
) -> Integration:
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
    if not state_nodes:  # IDAS needs a differential state: a constant one
        state_nodes = ["(constant)"]
    unknowns = state_nodes + algebraic
    y, t, p = ca.SX.sym("y", len(unknowns)), ca.SX.sym("t"), ca.SX.sym("p", len(levels))
    names = {**{n: y[k] for k, n in enumerate(unknowns)}, **{n: p[k] for k, n in enumerate(levels)}}

    def equations(b: _Builder, outputs: frozenset[int] = frozenset(), plain: _Builder | None = None) -> ca.SX:
        """[x' of each state; the algebraic residuals]; at the quiescent point [every 'dot; the integrals'
        states (held at 0); the algebraic residuals]. The algebraic rows in `outputs` are built by `plain`."""
        held = [y[k] for k in range(len(states), len(state_nodes))]
        ode = [b.node(d) for d in states] + (held if b.quiescent else [b(i) for i in system.integrals.values()])
        rows = [*system.residuals, *system.kcl.items()]
        alg = []
        for k, row in enumerate(rows):
            by = plain if plain is not None and k in outputs else b
            if isinstance(row, tuple):
                terminal, terms = row
                alg.append(sum((sign * by.node(th) for th, sign in terms), _SHUNT * by.node(terminal)))
            else:
                alg.append(by(row))
        return ca.vertcat(*(ode or [y[0] if b.quiescent else ca.SX(0)]), *alg)

    # The quiescent point: every 'dot 0, the integrals 0, the algebraic equations at time 0 in the quiescent domain.
    quiescent = equations(_Builder(dict(names), system.defined, t, True))
    segments = _segments([system.inputs[n] for n in levels], replay, times)
    from_here = np.full(len(unknowns), 1e-3)  # not 0: sqrt, |x| have no slope there
    try:
        root = ca.rootfinder(
            "quiescent",
            "newton",
            ca.Function("g", [y, p, t], [quiescent]),
            {"abstol": 1e-10, "max_iter": 200, "error_on_fail": False},
        )
        w0 = np.asarray(root(from_here, segments[0][2], 0.0)).ravel()
    except RuntimeError:  # structurally singular: unknowns the quiescent point leaves free
        w0 = _least_change_root(
            ca.Function("g", [y, p, t], [quiescent, ca.jacobian(quiescent, y)]), from_here, segments[0][2]
        )
    if not np.all(np.isfinite(w0)):
        raise WrsimError("the reference solver found no quiescent point")
    sites: list[tuple[int, ca.SX]] = []
    b = _Builder(dict(names), system.defined, t, False, sites)
    plain = _Builder(dict(names), system.defined, t, False)  # conditions evaluated, not modes
    outputs = frozenset(_outputs(equations(plain), len(state_nodes), y))
    eqs = equations(b, outputs, plain)
    guards = ca.vertcat(*(plain.node(g) for g in system.guards)) if system.guards else ca.SX(0, 1)
    m = b.modes()
    argument = ca.vertcat(*(a for _, a in sites)) if sites else ca.SX(0, 1)
    inputs = [t, y, p, m]
    functions = [
        ca.Function("wr_eqs", inputs, [eqs]),
        ca.Function("wr_jac", inputs, [ca.densify(ca.jacobian(eqs, y))]),
        ca.Function("wr_sites", inputs, [argument]),
        ca.Function("wr_guards", inputs, [guards]),
    ]
    program = _program(functions)
    text = [
        f"{len(unknowns)} {len(state_nodes)} {len(levels)} {len(sites)} {len(system.guards)}",
        " ".join(str(kind) for kind, _ in sites),
        f"{reltol!r} {_ABSTOL!r} {max_step!r} {_BAND!r}",
        " ".join(repr(float(v)) for v in w0),
        str(len(segments)),
        *(" ".join(repr(float(v)) for v in (start, end, *level)) for start, end, level in segments),
        str(len(times)),
        " ".join(repr(float(v)) for v in times),
    ]
    return Integration(program, "\n".join(text) + "\n", unknowns, list(system.guards), len(times), t0)


_SHUNT = 1e-12  # [through/across] every terminal node's tie to the reference (ngspice's gmin): a node that only
# slack elements reach (a massless cable end while the cable is slack) keeps an equation
_ABSTOL = 1e-6  # IDAS's absolute tolerance (1e-9 stalled it at the top of the stroke)
_BAND = 1e-9  # a mode changes when its argument is this far beyond zero (or its floor's interval): no chattering


def _program(functions: list[ca.Function]) -> Path:
    """The integrator program with `functions` generated into it, built once per generated C (cached)."""
    generator = ca.CodeGenerator("equations.c", {"with_header": False})
    for f in functions:
        generator.add(f)
    driver = paths.COSIM / "reference_idas.c"
    source = generator.dump()
    folder = paths.NATIVE / "reference" / digest(source, driver.read_bytes())[:20]
    program = folder / "reference"
    if not program.is_file():
        with staging(folder) as tmp:
            (tmp / "equations.c").write_text(source)
            compile_c(
                [
                    CC,
                    "-O2",
                    "-o",
                    str(tmp / "reference"),
                    str(driver),
                    str(tmp / "equations.c"),
                    "-l:libsundials_idas.so.5",
                    "-lm",
                ],
                "the reference solver (libsundials-idas5: make setup installs it)",
            )
    return program


def _outputs(eqs: ca.SX, nx: int, y: ca.SX) -> set[int]:
    """The algebraic rows of `eqs` (indices from 0 after the `nx` state rows) that no state's derivative depends on:
    each algebraic unknown matched to the row that determines it (a maximum bipartite matching of the algebraic
    rows' structure), the unknowns the states' rows read and, transitively, those the rows of the unknowns already
    reached read. What is left only follows the states (a Hall sensor's pole signals): its conditions need no
    event, the guards on it locate its crossings."""
    sparsity = ca.jacobian_sparsity(eqs, y)
    rows, cols = (np.asarray(v, dtype=int) for v in sparsity.get_triplet())
    n = y.shape[0]
    algebraic = rows >= nx
    structure = csr_matrix((np.ones(int(algebraic.sum())), (rows[algebraic] - nx, cols[algebraic])), shape=(n - nx, n))
    match = maximum_bipartite_matching(structure[:, nx:], perm_type="column")  # row -> unknown (- nx), -1 if none
    row_of = {int(u) + nx: r for r, u in enumerate(match) if u >= 0}
    reached = {int(c) for r, c in zip(rows, cols) if r < nx and c >= nx}
    todo = list(reached)
    while todo:
        r = row_of.get(todo.pop())
        if r is None:
            continue
        for c in structure.indices[structure.indptr[r] : structure.indptr[r + 1]]:
            if c >= nx and int(c) not in reached:
                reached.add(int(c))
                todo.append(int(c))
    return {r for r, u in enumerate(match) if u >= 0 and int(u) + nx not in reached}


def _least_change_root(g: ca.Function, w: np.ndarray, p: list[float], tol: float = 1e-10) -> np.ndarray:
    """A root of g(w, p, 0) by Newton with the least-squares step of least norm: where the quiescent system leaves
    unknowns free (a spring's deflection under no load and the angle it turns, a motor's angle: structurally
    singular, as 1076.1's quiescent point of `'dot == 0` can be), they keep their start, the way ngspice's gmin
    ties a floating node to ground; elsewhere it is Newton's step. NaN where no root is found."""
    for _ in range(200):
        r, jac = (np.asarray(v, dtype=float) for v in g(w, p, 0.0))
        r = r.ravel()
        if not np.all(np.isfinite(r)) or not np.all(np.isfinite(jac)):
            break
        if np.max(np.abs(r), initial=0.0) <= tol:
            return w
        step = np.linalg.lstsq(jac, -r, rcond=None)[0]
        w = w + step
    return np.full_like(w, np.nan)


def _segments(
    signals: list[str], replay: dict[str, tuple[np.ndarray, np.ndarray]], times: list[float]
) -> list[tuple[float, float, list[float]]]:
    """(start, end, the replayed levels) per interval between changes of any replayed signal up to the last output
    time."""
    starts = sorted({0.0, *(float(tc) for n in signals for tc in replay[n][0] if 0.0 < tc < times[-1])})
    ends = [*starts[1:], times[-1]]
    return [
        (start, end, [float(replay[n][1][np.searchsorted(replay[n][0], start, side="right") - 1]) for n in signals])
        for start, end in zip(starts, ends)
    ]
