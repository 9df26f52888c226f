"""Elaboration: library loading, name resolution, symbolic evaluation of expressions and functions, the
instance tree with concrete generic values (assertions, parameter sets), and one equation system per
architecture for the backend.

Two passes share one evaluator:
- the static pass walks the instance tree with concrete generic values (`Const`): it checks assertions and
  parameter sets and reports bad generics with the instance path;
- the model pass builds, once per architecture (and per length of its vector generics), the unknowns and
  residual equations with generics left symbolic (`Param`), which the backend turns into one `.subckt`.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from . import ir
from . import symbolic as sy
from .errors import Loc, SourceError, WrsimError
from .parser import parse_file
from .symbolic import S

__all__ = ["Library", "load_library", "Design", "ArchModel", "Equation", "Unknown", "BranchElem", "Derivative",
           "Integral", "ChildInstance", "DigitalChild", "AdcElem", "Signal", "InstanceInfo", "elaborate", "check_param_set", "QUIESCENT"]

# `domain = quiescent_domain` holds exactly at the DC operating point (time 0); from the first time step on
# the time-domain equations apply, so the switch falls on a step boundary.
QUIESCENT = sy.Op("<=", (sy.Time(), sy.Const(0.0)))
GROUND = "0"

_INTRINSICS = {  # IEEE.MATH_REAL function -> (ngspice function, number of arguments)
    "sin": ("sin", 1), "cos": ("cos", 1), "tan": ("tan", 1), "arctan": ("atan", 1), "arcsin": ("asin", 1),
    "arccos": ("acos", 1), "sinh": ("sinh", 1), "cosh": ("cosh", 1), "tanh": ("tanh", 1),
    "sqrt": ("sqrt", 1), "exp": ("exp", 1), "log": ("ln", 1), "sign": ("sgn", 1), "floor": ("floor", 1),
    "ceil": ("ceil", 1), "realmax": ("max", 2), "realmin": ("min", 2),
}
_MATH_CONSTANTS = {"math_pi": math.pi, "math_2_pi": 2 * math.pi, "math_pi_over_2": math.pi / 2,
                   "math_pi_over_4": math.pi / 4, "math_e": math.e, "math_1_over_pi": 1 / math.pi,
                   "math_sqrt_2": math.sqrt(2), "math_deg_to_rad": math.pi / 180,
                   "math_rad_to_deg": 180 / math.pi}
_BASE_TYPES = {"real": "real", "integer": "integer", "natural": "integer", "positive": "integer",
               "boolean": "boolean", "real_vector": "real_vector", "string": "string"}
_UNSUPPORTED_ATTRS = {"slew", "delayed", "ltf", "zoh", "ztf", "tolerance", "event", "last_value", "stable",
                      "contribution", "reference", "across", "through"}
_VHDL_OPS = {"=": "==", "/=": "!=", "<": "<", "<=": "<=", ">": ">", ">=": ">="}


# ================================================================================================
# Library
@dataclass
class Library:
    """Every design unit of the analysed files, by library."""

    files: list[ir.DesignFile] = field(default_factory=list)
    packages: dict[tuple[str, str], ir.Package] = field(default_factory=dict)
    bodies: dict[tuple[str, str], ir.PackageBody] = field(default_factory=dict)
    entities: dict[str, ir.Entity] = field(default_factory=dict)
    archs: dict[str, list[ir.Architecture | ir.DigitalArchitecture]] = field(default_factory=dict)

    def digital_files(self, tops: list[str]) -> list[Path]:
        """The digital files the units `tops` need, each after the files it uses (`work.<unit>` references),
        in the order GHDL must analyse them."""
        provider = {u.name: f for f in self.files if f.digital for u in f.units
                    if isinstance(u, (ir.Entity, ir.Package))}
        order: list[ir.DesignFile] = []

        def visit(f: ir.DesignFile, stack: tuple[str, ...]) -> None:
            if f in order:
                return
            if f.path in stack:
                raise WrsimError(f"{f.path}: circular work.* references between digital files ({' -> '.join(stack)})")
            for name in _work_references(f.path):
                if name in provider and provider[name] is not f:
                    visit(provider[name], stack + (f.path,))
            order.append(f)

        for top in tops:
            visit(provider[top], ())
        return [Path(f.path) for f in order]

    def add(self, df: ir.DesignFile) -> None:
        self.files.append(df)
        for u in df.units:
            if isinstance(u, ir.Package):
                self._unique(self.packages, (df.library, u.name), u, "package")
            elif isinstance(u, ir.PackageBody):
                self._unique(self.bodies, (df.library, u.name), u, "package body")
            elif isinstance(u, ir.Entity):
                self._unique(self.entities, u.name, u, "entity")
            else:
                for other in self.archs.get(u.entity, []):
                    if other.name == u.name:
                        raise SourceError(u.loc, f"architecture {u.name} of {u.entity} is already defined at "
                                                 f"{other.loc}")
                self.archs.setdefault(u.entity, []).append(u)

    @staticmethod
    def _unique(table: dict, key, unit, what: str) -> None:
        if key in table:
            raise SourceError(unit.loc, f"{what} {unit.name} is already defined at {table[key].loc}")
        table[key] = unit

    def entity(self, name: str, loc: Loc | None = None) -> ir.Entity:
        if name not in self.entities:
            known = ", ".join(sorted(self.entities)) or "none"
            msg = f"unknown entity '{name}' (known entities: {known})"
            raise SourceError(loc, msg) if loc else WrsimError(msg)
        return self.entities[name]

    def architecture(self, entity: str, name: str | None, loc: Loc | None) -> ir.Architecture:
        archs = self.archs.get(entity, [])
        if not archs:
            msg = f"entity '{entity}' has no architecture"
            raise SourceError(loc, msg) if loc else WrsimError(msg)
        if name is None:
            return archs[-1]              # the most recently analysed one, as in VHDL
        for a in archs:
            if a.name == name:
                return a
        msg = f"entity '{entity}' has no architecture '{name}' (it has: {', '.join(a.name for a in archs)})"
        raise SourceError(loc, msg) if loc else WrsimError(msg)


def load_library(paths: list[str | Path]) -> Library:
    """Parse every .vhd/.vhdl file under `paths`; files in a folder named `ieee` go to library IEEE."""
    lib = Library()
    files: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            files.extend(sorted(q for q in p.rglob("*") if q.suffix.lower() in (".vhd", ".vhdl")))
        elif p.is_file():
            files.append(p)
        else:
            raise WrsimError(f"{p}: no such VHDL-AMS file or folder")
    for f in files:
        lib.add(parse_file(f, "ieee" if f.parent.name.lower() == "ieee" else "work"))
    return lib


# ================================================================================================
# Scopes and bindings
@dataclass
class Value:
    s: S
    typ: str                      # real, integer, boolean, real_vector, string
    kind: str                     # generic, constant, variable, loop, literal
    loc: Loc | None = None


@dataclass
class Quantity:
    name: str
    s: S                          # Node or Diff
    role: str                     # through, across, free, in, out
    unit: str | None
    loc: Loc
    branch_through: str | None = None   # for an across quantity: the through quantity of its branch


@dataclass
class Signal:
    name: str
    nodes: list[str]              # one digital node per bit, bit 0 (LSB) first
    type_mark: str
    width: int | None
    mode: str                     # in, out, or "signal" (declared in the architecture)
    loc: Loc


@dataclass
class Terminal:
    node: str
    nature: str                   # base nature name
    loc: Loc | None


@dataclass
class Function:
    decl: ir.FunctionDecl
    scope: "Scope"


@dataclass
class Nature:
    decl: ir.NatureDecl
    units: tuple[str | None, str | None]


@dataclass
class Subtype:
    base: str
    unit: str | None


class Scope:
    def __init__(self, parent: "Scope | None" = None):
        self.parent = parent
        self.names: dict[str, object] = {}

    def lookup(self, name: str):
        s: Scope | None = self
        while s is not None:
            if name in s.names:
                return s.names[name]
            s = s.parent
        return None

    def declare(self, name: str, binding, loc: Loc) -> None:
        if name in self.names:
            prev = self.names[name]
            where = getattr(prev, "loc", None) or getattr(getattr(prev, "decl", None), "loc", None)
            raise SourceError(loc, f"'{name}' is already declared" + (f" at {where}" if where else ""))
        self.names[name] = binding


# ================================================================================================
# Evaluation
class Evaluator:
    """VHDL-AMS expression -> (symbolic value, type). `on_dot`/`on_integ` are called for q'dot / q'integ."""

    def __init__(self, scope: Scope, on_dot=None, on_integ=None, allow_quantities: bool = True, on_signal=None):
        self.scope = scope
        self.on_dot = on_dot
        self.on_integ = on_integ
        self.on_signal = on_signal
        self.allow_quantities = allow_quantities
        self.depth = 0

    # -------------------------------------------------------------- expressions
    def real(self, e: ir.Expr, scope: Scope | None = None) -> S:
        s, t = self.eval(e, scope)
        if t not in ("real", "integer"):
            raise SourceError(e.loc, f"expected a real expression, found {t}")
        return s

    def eval(self, e: ir.Expr, scope: Scope | None = None) -> tuple[S, str]:
        scope = scope or self.scope
        if isinstance(e, ir.Num):
            return sy.const(e.value), "integer" if e.is_int else "real"
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
                self.want(e.operand, t, "boolean")
                return sy.op("not", s), "boolean"
            self.want(e.operand, t, "real", "integer")
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
            return sy.Vec(items), "real_vector"
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
            if n == "frequency_domain":
                raise SourceError(e.loc, "unsupported construct: frequency_domain (wrsim runs transient analyses)")
            if n in ("quiescent_domain", "time_domain"):
                return sy.const(n == "quiescent_domain"), "domain"
            raise SourceError(e.loc, f"unknown name '{n}'")
        if isinstance(b, Value):
            return b.s, b.typ
        if isinstance(b, Quantity):
            if not self.allow_quantities:
                raise SourceError(e.loc, f"quantity '{n}' cannot be used here: the value must be static")
            return b.s, "real"
        if isinstance(b, Function):
            return self.apply(b, [], e.loc)
        if isinstance(b, Terminal):
            raise SourceError(e.loc, f"terminal '{n}' cannot be used as a value; declare a branch quantity")
        if isinstance(b, Signal):
            if self.on_signal is None:
                raise SourceError(e.loc, f"signal '{n}' cannot be used here: the value must be static")
            if b.mode == "out":
                raise SourceError(e.loc, f"signal '{n}' is an output of this model and cannot be read")
            levels = tuple(self.on_signal(b, k) for k in range(len(b.nodes)))
            if b.type_mark in ("integer", "natural"):
                return _bits_value(levels, signed=True), "integer"
            if b.width is None:
                return levels[0], "std_logic"
            return sy.Vec(levels), "std_logic_vector"
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
            test = sy.op(">" if value.value else "<", level, sy.const(0.5))
            return (test if e.op == "=" else sy.op("not", test)), "boolean"
        if e.op in _VHDL_OPS:
            if "domain" in (lt, rt):
                if lt != rt:
                    raise SourceError(e.loc, "'domain' can only be compared with quiescent_domain or time_domain")
                other = rs if isinstance(rs, sy.Const) else ls
                if e.op not in ("=", "/="):
                    raise SourceError(e.loc, "'domain' can only be compared with = or /=")
                test = QUIESCENT
                if other.value != 1.0:
                    test = sy.op("not", test)
                return (test if e.op == "=" else sy.op("not", test)), "boolean"
            if lt != rt or lt not in ("real", "integer"):
                raise SourceError(e.loc, f"type mismatch: cannot compare {lt} with {rt}")
            return sy.op(_VHDL_OPS[e.op], ls, rs), "boolean"
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
                s = sy.const(float(math.trunc(ls.value / rs.value)))
            return s, lt
        raise SourceError(e.loc, f"unsupported construct: operator '{e.op}'")

    def attribute(self, e: ir.Attr, scope: Scope) -> tuple[S, str]:
        a = e.attr
        if a in ("low", "high") and e.prefix in ("real", "integer"):
            big = 1.7976931348623157e308 if e.prefix == "real" else 2147483647.0
            return sy.const(-big if a == "low" else big), e.prefix
        b = scope.lookup(e.prefix)
        if a in ("dot", "integ", "above"):
            if not isinstance(b, Quantity):
                raise SourceError(e.loc, f"'{a} needs a quantity prefix, '{e.prefix}' is not a quantity")
            if a == "above":
                if len(e.args) != 1:
                    raise SourceError(e.loc, "'above takes one argument")
                return sy.op(">", b.s, self.real(e.args[0], scope)), "boolean"
            if e.args:
                raise SourceError(e.loc, f"'{a} takes no argument")
            if not self.allow_quantities or self.on_dot is None:
                raise SourceError(e.loc, f"'{a} cannot be used here")
            return (self.on_dot(b, e.loc) if a == "dot" else self.on_integ(b, e.loc)), "real"
        if a in ("length", "low", "high", "left", "right"):
            s, t = self.name(ir.Name(e.prefix, e.loc), scope)
            if t != "real_vector" or not isinstance(s, sy.Vec):
                raise SourceError(e.loc, f"'{a} needs a real_vector prefix")
            n = len(s.items)
            return sy.const(float({"length": n, "low": 0, "left": 0, "high": n - 1, "right": n - 1}[a])), \
                "integer"
        if a in _UNSUPPORTED_ATTRS or a in ("range", "reverse_range"):
            raise SourceError(e.loc, f"unsupported construct: attribute '{a}")
        raise SourceError(e.loc, f"unknown attribute '{a}")

    def call(self, e: ir.Call, scope: Scope) -> tuple[S, str]:
        n = e.name.split(".")[-1]
        b = scope.lookup(n)
        if any(a.formal is not None for a in e.args):
            raise SourceError(e.loc, "unsupported construct: named association in a call")
        if isinstance(b, (Value, Quantity)):
            s, t = self.name(ir.Name(n, e.loc), scope)
            if t != "real_vector" or len(e.args) != 1:
                raise SourceError(e.loc, f"'{n}' is not a function or a real_vector")
            k = self.eval(e.args[0].actual, scope)[0]
            if not isinstance(k, sy.Const):
                raise SourceError(e.loc, f"index into '{n}' must be static")
            idx = int(k.value)
            if not 0 <= idx < len(s.items):
                raise SourceError(e.loc, f"index {idx} out of range 0 to {len(s.items) - 1} of '{n}'")
            return s.items[idx], "real"
        if isinstance(b, Function):
            args = [self.eval(a.actual, scope) for a in e.args]
            return self.apply(b, args, e.loc)
        if isinstance(b, Signal) and len(e.args) == 1:
            s, t = self.name(ir.Name(n, e.loc), scope)
            k = self.eval(e.args[0].actual, scope)[0]
            if t != "std_logic_vector" or not isinstance(k, sy.Const) or not 0 <= k.value < len(s.items):
                raise SourceError(e.loc, f"'{n}(...)' needs a std_logic_vector signal and a static index in range")
            return s.items[int(k.value)], "std_logic"
        if b is None and n in ("unsigned", "signed") and len(e.args) == 1:
            s, t = self.eval(e.args[0].actual, scope)
            if t != "std_logic_vector":
                raise SourceError(e.loc, f"{n}(...) needs a std_logic_vector, found {t}")
            return s, n
        if b is None and n == "to_integer" and len(e.args) == 1:
            s, t = self.eval(e.args[0].actual, scope)
            if t not in ("signed", "unsigned"):
                raise SourceError(e.loc, "to_integer(...) needs signed(...) or unsigned(...) of a std_logic_vector")
            return _bits_value(s.items, signed=(t == "signed")), "integer"
        if n in ("real", "integer") and isinstance(b, Subtype) and len(e.args) == 1:
            s, t = self.eval(e.args[0].actual, scope)
            self.want(e.args[0].actual, t, "real", "integer")
            if n == "integer" and isinstance(s, sy.Const):
                s = sy.const(float(round(s.value)))
            return s, n
        if b is None and n in _INTRINSICS and self.scope_has_math(scope):
            fname, nargs = _INTRINSICS[n]
            if len(e.args) != nargs:
                raise SourceError(e.loc, f"{n} takes {nargs} argument(s)")
            args = [self.real(a.actual, scope) for a in e.args]
            try:
                return sy.fn(fname, *args), "real"
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

    def run(self, stmts: list, env: Scope, variables: dict[str, S], types: dict[str, str], d) -> S | None:
        """Execute `stmts`; return the returned value, or None when the list ends (variables updated)."""
        stmts = list(stmts)
        i = 0
        while i < len(stmts):
            s = stmts[i]
            i += 1
            if isinstance(s, ir.NullStmt):
                continue
            if isinstance(s, _Bind):
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
                        self.run(body, _copy_env(env, v1, types), v1, types, d)
                        self.run(other, _copy_env(env, v2, types), v2, types, d)
                        for name in variables:
                            variables[name] = sy.cond(test, v1[name], v2[name])
                            env.names[name] = Value(variables[name], types[name], "variable", s.loc)
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
            raise SourceError(s.loc, "unsupported construct: statement in a function body")
        return None

    def unroll(self, s: ir.ForLoop, env: Scope) -> list:
        if s.range_attr is not None:
            v, t = self.name(ir.Name(s.range_attr.prefix, s.range_attr.loc), env)
            if t != "real_vector":
                raise SourceError(s.range_attr.loc, "'range needs a real_vector prefix")
            values = list(range(len(v.items)))
            if s.range_attr.attr == "reverse_range":
                values.reverse()
        else:
            lo, hi = self.eval(s.low, env)[0], self.eval(s.high, env)[0]
            if not (isinstance(lo, sy.Const) and isinstance(hi, sy.Const)):
                raise SourceError(s.loc, "loop bounds must be static (known at elaboration)")
            a, b = int(lo.value), int(hi.value)
            values = list(range(a, b - 1, -1)) if s.downto else list(range(a, b + 1))
        out: list = []
        for k in values:
            out.append(_Bind(s.var, k, s.loc))
            out.extend(s.body)
        return out


@dataclass
class _Bind:
    name: str
    value: int
    loc: Loc


def _returns(stmts) -> bool:
    for s in stmts:
        if isinstance(s, ir.Return):
            return True
        if isinstance(s, ir.IfStmt) and any(_returns(b) for _, b in s.branches):
            return True
        if isinstance(s, ir.ForLoop) and _returns(s.body):
            return True
    return False


def _copy_env(env: Scope, variables: dict[str, S], types: dict[str, str]) -> Scope:
    c = Scope(env.parent)
    c.names = dict(env.names)
    for k, v in variables.items():
        c.names[k] = Value(v, types[k], "variable")
    return c


def base_type(type_mark: str, scope: Scope, loc: Loc) -> str:
    if type_mark in _BASE_TYPES:
        return _BASE_TYPES[type_mark]
    b = scope.lookup(type_mark)
    if isinstance(b, Subtype):
        return _BASE_TYPES.get(b.base, b.base)
    raise SourceError(loc, f"unknown type '{type_mark}'")


# ================================================================================================
# Package and unit scopes
class _Context:
    """Builds the scopes that `use` clauses make visible; package scopes are built once."""

    def __init__(self, lib: Library):
        self.lib = lib
        self.pkg_scopes: dict[tuple[str, str], Scope] = {}
        self.root = Scope()
        for name in ("real", "integer", "natural", "positive", "boolean", "real_vector", "string"):
            self.root.names[name] = Subtype(_BASE_TYPES[name], None)

    def unit_scope(self, uses: list[ir.UseClause]) -> Scope:
        scope = Scope(self.root)
        for u in uses:
            self.apply_use(scope, u)
        return scope

    def apply_use(self, scope: Scope, u: ir.UseClause) -> None:
        if u.library == "ieee" and u.package == "math_real":
            items = {k: Value(sy.const(v), "real", "constant") for k, v in _MATH_CONSTANTS.items()}
        elif u.library in ("std", "ieee") and u.package in ("standard", "std_logic_1164", "numeric_std",
                                                            "fundamental_constants", "textio", "env"):
            return
        else:
            lib = "work" if u.library == "work" else u.library
            items = self.package_scope(lib, u.package, u.loc).names
        if u.item == "all":
            for k, v in items.items():
                scope.names.setdefault(k, v)
        elif u.item in items:
            scope.names[u.item] = items[u.item]
        else:
            raise SourceError(u.loc, f"package {u.library}.{u.package} has no declaration '{u.item}'")

    def package_scope(self, lib: str, name: str, loc: Loc) -> Scope:
        key = (lib, name)
        if key in self.pkg_scopes:
            return self.pkg_scopes[key]
        pkg = self.lib.packages.get(key)
        if pkg is None:
            known = ", ".join(f"{l}.{n}" for l, n in sorted(self.lib.packages)) or "none"
            raise SourceError(loc, f"unknown package {lib}.{name} (known: {known}, and ieee.math_real)")
        visible = self.unit_scope(pkg.uses)
        own = Scope(visible)
        self.pkg_scopes[key] = own
        ev = Evaluator(own, allow_quantities=False)
        declare_all(own, pkg.decls, ev)
        body = self.lib.bodies.get(key)
        if body is not None:
            body_scope = Scope(own)
            for u in body.uses:
                self.apply_use(body_scope, u)
            for d in body.decls:
                if isinstance(d, ir.FunctionDecl):
                    prev = own.names.get(d.name)
                    if not isinstance(prev, Function):
                        raise SourceError(d.loc, f"function '{d.name}' is not declared in package {name}")
                    prev.decl = d
                    prev.scope = body_scope
                else:
                    declare_all(body_scope, [d], Evaluator(body_scope, allow_quantities=False))
        return own


def declare_all(scope: Scope, decls: list, ev: Evaluator) -> None:
    """Declare package-level items (and architecture constants/functions/subtypes) in `scope`."""
    for d in decls:
        if isinstance(d, ir.ConstantDecl):
            t = base_type(d.type_mark, scope, d.loc)
            if d.value is None:
                raise SourceError(d.loc, "unsupported construct: deferred constant")
            s, vt = ev.eval(d.value, scope)
            if vt != t and not (t == "real_vector" and vt == "real_vector"):
                raise SourceError(d.loc, f"type mismatch: constant '{d.name}' is {t}, value is {vt}")
            scope.declare(d.name, Value(s, t, "constant", d.loc), d.loc)
        elif isinstance(d, ir.SubtypeDecl):
            scope.declare(d.name, Subtype(_BASE_TYPES.get(d.base, d.base), d.unit), d.loc)
        elif isinstance(d, ir.NatureDecl):
            ua = scope.lookup(d.across)
            ut = scope.lookup(d.through)
            scope.declare(d.name, Nature(d, (getattr(ua, "unit", None), getattr(ut, "unit", None))), d.loc)
            scope.declare(d.reference, Terminal(GROUND, d.name, d.loc), d.loc)
        elif isinstance(d, ir.SubnatureDecl):
            base = scope.lookup(d.base)
            if not isinstance(base, Nature):
                raise SourceError(d.loc, f"'{d.base}' is not a nature")
            scope.declare(d.name, base, d.loc)
        elif isinstance(d, ir.FunctionDecl):
            existing = scope.names.get(d.name)
            if isinstance(existing, Function) and d.body is not None and existing.decl.body is None:
                existing.decl, existing.scope = d, scope
            else:
                scope.declare(d.name, Function(d, scope), d.loc)
        elif isinstance(d, ir.ComponentDecl):
            scope.declare(d.name, d, d.loc)
        else:
            raise SourceError(d.loc, "this declaration is not allowed in a package")


def nature_of(scope: Scope, name: str, loc: Loc) -> Nature:
    n = scope.lookup(name)
    if not isinstance(n, Nature):
        raise SourceError(loc, f"unknown nature '{name}'")
    return n


# ================================================================================================
# The elaborated design
@dataclass
class Unknown:
    node: str
    role: str                     # through, free, out
    unit: str | None
    loc: Loc


@dataclass
class Equation:
    residual: S
    loc: Loc
    alternatives: list[Loc]       # an if-use/case-use equation: the equation of every branch, in order
    unknowns: set[str]            # unknowns it involves (for the structural pairing)
    paired: str = ""              # the unknown whose node carries this equation


@dataclass
class BranchElem:
    through: str
    plus: str
    minus: str
    loc: Loc


@dataclass
class Derivative:
    quantity: str
    source: S                     # Node or Diff being differentiated
    element: str                  # name of the 0 V source whose current is the derivative


@dataclass
class Integral:
    quantity: str
    source: S
    node: str


@dataclass
class AdcElem:
    """A->D: the digital `node` follows the 0/1 analog `level` = cond."""

    node: str
    level: str
    cond: S
    loc: Loc


@dataclass
class DigitalChild:
    """An instance of a digital unit (GHDL) in the bench: one d_cosim element."""

    label: str
    entity: ir.Entity
    arch: ir.DigitalArchitecture
    generics: dict[str, int | bool | str]
    inputs: list[str]             # digital nodes, port by port in declaration order, bit 0 first
    outputs: list[str]
    loc: Loc


@dataclass
class ChildInstance:
    label: str
    model: "ArchModel"
    ports: list[str]              # actual nodes in the order of the child's ports
    params: dict[str, S]          # explicitly mapped generics (vector generics expanded as name_k)
    loc: Loc


@dataclass
class ArchModel:
    """One architecture with symbolic generics: becomes one .subckt."""

    key: str                      # subckt name
    entity: ir.Entity
    arch: ir.Architecture
    ports: list[str]
    params: dict[str, float]      # default value per scalar parameter (after the parameter set)
    quantities: dict[str, Quantity]
    branches: list[BranchElem]
    unknowns: dict[str, Unknown]
    equations: list[Equation]
    derivatives: dict[str, Derivative]
    integrals: dict[str, Integral]
    children: list[ChildInstance]
    natures: set[str]
    breaks: list[Loc]
    signals: dict[str, Signal] = field(default_factory=dict)
    dacs: dict[str, str] = field(default_factory=dict)        # digital node -> its 0/1 analog level node
    adcs: list[AdcElem] = field(default_factory=list)
    digital: list[DigitalChild] = field(default_factory=list)
    recorded: set[str] = field(default_factory=set)          # D->A nodes only recorded, read by no equation


@dataclass
class InstanceInfo:
    """An instance in the elaborated tree, with its concrete generic values."""

    path: str
    entity: str
    arch: str
    generics: dict[str, float | list[float]]
    loc: Loc | None
    children: list["InstanceInfo"]


@dataclass
class Design:
    top: ArchModel
    models: list[ArchModel]       # children first, top last
    tree: InstanceInfo
    natures: set[str]
    digital_files: list[Path] = field(default_factory=list)   # what GHDL analyses for the digital units


# ================================================================================================
class _Elaborator:
    def __init__(self, lib: Library, params=None):
        self.lib = lib
        self.ctx = _Context(lib)
        self.params = params
        self.models: dict[str, ArchModel] = {}
        self.order: list[ArchModel] = []
        self.defaults_cache: dict[str, dict[str, tuple[S, str]]] = {}
        self.origins: dict[tuple[str, str], str] = {}    # (entity, generic) -> "file:line" of a parameter set

    # -------------------------------------------------------------- generic defaults
    def entity_scope(self, ent: ir.Entity) -> Scope:
        return self.ctx.unit_scope(ent.uses)

    def generic_defaults(self, ent: ir.Entity) -> dict[str, tuple[S, str]]:
        """Entity generic defaults after the parameter set: name -> (Const or Vec of Const, type)."""
        if ent.name in self.defaults_cache:
            return self.defaults_cache[ent.name]
        scope = self.entity_scope(ent)
        ev = Evaluator(scope, allow_quantities=False)
        out: dict[str, tuple[S, str]] = {}
        for g in ent.generics:
            t = base_type(g.type_mark, scope, g.loc)
            unit = g.unit or getattr(scope.lookup(g.type_mark), "unit", None)
            given = self.params.sections.get(ent.name, {}).get(g.name) if self.params is not None else None
            if given is not None:
                self.origins[(ent.name, g.name)] = f"{given.file}:{given.line}"
                value = self.params.value_in(ent.name, g.name, unit or "1")
                if t == "real_vector":
                    if not isinstance(value, list):
                        raise WrsimError(f"{given.file}:{given.line}: [{ent.name}] {g.name}: expected a list "
                                         f"of values (generic is a real_vector)")
                    out[g.name] = (sy.Vec(tuple(sy.const(v) for v in value)), t)
                else:
                    if isinstance(value, list):
                        raise WrsimError(f"{given.file}:{given.line}: [{ent.name}] {g.name}: expected one "
                                         f"value, got a list")
                    out[g.name] = (sy.const(float(round(value)) if t == "integer" else value), t)
            elif g.default is not None:
                s, vt = ev.eval(g.default)
                if vt != t and not (t == "real_vector" and vt == "real_vector"):
                    raise SourceError(g.loc, f"type mismatch: generic '{g.name}' is {t}, default is {vt}")
                out[g.name] = (s, t)
            else:
                out[g.name] = (None, t)
        self.defaults_cache[ent.name] = out
        return out

    # -------------------------------------------------------------- static pass
    def static_instance(self, ent: ir.Entity, arch: ir.Architecture, path: str, actuals: dict[str, S],
                        loc: Loc | None) -> InstanceInfo:
        defaults = self.generic_defaults(ent)
        scope = Scope(self.entity_scope(ent))
        values: dict[str, float | list[float]] = {}
        for g in ent.generics:
            s, t = (actuals[g.name], defaults[g.name][1]) if g.name in actuals else defaults[g.name]
            if s is None:
                raise SourceError(loc or g.loc, f"generic '{g.name}' of {ent.name} (instance {path}) has no "
                                                f"value: map it or give it a default")
            scope.declare(g.name, Value(s, t, "generic", g.loc), g.loc)
            values[g.name] = [x.value for x in s.items] if isinstance(s, sy.Vec) else s.value
        if isinstance(arch, ir.DigitalArchitecture):
            return InstanceInfo(path, ent.name, arch.name, values, loc, [])
        arch_scope = Scope(scope)
        for u in arch.uses:
            self.ctx.apply_use(arch_scope, u)
        ev = Evaluator(arch_scope, allow_quantities=False)
        children: list[InstanceInfo] = []
        for d in arch.decls:
            if isinstance(d, (ir.ConstantDecl, ir.FunctionDecl, ir.SubtypeDecl, ir.ComponentDecl)):
                declare_all(arch_scope, [d], ev)
            elif isinstance(d, ir.SignalDecl):
                arch_scope.names.setdefault(d.name, _signal(d.name, d.type_mark, d.width, "signal", d.loc))
            elif isinstance(d, (ir.FreeQuantityDecl, ir.BranchQuantityDecl)):
                for name in (getattr(d, "name", None), getattr(d, "across", None), getattr(d, "through", None)):
                    if name:       # known here only so that a non-static use is reported as such
                        arch_scope.names.setdefault(name, Quantity(name, sy.Node(name), "free", None, d.loc))
        for p in ent.ports:
            if isinstance(p, ir.QuantityPort):
                arch_scope.names.setdefault(p.name, Quantity(p.name, sy.Node(p.name), p.mode, None, p.loc))
        for st in list(ent.stmts) + list(arch.stmts):
            if isinstance(st, ir.Assertion):
                c, t = ev.eval(st.cond)
                if t != "boolean" or not isinstance(c, sy.Const):
                    raise SourceError(st.loc, "an assertion condition must be a static boolean (generics "
                                              "and constants only)")
                if not c.value and st.severity in ("error", "failure"):
                    shown = ", ".join(f"{k} = {_fmt_value(v)}" for k, v in values.items())
                    named = {n.ident for n in _names(st.cond)}
                    sources = [f"{self.origins[(ent.name, g)]}: [{ent.name}] {g} = {_fmt_value(values[g])}"
                               for g in values if g in named and g not in actuals and (ent.name, g) in self.origins]
                    where = f"; set by the parameter set at {'; '.join(sources)}" if sources else ""
                    raise SourceError(st.loc, f"{st.report} (instance {path}: {shown}){where}")
            elif isinstance(st, ir.Instance):
                cent, carch = self.resolve_instance(st, arch_scope)
                cact = self.static_actuals(st, cent, ev)
                children.append(self.static_instance(cent, carch, f"{path}.{st.label}", cact, st.loc))
        return InstanceInfo(path, ent.name, arch.name, values, loc, children)

    def static_actuals(self, st: ir.Instance, cent: ir.Entity, ev: Evaluator) -> dict[str, S]:
        out = {}
        for name, actual in self.associate(st.generic_map, [g.name for g in cent.generics], st, "generic"):
            if actual is None:
                continue
            s, _ = ev.eval(actual)
            if not isinstance(s, (sy.Const, sy.Vec, sy.Text)):
                raise SourceError(actual.loc, f"generic '{name}' must be static")
            out[name] = s
        return out

    # -------------------------------------------------------------- instances
    def resolve_instance(self, st: ir.Instance, scope: Scope) -> tuple[ir.Entity, ir.Architecture]:
        if st.kind == "component":
            comp = scope.lookup(st.unit)
            if not isinstance(comp, ir.ComponentDecl) and st.unit not in self.lib.entities:
                raise SourceError(st.loc, f"unknown component '{st.unit}'")
            ent = self.lib.entity(st.unit, st.loc)
            if isinstance(comp, ir.ComponentDecl):
                self.check_component(comp, ent)
        else:
            ent = self.lib.entity(st.unit, st.loc)
        return ent, self.lib.architecture(ent.name, st.arch, st.loc)

    @staticmethod
    def check_component(comp: ir.ComponentDecl, ent: ir.Entity) -> None:
        eports = {p.name: p for p in ent.ports}
        for p in comp.ports:
            ep = eports.get(p.name)
            if ep is None or type(ep) is not type(p) or getattr(ep, "nature", None) != getattr(p, "nature", None):
                raise SourceError(p.loc, f"component port '{p.name}' does not match entity {ent.name} ({ent.loc})")

    @staticmethod
    def associate(assocs: list[ir.Assoc], formals: list[str], st: ir.Instance, what: str):
        out: list[tuple[str, ir.Expr | None]] = []
        seen: set[str] = set()
        positional = True
        for k, a in enumerate(assocs):
            if a.formal is None:
                if not positional:
                    raise SourceError(a.loc, "positional association after named association")
                if k >= len(formals):
                    raise SourceError(a.loc, f"too many {what} associations for {st.unit}")
                name = formals[k]
            else:
                positional = False
                name = a.formal
                if name not in formals:
                    raise SourceError(a.loc, f"{st.unit} has no {what} '{name}' (it has: {', '.join(formals)})")
            if name in seen:
                raise SourceError(a.loc, f"{what} '{name}' is associated twice")
            seen.add(name)
            out.append((name, a.actual))
        return out

    # -------------------------------------------------------------- model pass
    def model(self, ent: ir.Entity, arch: ir.Architecture, shape: dict[str, float], top_values=None) -> ArchModel:
        """The equation system of `arch`. `shape` fixes what VHDL needs statically and a .subckt parameter
        cannot carry: the length of every real_vector generic and the value of every integer and boolean
        generic (loop bounds, case selectors); each distinct shape is its own .subckt."""
        key = ent.name if top_values is None else "top"
        archs = self.lib.archs.get(ent.name, [])
        if top_values is None:
            if len(archs) > 1 and archs[-1] is not arch:
                key += "__" + arch.name
            key += "".join(f"__{n}{_shape_tag(v)}" for n, v in sorted(shape.items()))
            if key in self.models:
                return self.models[key]
        defaults = self.generic_defaults(ent)
        scope = Scope(self.entity_scope(ent))
        params: dict[str, float] = {}
        for g in ent.generics:
            dflt, t = defaults[g.name]
            if top_values is not None:
                s = top_values.get(g.name, dflt)
                scope.declare(g.name, Value(s, t, "generic", g.loc), g.loc)
            elif t == "string":
                raise SourceError(g.loc, f"string generic '{g.name}': only digital units (GHDL) take strings")
            elif t in ("integer", "boolean"):
                scope.declare(g.name, Value(sy.const(shape[g.name]) if t == "integer" else sy.const(bool(shape[g.name])),
                                            t, "generic", g.loc), g.loc)
            elif t == "real_vector":
                n = int(shape[g.name])
                items = tuple(sy.Param(f"{g.name}_{k}") for k in range(n))
                for k in range(n):
                    params[f"{g.name}_{k}"] = dflt.items[k].value if dflt is not None and k < len(dflt.items) \
                        else 0.0
                scope.declare(g.name, Value(sy.Vec(items), t, "generic", g.loc), g.loc)
            else:
                params[g.name] = dflt.value if dflt is not None else 0.0
                scope.declare(g.name, Value(sy.Param(g.name), t, "generic", g.loc), g.loc)
        m = ArchModel(key, ent, arch, [], params, {}, [], {}, [], {}, {}, [], set(), [])
        for p in ent.ports:
            if isinstance(p, ir.TerminalPort):
                nat = nature_of(scope, p.nature, p.loc)
                scope.declare(p.name, Terminal(p.name, nat.decl.name, p.loc), p.loc)
                m.natures.add(nat.decl.name)
                m.ports.append(p.name)
            elif isinstance(p, ir.SignalPort):
                sig = _signal(p.name, p.type_mark, p.width, p.mode, p.loc)
                scope.declare(p.name, sig, p.loc)
                m.signals[p.name] = sig
                m.ports.extend(sig.nodes)
            else:
                q = Quantity(p.name, sy.Node(p.name), p.mode, p.unit, p.loc)
                scope.declare(p.name, q, p.loc)
                m.quantities[p.name] = q
                if p.mode == "out":
                    m.unknowns[p.name] = Unknown(p.name, "out", p.unit, p.loc)
                m.ports.append(p.name)
        arch_scope = Scope(scope)
        for u in arch.uses:
            self.ctx.apply_use(arch_scope, u)

        def on_dot(q: Quantity, loc: Loc) -> S:
            d = m.derivatives.get(q.name)
            if d is None:
                d = m.derivatives[q.name] = Derivative(q.name, q.s, f"v_{q.name}__d")
            return sy.Branch(d.element)

        def on_integ(q: Quantity, loc: Loc) -> S:
            it = m.integrals.get(q.name)
            if it is None:
                it = m.integrals[q.name] = Integral(q.name, q.s, f"{q.name}__i")
            return sy.Node(it.node)

        def on_signal(sig: Signal, bit: int) -> S:
            node = sig.nodes[bit]
            m.dacs.setdefault(node, f"{node}__a")
            return sy.Node(m.dacs[node])

        ev = Evaluator(arch_scope, on_dot, on_integ, on_signal=on_signal)
        for d in arch.decls:
            self.declare_arch_item(m, arch_scope, ev, d)
        for st in arch.stmts:
            self.statement(m, arch_scope, ev, st, top=top_values is not None)
        for d in m.digital:            # what digital units drive is also recorded as a 0/1 waveform
            for node in d.outputs:
                if node not in m.dacs:
                    m.recorded.add(node)
                m.dacs.setdefault(node, f"{node}__a")
        if top_values is None:
            self.models[key] = m
        self.order.append(m)
        from .checks import check_model     # checks import this module's dataclasses
        check_model(m)
        return m

    def declare_arch_item(self, m: ArchModel, scope: Scope, ev: Evaluator, d) -> None:
        if isinstance(d, (ir.ConstantDecl, ir.FunctionDecl, ir.SubtypeDecl, ir.ComponentDecl)):
            declare_all(scope, [d], Evaluator(scope, allow_quantities=False))
        elif isinstance(d, ir.SignalDecl):
            sig = _signal(d.name, d.type_mark, d.width, "signal", d.loc)
            scope.declare(d.name, sig, d.loc)
            m.signals[d.name] = sig
        elif isinstance(d, ir.TerminalDecl):
            nat = nature_of(scope, d.nature, d.loc)
            scope.declare(d.name, Terminal(d.name, nat.decl.name, d.loc), d.loc)
            m.natures.add(nat.decl.name)
        elif isinstance(d, ir.FreeQuantityDecl):
            t = base_type(d.type_mark, scope, d.loc)
            if t != "real":
                raise SourceError(d.loc, f"unsupported construct: quantity of type {t}")
            unit = d.unit or getattr(scope.lookup(d.type_mark), "unit", None)
            q = Quantity(d.name, sy.Node(d.name), "free", unit, d.loc)
            scope.declare(d.name, q, d.loc)
            m.quantities[d.name] = q
            m.unknowns[d.name] = Unknown(d.name, "free", unit, d.loc)
        elif isinstance(d, ir.BranchQuantityDecl):
            plus = self.terminal(scope, d.plus, d.loc)
            if d.minus is not None:
                minus = self.terminal(scope, d.minus, d.loc)
                if minus.nature != plus.nature:
                    raise SourceError(d.loc, f"nature mismatch: terminal '{d.plus}' is {plus.nature}, "
                                             f"'{d.minus}' is {minus.nature}")
            else:
                minus = Terminal(GROUND, plus.nature, None)
            nat = nature_of(scope, plus.nature, d.loc)
            if d.through:
                q = Quantity(d.through, sy.Node(d.through), "through", nat.units[1], d.loc)
                scope.declare(d.through, q, d.loc)
                m.quantities[d.through] = q
                m.unknowns[d.through] = Unknown(d.through, "through", nat.units[1], d.loc)
                m.branches.append(BranchElem(d.through, plus.node, minus.node, d.loc))
            if d.across:
                q = Quantity(d.across, sy.Diff(plus.node, minus.node), "across", nat.units[0], d.loc, d.through)
                scope.declare(d.across, q, d.loc)
                m.quantities[d.across] = q
        else:
            raise SourceError(d.loc, "unsupported construct: declaration in an architecture")

    @staticmethod
    def terminal(scope: Scope, name: str, loc: Loc) -> Terminal:
        t = scope.lookup(name)
        if not isinstance(t, Terminal):
            raise SourceError(loc, f"unknown terminal '{name}'" if t is None else f"'{name}' is not a terminal")
        return t

    def statement(self, m: ArchModel, scope: Scope, ev: Evaluator, st, top: bool = False) -> None:
        if isinstance(st, (ir.SimpleSimultaneous, ir.SimultaneousIf, ir.SimultaneousCase)):
            for res, locs in self.equations(st, ev):
                m.equations.append(Equation(res, locs[0], locs[1:], self.involved(m, res)))
        elif isinstance(st, ir.SimultaneousNull):
            pass
        elif isinstance(st, ir.Break):
            for e in st.on:
                ev.eval(e)
            m.breaks.append(st.loc)
        elif isinstance(st, ir.Assertion):
            pass                       # checked in the static pass with concrete generics
        elif isinstance(st, ir.SignalAssign):
            sig = scope.lookup(st.target)
            if not isinstance(sig, Signal) or sig.mode == "in":
                raise SourceError(st.loc, f"'{st.target}' is not an output signal of this model")
            if (st.index is None) != (sig.width is None or sig.type_mark in ("integer", "natural")) or \
                    (st.index is not None and not 0 <= st.index < len(sig.nodes)):
                raise SourceError(st.loc, f"assign std_logic signals whole and vector signals bit by bit "
                                          f"({st.target}(k), k in 0..{len(sig.nodes) - 1})")
            node = sig.nodes[st.index or 0]
            if any(a.node == node for a in m.adcs):
                raise SourceError(st.loc, f"'{st.target}' already has a driver in this architecture")
            cond, t = ev.eval(st.cond)
            if t != "boolean":
                raise SourceError(st.cond.loc, f"the condition of a signal assignment must be boolean, found {t}")
            m.adcs.append(AdcElem(node, f"{node}__lvl", cond, st.loc))
        elif isinstance(st, ir.Instance):
            cent, carch = self.resolve_instance(st, scope)
            if isinstance(carch, ir.DigitalArchitecture):
                if not top:
                    raise SourceError(st.loc, f"digital unit {cent.name} (GHDL) must be instantiated in the bench "
                                              f"itself, not inside a model")
                m.digital.append(self.digital_child(scope, ev, st, cent, carch))
            else:
                m.children.append(self.child(m, scope, ev, st))
        else:
            raise SourceError(st.loc, "unsupported construct: concurrent statement")

    def equations(self, st, ev: Evaluator) -> list[tuple[S, list[Loc]]]:
        """Residuals of a simultaneous statement with the location of each branch's equation; an if/case
        becomes one conditional residual per position."""
        if isinstance(st, ir.SimpleSimultaneous):
            lhs, rhs = ev.real(st.lhs), ev.real(st.rhs)
            return [(sy.op("-", lhs, rhs), [st.loc])]
        if isinstance(st, ir.SimultaneousNull):
            return []
        if isinstance(st, ir.SimultaneousIf):
            arms = []
            for c, body in st.branches:
                test = sy.const(True) if c is None else ev.eval(c)
                if c is not None:
                    test, t = test
                    if t != "boolean":
                        raise SourceError(c.loc, f"an if-use condition must be boolean, found {t}")
                arms.append((test, [x for s in body for x in self.equations(s, ev)]))
            if not any(c is None for c, _ in st.branches):
                arms.append((sy.const(True), []))
        else:
            sel, t = ev.eval(st.selector)
            arms = []
            for choices, body in st.alternatives:
                if choices is None:
                    test: S = sy.const(True)
                else:
                    test = sy.const(False)
                    for ch in choices:
                        cs, ct = ev.eval(ch)
                        if ct != t:
                            raise SourceError(ch.loc, f"type mismatch: case choice is {ct}, selector is {t}")
                        test = sy.op("or", test, sy.op("==", sel, cs))
                arms.append((test, [x for s in body for x in self.equations(s, ev)]))
        counts = {len(eqs) for _, eqs in arms}
        if len(counts) > 1:
            detail = ", ".join(str(len(eqs)) for _, eqs in arms)
            raise SourceError(st.loc, f"the branches of this simultaneous {'if' if isinstance(st, ir.SimultaneousIf) else 'case'} "
                                      f"have different numbers of equations ({detail}); 1076.1 requires the same")
        n = counts.pop() if counts else 0
        out = []
        for k in range(n):
            res: S | None = None
            for test, eqs in reversed(arms):
                res = eqs[k][0] if res is None else sy.cond(test, eqs[k][0], res)
            out.append((res, [loc for _, eqs in arms if eqs for loc in eqs[k][1]]))
        return out

    @staticmethod
    def involved(m: ArchModel, res: S) -> set[str]:
        """Unknowns an equation involves: those it reads, those it differentiates, and the through quantity
        of every branch whose across quantity it reads (an equation on an across quantity alone, like an
        ideal source's, is solved by its branch's through quantity, as in MNA)."""
        names = set()
        by_source = {q.s: q for q in m.quantities.values()}
        derived = {d.element: d for d in m.derivatives.values()}
        for x in sy.walk(res):
            q = None
            if isinstance(x, (sy.Node, sy.Diff)):
                q = by_source.get(x)
            elif isinstance(x, sy.Branch) and x.name in derived:
                q = m.quantities.get(derived[x.name].quantity)
            if q is None:
                continue
            if q.name in m.unknowns:
                names.add(q.name)
            if q.branch_through:
                names.add(q.branch_through)
        return names

    def digital_child(self, scope: Scope, ev: Evaluator, st: ir.Instance, cent: ir.Entity,
                      carch: ir.DigitalArchitecture) -> DigitalChild:
        generics: dict[str, int | bool | str] = {}
        for name, actual in self.associate(st.generic_map, [g.name for g in cent.generics], st, "generic"):
            s, t = ev.eval(actual)
            if isinstance(s, sy.Text):
                generics[name] = s.value
            elif isinstance(s, sy.Const) and t in ("integer", "boolean"):
                generics[name] = bool(s.value) if t == "boolean" else int(s.value)
            else:
                raise SourceError(actual.loc, f"generic '{name}' of digital unit {cent.name}: GHDL takes static "
                                              f"integer, boolean or string generics only")
        for g in cent.generics:     # the parameter set replaces the defaults the instance leaves alone
            given = self.params.sections.get(cent.name, {}).get(g.name) if self.params is not None else None
            if given is not None and g.name not in generics:
                self.origins[(cent.name, g.name)] = f"{given.file}:{given.line}"
                value, t = self.params.value_in(cent.name, g.name, g.unit or "1"), base_type(g.type_mark, scope, g.loc)
                if t not in ("integer", "boolean"):
                    raise WrsimError(f"{given.file}:{given.line}: [{cent.name}] {g.name}: a digital unit takes "
                                     f"integer or boolean values from a parameter set")
                generics[g.name] = bool(value) if t == "boolean" else int(round(value))
        mapped = dict(self.associate(st.port_map, [p.name for p in cent.ports], st, "port"))
        inputs: list[str] = []
        outputs: list[str] = []
        for p in cent.ports:
            actual = mapped.get(p.name)
            if not isinstance(p, ir.SignalPort):
                raise SourceError(p.loc, f"digital unit {cent.name} may only have signal ports")
            if p.mode == "in" and p.type_mark in ("integer", "natural"):
                raise SourceError(p.loc, f"input port '{p.name}' of digital unit {cent.name}: GHDL 2.0 cannot set "
                                         f"integer inputs through VPI; use std_logic_vector")
            if actual is None or not isinstance(actual, ir.Name):
                raise SourceError(st.loc, f"port '{p.name}' of {cent.name} must be connected to a signal")
            nodes = _connect_signal(p, scope.lookup(actual.ident), actual, cent)
            # d_cosim takes every port's bits left index first: MSB first for downto vectors and integers
            (inputs if p.mode == "in" else outputs).extend(reversed(nodes))
        return DigitalChild(st.label, cent, carch, generics, inputs, outputs, st.loc)

    def child(self, m: ArchModel, scope: Scope, ev: Evaluator, st: ir.Instance) -> ChildInstance:
        cent, carch = self.resolve_instance(st, scope)
        gformals = [g.name for g in cent.generics]
        params: dict[str, S] = {}
        shape: dict[str, float] = {}
        cdefaults = self.generic_defaults(cent)
        for name, actual in self.associate(st.generic_map, gformals, st, "generic"):
            if actual is None:
                continue
            s, t = ev.eval(actual)
            gt = cdefaults[name][1]
            if t != gt:
                raise SourceError(actual.loc, f"type mismatch: generic '{name}' of {cent.name} is {gt}, actual is {t}")
            if sy.nodes_of(s) or sy.branches_of(s) or _has_time(s):
                raise SourceError(actual.loc, f"generic '{name}' must be static (a quantity is not allowed)")
            if gt in ("integer", "boolean"):
                if not isinstance(s, sy.Const):
                    raise SourceError(actual.loc, f"generic '{name}' must be static")
                shape[name] = s.value
            elif isinstance(s, sy.Vec):
                shape[name] = len(s.items)
                for k, item in enumerate(s.items):
                    params[f"{name}_{k}"] = item
            else:
                params[name] = s
        for g in cent.generics:
            d, gt = cdefaults[g.name]
            if gt in ("integer", "boolean", "real_vector") and g.name not in shape:
                if d is None:
                    raise SourceError(st.loc, f"generic '{g.name}' of {cent.name} has no value")
                shape[g.name] = len(d.items) if gt == "real_vector" else d.value
        cm = self.model(cent, carch, shape)
        formals = [p for p in cent.ports]
        mapped = dict(self.associate(st.port_map, [p.name for p in formals], st, "port"))
        nodes = []
        for p in formals:
            actual = mapped.get(p.name)
            if actual is None:
                raise SourceError(st.loc, f"port '{p.name}' of {cent.name} is not connected (instance {st.label})")
            if not isinstance(actual, ir.Name):
                raise SourceError(actual.loc, f"port '{p.name}' must be connected to a terminal or quantity name")
            b = scope.lookup(actual.ident)
            if b is None:
                raise SourceError(actual.loc, f"unknown name '{actual.ident}' in the port map of {st.label}")
            if isinstance(p, ir.SignalPort):
                nodes.extend(_connect_signal(p, b, actual, cent))
                continue
            if isinstance(p, ir.TerminalPort):
                pn = nature_of(self.entity_scope(cent), p.nature, p.loc).decl.name
                if not isinstance(b, Terminal):
                    raise SourceError(actual.loc, f"port '{p.name}' is a terminal; '{actual.ident}' is not a terminal")
                if b.nature != pn:
                    raise SourceError(actual.loc, f"nature mismatch: port '{p.name}' of {cent.name} is {pn}, "
                                                  f"terminal '{actual.ident}' is {b.nature}")
                nodes.append(b.node)
            else:
                if not isinstance(b, Quantity) or b.role == "across":
                    raise SourceError(actual.loc, f"port '{p.name}' is a quantity port; connect a free quantity")
                nodes.append(b.name)
                if p.mode == "out" and b.name in m.unknowns and b.role in ("free", "out"):
                    m.unknowns.pop(b.name)      # its equation lives in the child
        return ChildInstance(st.label, cm, nodes, params, st.loc)


def _shape_tag(v: float) -> str:
    return str(int(v)).replace("-", "m")


def _work_references(path: str) -> set[str]:
    """Units a digital file names as work.<unit> (use clauses, entity instantiations)."""
    return {m.lower() for m in re.findall(r"\bwork\.(\w+)", Path(path).read_text(encoding="utf-8"), re.I)}


def _signal(name: str, type_mark: str, width: int | None, mode: str, loc: Loc) -> Signal:
    nodes = [name] if width is None else [f"{name}_{k}" for k in range(width)]
    return Signal(name, nodes, type_mark, width, mode, loc)


def _connect_signal(p: ir.SignalPort, b, actual: ir.Name, ent: ir.Entity) -> list[str]:
    """The digital nodes a signal port is connected to (widths and kinds must match)."""
    if not isinstance(b, Signal):
        raise SourceError(actual.loc, f"port '{p.name}' of {ent.name} is a signal; '{actual.ident}' is not a signal")
    kind = lambda t: "integer" if t in ("integer", "natural") else t
    if kind(b.type_mark) != kind(p.type_mark) or b.width != p.width:
        raise SourceError(actual.loc, f"signal '{actual.ident}' ({b.type_mark}{f'({b.width})' if b.width else ''}) "
                                      f"does not fit port '{p.name}' of {ent.name} ({p.type_mark}"
                                      f"{f'({p.width})' if p.width else ''})")
    return list(b.nodes)


def _bits_value(levels, signed: bool) -> S:
    """The integer a vector of 0/1 bit levels (bit 0 first) stands for; two's complement when signed."""
    total: S = sy.const(0.0)
    n = len(levels)
    for k, level in enumerate(levels):
        weight = -(2.0 ** k) if signed and k == n - 1 else 2.0 ** k
        total = sy.op("+", total, sy.cond(sy.op(">", level, sy.const(0.5)), sy.const(weight), sy.const(0.0)))
    return total


def _names(e) -> list[ir.Name]:
    """Every simple name an expression mentions."""
    if isinstance(e, ir.Name):
        return [e]
    if isinstance(e, ir.Unary):
        return _names(e.operand)
    if isinstance(e, ir.Binary):
        return _names(e.left) + _names(e.right)
    if isinstance(e, ir.Call):
        return [ir.Name(e.name, e.loc)] + [n for a in e.args if a.actual is not None for n in _names(a.actual)]
    if isinstance(e, ir.Attr):
        return [ir.Name(e.prefix, e.loc)] + [n for a in e.args for n in _names(a)]
    if isinstance(e, ir.Aggregate):
        return [n for x in e.items for n in _names(x)]
    return []


def _has_time(s: S) -> bool:
    return any(isinstance(x, sy.Time) for x in sy.walk(s))


def _fmt_value(v) -> str:
    if isinstance(v, str):
        return repr(v)
    if isinstance(v, list):
        return "(" + ", ".join(f"{x:g}" for x in v) + ")"
    return f"{v:g}"


def check_param_set(lib: Library, params) -> None:
    """Every section of a parameter set must name an entity and every key one of its generics."""
    for entity, keys in params.sections.items():
        if entity not in lib.entities:
            where = next((f"{p.file}:{p.line}" for p in keys.values()), str(params.path))
            raise WrsimError(f"{where}: [{entity}] names no entity of the library (entities: "
                             f"{', '.join(sorted(lib.entities))})")
        for key, p in keys.items():
            generics = [g.name for g in lib.entities[entity].generics]
            if key not in generics:
                raise WrsimError(f"{p.file}:{p.line}: [{entity}] {key}: {entity} has no generic '{key}' "
                                 f"(it has: {', '.join(generics)})")


def elaborate(lib: Library, top: str, params=None, overrides: dict[str, float | str] | None = None) -> Design:
    """Elaborate entity `top` (a bench without ports) with a parameter set and top-level generic overrides."""
    ent = lib.entity(top)
    arch = lib.architecture(top, None, None)
    if any(True for _ in ent.ports):
        raise WrsimError(f"{ent.loc}: top-level entity '{top}' must not have ports (it is a bench)")
    el = _Elaborator(lib, params)
    if params is not None:
        check_param_set(lib, params)
    defaults = el.generic_defaults(ent)
    actuals: dict[str, S] = {}
    for k, v in (overrides or {}).items():
        if k not in defaults:
            raise WrsimError(f"bench {top} has no generic '{k}' (it has: {', '.join(defaults) or 'none'})")
        actuals[k] = sy.Text(v) if isinstance(v, str) else sy.const(v)
    tree = el.static_instance(ent, arch, top, actuals, None)
    top_values = {g.name: actuals.get(g.name, defaults[g.name][0]) for g in ent.generics}
    topm = el.model(ent, arch, {}, top_values)
    natures = set()
    for mm in el.order:
        natures |= mm.natures
    models = [mm for mm in el.order if mm is not topm]
    return Design(topm, models, tree, natures, lib.digital_files([d.entity.name for d in topm.digital]))
