"""Simultaneous statements of the model pass (simple, if-use, case-use, null: their residual equations and the
unknowns each involves) and break statements (a discontinuity; with a break list, initial values or a
re-initialisation at events)."""

from __future__ import annotations

from wrsim.elab import events
from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT, ArchModel, Equation
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.scope import GROUND, Quantity, Scope
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast

__all__ = ["simultaneous", "break_statement", "equations", "involved"]


def simultaneous(
    m: ArchModel, ev: Evaluator, st: ast.SimpleSimultaneous | ast.SimultaneousIf | ast.SimultaneousCase
) -> None:
    """The equations of a simultaneous statement, added to `m`."""
    for res, locs in equations(st, ev):
        m.equations.append(Equation(res, locs[0], locs[1:], involved(m, res)))


def break_statement(m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Break, top: bool) -> None:
    """`break [list] [on ...] [when ...];`: a discontinuity; a break list sets initial values (without a
    condition) or re-initialises quantities at events."""
    for e in [*st.on, *([st.cond] if st.cond is not None else [])]:
        ev.eval(e)  # without a break list: a discontinuity, ngspice's step control sees it
    if st.sets and st.cond is None:  # runs once at initialisation, like its equivalent process
        initial_values(m, scope, ev, st, top, strict=not st.on)
    if st.sets and (st.on or st.cond is not None):
        events.reinitialisation(m, scope, ev, st)
    m.breaks.append(st.loc)


def initial_values(m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Break, top: bool, strict: bool) -> None:
    """A break list at initialisation: the quiescent point takes q = value instead of q'dot = 0 (1076.1). Not
    `strict` (a break on events): only what a plain break list could do is done, the rest is left out."""
    if not strict and (not top or any(not isinstance(ev.real(v, scope), sy.Const) for _, v in st.sets)):
        return
    for name, value in st.sets:
        q = scope.lookup(name.removesuffix("'dot"))
        if not isinstance(q, Quantity):
            raise SourceError(st.loc, f"break list: '{name.removesuffix(chr(39) + 'dot')}' is not a quantity")
        v = ev.real(value, scope)
        if not top or not isinstance(v, sy.Const):
            raise SourceError(
                st.loc,
                "unsupported construct: break list at t = 0 "
                + (
                    "in an instantiated model (only in the testbench)" if not top else "with a value that is not static"
                ),
            )
        if name.endswith("'dot"):  # the quiescent point takes q'dot = value instead of 0 (`quiescent_dots`)
            m.initial_dots.append((ev.on_dot(q, st.loc), sy.value(v)))
            continue
        if not isinstance(q.s, sy.Node) and not (isinstance(q.s, sy.Diff) and q.s.minus == GROUND):
            raise SourceError(
                st.loc,
                f"unsupported construct: break list on '{name}', an across quantity "
                f"between two terminals (only to the reference terminal)",
            )
        node = q.s.name if isinstance(q.s, sy.Node) else q.s.plus
        m.initial = [i for i in m.initial if i[0] != node] + [(node, sy.value(v), st.loc)]


def quiescent_dots(m: ArchModel) -> None:
    """`break q'dot => v;` at initialisation: where an equation reads q'dot, the quiescent point reads v (1076.1: the
    break list replaces q'dot = 0 there), the transient q'dot itself."""
    for dot, value in m.initial_dots:
        at_rest = sy.const(value)

        def leaf(x: S, dot: S = dot, at_rest: S = at_rest) -> S | None:
            return sy.cond(QUIESCENT, at_rest, x) if x == dot else None

        for eq in m.equations:
            eq.residual = sy.substitute(eq.residual, {}, leaf)


def equations(st, ev: Evaluator) -> list[tuple[S, list[Loc]]]:
    """Residuals of a simultaneous statement with the location of each branch's equation; an if/case
    becomes one conditional residual per position."""
    if isinstance(st, ast.SimpleSimultaneous):
        lhs, rhs = ev.real(st.lhs), ev.real(st.rhs)
        return [(sy.op("-", lhs, rhs), [st.loc])]
    if isinstance(st, ast.SimultaneousNull):
        return []
    test: S
    if isinstance(st, ast.SimultaneousIf):
        arms = []
        for c, body in st.branches:
            test = sy.const(True)
            if c is not None:
                test, t = ev.eval(c)
                if t != "boolean":
                    raise SourceError(c.loc, f"an if-use condition must be boolean, found {t}")
            arms.append((test, [x for s in body for x in equations(s, ev)]))
        if not any(c is None for c, _ in st.branches):
            arms.append((sy.const(True), []))
    elif isinstance(st, ast.SimultaneousCase):
        sel, t = ev.eval(st.selector)
        arms = []
        for choices, body in st.alternatives:
            if choices is None:
                test = sy.const(True)
            else:
                test = sy.const(False)
                for ch in choices:
                    cs, ct = ev.eval(ch)
                    if ct != t:
                        raise SourceError(ch.loc, f"type mismatch: case choice is {ct}, selector is {t}")
                    test = sy.op("or", test, sy.op("==", sel, cs))
            arms.append((test, [x for s in body for x in equations(s, ev)]))
    else:  # a concurrent statement in a branch (a signal assignment, a process): 1076.1 allows only simultaneous ones
        raise SourceError(
            st.loc,
            "a branch of a simultaneous if or case holds only simultaneous statements (equations, procedurals, nested "
            "if/case, null); a signal assignment or a process goes beside it",
        )
    counts = {len(eqs) for _, eqs in arms}
    if len(counts) > 1:
        detail = ", ".join(str(len(eqs)) for _, eqs in arms)
        raise SourceError(
            st.loc,
            "the branches of this simultaneous "
            f"{'if' if isinstance(st, ast.SimultaneousIf) else 'case'} "
            f"have different numbers of equations ({detail}); 1076.1 requires the same",
        )
    n = counts.pop() if counts else 0
    out = []
    for k in range(n):
        res: S | None = None
        for test, eqs in reversed(arms):
            res = eqs[k][0] if res is None else sy.cond(test, eqs[k][0], res)
        if res is None:
            raise SourceError(st.loc, "internal: a simultaneous statement without branches")
        out.append((res, [loc for _, eqs in arms if eqs for loc in eqs[k][1]]))
    return out


def involved(m: ArchModel, res: S) -> set[str]:
    """Unknowns an equation involves: those it reads, those it differentiates, and the through quantity
    of every branch whose across quantity it reads (an equation on an across quantity alone, like an
    ideal source's, is solved by its branch's through quantity, as in MNA; every branch on that node pair)."""
    names = set()
    by_source: dict[S, list[Quantity]] = {}
    for q in m.quantities.values():  # several branches may share a node pair (a source across a load)
        by_source.setdefault(q.s, []).append(q)
    derived = {d.element: d for d in m.derivatives.values()}
    for x in sy.walk(res):
        qs: list[Quantity] = []
        if isinstance(x, (sy.Node, sy.Diff)):
            qs = by_source.get(x, [])
        elif isinstance(x, sy.Branch) and x.name in derived:
            qs = [m.quantities[derived[x.name].quantity]] if derived[x.name].quantity in m.quantities else []
        for q in qs:
            if q.name in m.unknowns:
                names.add(q.name)
            if q.branch_through:
                names.add(q.branch_through)
    return names
