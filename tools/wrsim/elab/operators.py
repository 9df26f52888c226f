"""Literals and operators of the expression evaluator: the value and type of a literal, and of a unary or binary
operation on operands already evaluated (logical, relational, arithmetic, time arithmetic, std_logic and domain
comparisons); the integer a vector of bit levels stands for."""

from __future__ import annotations

import math

from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT
from wrsim.elab.evaluator_base import MAX_INTEGER
from wrsim.elab.symbolic import S
from wrsim.errors import SourceError
from wrsim.frontend import ast

__all__ = ["literal", "unary", "binary", "time_arithmetic", "want", "bits_value"]

_VHDL_OPS = {"=": "==", "/=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">="}


def literal(e: ast.Num | ast.Str | ast.Char) -> tuple[S, str]:
    """A number (integer, real or time in seconds), a string, or the std_logic character '0' or '1'."""
    if isinstance(e, ast.Num):
        return sy.const(e.value), "time" if e.time else "integer" if e.is_int else "real"
    if isinstance(e, ast.Str):
        return sy.Text(e.value), "string"
    if e.value not in "01":
        raise SourceError(e.loc, f"unsupported construct: std_logic value '{e.value}' (use '0' or '1')")
    return sy.const(float(e.value)), "std_logic"


def unary(e: ast.Unary, s: S, t: str) -> tuple[S, str]:
    """`not`, `-`, `abs` or `+` applied to the operand's value `s` of type `t`."""
    if e.op == "not":
        want(e.operand, t, "boolean", "std_logic")
        if t == "std_logic":  # a bit or std_ulogic level, 0/1
            return sy.op("-", sy.const(1.0), s), t
        return sy.op("not", s), "boolean"
    want(e.operand, t, "real", "integer", "time")
    if e.op == "-":
        return sy.op("neg", s), t
    if e.op == "abs":
        return sy.op("abs", s), t
    return s, t


def binary(e: ast.Binary, ls: S, lt: str, rs: S, rt: str) -> tuple[S, str]:
    """The operation `e` on its left operand's value and type (`ls`, `lt`) and its right one's (`rs`, `rt`)."""
    if e.op in ("and", "or", "xor", "nand", "nor", "xnor"):
        want(e.left, lt, "boolean")
        want(e.right, rt, "boolean")
        if e.op in ("and", "or"):
            return sy.op(e.op, ls, rs), "boolean"
        if e.op == "nand":
            return sy.op("not", sy.op("and", ls, rs)), "boolean"
        if e.op == "nor":
            return sy.op("not", sy.op("or", ls, rs)), "boolean"
        x = sy.op("!=", ls, rs)
        return (x if e.op == "xor" else sy.op("not", x)), "boolean"
    if e.op in _VHDL_OPS and "std_logic" in (lt, rt):
        if lt != rt or e.op not in ("=", "/=") or not (isinstance(ls, sy.Const) or isinstance(rs, sy.Const)):
            raise SourceError(e.loc, "a std_logic signal can only be compared with '0' or '1' (= or /=)")
        level, value = (rs, ls) if isinstance(ls, sy.Const) else (ls, rs)
        test = sy.op(">" if sy.value(value) else "<", level, sy.const(0.5))
        return (test if e.op == "=" else sy.op("not", test)), "boolean"
    if e.op in _VHDL_OPS:
        if "domain" in (lt, rt):
            if lt != rt:
                raise SourceError(e.loc, "'domain' can only be compared with quiescent_domain or time_domain")
            other = rs if isinstance(rs, sy.Const) else ls
            if e.op not in ("=", "/="):
                raise SourceError(e.loc, "'domain' can only be compared with = or /=")
            test = QUIESCENT
            if sy.value(other) == 2.0:  # frequency_domain
                test = sy.const(False)
            elif sy.value(other) != 1.0:
                test = sy.op("not", test)
            return (test if e.op == "=" else sy.op("not", test)), "boolean"
        if lt == rt == "string" and e.op in ("=", "/=") and isinstance(ls, sy.Text) and isinstance(rs, sy.Text):
            return sy.const((ls.value == rs.value) == (e.op == "=")), "boolean"  # e.g. a string generic
        if lt != rt or lt not in ("real", "integer", "time"):
            raise SourceError(e.loc, f"type mismatch: cannot compare {lt} with {rt}")
        return sy.op(_VHDL_OPS[e.op], ls, rs), "boolean"
    if e.op in ("+", "-", "*", "/") and "time" in (lt, rt):
        try:
            return time_arithmetic(e, ls, lt, rs, rt)
        except sy.FoldError as ex:
            raise SourceError(e.loc, str(ex)) from None
    if e.op in ("+", "-", "*", "/", "**"):
        want(e.left, lt, "real", "integer")
        want(e.right, rt, "real", "integer")
        if e.op == "**":
            if rt != "integer" and lt == "integer":
                raise SourceError(e.loc, "type mismatch: integer ** real")
            if lt == "integer" and isinstance(rs, sy.Const) and rs.value < 0.0:
                raise SourceError(  # IEEE 1076-2008 9.2.8
                    e.loc,
                    f"integer ** {rs.value:g}: a negative power of an integer is an error (a real base takes one)",
                )
        elif lt != rt:
            raise SourceError(
                e.loc, f"type mismatch: {lt} {e.op} {rt} (write real literals as 2.0, or convert with real(...))"
            )
        try:
            s = sy.op(e.op, ls, rs)
        except sy.FoldError as ex:
            raise SourceError(e.loc, str(ex)) from None
        if lt == "integer" and e.op == "/":  # IEEE 1076 9.2.7: an integer quotient truncates toward zero
            s = sy.const(float(math.trunc(sy.value(ls) / sy.value(rs)))) if isinstance(s, sy.Const) else _trunc(s)
        return s, lt
    if e.op in ("mod", "rem"):
        want(e.left, lt, "integer")
        want(e.right, rt, "integer")
        if isinstance(rs, sy.Const) and rs.value == 0.0:
            raise SourceError(e.loc, f"{e.op} by zero")
        try:  # IEEE 1076 9.2.7: a rem b = a - b*trunc(a/b) (the sign of a), a mod b = a - b*floor(a/b) (of b)
            q = sy.op("/", ls, rs)
            whole = _trunc(q) if e.op == "rem" else sy.fn("floor", q)
            return sy.op("-", ls, sy.op("*", rs, whole)), "integer"
        except sy.FoldError as ex:
            raise SourceError(e.loc, str(ex)) from None
    raise SourceError(e.loc, f"unsupported construct: operator '{e.op}'")


def _trunc(q: S) -> S:
    """q rounded toward zero, from the function table's floor: sgn(q) * floor(|q|)."""
    return sy.op("*", sy.fn("sgn", q), sy.fn("floor", sy.op("abs", q)))


def time_arithmetic(e: ast.Binary, ls: S, lt: str, rs: S, rt: str) -> tuple[S, str]:
    """time +- time, time * or / a number, a number * time: time (in seconds); time / time: integer."""
    numbers = ("real", "integer")
    if e.op in ("+", "-") and lt == rt == "time":
        return sy.op(e.op, ls, rs), "time"
    if e.op == "*" and {lt, rt} in ({"time", "real"}, {"time", "integer"}):
        return sy.op("*", ls, rs), "time"
    if e.op == "/" and lt == "time" and rt in numbers:
        return sy.op("/", ls, rs), "time"
    if e.op == "/" and lt == rt == "time" and isinstance(ls, sy.Const) and isinstance(rs, sy.Const):
        ratio = sy.value(ls) / sy.value(rs) if sy.value(rs) != 0.0 else math.inf
        if not math.isfinite(ratio) or abs(ratio) > MAX_INTEGER:
            raise SourceError(e.loc, f"{lt} / {rt}: the ratio is not an integer in range")
        return sy.const(float(math.trunc(ratio))), "integer"
    raise SourceError(
        e.loc,
        f"type mismatch: {lt} {e.op} {rt}" + (" (a ratio of times that are not static)" if lt == rt == "time" else ""),
    )


def want(e: ast.Expr, t: str, *types: str) -> None:
    """A type mismatch at `e` unless its type `t` is one of `types`."""
    if t not in types:
        raise SourceError(e.loc, f"type mismatch: expected {' or '.join(types)}, found {t}")


def bits_value(levels, signed: bool) -> S:
    """The integer a vector of 0/1 bit levels (bit 0 first) stands for; two's complement when signed."""
    total: S = sy.const(0.0)
    n = len(levels)
    for k, level in enumerate(levels):
        weight = -(2.0**k) if signed and k == n - 1 else 2.0**k
        total = sy.op("+", total, sy.cond(sy.op(">", level, sy.const(0.5)), sy.const(weight), sy.const(0.0)))
    return total
