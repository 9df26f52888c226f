"""The event side of an AMS architecture (IEEE 1076.1's mixed-signal cycle, as far as the analog solver sees it):
signals of type real, integer, boolean, bit and std_ulogic that processes assign (at once or `after` a delay),
process variables, break lists that re-initialise quantities, and the events that change them: crossings of 'above
signals, changes of signals, `wait for` periods and wake-up times, and the run at initialisation. Each such value is
a `Hold` of the architecture; the backend gives it to the crossing driver, which changes it only at events
(`HoldEvent`)."""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from wrsim.elab import symbolic as sy
from wrsim.elab import waveforms
from wrsim.elab.calls import Bind
from wrsim.elab.design import ArchModel, Element, Hold, HoldEvent
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.scope import INTEGER_LOW, Quantity, Scope, Signal, Value, base_type
from wrsim.elab.symbolic import S, substitute
from wrsim.elab.waveforms import hold_event, stored
from wrsim.errors import SourceError
from wrsim.frontend import ast

__all__ = [
    "NEVER",
    "HELD_TYPES",
    "assigned_signals",
    "held_signal",
    "reinitialisation",
    "process",
    "guards",
    "fold_initial_runs",
]

HELD_TYPES = ("real", "integer", "boolean", "std_logic", "time")  # base types a held signal may have
_DEFAULTS = {"real": -1e300, "integer": INTEGER_LOW, "boolean": 0.0, "std_logic": 0.0, "time": -1e300}  # T'left
_NO_EVENT: Mapping[str, S] = {}  # a run in which no signal has an event


def guards(m: ArchModel, s: S) -> list[str]:
    """The guard nodes of the 'above tests `s` reads."""
    tests = {x for x in sy.walk(s) if isinstance(x, sy.Op) and x.name == ">"}
    return [c.node for c in m.crossings if c.test in tests]


def _signals(m: ArchModel, s: S) -> list[str]:
    """The held signals `s` reads (their hold nodes)."""
    return sorted(h for h in sy.nodes_of(s) if h in m.holds and m.holds[h].name is not None)


def _sensitivity(m: ArchModel, exprs: list[tuple[S, ast.Expr]], what: str) -> tuple[list[str], list[str]]:
    """The 'above guards and held signals a sensitivity list of `exprs` names; each must name one."""
    found: list[str] = []
    changes: list[str] = []
    for s, e in exprs:
        g, h = guards(m, s), _signals(m, s)
        if not g and not h:
            raise SourceError(
                e.loc,
                f"unsupported construct: {what} other than q'above(e) or a signal a process "
                f"of this architecture assigns",
            )
        found += g
        changes += h
    return list(dict.fromkeys(found)), list(dict.fromkeys(changes))


def assigned_signals(stmts: list) -> set[str]:
    """The names of the signals the processes among `stmts` assign."""
    return {
        s.target
        for st in stmts
        if isinstance(st, ast.Process)
        for s, _ in ast.nested(st.body)
        if isinstance(s, ast.SeqSignalAssign)
    }


def _read(node: str, typ: str) -> S:
    """How an expression reads a held value of base type `typ` (a boolean is held as 0/1)."""
    return sy.op(">", sy.Node(node), sy.const(0.5)) if typ == "boolean" else sy.Node(node)


def _static(ev: Evaluator, e: ast.Expr | None, typ: str, scope: Scope) -> S:
    if e is None:
        return sy.const(_DEFAULTS[typ])
    s, t = ev.eval(e, scope)
    if t != typ or sy.nodes_of(s):
        raise SourceError(e.loc, f"the initial value must be a static {typ}" + (f", found {t}" if t != typ else ""))
    return stored(s, typ)


def held_signal(m: ArchModel, scope: Scope, ev: Evaluator, d: ast.SignalDecl) -> None:
    """Declare signal `d` as a held value (its node is <name>__s)."""
    typ = base_type(d.type_mark, scope, d.loc)
    if typ not in HELD_TYPES or (d.width is not None and typ != "integer"):
        raise SourceError(
            d.loc,
            f"unsupported construct: signal of type {d.type_mark} (a signal the analog side holds is real, integer, "
            f"boolean, bit, std_logic or time, or a subtype of one; an integer vector as std_logic_vector)",
        )
    node = f"{d.name}__s"
    m.holds[node] = Hold(node, _static(ev, d.value, typ, scope), d.loc, name=d.name, integer=typ == "integer")
    scope.declare(d.name, Value(_read(node, typ), typ, "signal", d.loc), d.loc)


def _quantity_hold(m: ArchModel, q: Quantity, st: ast.Break) -> str:
    hold = f"{q.name}__h"
    m.holds.setdefault(hold, Hold(hold, sy.const(0.0), st.loc, q.name))
    return hold


def _break_sets(m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Break, when: S | None) -> list[tuple[str, S]]:
    """The held offsets a break list sets and the values their quantities take (unchanged where `when` fails)."""
    sets = []
    for name, value in st.sets:
        if name.endswith("'dot"):
            raise SourceError(
                st.loc,
                f"unsupported construct: a break on {name} at an event (a derivative is set at initialisation only; "
                f"break the quantity it derives or the state that gives it)",
            )
        q = scope.lookup(name)
        if not isinstance(q, Quantity):
            raise SourceError(st.loc, f"break list: '{name}' is not a quantity")
        e = ev.real(value, scope)
        sets.append((_quantity_hold(m, q, st), e if when is None else sy.cond(when, e, q.s)))
    return sets


def _boolean(ev: Evaluator, e: ast.Expr, scope: Scope, what: str) -> S:
    s, t = ev.eval(e, scope)
    if t != "boolean":
        raise SourceError(e.loc, f"the condition of {what} must be boolean, found {t}")
    return s


def reinitialisation(m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Break) -> None:
    """`break q => e, ... [on s, ...] [when c];`: at every event of the sensitivity signals (those of `c` when there
    is no `on`) at which c holds, each q restarts from e (evaluated at the event), as 1076.1's analog solver
    re-initialises at a break. The signals are 'above signals; each q is a quantity whose 'dot the architecture
    takes (the integrated state that restarts)."""
    found, changes = _sensitivity(m, [(ev.eval(e, scope)[0], e) for e in st.on], "break on a signal")
    cond = None if st.cond is None else _boolean(ev, st.cond, scope, "a break")
    if not st.on and cond is not None:
        found, changes = guards(m, cond), _signals(m, cond)
    if not found and not changes:
        raise SourceError(
            st.loc,
            "unsupported construct: break whose condition reads no q'above(e) or signal (it "
            "is sensitive to no event after t = 0)",
        )
    m.hold_events.append(HoldEvent(_break_sets(m, scope, ev, st, None), st.loc, found, changes, cond))


@dataclass
class _Named:
    name: str


NEVER = 1e300  # [s] the period of an event that happens once


def _is_signal(b: object) -> bool:
    return isinstance(b, Signal) or (isinstance(b, Value) and b.kind == "signal")


def process(m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Process) -> None:
    """A process of the subset: a sensitivity list and no wait; one wait statement (`on` 'above or held signals,
    `until` a condition on them), first or last; waits that are all `wait for T` (a stimulus, repeated, or run
    once when it ends with `wait;`); or waits of several kinds in sequence (`_sequence`), for loops of waits
    unrolled. The statements run at the events of their wait and, when the process starts with statements, once at
    initialisation. Signal assignments and break lists take effect after the statements (all at once, or `after`
    a delay), variables keep their values between runs."""
    label = st.label or f"process_{st.loc.line}"
    wait = next((s for s, _ in ast.nested(st.body) if isinstance(s, ast.Wait)), None)
    if wait is not None and (st.sensitivity or st.implied):
        raise SourceError(wait.loc, "a process with a sensitivity list must not contain a wait statement")
    if st.implied:  # a concurrent signal assignment or `process (all)`: sensitive to the signals (and 'above) among
        # the names it reads
        sensitivity: list[ast.Expr] = []
        for x in st.sensitivity:
            if isinstance(x, ast.Attr) or (
                isinstance(x, ast.Name)
                and _is_signal(scope.lookup(x.ident))
                and all(not (isinstance(y, ast.Name) and y.ident == x.ident) for y in sensitivity)
            ):
                sensitivity.append(x)
        body = st.body if sensitivity else [*st.body, ast.Wait([], None, None, st.loc)]  # none: runs once
        st = ast.Process(st.label, sensitivity, st.decls, body, st.loc)
    env = Scope(scope)
    held: dict[str, tuple[str, str]] = {}  # variable -> (hold node, base type)
    for d in st.decls:
        t = base_type(d.type_mark, scope, d.loc)
        if isinstance(d, ast.ConstantDecl):
            if d.value is None:
                raise SourceError(d.loc, "unsupported construct: deferred constant")
            env.declare(d.name, Value(ev.eval(d.value, env)[0], t, "constant", d.loc), d.loc)
            continue
        if t not in HELD_TYPES:
            raise SourceError(d.loc, f"unsupported construct: process variable of type {d.type_mark}")
        node = f"{label}__{d.name}"
        m.holds[node] = Hold(
            node, _static(ev, d.value, t, env), d.loc, name=f"{label}.{d.name}", integer=t == "integer"
        )
        held[d.name] = (node, t)
        env.declare(d.name, Value(_read(node, t), t, "variable", d.loc), d.loc)
    body = list(st.body)
    if len(body) == 1 and isinstance(body[0], ast.WhileLoop) and body[0].cond is None:
        body = list(body[0].body)  # a plain loop that is the whole body: the process's own repetition
    body = _flattened(ev, env, body, [])
    _no_nested_wait(body)
    for k, s in enumerate(body):  # what follows a `wait;` never runs (the process is suspended for good)
        if isinstance(s, ast.Wait) and s.timeout is None and not s.on and s.until is None:
            del body[k + 1 :]
            break
    waits = [k for k, s in enumerate(body) if isinstance(s, ast.Wait)]

    def run(stmts: list, events: Mapping[str, S] = _NO_EVENT) -> list[tuple[str, S]]:
        return _statements(m, ev, env, held, label, stmts, assigned_signals([st]), events)

    if st.sensitivity:
        _triggered(m, ev, env, ast.Wait(st.sensitivity, None, None, st.loc), lambda e: run(body, e), True, st.loc)
    elif not waits:
        raise SourceError(st.loc, "a process without a sensitivity list or a wait statement never suspends")
    elif all(
        body[k].timeout is not None
        and not body[k].on
        and body[k].until is None
        or (k == len(body) - 1 and body[k].timeout is None and not body[k].on and body[k].until is None)
        for k in waits
    ):
        _stimulus(m, ev, env, body, waits, run, st.loc)
    elif len(waits) == 1 and waits[0] in (0, len(body) - 1) and not _with_timeout(body[waits[0]]):
        trigger = body.pop(waits[0])
        _triggered(m, ev, env, trigger, lambda e: run(body, e), waits[0] != 0, st.loc)
    else:
        _sequence(m, ev, env, body, waits, run, label, st.loc)


def _sequence(m: ArchModel, ev: Evaluator, env: Scope, body: list, waits: list[int], run, label: str, loc) -> None:
    """A process with waits of several kinds in sequence (none inside an if), as a state machine: the held
    value `<label>__state` is the number of the wait the process is suspended in, from 1 (0: at `wait;`, for good).
    Each wait resumes on its own events, in its state only, runs the statements up to the next wait and enters
    that one; `wait [on s] [until c] for T` sets `<label>__wake` to now + T as it is entered and resumes when the
    time reaches it (or at its condition's event, the earlier). The statements before the first wait run at
    initialisation."""
    state, wake = f"{label}__state", f"{label}__wake"
    m.holds[state] = Hold(state, sy.const(0.0), loc)
    bounds = [-1, *waits, len(body)]
    segments = [body[a + 1 : b] for a, b in zip(bounds, bounds[1:])]

    def enter(k: int) -> list[tuple[str, S]]:  # the sets that suspend the process in wait k (1-based)
        w = body[waits[k - 1]]
        if w.timeout is None and not w.on and w.until is None:
            return [(state, sy.const(0.0))]  # `wait;`
        if w.timeout is None:
            return [(state, sy.const(float(k)))]
        m.holds.setdefault(wake, Hold(wake, sy.const(NEVER), loc))
        return [(state, sy.const(float(k))), (wake, sy.op("+", sy.Time(), _time(ev, w.timeout, env)))]

    m.hold_events.append(hold_event(run(segments[0]) + enter(1), loc, first=True))
    for k in range(1, len(waits) + 1):
        w = body[waits[k - 1]]
        if w.timeout is None and not w.on and w.until is None:
            continue  # `wait;` never resumes
        stmts = segments[k] + (segments[0] if k == len(waits) else [])  # the last wait goes round to the first
        then = k + 1 if k < len(waits) else 1

        def resume(events: Mapping[str, S], stmts=stmts, then=then) -> list[tuple[str, S]]:
            return run(stmts, events) + enter(then)

        in_state = sy.op("==", sy.Node(state), sy.const(float(k)))
        if w.timeout is not None:
            m.hold_events.append(hold_event(resume(_NO_EVENT), loc, cond=in_state, at=wake))
        if _with_timeout(w) or w.timeout is None:
            _triggered(m, ev, env, ast.Wait(w.on, w.until, None, w.loc), resume, False, loc, in_state)


def _with_timeout(w: ast.Wait) -> bool:
    """A wait on a condition with a timeout (`wait on s for T`, `wait until c for T`)."""
    return w.timeout is not None and (bool(w.on) or w.until is not None)


def _statements(
    m: ArchModel,
    ev: Evaluator,
    env: Scope,
    held: dict[str, tuple[str, str]],
    label: str,
    stmts: list,
    signals: set[str],
    events: Mapping[str, S],
) -> list[tuple[str, S]]:
    """Run `stmts` of a process from the held values, the signals of the hold nodes of `events` having an event
    where their boolean holds: the (hold node, value) pairs their assignments, breaks and variables set.
    `ev.event_read` tells whether the run asked for an event ('event, rising_edge)."""
    at = Scope(env)
    variables = {n: _read(node, t) for n, (node, t) in held.items()}
    types = {n: t for n, (_, t) in held.items()}
    for n, t in types.items():
        at.names[n] = Value(variables[n], t, "variable")
    effects = {
        **{h.node: sy.Node(h.node) for h in m.holds.values() if h.name in signals},
        **{_quantity_hold(m, q, b): q.s for b, q in _breaks(stmts, env)},
        **waveforms.effect_keys([s for s, _ in ast.nested(stmts) if isinstance(s, ast.SeqSignalAssign)]),
    }
    unchanged = dict(effects)

    def effect(s: ast.SeqSignalAssign | ast.Break, scope: Scope, so_far: dict[str, S]) -> list[tuple[str, S]]:
        if isinstance(s, ast.Break):
            if s.on:
                raise SourceError(s.on[0].loc, "a break statement in a process has no 'on' (it runs where it is)")
            return _break_sets(m, scope, ev, s, None if s.cond is None else _boolean(ev, s.cond, scope, "a break"))
        target = scope.lookup(s.target)
        if isinstance(target, Signal):
            raise SourceError(
                s.loc,
                f"'{s.target}' is a signal port: the analog side drives it with the A->D form "
                f"{s.target} <= '1' when <condition> else '0'; (a process drives the signals it declares)",
            )
        if not (isinstance(target, Value) and target.kind == "signal"):
            raise SourceError(s.loc, f"'{s.target}' is not a signal this architecture declares")
        return waveforms.assignment(ev, scope, s, target.typ, so_far)

    ev.on_effect, ev.events = effect, events
    try:
        ev.run(stmts, at, variables, types, _Named(f"process {label}"), effects)
    finally:
        ev.on_effect, ev.events = None, None
    after = waveforms.AFTER
    sets = [
        (h, v)
        for h, v in effects.items()
        if v != unchanged[h] or effects.get(after + h, unchanged[h]) != unchanged.get(after + h, unchanged[h])
    ]
    return sets + [(held[n][0], stored(v, types[n])) for n, v in variables.items() if v != _read(*held[n])]


def _triggered(
    m: ArchModel,
    ev: Evaluator,
    env: Scope,
    trigger: ast.Wait,
    run: Callable[[Mapping[str, S]], list[tuple[str, S]]],
    first: bool,
    loc,
    when: S | None = None,
) -> None:
    """The events of a process whose one wait is `trigger` (or its sensitivity list; a wait without a timeout:
    `wait for` is `_stimulus`'s or `_sequence`'s); `run` runs its statements with the signals of the given hold
    nodes having an event where their booleans hold; `when`: a condition of every event besides the wait's (a state
    of `_sequence`). A process that asks for no event ('event, rising_edge) gets one event for all its triggers; one
    that asks gets one for its 'above crossings and its run at initialisation, run with no event, and one for the
    changes of the signals it waits on, run with their events (`_event_flags`)."""
    ev.event_read = False
    sets = run(_NO_EVENT)
    cond = None
    found, changes = _sensitivity(m, [(ev.eval(e, env)[0], e) for e in trigger.on], "wait on a signal")
    if trigger.until is not None:
        cond = _condition(ev, trigger.until, env, _NO_EVENT)
        if not trigger.on:  # its signals: those it reads, and those whose event it asks for (clk'event)
            marks = {h: sy.Node(f"{h}{_EVENT_MARK}") for h in m.holds}
            every = _condition(ev, trigger.until, env, marks)
            asked = sorted({n.removesuffix(_EVENT_MARK) for n in sy.nodes_of(every) if n.endswith(_EVENT_MARK)})
            found, changes = guards(m, every), sorted({*_signals(m, every), *asked})
            if not found and not changes:
                raise SourceError(
                    trigger.until.loc,
                    "unsupported construct: wait until a condition that reads no q'above(e) or signal",
                )

    def both(c: S | None) -> S | None:
        return c if when is None else when if c is None else sy.op("and", when, c)

    cond = both(cond)
    if not ev.event_read:  # no event asked for: one event for all its triggers
        if sets:
            m.hold_events.append(hold_event(sets, loc, found, changes, cond, first=first))
        return
    if sets and (first or found):
        m.hold_events.append(hold_event(sets, loc, found, [], cond, first=first))
    if not changes:
        return
    events = _event_flags(changes)
    sets = run(events)
    if sets:
        c = None if trigger.until is None else _condition(ev, trigger.until, env, events)
        m.hold_events.append(hold_event(sets, loc, [], changes, both(c)))
        _flag_elements(m, m.hold_events[-1], changes)


def _flag(hold: str) -> str:
    """The node of the event flag of held signal `hold`."""
    return f"{hold}__event"


def _event_flags(changes: list[str]) -> dict[str, S]:
    """How a run at a change of one of the held signals `changes` reads their 'event (IEEE 1076: a process runs
    once per simulation cycle in which one of them changes, with 'event true for each that did): true when it is
    the only one; else the event flag of each, a source the crossing driver sets to 1 at the delta cycle that sees
    a change of its signal and to 0 at the others (`_flag_elements`)."""
    if len(changes) == 1:
        return {changes[0]: sy.const(True)}
    return {h: _read(_flag(h), "boolean") for h in changes}


def _flag_elements(m: ArchModel, e: HoldEvent, changes: list[str]) -> None:
    """The `flag` elements of the event flags of `changes` that event `e` reads (one per signal in `m`)."""
    exprs = [v for _, v in e.sets] + [*e.delays.values(), *e.limits.values()] + ([e.cond] if e.cond is not None else [])
    read = set().union(*map(sy.nodes_of, exprs))
    for h in changes:
        if _flag(h) in read and all(el.node != _flag(h) for el in m.elements):
            m.elements.append(Element("flag", _flag(h), sy.Node(h), (), e.loc))


_EVENT_MARK = "\0event"  # a signal's event in the condition read once to find what a `wait until` waits on


def _condition(ev: Evaluator, until: ast.Expr, env: Scope, events: Mapping[str, S]) -> S:
    """The condition of `wait until`, the signals of `events` having an event where their booleans hold."""
    ev.events = events
    try:
        return _boolean(ev, until, env, "a wait")
    finally:
        ev.events = None


def _time(ev: Evaluator, e: ast.Expr, env: Scope) -> S:
    s, t = ev.eval(e, env)
    if t != "time" or sy.nodes_of(s):
        raise SourceError(e.loc, f"wait for needs a static time, found {t}")
    if isinstance(s, sy.Const) and s.value < 0.0:  # IEEE 1076-2008 10.2: a negative timeout is an error
        raise SourceError(e.loc, f"wait for {s.value:g} s: a timeout must not be negative")
    return s


def _stimulus(m: ArchModel, ev: Evaluator, env: Scope, body: list, waits: list[int], run, loc) -> None:
    """A process whose waits are all `wait for T`: its statements between the waits run at the sums of the times,
    over and over with the period of their total, or once if it ends with `wait;`."""
    once = body[waits[-1]].timeout is None
    bounds = [-1, *waits, len(body)]
    segments = [body[a + 1 : b] for a, b in zip(bounds, bounds[1:])]
    times: list[S] = [sy.const(0.0)]
    for k in waits:
        if body[k].timeout is not None:
            step = _time(ev, body[k].timeout, env)
            try:
                times.append(sy.op("+", times[-1], step))
            except sy.FoldError:
                raise SourceError(body[k].loc, "the waits' times add up past the largest time (real'high s)") from None
    cycle = times[-1]
    if not once and isinstance(cycle, sy.Const) and cycle.value <= 0.0:
        raise SourceError(loc, "a process whose waits add up to no time never suspends")
    if not once and segments[-1]:  # the statements after the last wait run with the first
        segments = [segments[0]] + segments[1:-1] + [segments[-1] + segments[0]]
    for k, stmts in enumerate(segments[: len(times)]):
        sets = run(stmts)
        if not sets:
            continue
        if k == 0:
            m.hold_events.append(hold_event(sets, loc, first=True))
            if not once and not segments[-1]:
                m.hold_events.append(hold_event(list(sets), loc, period=cycle, offset=cycle))
        else:
            m.hold_events.append(hold_event(sets, loc, period=sy.const(NEVER) if once else cycle, offset=times[k]))


def _breaks(body: list, scope: Scope) -> list[tuple[ast.Break, Quantity]]:
    return [
        (s, q)
        for s, _ in ast.nested(body)
        if isinstance(s, ast.Break)
        for name, _ in s.sets
        if isinstance(q := scope.lookup(name), Quantity)
    ]


def _flattened(ev: Evaluator, env: Scope, body: list, binds: list[Bind]) -> list:
    """`body` with the for loops and ifs that contain a wait turned into a sequence of statements, so that its waits
    are in sequence: a loop unrolled (its bounds static), an if replaced by the branch its static condition takes
    (a generic's, a constant's or a loop variable's). The loop variables are bound again after each wait (the
    statements between two waits run on their own). An if whose condition is not static stays (an error later)."""
    here = Scope(env)
    for b in binds:
        here.names[b.name] = Value(sy.const(float(b.value)), "integer", "loop", b.loc)
    out: list = []
    for s in body:
        waits = any(isinstance(x, ast.Wait) for x, _ in ast.nested([s]))
        if waits and isinstance(s, ast.WhileLoop):
            raise SourceError(
                s.loc,
                "unsupported construct: a while loop or plain loop with a wait inside (a plain loop that is the whole "
                "process body is its repetition)",
            )
        if waits and isinstance(s, ast.ForLoop) and any(isinstance(x, ast.LoopExit) for x, _ in ast.nested(s.body)):
            raise SourceError(s.loc, "unsupported construct: exit or next in a for loop with a wait inside")
        if not (isinstance(s, (ast.ForLoop, ast.IfStmt)) and waits):
            out += [s, *binds] if isinstance(s, ast.Wait) else [s]
        elif isinstance(s, ast.ForLoop):
            for k in ev.iterations(s, here):
                bind = Bind(s.var, k, s.loc)
                out += [bind, *_flattened(ev, env, s.body, [*binds, bind])]
        else:
            branch = _static_branch(ev, here, s)
            out += [s] if branch is None else _flattened(ev, env, branch, binds)
    return out


def _static_branch(ev: Evaluator, scope: Scope, s: ast.IfStmt) -> list | None:
    """The statements of the branch `s` takes when its conditions are static up to the one that holds, else None."""
    for cond, stmts in s.branches:
        if cond is None:
            return stmts
        value = _boolean(ev, cond, scope, "an if")
        if not isinstance(value, sy.Const):
            return None
        if value.value:
            return stmts
    return []


def _no_nested_wait(body: list) -> None:
    for s, depth in ast.nested(body):
        if isinstance(s, ast.Wait) and depth:
            raise SourceError(s.loc, "unsupported construct: wait statement inside an if whose condition is not static")


def _at_initialisation(s: S) -> S | None:
    return sy.const(0.0) if isinstance(s, sy.Time) else None  # now = 0, so domain (now <= 0) is quiescent_domain


def fold_initial_runs(m: ArchModel) -> None:
    """The runs at initialisation whose values are static (they read no quantity, only held values, constants,
    `now` and `domain`) set the held values' starting values, so the quiescent point already sees them (1076.1
    solves it again after the delta cycles at t = 0); the others run at the first time point. At initialisation
    `now` is 0 and `domain` is quiescent_domain."""
    start = {h.node: h.initial for h in m.holds.values()}
    folded: dict[str, S] = {}
    for e in m.hold_events:
        if not e.first or e.cond is not None or e.delays:
            continue
        try:
            values = [(h, substitute(v, start, _at_initialisation)) for h, v in e.sets]
        except sy.FoldError as ex:
            raise SourceError(e.loc, f"at initialisation: {ex}") from None
        if all(isinstance(v, sy.Const) for _, v in values):
            folded.update(values)
            e.first = False
    for node, value in folded.items():
        m.holds[node].initial = value
    m.hold_events = [e for e in m.hold_events if e.first or e.guards or e.changes or e.period is not None or e.at]
