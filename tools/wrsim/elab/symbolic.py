"""Symbolic expressions produced by elaboration (VHDL-AMS expressions with static parts folded) and read by
the backend. Constructors fold constants, so a condition on generics disappears once the generic is known."""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from dataclasses import dataclass, field

__all__ = [
    "S",
    "undefined",
    "Const",
    "Param",
    "Node",
    "Diff",
    "Branch",
    "Time",
    "Op",
    "Fn",
    "Cond",
    "Vec",
    "Text",
    "const",
    "value",
    "items",
    "op",
    "fn",
    "cond",
    "vec",
    "walk",
    "nodes_of",
    "branches_of",
    "is_static",
    "substitute",
    "FoldError",
    "MAX_DEPTH",
]

MAX_DEPTH = 256  # nested operations in one expression (an unrolled loop or a call chain included)


class FoldError(ArithmeticError):
    """An operation on constants without a finite result, or an expression deeper than MAX_DEPTH."""


@dataclass(frozen=True)
class Const:
    value: float  # booleans are 1.0 / 0.0; `boolean` marks them for messages
    boolean: bool = False


@dataclass(frozen=True)
class Param:
    name: str  # a .subckt parameter (an entity generic)


@dataclass(frozen=True)
class Node:
    name: str  # v(name): a quantity held on an internal node


@dataclass(frozen=True)
class Diff:
    plus: str  # v(plus) - v(minus): an across quantity; minus "0" is the reference
    minus: str


@dataclass(frozen=True)
class Branch:
    name: str  # i(name): current through a voltage source (the 'dot of a quantity)


@dataclass(frozen=True)
class Time:
    pass


@dataclass(frozen=True)
class Op:
    name: str  # + - * / ** neg abs < <= > >= == != and or not
    args: tuple[S, ...]
    depth: int = field(default=1, compare=False, repr=False)  # nested operations, this one included


@dataclass(frozen=True)
class Fn:
    name: str  # an ngspice function: sin cos tan atan sqrt exp ln sgn min max floor ...
    args: tuple[S, ...]
    depth: int = field(default=1, compare=False, repr=False)  # nested operations, this one included


@dataclass(frozen=True)
class Cond:
    test: S
    then: S
    other: S
    depth: int = field(default=1, compare=False, repr=False)  # nested operations, this one included


@dataclass(frozen=True)
class Text:
    value: str  # a string literal or generic (digital units; compared by = and /=)


@dataclass(frozen=True)
class Vec:
    items: tuple[S, ...]  # a real_vector of static length
    depth: int = field(default=1, compare=False, repr=False)  # nested operations, this one included


S = Const | Param | Node | Diff | Branch | Time | Op | Fn | Cond | Vec | Text

_ARITH = {"+": operator.add, "-": operator.sub, "*": operator.mul, "/": operator.truediv, "**": operator.pow}
_REL = {"<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge, "==": operator.eq, "!=": operator.ne}
_FN: dict[str, Callable[..., float]] = {
    "sin": math.sin,
    "cos": math.cos,
    "tan": math.tan,
    "atan": math.atan,
    "sqrt": math.sqrt,
    "exp": math.exp,
    "ln": math.log,
    "sinh": math.sinh,
    "cosh": math.cosh,
    "tanh": math.tanh,
    "asin": math.asin,
    "acos": math.acos,
    "floor": math.floor,
    "ceil": math.ceil,
    "sgn": lambda x: float((x > 0) - (x < 0)),
    "min": min,
    "max": max,
    "abs": abs,
}


def const(value: float | bool) -> Const:
    if isinstance(value, bool):
        return Const(1.0 if value else 0.0, True)
    if not math.isfinite(value):
        raise FoldError(f"the value is {value} (not a finite number)")
    return Const(float(value))


def _depth(args: tuple[S, ...]) -> int:
    d = 1 + max((getattr(a, "depth", 0) for a in args), default=0)
    if d > MAX_DEPTH:
        raise FoldError(
            f"the expression is more than {MAX_DEPTH} operations deep (a loop or a chain of calls "
            f"builds it): split it with intermediate quantities"
        )
    return d


def value(s: S) -> float:
    """The number of a folded expression (the caller has checked it is one)."""
    if not isinstance(s, Const):
        raise TypeError(f"internal: {s} is not a constant")
    return s.value


def items(s: S) -> tuple[S, ...]:
    """The items of a vector expression (the caller has checked it is one)."""
    if not isinstance(s, Vec):
        raise TypeError(f"internal: {s} is not a vector")
    return s.items


def is_static(s: S) -> bool:
    return isinstance(s, Const)


def _power_domain(x: float, y: float) -> None:
    """x ** y has a real value (IEEE 1076.2 MATH_REAL's "**" on reals: a negative base takes integer powers only,
    zero positive powers only); FoldError otherwise."""
    if x < 0.0 and y != math.floor(y):
        raise FoldError(f"({x:g}) ** {y:g}: a negative base to a power that is not a whole number has no real value")
    if x == 0.0 and y < 0.0:
        raise FoldError(f"0.0 ** {y:g}: division by zero")


def op(name: str, *args: S) -> S:
    """Build an operation, folding constants and trivial identities."""
    if all(isinstance(a, Const) for a in args):
        v = [value(a) for a in args]
        if name in _ARITH:
            if name == "/" and v[1] == 0.0:
                raise FoldError("division by zero")
            if name == "**":
                _power_domain(v[0], v[1])
            try:
                return const(_ARITH[name](v[0], v[1]))
            except OverflowError:
                raise FoldError(f"'{name}' overflows ({v[0]:g} {name} {v[1]:g})") from None
        if name in _REL:
            return const(_REL[name](v[0], v[1]))
        if name == "neg":
            return const(-v[0])
        if name == "abs":
            return const(abs(v[0]))
        if name == "and":
            return const(bool(v[0]) and bool(v[1]))
        if name == "or":
            return const(bool(v[0]) or bool(v[1]))
        if name == "not":
            return const(not bool(v[0]))
        raise ValueError(name)
    if name in ("+", "-") and isinstance(args[1], Const) and args[1].value == 0.0:
        return args[0]
    if name == "+" and isinstance(args[0], Const) and args[0].value == 0.0:
        return args[1]
    if name == "-" and isinstance(args[0], Const) and args[0].value == 0.0:
        return op("neg", args[1])
    if name == "*":
        for a, b in ((args[0], args[1]), (args[1], args[0])):
            if isinstance(a, Const) and a.value == 1.0:
                return b
            if isinstance(a, Const) and a.value == 0.0:
                return const(0.0)
    if name == "/" and isinstance(args[1], Const) and args[1].value == 1.0:
        return args[0]
    if name == "and":
        for a, b in ((args[0], args[1]), (args[1], args[0])):
            if isinstance(a, Const):
                return b if a.value else const(False)
    if name == "or":
        for a, b in ((args[0], args[1]), (args[1], args[0])):
            if isinstance(a, Const):
                return const(True) if a.value else b
    return Op(name, tuple(args), _depth(args))


def fn(name: str, *args: S) -> S:
    if all(isinstance(a, Const) for a in args):
        return const(float(_FN[name](*[value(a) for a in args])))
    return Fn(name, tuple(args), _depth(args))


def undefined(s: S) -> S:
    """The condition (boolean) under which `s` has no real value at run time: a division by zero, the square root of
    a negative number, the logarithm of one not above zero, asin or acos beyond -1 .. 1, a negative base to a power
    that is not a whole number or zero to a negative power (IEEE 1076.2's "**", as _power_domain folds it), in the
    branches a conditional takes; const(False) when `s` is defined everywhere. What a held value's event reads is
    checked with it (HoldEvent.fault; the crossing driver stops the run with the event's source line): the compiled
    device's guarded operations would give a number instead (1e33 for a division, |x| ** y for a power)."""
    if isinstance(s, Cond):
        return op("or", undefined(s.test), cond(s.test, undefined(s.then), undefined(s.other)))
    if not isinstance(s, (Op, Fn)):
        return const(False)
    out: S = const(False)
    for a in s.args:
        out = op("or", out, undefined(a))
    x = s.args[-1] if s.args else None
    if isinstance(s, Op) and s.name == "/":
        out = op("or", out, op("==", s.args[1], const(0.0)))
    elif isinstance(s, Op) and s.name == "**":
        base, power = s.args
        fractional = op("!=", power, fn("floor", power))
        out = op("or", out, op("and", op("<", base, const(0.0)), fractional))
        out = op("or", out, op("and", op("==", base, const(0.0)), op("<", power, const(0.0))))
    elif isinstance(s, Fn) and s.name == "sqrt" and x is not None:
        out = op("or", out, op("<", x, const(0.0)))
    elif isinstance(s, Fn) and s.name == "ln" and x is not None:
        out = op("or", out, op("<=", x, const(0.0)))
    elif isinstance(s, Fn) and s.name in ("asin", "acos") and x is not None:
        out = op("or", out, op(">", op("abs", x), const(1.0)))
    return out


def cond(test: S, then: S, other: S) -> S:
    if isinstance(test, Const):
        return then if test.value else other
    if then == other:
        return then
    return Cond(test, then, other, _depth((test, then, other)))


def vec(items: tuple[S, ...]) -> Vec:
    return Vec(items, _depth(items))


def walk(s: S):
    """`s` and every sub-expression of it."""
    yield s
    if isinstance(s, (Op, Fn)):
        for a in s.args:
            yield from walk(a)
    elif isinstance(s, Cond):
        yield from walk(s.test)
        yield from walk(s.then)
        yield from walk(s.other)
    elif isinstance(s, Vec):
        for a in s.items:
            yield from walk(a)


def nodes_of(s: S) -> set[str]:
    """Every node whose voltage `s` reads (Diff contributes both terminals)."""
    out: set[str] = set()
    for x in walk(s):
        if isinstance(x, Node):
            out.add(x.name)
        elif isinstance(x, Diff):
            out.update((x.plus, x.minus))
    return out


def branches_of(s: S) -> set[str]:
    return {x.name for x in walk(s) if isinstance(x, Branch)}


def substitute(s: S, nodes: dict[str, S], leaf: Callable[[S], S | None] | None = None) -> S:
    """`s` with every Node in `nodes` replaced by its expression (and any leaf for which `leaf` returns an
    expression replaced by it), constants folded again. Raises FoldError when the result nests too deep."""
    if leaf is not None:
        new = leaf(s)
        if new is not None:
            return new
    if isinstance(s, Node):
        return nodes.get(s.name, s)
    if isinstance(s, Op):
        return op(s.name, *(substitute(a, nodes, leaf) for a in s.args))
    if isinstance(s, Fn):
        return fn(s.name, *(substitute(a, nodes, leaf) for a in s.args))
    if isinstance(s, Cond):
        return cond(substitute(s.test, nodes, leaf), substitute(s.then, nodes, leaf), substitute(s.other, nodes, leaf))
    if isinstance(s, Vec):
        return vec(tuple(substitute(a, nodes, leaf) for a in s.items))
    return s
