"""Names and attributes in the expression evaluator: what a simple name stands for (a constant, generic,
quantity, signal, function without arguments, or a predefined name such as `now` and `domain`), the elements of
array quantities and vector terminals, and the attributes ('dot, 'integ, 'above, the attributes that are systems of
their own, 'event, 'stable, 'last_value, array bounds, user-defined attributes)."""

from __future__ import annotations

from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT
from wrsim.elab.evaluator_base import EvaluatorBase
from wrsim.elab.operators import bits_value
from wrsim.elab.scope import INTEGER_HIGH, INTEGER_LOW, Elements, Function, Quantity, Scope, Signal, Terminal, Value
from wrsim.elab.symbolic import S
from wrsim.errors import SourceError
from wrsim.frontend import ast

__all__ = ["NamesAndAttributes", "SYSTEM_ATTRS"]

SYSTEM_ATTRS = ("ltf", "ztf", "zoh", "delayed", "slew", "ramp")  # attributes that are systems of their own
_FS = 1e-15  # [s] the base unit of type time: time'pos counts it
_UNSUPPORTED_ATTRS = {"tolerance", "contribution", "reference", "across", "through"}


class NamesAndAttributes(EvaluatorBase):
    """The evaluator's names and attributes."""

    def name(self, e: ast.Name, scope: Scope) -> tuple[S, str]:
        n = e.ident.split(".")[-1] if "." in e.ident else e.ident
        b = scope.lookup(n)
        if b is None:
            if n in ("true", "false"):
                return sy.const(n == "true"), "boolean"
            if n == "now":
                return sy.Time(), "real"
            if n == "domain":
                return QUIESCENT, "domain"
            if n == "frequency_domain":  # never the domain of a transient analysis
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
        if isinstance(b, ast.ConstantDecl):
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

    def attribute(self, e: ast.Attr, scope: Scope) -> tuple[S, str]:
        a = e.attr
        if a in ("low", "high") and e.prefix == "real":
            big = 1.7976931348623157e308
            return sy.const(-big if a == "low" else big), e.prefix
        if a in ("low", "high") and e.prefix == "integer":
            return sy.const(INTEGER_LOW if a == "low" else INTEGER_HIGH), e.prefix
        if a in ("pos", "val") and e.prefix == "time":  # the position number of a time: its value in fs
            given, want = ("time", "integer") if a == "pos" else ("integer", "time")
            if len(e.args) != 1:
                raise SourceError(e.loc, f"time'{a} takes one argument")
            x, t = self.eval(e.args[0], scope)
            if isinstance(x, sy.Time):  # `now`: 1076.1's real overload, or the time one where a time is wanted
                t = "time"
            if t != given:
                raise SourceError(e.args[0].loc, f"time'{a} takes a{'' if a == 'pos' else 'n'} {given}, found {t}")
            return sy.op("/" if a == "pos" else "*", x, sy.const(_FS)), want
        b = scope.lookup(e.prefix)
        if e.index is not None:  # a(k)'attr
            b = self.element(ast.Call(e.prefix, [ast.Assoc(None, e.index, e.loc)], e.loc), scope)
        if a == "dot'dot":
            if not isinstance(b, Quantity):
                raise SourceError(e.loc, f"'{a} needs a quantity prefix, '{e.prefix}' is not a quantity")
            if e.args or not self.allow_quantities or self.on_dot is None:
                raise SourceError(e.loc, f"'{a} cannot be used here" if not e.args else f"'{a} takes no argument")
            return self.on_dot(b, e.loc, 2), "real"
        if "'" in a:
            raise SourceError(
                e.loc,
                f"unsupported construct: attribute '{a} (of the attributes only 'dot'dot is read on an attribute)",
            )
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
                raise SourceError(
                    e.loc,
                    "'last_value takes no argument"
                    if e.args
                    else f"'last_value needs a signal a process assigns, '{e.prefix}' is not one",
                )
            if self.on_system is None:
                raise SourceError(e.loc, "'last_value cannot be used here")
            last = self.on_system("last_value", sy.Node(next(iter(sy.nodes_of(b.s)))), [], e.loc)
            return (sy.op(">", last, sy.const(0.5)) if b.typ == "boolean" else last), b.typ
        if a in ("event", "stable"):  # s'stable (and s'stable(0 ns)): no event on s in this simulation cycle
            if (a == "event" and e.args) or len(e.args) > 1:
                raise SourceError(e.loc, f"'{a} takes no argument" if a == "event" else "'stable takes one argument")
            if not (isinstance(b, Value) and b.kind == "signal"):
                raise SourceError(e.loc, f"'{a} needs a signal prefix, '{e.prefix}' is not a signal")
            if e.args:
                span, t = self.eval(e.args[0], scope)
                if t != "time" or not isinstance(span, sy.Const) or span.value != 0.0:
                    raise SourceError(e.loc, "unsupported construct: 'stable(T) with T other than 0 ns")
            if self.events is None:
                raise SourceError(e.loc, f"unsupported construct: '{a} outside a process")
            happened = self.event(b.s, e.loc)
            return (happened if a == "event" else sy.op("not", happened)), "boolean"
        if a in ("length", "low", "high", "left", "right"):
            s, t = self.name(ast.Name(e.prefix, e.loc), scope)
            if t != "real_vector" or not isinstance(s, sy.Vec):
                raise SourceError(e.loc, f"'{a} needs a real_vector prefix")
            r = b.index_range() if isinstance(b, Value) else list(range(len(s.items)))
            if not r:
                raise SourceError(e.loc, f"'{a} of '{e.prefix}', which has no elements")
            at = {"length": len(r), "low": min(r), "high": max(r), "left": r[0], "right": r[-1]}
            return sy.const(float(at[a])), "integer"
        user = scope.lookup(f"{e.prefix}'{a}")  # a user-defined attribute's specification
        if isinstance(user, Value):
            return user.s, user.typ
        if a in _UNSUPPORTED_ATTRS or a in ("range", "reverse_range"):
            raise SourceError(e.loc, f"unsupported construct: attribute '{a}")
        raise SourceError(e.loc, f"unknown attribute '{a}")

    def element(self, e: ast.Call, scope: Scope):
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
            raise SourceError(
                e.loc,
                f"index {int(k.value)} out of the range {min(b.items)} to {max(b.items)} of '{b.name}'"
                if b.items
                else f"index {int(k.value)}: '{b.name}' has no elements (a null range)",
            )
        return b.items[int(k.value)]
