"""Symbolic evaluation of VHDL-AMS expressions and function bodies: static parts fold to numbers, branches
on quantities become conditional expressions, loops unroll."""
from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from wrsim.elab import symbolic as sy
from wrsim.elab.scope import (
    Elements,
    Function,
    Quantity,
    Scope,
    Signal,
    Subtype,
    Terminal,
    Value,
    base_type,
)
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast as ir

__all__ = ["Evaluator", "QUIESCENT", "bits_value", "MAX_INTEGER", "MAX_ITERATIONS", "MAX_STEPS"]

MAX_INTEGER = 2.0**63 - 1       # VHDL-2008 integers are at most 64-bit
MAX_ITERATIONS = 10_000         # iterations of one loop unrolled at elaboration
MAX_STEPS = 1_000_000           # statements one evaluator executes in function bodies (nested loops included)

# `domain = quiescent_domain` holds exactly at the DC operating point (time 0); from the first time step on
# the time-domain equations apply, so the switch falls on a step boundary.
QUIESCENT = sy.Op("<=", (sy.Time(), sy.Const(0.0)))

_INTRINSICS = {  # IEEE.MATH_REAL function -> (ngspice function, number of arguments)
    "sin": ("sin", 1), "cos": ("cos", 1), "tan": ("tan", 1), "arctan": ("atan", 1), "arcsin": ("asin", 1),
    "arccos": ("acos", 1), "sinh": ("sinh", 1), "cosh": ("cosh", 1), "tanh": ("tanh", 1),
    "sqrt": ("sqrt", 1), "exp": ("exp", 1), "log": ("ln", 1), "sign": ("sgn", 1), "floor": ("floor", 1),
    "ceil": ("ceil", 1), "realmax": ("max", 2), "realmin": ("min", 2),
}
SYSTEM_ATTRS = ("ltf", "ztf", "zoh", "delayed", "slew", "ramp")   # attributes that are systems of their own
_UNSUPPORTED_ATTRS = {"tolerance", "stable",
                      "contribution", "reference", "across", "through"}
_VHDL_OPS = {"=": "==", "/=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">="}


# ================================================================================================
# Evaluation
class Evaluator:
    """VHDL-AMS expression -> (symbolic value, type). `on_dot`/`on_integ` are called for q'dot / q'integ."""

    def __init__(self, scope: Scope, on_dot=None, on_integ=None, allow_quantities: bool = True, on_signal=None,
                 on_above=None, on_system=None):
        self.scope = scope
        self.on_dot = on_dot
        self.on_integ = on_integ
        self.on_signal = on_signal
        self.on_above = on_above
        self.on_system = on_system    # (attribute, prefix, [(argument, type)], loc) -> value, for SYSTEM_ATTRS
        self.on_effect: Callable[..., list[tuple[str, S]]] | None = None   # in a process: (signal assignment or
                                                                         # break, scope) -> [(held node, value)]
        self.events: frozenset[str] | None = None   # in a process's run: the held nodes of the signals with an
        self.event_read = False                    # event ('event, rising_edge); whether the run read one
        self.allow_quantities = allow_quantities
        self.depth = 0
        self.steps = 0                # statements executed in function bodies (bounded by MAX_STEPS)

    def event(self, signal: S, loc: Loc) -> bool:
        """Whether the held signal `signal` has an event in the process run under way (`events`)."""
        nodes = sy.nodes_of(signal)
        if len(nodes) != 1 or self.events is None:
            raise SourceError(loc, "unsupported construct: an event of something other than a signal a process of "
                                   "this architecture assigns")
        self.event_read = True
        return next(iter(nodes)) in self.events

    # -------------------------------------------------------------- expressions
    def real(self, e: ir.Expr, scope: Scope | None = None) -> S:
        s, t = self.eval(e, scope)
        if t not in ("real", "integer"):
            raise SourceError(e.loc, f"expected a real expression, found {t}")
        return s

    def eval(self, e: ir.Expr, scope: Scope | None = None) -> tuple[S, str]:
        """The symbolic value and type of `e`; an operation on constants without a finite result, an integer out of
        range or an expression too deep is a SourceError at the operation."""
        try:
            s, t = self.evaluate(e, scope or self.scope)
        except sy.FoldError as ex:
            raise SourceError(e.loc, str(ex)) from None
        if t == "integer" and isinstance(s, sy.Const) and abs(s.value) > MAX_INTEGER:
            raise SourceError(e.loc, f"integer {s.value:g} is out of the integer range")
        return s, t

    def evaluate(self, e: ir.Expr, scope: Scope) -> tuple[S, str]:
        if isinstance(e, ir.Num):
            return sy.const(e.value), "time" if e.time else "integer" if e.is_int else "real"
        if isinstance(e, ir.Str):
            return sy.Text(e.value), "string"
        if isinstance(e, ir.Char):
            if e.value not in "01":
                raise SourceError(e.loc, f"unsupported construct: std_logic value '{e.value}' (use '0' or '1')")
            return sy.const(float(e.value)), "std_logic"
        if isinstance(e, ir.Name):
            return self.name(e, scope)
        if isinstance(e, ir.Unary):
            s, t = self.eval(e.operand, scope)
            if e.op == "not":
                self.want(e.operand, t, "boolean", "std_logic")
                if t == "std_logic":          # a bit or std_ulogic level, 0/1
                    return sy.op("-", sy.const(1.0), s), t
                return sy.op("not", s), "boolean"
            self.want(e.operand, t, "real", "integer", "time")
            if e.op == "-":
                return sy.op("neg", s), t
            if e.op == "abs":
                return sy.op("abs", s), t
            return s, t
        if isinstance(e, ir.Binary):
            return self.binary(e, scope)
        if isinstance(e, ir.Call):
            return self.call(e, scope)
        if isinstance(e, ir.Attr):
            return self.attribute(e, scope)
        if isinstance(e, ir.Aggregate):
            items = tuple(self.real(x, scope) for x in e.items)
            return sy.vec(items), "real_vector"
        raise SourceError(e.loc, "unsupported construct: expression")

    @staticmethod
    def want(e: ir.Expr, t: str, *types: str) -> None:
        if t not in types:
            raise SourceError(e.loc, f"type mismatch: expected {' or '.join(types)}, found {t}")

    def name(self, e: ir.Name, scope: Scope) -> tuple[S, str]:
        n = e.ident.split(".")[-1] if "." in e.ident else e.ident
        b = scope.lookup(n)
        if b is None:
            if n in ("true", "false"):
                return sy.const(n == "true"), "boolean"
            if n == "now":
                return sy.Time(), "real"
            if n == "domain":
                return QUIESCENT, "domain"
            if n == "frequency_domain":      # never the domain of a transient analysis
                return sy.const(2.0), "domain"
            if n in ("quiescent_domain", "time_domain"):
                return sy.const(n == "quiescent_domain"), "domain"
            raise SourceError(e.loc, f"unknown name '{n}'")
        if isinstance(b, Value):
            return b.s, b.typ
        if isinstance(b, Quantity):
            if not self.allow_quantities:
                raise SourceError(e.loc, f"quantity '{n}' cannot be used here: the value must be static")
            return b.s, "real"
        if isinstance(b, Elements) and all(isinstance(x, Quantity) for x in b.items.values()):
            if not self.allow_quantities:
                raise SourceError(e.loc, f"quantity '{n}' cannot be used here: the value must be static")
            return sy.vec(tuple(x.s for x in b.items.values() if isinstance(x, Quantity))), "real_vector"
        if isinstance(b, Function):
            return self.apply(b, [], e.loc)
        if isinstance(b, Terminal):
            raise SourceError(e.loc, f"terminal '{n}' cannot be used as a value; declare a branch quantity")
        if isinstance(b, ir.ConstantDecl):
            raise SourceError(e.loc, f"deferred constant '{n}' has no value (its package body gives none)")
        if isinstance(b, Signal):
            if self.on_signal is None:
                raise SourceError(e.loc, f"signal '{n}' cannot be used here: the value must be static")
            if b.mode == "out":
                raise SourceError(e.loc, f"signal '{n}' is an output of this model and cannot be read")
            levels = tuple(self.on_signal(b, k) for k in range(len(b.nodes)))
            if b.type_mark in ("integer", "natural"):
                return bits_value(levels, signed=True), "integer"
            if b.width is None:
                return levels[0], "std_logic"
            return sy.vec(levels), "std_logic_vector"
        raise SourceError(e.loc, f"'{n}' is not a value")

    def binary(self, e: ir.Binary, scope: Scope) -> tuple[S, str]:
        ls, lt = self.eval(e.left, scope)
        rs, rt = self.eval(e.right, scope)
        if e.op in ("and", "or", "xor", "nand", "nor", "xnor"):
            self.want(e.left, lt, "boolean")
            self.want(e.right, rt, "boolean")
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
                if sy.value(other) == 2.0:           # frequency_domain
                    test = sy.const(False)
                elif sy.value(other) != 1.0:
                    test = sy.op("not", test)
                return (test if e.op == "=" else sy.op("not", test)), "boolean"
            if lt == rt == "string" and e.op in ("=", "/=") and isinstance(ls, sy.Text) and isinstance(rs, sy.Text):
                return sy.const((ls.value == rs.value) == (e.op == "=")), "boolean"   # e.g. a string generic
            if lt != rt or lt not in ("real", "integer", "time"):
                raise SourceError(e.loc, f"type mismatch: cannot compare {lt} with {rt}")
            return sy.op(_VHDL_OPS[e.op], ls, rs), "boolean"
        if e.op in ("+", "-", "*", "/") and "time" in (lt, rt):
            try:
                return self.time_arithmetic(e, ls, lt, rs, rt)
            except ZeroDivisionError:
                raise SourceError(e.loc, "division by zero") from None
        if e.op in ("+", "-", "*", "/", "**"):
            self.want(e.left, lt, "real", "integer")
            self.want(e.right, rt, "real", "integer")
            if e.op == "**":
                if rt != "integer" and lt == "integer":
                    raise SourceError(e.loc, "type mismatch: integer ** real")
            elif lt != rt:
                raise SourceError(e.loc, f"type mismatch: {lt} {e.op} {rt} (write real literals as 2.0, or "
                                         f"convert with real(...))")
            try:
                s = sy.op(e.op, ls, rs)
            except ZeroDivisionError:
                raise SourceError(e.loc, "division by zero") from None
            if lt == "integer" and e.op == "/" and isinstance(s, sy.Const):
                s = sy.const(float(math.trunc(sy.value(ls) / sy.value(rs))))
            return s, lt
        raise SourceError(e.loc, f"unsupported construct: operator '{e.op}'")

    @staticmethod
    def time_arithmetic(e: ir.Binary, ls: S, lt: str, rs: S, rt: str) -> tuple[S, str]:
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
        raise SourceError(e.loc, f"type mismatch: {lt} {e.op} {rt}" + (
            " (a ratio of times that are not static)" if lt == rt == "time" else ""))

    def attribute(self, e: ir.Attr, scope: Scope) -> tuple[S, str]:
        a = e.attr
        if a in ("low", "high") and e.prefix in ("real", "integer"):
            big = 1.7976931348623157e308 if e.prefix == "real" else 2147483647.0
            return sy.const(-big if a == "low" else big), e.prefix
        b = scope.lookup(e.prefix)
        if e.index is not None:          # a(k)'attr
            b = self.element(ir.Call(e.prefix, [ir.Assoc(None, e.index, e.loc)], e.loc), scope)
        if a == "dot'dot":
            if not isinstance(b, Quantity):
                raise SourceError(e.loc, f"'{a} needs a quantity prefix, '{e.prefix}' is not a quantity")
            if e.args or not self.allow_quantities or self.on_dot is None:
                raise SourceError(e.loc, f"'{a} cannot be used here" if not e.args else f"'{a} takes no argument")
            return self.on_dot(b, e.loc, 2), "real"
        if "'" in a:
            raise SourceError(e.loc, f"unsupported construct: attribute '{a} (of the attributes only 'dot'dot is "
                                     f"read on an attribute)")
        if a in ("dot", "integ", "above"):
            if not isinstance(b, Quantity):
                raise SourceError(e.loc, f"'{a} needs a quantity prefix, '{e.prefix}' is not a quantity")
            if a == "above":
                if len(e.args) != 1:
                    raise SourceError(e.loc, "'above takes one argument")
                level = self.real(e.args[0], scope)
                if self.on_above is not None:
                    self.on_above(b.s, level, e.loc)
                return sy.op(">", b.s, level), "boolean"
            if e.args:
                raise SourceError(e.loc, f"'{a} takes no argument")
            if not self.allow_quantities or self.on_dot is None:
                raise SourceError(e.loc, f"'{a} cannot be used here")
            return (self.on_dot(b, e.loc) if a == "dot" else self.on_integ(b, e.loc)), "real"
        if a in SYSTEM_ATTRS:
            if a == "ramp" and not (isinstance(b, Value) and b.kind == "signal" and b.typ == "real"):
                raise SourceError(e.loc, f"'ramp needs a real signal prefix, '{e.prefix}' is not one")
            if a != "ramp" and not isinstance(b, Quantity):
                raise SourceError(e.loc, f"'{a} needs a quantity prefix, '{e.prefix}' is not a quantity")
            if not self.allow_quantities or self.on_system is None:
                raise SourceError(e.loc, f"'{a} cannot be used here")
            return self.on_system(a, b.s, [self.eval(x, scope) for x in e.args], e.loc), "real"
        if a == "last_value":
            if e.args or not (isinstance(b, Value) and b.kind == "signal") or len(sy.nodes_of(b.s)) != 1:
                raise SourceError(e.loc, "'last_value takes no argument" if e.args else
                                  f"'last_value needs a signal a process assigns, '{e.prefix}' is not one")
            if self.on_system is None:
                raise SourceError(e.loc, "'last_value cannot be used here")
            last = self.on_system("last_value", sy.Node(next(iter(sy.nodes_of(b.s)))), [], e.loc)
            return (sy.op(">", last, sy.const(0.5)) if b.typ == "boolean" else last), b.typ
        if a == "event":
            if e.args or not (isinstance(b, Value) and b.kind == "signal"):
                raise SourceError(e.loc, "'event takes no argument" if e.args else
                                  f"'event needs a signal prefix, '{e.prefix}' is not a signal")
            if self.events is None:
                raise SourceError(e.loc, "unsupported construct: 'event outside a process")
            return sy.const(self.event(b.s, e.loc)), "boolean"
        if a in ("length", "low", "high", "left", "right"):
            s, t = self.name(ir.Name(e.prefix, e.loc), scope)
            if t != "real_vector" or not isinstance(s, sy.Vec):
                raise SourceError(e.loc, f"'{a} needs a real_vector prefix")
            n = len(s.items)
            return sy.const(float({"length": n, "low": 0, "left": 0, "high": n - 1, "right": n - 1}[a])), \
                "integer"
        user = scope.lookup(f"{e.prefix}'{a}")          # a user-defined attribute's specification
        if isinstance(user, Value):
            return user.s, user.typ
        if a in _UNSUPPORTED_ATTRS or a in ("range", "reverse_range"):
            raise SourceError(e.loc, f"unsupported construct: attribute '{a}")
        raise SourceError(e.loc, f"unknown attribute '{a}")

    def element(self, e: ir.Call, scope: Scope):
        """The element `a(k)` of an array quantity or vector terminal (k static), None when `a` is neither."""
        b = scope.lookup(e.name.split(".")[-1])
        if not isinstance(b, Elements):
            return None
        if len(e.args) != 1 or e.args[0].formal is not None or e.args[0].actual is None:
            raise SourceError(e.loc, f"'{b.name}(...)' takes one index")
        k, t = self.eval(e.args[0].actual, scope)
        if t != "integer" or not isinstance(k, sy.Const):
            raise SourceError(e.loc, f"an index into '{b.name}' must be a static integer")
        if int(k.value) not in b.items:
            raise SourceError(e.loc, f"index {int(k.value)} out of the range {min(b.items)} to {max(b.items)} of "
                                     f"'{b.name}'" if b.items else f"index {int(k.value)}: '{b.name}' has no "
                                                                   f"elements (a null range)")
        return b.items[int(k.value)]

    def call(self, e: ir.Call, scope: Scope) -> tuple[S, str]:
        n = e.name.split(".")[-1]
        b = scope.lookup(n)
        if isinstance(b, Elements):
            q = self.element(e, scope)
            if not isinstance(q, Quantity):
                raise SourceError(e.loc, f"terminal '{n}(...)' cannot be used as a value; declare a branch quantity")
            if not self.allow_quantities:
                raise SourceError(e.loc, f"quantity '{n}' cannot be used here: the value must be static")
            return q.s, "real"
        if any(a.formal is not None for a in e.args):
            raise SourceError(e.loc, "unsupported construct: named association in a call")
        if any(a.actual is None for a in e.args):
            raise SourceError(e.loc, f"unsupported construct: 'open' as an argument of '{n}'")
        actuals = [a.actual for a in e.args if a.actual is not None]
        if isinstance(b, (Value, Quantity)):
            s, t = self.name(ir.Name(n, e.loc), scope)
            if t != "real_vector" or len(e.args) != 1:
                raise SourceError(e.loc, f"'{n}' is not a function or a real_vector")
            k = self.eval(actuals[0], scope)[0]
            if not isinstance(k, sy.Const):
                raise SourceError(e.loc, f"index into '{n}' must be static")
            idx = int(k.value)
            if idx != k.value:
                raise SourceError(e.loc, f"index into '{n}' must be an integer, found {k.value:g}")
            if not 0 <= idx < len(sy.items(s)):
                raise SourceError(e.loc, f"index {idx} out of range 0 to {len(sy.items(s)) - 1} of '{n}'")
            return sy.items(s)[idx], "real"
        if isinstance(b, Function):
            return self.apply(b, [self.eval(x, scope) for x in actuals], e.loc)
        if isinstance(b, Signal) and len(e.args) == 1:
            s, t = self.name(ir.Name(n, e.loc), scope)
            k = self.eval(actuals[0], scope)[0]
            if t != "std_logic_vector" or not isinstance(k, sy.Const) or not 0 <= k.value < len(sy.items(s)):
                raise SourceError(e.loc, f"'{n}(...)' needs a std_logic_vector signal and a static index in range")
            return sy.items(s)[int(k.value)], "std_logic"
        if b is None and n in ("unsigned", "signed") and len(e.args) == 1:
            s, t = self.eval(actuals[0], scope)
            if t != "std_logic_vector":
                raise SourceError(e.loc, f"{n}(...) needs a std_logic_vector, found {t}")
            return s, n
        if b is None and n == "to_integer" and len(e.args) == 1:
            s, t = self.eval(actuals[0], scope)
            if t not in ("signed", "unsigned"):
                raise SourceError(e.loc, "to_integer(...) needs signed(...) or unsigned(...) of a std_logic_vector")
            return bits_value(sy.items(s), signed=(t == "signed")), "integer"
        if b is None and n in ("rising_edge", "falling_edge") and len(e.args) == 1:
            s, t = self.eval(actuals[0], scope)      # a held bit or std_ulogic
            if t != "std_logic" or not isinstance(actuals[0], ir.Name):
                raise SourceError(e.loc, f"{n}(...) needs a signal of type bit or std_ulogic")
            level = sy.op(">" if n == "rising_edge" else "<", s, sy.const(0.5))
            if self.events is None:                  # outside a process (a break's condition): the level alone
                return level, "boolean"
            return (level if self.event(s, e.loc) else sy.const(False)), "boolean"
        if n in ("real", "integer") and isinstance(b, Subtype) and len(e.args) == 1:
            s, t = self.eval(actuals[0], scope)
            self.want(actuals[0], t, "real", "integer")
            if n == "integer" and isinstance(s, sy.Const):
                s = sy.const(float(round(s.value)))
            return s, n
        if b is None and n in _INTRINSICS and self.scope_has_math(scope):
            fname, nargs = _INTRINSICS[n]
            if len(e.args) != nargs:
                raise SourceError(e.loc, f"{n} takes {nargs} argument(s)")
            reals = [self.real(x, scope) for x in actuals]
            try:
                return sy.fn(fname, *reals), "real"
            except (ValueError, OverflowError) as ex:
                raise SourceError(e.loc, f"{n}: {ex}") from None
        raise SourceError(e.loc, f"unknown function '{n}'")

    @staticmethod
    def scope_has_math(scope: Scope) -> bool:
        return isinstance(scope.lookup("math_pi"), Value)

    # -------------------------------------------------------------- functions (partial evaluation)
    def apply(self, f: Function, args: list[tuple[S, str]], loc: Loc) -> tuple[S, str]:
        d = f.decl
        if d.body is None:
            raise SourceError(loc, f"function '{d.name}' has no body (missing package body?)")
        if len(args) != len(d.params):
            raise SourceError(loc, f"function '{d.name}' takes {len(d.params)} argument(s), got {len(args)}")
        if self.depth > 40:
            raise SourceError(loc, f"unsupported construct: recursion in function '{d.name}'")
        env = Scope(f.scope)
        for p, (s, t) in zip(d.params, args):
            pt = base_type(p.type_mark, f.scope, p.loc)
            if pt != t:
                raise SourceError(loc, f"argument '{p.name}' of '{d.name}' must be {pt}, found {t}")
            env.declare(p.name, Value(s, t, "constant", p.loc), p.loc)
        variables: dict[str, S] = {}
        types: dict[str, str] = {}
        for v in d.decls or []:
            t = base_type(v.type_mark, f.scope, v.loc)
            if isinstance(v, ir.ConstantDecl):
                if v.value is None:
                    raise SourceError(v.loc, "unsupported construct: deferred constant")
                env.declare(v.name, Value(self.eval(v.value, env)[0], t, "constant", v.loc), v.loc)
                continue
            types[v.name] = t
            variables[v.name] = self.eval(v.value, env)[0] if v.value is not None else sy.const(0.0)
            env.declare(v.name, Value(variables[v.name], t, "variable", v.loc), v.loc)
        self.depth += 1
        try:
            result = self.run(d.body, env, variables, types, d)
        finally:
            self.depth -= 1
        if result is None:
            raise SourceError(d.loc, f"function '{d.name}' can end without a return statement")
        return result, base_type(d.return_type, f.scope, d.loc)

    def run(self, stmts: list, env: Scope, variables: dict[str, S], types: dict[str, str], d,
            effects: dict[str, S] | None = None) -> S | None:
        """Execute `stmts`; return the returned value, or None when the list ends (variables updated). In a
        process, `effects` holds what its signal assignments and breaks schedule (by held node, from `on_effect`),
        each key present from the start with the value that means "unchanged"."""
        stmts = list(stmts)
        i = 0
        while i < len(stmts):
            s = stmts[i]
            i += 1
            if isinstance(s, ir.NullStmt):
                continue
            if isinstance(s, Bind):
                env.names[s.name] = Value(sy.const(float(s.value)), "integer", "loop", s.loc)
                continue
            if isinstance(s, ir.VarAssign):
                if s.target not in variables:
                    raise SourceError(s.loc, f"'{s.target}' is not a variable of function '{d.name}'")
                val, t = self.eval(s.value, env)
                if t != types[s.target]:
                    raise SourceError(s.loc, f"type mismatch: assigning {t} to {types[s.target]} '{s.target}'")
                variables[s.target] = val
                env.names[s.target] = Value(val, t, "variable", s.loc)
                continue
            if isinstance(s, ir.Return):
                return self.eval(s.value, env)[0]
            if isinstance(s, (ir.SeqSignalAssign, ir.Break)) and effects is not None and self.on_effect is not None:
                effects.update(self.on_effect(s, env))
                continue
            if isinstance(s, ir.ForLoop):
                stmts[i:i] = self.unroll(s, env)
                continue
            if isinstance(s, ir.IfStmt):
                rest = stmts[i:]
                for k, (c, body) in enumerate(s.branches):
                    test = sy.const(True) if c is None else self.eval(c, env)[0]
                    if isinstance(test, sy.Const):
                        if test.value:
                            stmts = list(body) + rest
                            i = 0
                            break
                        continue
                    other = [ir.IfStmt(s.branches[k + 1:], s.loc)] if s.branches[k + 1:] else []
                    if not _returns(body) and not any(_returns(b) for _, b in s.branches[k + 1:]):
                        v1, v2 = dict(variables), dict(variables)
                        e1, e2 = (None, None) if effects is None else (dict(effects), dict(effects))
                        self.run(body, _copy_env(env, v1, types), v1, types, d, e1)
                        self.run(other, _copy_env(env, v2, types), v2, types, d, e2)
                        for name in variables:
                            variables[name] = sy.cond(test, v1[name], v2[name])
                            env.names[name] = Value(variables[name], types[name], "variable", s.loc)
                        if effects is not None and e1 is not None and e2 is not None:
                            effects.update({k: sy.cond(test, e1[k], e2[k]) for k in effects})
                        stmts = rest
                        i = 0
                        break
                    v1, v2 = dict(variables), dict(variables)
                    r1 = self.run(list(body) + rest, _copy_env(env, v1, types), v1, types, d)
                    r2 = self.run(other + rest, _copy_env(env, v2, types), v2, types, d)
                    if r1 is None or r2 is None:
                        return None
                    return sy.cond(test, r1, r2)
                else:
                    stmts = rest
                    i = 0
                continue
            raise SourceError(s.loc, "unsupported construct: " + (
                "wait statement other than the first or last statement of a process"
                if isinstance(s, ir.Wait) else "statement in a function body"))
        return None

    def unroll(self, s: ir.ForLoop, env: Scope) -> list:
        """The loop's body once per value of its variable, each copy after the `Bind` of that value."""
        out: list = []
        for k in self.iterations(s, env):
            out.append(Bind(s.var, k, s.loc))
            out.extend(s.body)
        return out

    def iterations(self, s: ir.ForLoop, env: Scope) -> list[int]:
        """The values a for loop's variable takes (static bounds, at most MAX_ITERATIONS)."""
        if s.range_attr is not None:
            v, t = self.name(ir.Name(s.range_attr.prefix, s.range_attr.loc), env)
            if t != "real_vector":
                raise SourceError(s.range_attr.loc, "'range needs a real_vector prefix")
            values = list(range(len(sy.items(v))))
            if s.range_attr.attr == "reverse_range":
                values.reverse()
        else:
            if s.low is None or s.high is None:
                raise SourceError(s.loc, "loop range without bounds")
            (lo, lt), (hi, ht) = self.eval(s.low, env), self.eval(s.high, env)
            if not (isinstance(lo, sy.Const) and isinstance(hi, sy.Const)):
                raise SourceError(s.loc, "loop bounds must be static (known at elaboration)")
            if lt != "integer" or ht != "integer":
                raise SourceError(s.loc, f"loop bounds must be integers, found {lt} and {ht}")
            a, b = int(lo.value), int(hi.value)
            if abs(b - a) >= MAX_ITERATIONS:
                raise SourceError(s.loc, f"loop of {abs(b - a) + 1:g} iterations: at most {MAX_ITERATIONS} are "
                                         f"unrolled at elaboration")
            values = list(range(a, b - 1, -1)) if s.downto else list(range(a, b + 1))
        self.steps += len(values) * max(1, len(s.body))
        if self.steps > MAX_STEPS:
            raise SourceError(s.loc, f"function evaluation takes more than {MAX_STEPS} steps at elaboration")
        return values


@dataclass
class Bind:
    """A pseudo-statement of an unrolled loop: the loop variable takes `value` from here on."""

    name: str
    value: int
    loc: Loc


def _returns(stmts) -> bool:
    return any(isinstance(s, ir.Return) for s, _ in ir.nested(stmts))


def _copy_env(env: Scope, variables: dict[str, S], types: dict[str, str]) -> Scope:
    c = Scope(env.parent)
    c.names = dict(env.names)
    for k, v in variables.items():
        c.names[k] = Value(v, types[k], "variable")
    return c


def bits_value(levels, signed: bool) -> S:
    """The integer a vector of 0/1 bit levels (bit 0 first) stands for; two's complement when signed."""
    total: S = sy.const(0.0)
    n = len(levels)
    for k, level in enumerate(levels):
        weight = -(2.0 ** k) if signed and k == n - 1 else 2.0 ** k
        total = sy.op("+", total, sy.cond(sy.op(">", level, sy.const(0.5)), sy.const(weight), sy.const(0.0)))
    return total
