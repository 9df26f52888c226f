"""Function calls and function bodies in the expression evaluator: calls of user functions (their bodies run
symbolically: static branches are taken, branches on quantities become conditional expressions, loops unroll),
indexing, type conversions, numeric_std and edge functions, and the IEEE.MATH_REAL functions ngspice has."""

from __future__ import annotations

from dataclasses import dataclass

from wrsim.elab import symbolic as sy
from wrsim.elab.evaluator_base import MAX_ITERATIONS, MAX_STEPS, EvaluatorBase
from wrsim.elab.operators import bits_value, want
from wrsim.elab.scope import Elements, Function, Quantity, Scope, Signal, Subtype, Value, base_type
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast

__all__ = ["CallsAndBodies", "Bind"]

_INTRINSICS = {  # IEEE.MATH_REAL function -> (ngspice function, number of arguments)
    "sin": ("sin", 1),
    "cos": ("cos", 1),
    "tan": ("tan", 1),
    "arctan": ("atan", 1),
    "arcsin": ("asin", 1),
    "arccos": ("acos", 1),
    "sinh": ("sinh", 1),
    "cosh": ("cosh", 1),
    "tanh": ("tanh", 1),
    "sqrt": ("sqrt", 1),
    "exp": ("exp", 1),
    "log": ("ln", 1),
    "sign": ("sgn", 1),
    "floor": ("floor", 1),
    "ceil": ("ceil", 1),
    "realmax": ("max", 2),
    "realmin": ("min", 2),
}


class CallsAndBodies(EvaluatorBase):
    """The evaluator's calls and the partial evaluation of function bodies."""

    def call(self, e: ast.Call, scope: Scope) -> tuple[S, str]:
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
            s, t = self.name(ast.Name(n, e.loc), scope)
            if t != "real_vector" or len(e.args) != 1:
                raise SourceError(e.loc, f"'{n}' is not a function or a real_vector")
            k = self.eval(actuals[0], scope)[0]
            if not isinstance(k, sy.Const):
                raise SourceError(e.loc, f"index into '{n}' must be static")
            idx = int(k.value)
            if idx != k.value:
                raise SourceError(e.loc, f"index into '{n}' must be an integer, found {k.value:g}")
            vector = b if isinstance(b, Value) else Value(s, t, "quantity")
            at = vector.position(idx)
            if at is None:
                r = vector.index_range()
                raise SourceError(
                    e.loc,
                    f"index {idx} out of range {r[0]} to {r[-1]} of '{n}'" if r else f"index {idx}: '{n}' is empty",
                )
            return sy.items(s)[at], "real"
        if isinstance(b, Function):
            return self.apply(b, [self.eval(x, scope) for x in actuals], e.loc)
        if isinstance(b, Signal) and len(e.args) == 1:
            s, t = self.name(ast.Name(n, e.loc), scope)
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
            s, t = self.eval(actuals[0], scope)  # a held bit or std_ulogic
            if t != "std_logic" or not isinstance(actuals[0], ast.Name):
                raise SourceError(e.loc, f"{n}(...) needs a signal of type bit or std_ulogic")
            level = sy.op(">" if n == "rising_edge" else "<", s, sy.const(0.5))
            if self.events is None:  # outside a process (a break's condition): the level alone
                return level, "boolean"
            return sy.op("and", self.event(s, e.loc), level), "boolean"
        if n in ("real", "integer") and isinstance(b, Subtype) and len(e.args) == 1:
            s, t = self.eval(actuals[0], scope)
            want(actuals[0], t, "real", "integer")
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
            if isinstance(v, ast.ConstantDecl):
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

    def run(
        self,
        stmts: list,
        env: Scope,
        variables: dict[str, S],
        types: dict[str, str],
        d,
        effects: dict[str, S] | None = None,
    ) -> S | None:
        """Execute `stmts`; return the returned value, or None when the list ends (variables updated). In a
        process, `effects` holds what its signal assignments and breaks schedule (by held node, from `on_effect`),
        each key present from the start with the value that means "unchanged"."""
        stmts = list(stmts)
        i = 0
        while i < len(stmts):
            s = stmts[i]
            i += 1
            if isinstance(s, ast.NullStmt):
                continue
            if isinstance(s, Bind):
                env.names[s.name] = Value(sy.const(float(s.value)), "integer", "loop", s.loc)
                continue
            if isinstance(s, ast.VarAssign):
                if s.target not in variables:
                    raise SourceError(s.loc, f"'{s.target}' is not a variable of function '{d.name}'")
                val, t = self.eval(s.value, env)
                if t != types[s.target]:
                    raise SourceError(s.loc, f"type mismatch: assigning {t} to {types[s.target]} '{s.target}'")
                variables[s.target] = val
                env.names[s.target] = Value(val, t, "variable", s.loc)
                continue
            if isinstance(s, ast.Return):
                return self.eval(s.value, env)[0]
            if isinstance(s, (ast.SeqSignalAssign, ast.Break)) and effects is not None and self.on_effect is not None:
                effects.update(self.on_effect(s, env, effects))
                continue
            if isinstance(s, ast.ForLoop):
                stmts[i:i] = self.unroll(s, env)
                continue
            if isinstance(s, ast.WhileLoop):  # entered: its steps, then where an exit goes
                stmts[i:i] = [_Step(s), _LoopEnd(s.loc)]
                continue
            if isinstance(s, _Step):  # one more turn while the condition holds (static: known at elaboration)
                if s.loop.cond is not None:
                    test, t = self.eval(s.loop.cond, env)
                    if t != "boolean":
                        raise SourceError(s.loop.cond.loc, f"a while condition must be boolean, found {t}")
                    if not isinstance(test, sy.Const):
                        raise SourceError(
                            s.loop.loc,
                            "unsupported construct: a while loop whose condition is not static (it reads quantities "
                            "or signals): each turn is unrolled at elaboration",
                        )
                    if not test.value:
                        continue
                self.count_steps(max(1, len(s.loop.body)), s.loop.loc)
                stmts[i:i] = [*s.loop.body, _TurnEnd(s.loop.loc), s]
                continue
            if isinstance(s, (_TurnEnd, _LoopEnd)):
                continue
            if isinstance(s, ast.LoopExit):  # to the end of the innermost loop's turn (next) or of the loop (exit)
                ends = (_TurnEnd, _LoopEnd) if s.kind == "next" else (_LoopEnd,)
                k = next((k for k in range(i, len(stmts)) if isinstance(stmts[k], ends)), None)
                if k is None:
                    raise SourceError(
                        s.loc,
                        f"unsupported construct: '{s.kind}' outside a loop, or under a condition that is not static "
                        f"(it reads quantities or signals)",
                    )
                i = k + 1
                continue
            if isinstance(s, ast.IfStmt):
                rest = stmts[i:]
                for k, (c, body) in enumerate(s.branches):
                    test = sy.const(True) if c is None else self.eval(c, env)[0]
                    if isinstance(test, sy.Const):
                        if test.value:
                            stmts = list(body) + rest
                            i = 0
                            break
                        continue
                    other = [ast.IfStmt(s.branches[k + 1 :], s.loc)] if s.branches[k + 1 :] else []
                    if not _returns(body) and not any(_returns(b) for _, b in s.branches[k + 1 :]):
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
            raise SourceError(
                s.loc,
                "unsupported construct: "
                + (
                    "wait statement other than the first or last statement of a process"
                    if isinstance(s, ast.Wait)
                    else "statement in a function body"
                ),
            )
        return None

    def unroll(self, s: ast.ForLoop, env: Scope) -> list:
        """The loop's body once per value of its variable, each copy after the `Bind` of that value."""
        out: list = []
        for k in self.iterations(s, env):
            out.append(Bind(s.var, k, s.loc))
            out.extend(s.body)
            out.append(_TurnEnd(s.loc))
        out.append(_LoopEnd(s.loc))
        return out

    def iterations(self, s: ast.ForLoop, env: Scope) -> list[int]:
        """The values a for loop's variable takes (static bounds, at most MAX_ITERATIONS)."""
        if s.range_attr is not None:
            v, t = self.name(ast.Name(s.range_attr.prefix, s.range_attr.loc), env)
            if t != "real_vector":
                raise SourceError(s.range_attr.loc, "'range needs a real_vector prefix")
            b = env.lookup(s.range_attr.prefix)
            values = b.index_range() if isinstance(b, Value) else list(range(len(sy.items(v))))
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
                raise SourceError(
                    s.loc,
                    f"loop of {abs(b - a) + 1:g} iterations: at most {MAX_ITERATIONS} are unrolled at elaboration",
                )
            values = list(range(a, b - 1, -1)) if s.downto else list(range(a, b + 1))
        self.count_steps(len(values) * max(1, len(s.body)), s.loc)
        return values

    def count_steps(self, n: int, loc: Loc) -> None:
        """Count `n` more statements a loop unrolls; past MAX_STEPS one error at the loop `loc`."""
        self.steps += n
        if self.steps > MAX_STEPS:
            raise SourceError(loc, f"function evaluation takes more than {MAX_STEPS} steps at elaboration")


@dataclass
class Bind:
    """A pseudo-statement of an unrolled loop: the loop variable takes `value` from here on."""

    name: str
    value: int
    loc: Loc


@dataclass
class _Step:
    """A pseudo-statement of a while loop (or plain loop) entered: test its condition, and if it holds, run its body
    and come back here."""

    loop: ast.WhileLoop


@dataclass
class _TurnEnd:
    """The end of one turn of a loop's body: where `next` goes."""

    loc: Loc


@dataclass
class _LoopEnd:
    """The end of a loop: where `exit` goes."""

    loc: Loc


def _returns(stmts) -> bool:
    return any(isinstance(s, ast.Return) for s, _ in ast.nested(stmts))


def _copy_env(env: Scope, variables: dict[str, S], types: dict[str, str]) -> Scope:
    c = Scope(env.parent)
    c.names = dict(env.names)
    for k, v in variables.items():
        c.names[k] = Value(v, types[k], "variable")
    return c
