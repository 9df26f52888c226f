"""The elimination pass, between elaboration and a backend: a free quantity that its own equation gives
explicitly (`speed_rpm == omega * k`, an alias `pos == x`) is no unknown of the simulator; its expression takes its
place wherever it is read. Every quantity stays observable: `ArchModel.eliminated` keeps the expression, which the
backend evaluates from the simulated waveforms. `elaborate` leaves the elaborated design whole (one unknown per
quantity); `eliminated(design)` is the smaller copy a backend lowers."""

from __future__ import annotations

import dataclasses

from wrsim.elab import symbolic as sy
from wrsim.elab.design import ArchModel, Design
from wrsim.elab.symbolic import S, substitute

__all__ = ["eliminated", "eliminate", "event_exprs", "SMALL"]

SMALL = 12  # sub-expressions an eliminated quantity read in more than one place may have (ngspice evaluates a
# behavioural source's expression and its derivative per variable: a large expression copied into
# several readers costs more than the node it saves)


def eliminated(design: Design) -> Design:
    """A copy of `design` with the elimination pass applied to every architecture (`design` is left as it is)."""
    copies: dict[int, ArchModel] = {}
    for m in design.models + [design.top]:  # children first
        r = dataclasses.replace
        copies[id(m)] = c = r(
            m,
            equations=[r(eq) for eq in m.equations],
            unknowns=dict(m.unknowns),
            integrals={k: r(it) for k, it in m.integrals.items()},
            crossings=[r(x) for x in m.crossings],
            adcs=[r(a) for a in m.adcs],
            children=[r(ch, model=copies[id(ch.model)]) for ch in m.children],
            hold_events=[r(e, sets=list(e.sets), delays=dict(e.delays), limits=dict(e.limits)) for e in m.hold_events],
            elements=[r(e) for e in m.elements],
            eliminated=dict(m.eliminated),
        )
        eliminate(c)
    return dataclasses.replace(design, top=copies[id(design.top)], models=[copies[id(m)] for m in design.models])


def eliminate(m: ArchModel) -> None:
    """Remove from `m` the free quantities that their paired equation solves explicitly, `u == e` or `e == u` with
    `u` not in `e`, `e` neither a constant nor reading a 'dot, and `e` small (SMALL) unless `u` is read in one place
    at most. Kept as unknowns: ports, actuals of an instance's ports, quantities whose 'dot is taken (the derivative
    element needs their node), and those whose substitution would close a loop. The pass changes `m` only as a
    whole: if a substituted expression would nest too deep, `m` keeps every unknown."""
    pinned = set(m.ports) | {p for c in m.children for p in c.ports}
    pinned |= {n for d in m.derivatives.values() for n in sy.nodes_of(d.source)}
    pinned |= {node for node, _, _ in m.initial} | set(m.noise_sources)  # a noise source's node carries its noise
    readers = [eq.residual for eq in m.equations] + [it.source for it in m.integrals.values()]
    readers += [x.guard for x in m.crossings] + [a.cond for a in m.adcs] + event_exprs(m)
    reads = {u: sum(1 for r in readers if u in sy.nodes_of(r)) - 1 for u in m.unknowns}  # less its own equation
    aliases: dict[str, S] = {}
    try:
        for eq in m.equations:
            u = eq.paired
            if m.unknowns[u].role != "free" or u in pinned or eq.alternatives:
                continue
            expr = _solved(eq.residual, u)
            if expr is None or isinstance(expr, sy.Const) or sy.branches_of(expr):
                continue  # a constant, or a 'dot's branch current (not observable from the waveforms)
            expr = substitute(expr, aliases)
            if reads[u] > 1 and sum(1 for _ in sy.walk(expr)) > SMALL:
                continue  # large and read in several places: one node is cheaper than the copies
            if u in sy.nodes_of(expr):
                continue  # an algebraic loop through earlier aliases: u stays an unknown
            aliases = {w: substitute(e, {u: expr}) for w, e in aliases.items()}
            aliases[u] = expr
        if not aliases:
            return
        kept = [eq for eq in m.equations if eq.paired not in aliases]
        residuals = [substitute(eq.residual, aliases) for eq in kept]
        integrals = [substitute(it.source, aliases) for it in m.integrals.values()]
        crossings = [(substitute(x.guard, aliases), substitute(x.test, aliases)) for x in m.crossings]
        conds = [substitute(a.cond, aliases) for a in m.adcs]
        sources = [substitute(el.source, aliases) for el in m.elements]
        events = [
            (
                [(h, substitute(v, aliases)) for h, v in e.sets],
                None if e.cond is None else substitute(e.cond, aliases),
                {j: substitute(d, aliases) for j, d in e.delays.items()},
                {j: substitute(x, aliases) for j, x in e.limits.items()},
            )
            for e in m.hold_events
        ]
    except sy.FoldError:
        return
    m.equations = kept
    for u in aliases:
        del m.unknowns[u]
    for eq, r in zip(kept, residuals):
        eq.residual = r
        eq.unknowns = sy.nodes_of(r) & set(m.unknowns)
    for it, src in zip(m.integrals.values(), integrals):
        it.source = src
    for x, (guard, test) in zip(m.crossings, crossings):
        x.guard, x.test = guard, test
    for a, cond in zip(m.adcs, conds):
        a.cond = cond
    for e, (sets, when, delays, limits) in zip(m.hold_events, events):
        e.sets, e.cond, e.delays, e.limits = sets, when, delays, limits
    for el, source in zip(m.elements, sources):
        el.source = source
    m.eliminated.update(aliases)


def event_exprs(m: ArchModel) -> list[S]:
    """What the events of `m` evaluate (the values holds take, the conditions) and the inputs of its elements."""
    return (
        [v for e in m.hold_events for _, v in e.sets]
        + [e.cond for e in m.hold_events if e.cond is not None]
        + [e.source for e in m.elements]
    )


def _solved(residual: S, u: str) -> S | None:
    """`e` when `residual` is `u - e` or `e - u` with `u` not in `e`, else None."""
    if not (isinstance(residual, sy.Op) and residual.name == "-"):
        return None
    a, b = residual.args
    for this, other in ((a, b), (b, a)):
        if this == sy.Node(u) and u not in sy.nodes_of(other):
            return other
    return None
