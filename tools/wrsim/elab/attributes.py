"""The attributes of IEEE 1076.1 that are systems of their own, each lowered with its LRM meaning:

- `Q'ltf(num, den)`: the Laplace transfer function num(s)/den(s) (coefficients in ascending powers of s) as a
  controllable canonical state space of hidden free quantities; in the quiescent domain its DC gain.
- `Q'ztf(num, den, T, initial_delay)`: the z-domain transfer function (ascending powers of z**-1) sampled at
  initial_delay + k*T, held between samples; its history starts in the steady state of the quiescent point.
- `Q'zoh(T, initial_delay)`: Q sampled at initial_delay + k*T and held; Q itself in the quiescent domain.
- `Q'delayed(T)`: Q(t - T), the quiescent value of Q before T (a lossless line of delay T).
- `Q'slew(rising, falling)`: Q with its slope limited to rising > 0 and falling < 0 (XSPICE `slew`); falling
  defaults to -rising, and without arguments Q'slew is Q.
- `S'ramp(rise, fall)`: a real signal S followed with linear ramps of the given times (fall defaults to rise,
  both to 0: a step), by the crossing driver.

Holds and their events are those of `wrsim.elab.events`; the lossless line, the slew limiter and the ramp are
`Element`s of the backend."""

from __future__ import annotations

from collections.abc import Callable

from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT, ArchModel, Element, Hold, HoldEvent
from wrsim.elab.events import NEVER
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError

__all__ = ["system_attribute"]


def _real(args: list[tuple[S, str]], k: int, loc: Loc, what: str, default: S | None = None) -> S:
    if k >= len(args):
        if default is None:
            raise SourceError(loc, f"missing argument: {what}")
        return default
    s, t = args[k]
    if t not in ("real", "time", "integer") or sy.nodes_of(s) or sy.branches_of(s):
        raise SourceError(loc, f"{what} must be a static real, found {t}")
    if any(isinstance(x, sy.Time) for x in sy.walk(s)):
        raise SourceError(loc, f"{what} must be static, found an expression of now")
    return s


def _vector(args: list[tuple[S, str]], k: int, loc: Loc, what: str) -> tuple[S, ...]:
    if k >= len(args) or args[k][1] != "real_vector":
        raise SourceError(loc, f"{what} must be a real_vector")
    items = sy.items(args[k][0])
    if any(sy.nodes_of(x) or sy.branches_of(x) for x in items):
        raise SourceError(loc, f"{what} must be static")
    return items


def _nonzero(x: S, loc: Loc, what: str) -> S:
    if isinstance(x, sy.Const) and x.value == 0.0:
        raise SourceError(loc, f"{what} must not be 0")
    return x


def _sum(terms: list[S]) -> S:
    total: S = sy.const(0.0)
    for x in terms:
        total = sy.op("+", total, x)
    return total


def system_attribute(
    m: ArchModel,
    attr: str,
    u: S,
    args: list[tuple[S, str]],
    loc: Loc,
    state: Callable[[str, Loc], S],
    dot: Callable[[str, Loc], S],
    equation: Callable[[S, Loc], None],
) -> S:
    """The value of `u'attr(args)` in architecture `m`. `state(name, loc)` declares a hidden free quantity and
    returns it, `dot(name, loc)` its 'dot, `equation(residual, loc)` adds an equation."""
    nargs = {
        "ltf": (2, 2),
        "ztf": (3, 4),
        "zoh": (1, 2),
        "delayed": (1, 1),
        "slew": (0, 2),
        "ramp": (0, 2),
        "last_value": (0, 0),
    }[attr]
    if not nargs[0] <= len(args) <= nargs[1]:
        raise SourceError(loc, f"'{attr} takes {nargs[0]} to {nargs[1]} arguments, found {len(args)}")
    taken = {*m.quantities, *m.holds, *(e.node for e in m.elements)}
    k = 0
    while f"{_base(u)}__{attr}{k}" in taken or f"{_base(u)}__{attr}{k}_x0" in taken:
        k += 1
    name = f"{_base(u)}__{attr}{k}"
    if attr == "ltf":
        return _ltf(
            name,
            u,
            _vector(args, 0, loc, "the numerator"),
            _vector(args, 1, loc, "the denominator"),
            loc,
            state,
            dot,
            equation,
        )
    if attr == "delayed":
        delay = _real(args, 0, loc, "the delay")
        if isinstance(delay, sy.Const) and delay.value == 0.0:
            return u
        m.elements.append(Element("delayed", name, u, (delay,), loc))
        m.hold_events.append(HoldEvent([], loc, period=sy.const(NEVER), offset=delay))  # a time point where the
        return sy.Node(name)  # quiescent value ends
    if attr == "slew":
        if not args:
            return u
        rising = _real(args, 0, loc, "the rising slope")
        falling = _real(args, 1, loc, "the falling slope", sy.op("neg", rising))
        m.elements.append(Element("slew", name, u, (rising, falling), loc))
        return sy.Node(name)
    if attr == "last_value":
        m.elements.append(Element("last", name, u, (), loc))
        return sy.Node(name)
    if attr == "ramp":
        rise = _real(args, 0, loc, "the rise time", sy.const(0.0))
        m.elements.append(Element("ramp", name, u, (rise, _real(args, 1, loc, "the fall time", rise)), loc))
        return sy.Node(name)
    if attr == "zoh":
        period, start = _real(args, 0, loc, "the sampling period"), _real(args, 1, loc, "the delay", sy.const(0.0))
        m.holds[name] = Hold(name, sy.const(0.0), loc)
        m.hold_events.append(HoldEvent([(name, u)], loc, first=True))  # before the first sample: Q at t = 0
        m.hold_events.append(HoldEvent([(name, u)], loc, period=period, offset=_first_sample(period, start)))
        return sy.cond(QUIESCENT, u, sy.Node(name))
    return _ztf(m, name, u, args, loc)


def _base(u: S) -> str:
    if isinstance(u, sy.Node):
        return u.name
    if isinstance(u, sy.Diff):
        return f"{u.plus}_{u.minus}"
    return "signal"


def _first_sample(period: S, start: S) -> S:
    """A sample at t = 0 repeats the starting values: the first one the events need is at T, or at the delay."""
    return period if isinstance(start, sy.Const) and start.value == 0.0 else start


def _ltf(name: str, u: S, num: tuple[S, ...], den: tuple[S, ...], loc: Loc, state, dot, equation) -> S:
    n, m = len(den) - 1, len(num) - 1
    if n < 0 or m < 0 or m > n:
        raise SourceError(
            loc,
            f"'ltf needs a denominator of at least the numerator's order (numerator order {m}, denominator order {n})",
        )
    _nonzero(den[n], loc, "the highest denominator coefficient of 'ltf")
    if n == 0:
        return sy.op("/", sy.op("*", num[0], u), den[0])
    xs = [state(f"{name}_x{i}", loc) for i in range(n)]  # x0 = the filtered input, x_i = its i-th derivative
    for i in range(n - 1):
        equation(sy.op("-", dot(f"{name}_x{i}", loc), xs[i + 1]), loc)
    rest = _sum([sy.op("*", den[i], xs[i]) for i in range(n)])
    top = dot(f"{name}_x{n - 1}", loc)  # den[n] * x0^(n) = u - sum den[i] x0^(i)
    equation(sy.op("-", sy.op("*", den[n], top), sy.op("-", u, rest)), loc)
    out = _sum([sy.op("*", num[j], xs[j]) for j in range(min(m + 1, n))])
    if m == n:
        out = sy.op("+", out, sy.op("/", sy.op("*", num[n], sy.op("-", u, rest)), den[n]))
    return out


def _ztf(m: ArchModel, name: str, u: S, args: list[tuple[S, str]], loc: Loc) -> S:
    num, den = _vector(args, 0, loc, "the numerator"), _vector(args, 1, loc, "the denominator")
    period, start = _real(args, 2, loc, "the sampling period"), _real(args, 3, loc, "the delay", sy.const(0.0))
    if not num or not den:
        raise SourceError(loc, "'ztf needs a numerator and a denominator")
    _nonzero(den[0], loc, "the first denominator coefficient of 'ztf")
    gain = sy.op(
        "/",
        _sum(list(num)),
        _nonzero(_sum(list(den)), loc, "the sum of the denominator of 'ztf (its DC gain is infinite)"),
    )
    us = [f"{name}_u{i}" for i in range(1, len(num))]  # u(k-i)
    ys = [f"{name}_y{j}" for j in range(1, len(den))]  # y(k-j)
    for h in [name, *us, *ys]:
        m.holds[h] = Hold(h, sy.const(0.0), loc)
    inputs = _sum([sy.op("*", num[0], u)] + [sy.op("*", b, sy.Node(x)) for b, x in zip(num[1:], us)])
    outputs = _sum([sy.op("*", a, sy.Node(y)) for a, y in zip(den[1:], ys)])
    new = sy.op("/", sy.op("-", inputs, outputs), den[0])
    shift = [(us[0], u)] if us else []
    shift += [(us[i], sy.Node(us[i - 1])) for i in range(1, len(us))]
    shift += [(ys[0], new)] if ys else []
    shift += [(ys[j], sy.Node(ys[j - 1])) for j in range(1, len(ys))]
    steady = [(name, sy.op("*", gain, u))] + [(x, u) for x in us] + [(y, sy.op("*", gain, u)) for y in ys]
    m.hold_events.append(HoldEvent(steady, loc, first=True))
    m.hold_events.append(HoldEvent([(name, new), *shift], loc, period=period, offset=_first_sample(period, start)))
    return sy.cond(QUIESCENT, sy.op("*", gain, u), sy.Node(name))
