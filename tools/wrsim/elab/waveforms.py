"""Signal assignments in a process's run (IEEE 1076 10.5.2): the value, delay and pulse rejection limit of each
element of a waveform, as keys of the run's effects (`wrsim.elab.events`), and the HoldEvent a run's sets make.

The first element of `s <= [transport | [reject r] inertial] e1 [after d1], e2 after d2, ...;` arrives with the
assignment's mechanism: inertial rejects the values pending within its limit (r, else d1) before it, transport
none (limit 0); the later elements are transactions added after it (limit 0). The crossing driver applies the
rule (tools/cosim/wrsim_ngspice.c, `schedule`)."""

from __future__ import annotations

from wrsim.elab import symbolic as sy
from wrsim.elab.design import HoldEvent
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.scope import Scope
from wrsim.elab.symbolic import S
from wrsim.errors import SourceError
from wrsim.frontend import ast

__all__ = ["AFTER", "stored", "effect_keys", "assignment", "hold_event"]

AFTER = "after:"  # the key of an element's delay among a run's effects: `after:<key of its value>`
_LIMIT = "limit:"  # the key of a first element's pulse rejection limit: `limit:<hold node>`
_ELEMENT = "#"  # the key of the value of a waveform's element k > 1: `<hold node>#<k>`
_NONE = sy.const(-1.0)  # a delay that means "no transaction" (and an unset limit)


def stored(value: S, typ: str) -> S:
    """The number a held value of base type `typ` stores for `value`."""
    return sy.cond(value, sy.const(1.0), sy.const(0.0)) if typ == "boolean" else value


def effect_keys(assigns: list[ast.SeqSignalAssign]) -> dict[str, S]:
    """The keys the signal assignments `assigns` of a process set among a run's effects besides their signals'
    hold nodes, each with the value that means "unchanged": the delays of the signals assigned after one or with
    several elements, the limits of those assigned with transport or reject, the later elements' values."""
    keys: dict[str, S] = {}
    for s in assigns:
        node = f"{s.target}__s"
        if s.after is not None or s.more:
            keys.setdefault(AFTER + node, _NONE)
        if s.transport or s.reject is not None:
            keys.setdefault(_LIMIT + node, _NONE)
        for k in range(2, len(s.more) + 2):
            keys.setdefault(f"{node}{_ELEMENT}{k}", sy.Node(node))
            keys.setdefault(f"{AFTER}{node}{_ELEMENT}{k}", _NONE)
    return keys


def _time(ev: Evaluator, e: ast.Expr | None, scope: Scope, what: str, noun: str) -> S:
    """The time `e` (None: 0); `what` names it when it is no time, `noun` when it is negative."""
    if e is None:
        return sy.const(0.0)
    delay, t = ev.eval(e, scope)
    if t != "time":
        raise SourceError(e.loc, f"{what} must be a time, found {t}")
    if isinstance(delay, sy.Const) and delay.value < 0.0:
        raise SourceError(e.loc, f"a negative {noun}")
    return delay


def assignment(
    ev: Evaluator, scope: Scope, s: ast.SeqSignalAssign, typ: str, so_far: dict[str, S]
) -> list[tuple[str, S]]:
    """The effects of `s` to a signal of base type `typ`, after the run's effects `so_far` (on this path of its
    ifs): the first element's value (and delay and limit where the process has those keys), each later element's
    value and delay, and no transaction for the later elements of the signal's other assignments that `s` does not
    have. They replace the effects of an assignment before it in the run, which is 1076's rule where `s` deletes
    all the transactions that one made: when s has no delay, or the same first delay."""
    node = f"{s.target}__s"
    out: list[tuple[str, S]] = []
    delays: list[S] = []
    for k, (e, after) in enumerate([(s.value, s.after), *s.more], 1):
        value, t = ev.eval(e, scope)
        if t != typ:
            raise SourceError(e.loc, f"type mismatch: assigning {t} to {typ} signal '{s.target}'")
        delays.append(_time(ev, after, scope, "the delay after `after`", "delay"))
        if k > 1 and not all(isinstance(d, sy.Const) for d in delays):
            raise SourceError(
                (after or e).loc, "unsupported construct: a waveform of several elements whose delays are not static"
            )
        if k > 1 and sy.value(delays[-1]) <= sy.value(delays[-2]):
            raise SourceError((after or e).loc, "the delays of a waveform's elements must ascend (1076 10.5.2.1)")
        if k == 1 and so_far.get(AFTER + node, _NONE) not in (_NONE, delays[0]) and after is not None:
            raise SourceError(
                s.loc,
                f"unsupported construct: a second assignment to '{s.target}' after a delay in one run of a "
                f"process, with a delay other than the first one's (1076 may keep the transactions of both)",
            )
        key = node if k == 1 else f"{node}{_ELEMENT}{k}"
        out += [(key, stored(value, t))] + ([(AFTER + key, delays[-1])] if AFTER + key in so_far else [])
    if _LIMIT + node in so_far:
        limit = sy.const(0.0) if s.transport else delays[0]
        if s.reject is not None:
            limit = _time(ev, s.reject, scope, "the 'reject' limit", "'reject' limit")
            if isinstance(limit, sy.Const) and isinstance(delays[0], sy.Const) and limit.value > delays[0].value:
                raise SourceError(s.reject.loc, "the 'reject' limit is longer than the delay (1076 10.5.2.1)")
        out.append((_LIMIT + node, limit))
    k = len(s.more) + 2
    while f"{AFTER}{node}{_ELEMENT}{k}" in so_far:
        out.append((f"{AFTER}{node}{_ELEMENT}{k}", _NONE))
        k += 1
    return out


def hold_event(sets: list[tuple[str, S]], loc, *args, **kwargs) -> HoldEvent:
    """The HoldEvent of a process run's sets: the values (a waveform's later elements as more sets of their
    hold), and the delays and limits of those assigned `after` a delay."""
    marks = {h: v for h, v in sets if h.startswith((AFTER, _LIMIT))}
    values = [(h, v) for h, v in sets if not h.startswith((AFTER, _LIMIT))]
    event = HoldEvent([(h.split(_ELEMENT)[0], v) for h, v in values], loc, *args, **kwargs)
    for j, (h, _) in enumerate(values):
        if AFTER + h in marks:
            event.delays[j] = marks[AFTER + h]
            if _ELEMENT in h:
                event.limits[j] = sy.const(0.0)  # a later element: a transaction added after the first
            elif _LIMIT + h in marks:
                event.limits[j] = marks[_LIMIT + h]
    return event
