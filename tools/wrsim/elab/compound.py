"""Compound concurrent statements of the model pass: `procedural` (its quantities' equations, symbolically) and
`generate` (if/for/case: its declarations and statements once or once per index)."""

from __future__ import annotations

import copy
import dataclasses
from types import SimpleNamespace
from typing import Protocol

from wrsim.elab import symbolic as sy
from wrsim.elab.declare import declare
from wrsim.elab.design import ArchModel, Equation
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.evaluator_base import MAX_ITERATIONS
from wrsim.elab.scope import Quantity, Scope, Value, base_type
from wrsim.elab.simultaneous import involved
from wrsim.elab.symbolic import S
from wrsim.errors import SourceError
from wrsim.frontend import ast

__all__ = ["ConcurrentStatements", "procedural", "generate", "chosen", "generate_values", "generated", "labelled"]


class ConcurrentStatements(Protocol):
    """What a generate statement needs of the model pass: the elaboration of one concurrent statement of `m`
    (`top`: of the bench itself) in a scope."""

    def statement(self, m: ArchModel, scope: Scope, ev: Evaluator, st, top: bool = False) -> None: ...


def procedural(m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Procedural) -> None:
    """`procedural`: its statements run symbolically (like a function body); each quantity it assigns gets the
    equation q == its final value, which is what 1076.1's procedural means for the analog solver."""
    env = Scope(scope)
    variables: dict[str, S] = {}
    types: dict[str, str] = {}
    for d in st.decls:
        t = base_type(d.type_mark, scope, d.loc)
        value = (
            ev.eval(d.value, env)[0]
            if d.value is not None
            else sy.const(-1.7976931348623157e308 if t == "real" else 0.0)
        )  # T'left, as every run of the body starts
        if isinstance(d, ast.ConstantDecl):
            env.declare(d.name, Value(value, t, "constant", d.loc), d.loc)
            continue
        variables[d.name], types[d.name] = value, t
        env.declare(d.name, Value(value, t, "variable", d.loc), d.loc)
    targets = [n for n in dict.fromkeys(_assigned(st.body)) if n not in variables]
    for n in targets:
        q = scope.lookup(n)
        if not isinstance(q, Quantity):
            raise SourceError(st.loc, f"procedural: '{n}' is neither a variable of it nor a quantity")
        variables[n], types[n] = q.s, "real"
    ev.run(st.body, env, variables, types, SimpleNamespace(name="procedural"))
    for n in targets:
        res = sy.op("-", scope.lookup(n).s, variables[n])
        m.equations.append(Equation(res, st.loc, [], involved(m, res)))


def chosen(ev: Evaluator, st: ast.CaseGenerate) -> ast.Generate:
    """The alternative of a case-generate that its static selector chooses (VHDL-2008): the one alternative with a
    choice equal to the selector, else `others`; its body is elaborated once, like an if-generate's."""
    matching = []
    others = None
    for choices, alternative in st.alternatives:
        if choices is None:
            others = alternative
        for choice in choices or []:
            equal, t = ev.eval(ast.Binary("=", st.selector, choice, choice.loc))
            if t != "boolean" or not isinstance(equal, sy.Const):
                raise SourceError(
                    st.selector.loc,
                    f"the selector and the choices of case-generate '{st.label}' must be static (generics, constants)",
                )
            if equal.value:
                matching.append(alternative)
    if len(matching) > 1:
        raise SourceError(matching[1].loc, f"case-generate '{st.label}': a second choice equals the selector's value")
    body = matching[0] if matching else others
    if body is None:
        raise SourceError(
            st.selector.loc,
            f"case-generate '{st.label}': no alternative has the selector's value, and there is no others",
        )
    return dataclasses.replace(body, label=st.label)  # the label of the case-generate (prefixed in a copy)


def generate_values(ev: Evaluator, st: ast.Generate) -> list[int | None]:
    """The values of a generate's parameter: [None] for an if-generate whose condition holds or the alternative a
    case-generate chose, [] when the condition does not hold, the index values of a for-generate (its condition and
    range must be static)."""
    if st.cond is None and st.var is None:
        return [None]
    if st.cond is not None:
        c, t = ev.eval(st.cond)
        if t != "boolean" or not isinstance(c, sy.Const):
            raise SourceError(st.cond.loc, "the condition of an if-generate must be a static boolean")
        return [None] if c.value else []
    bounds = [ev.eval(x) for x in (st.low, st.high) if x is not None]
    if any(t != "integer" or not isinstance(b, sy.Const) for b, t in bounds):
        raise SourceError(st.loc, "the range of a for-generate must be static integers")
    lo, hi = (int(sy.value(b)) for b, _ in bounds)
    if abs(hi - lo) >= MAX_ITERATIONS:
        raise SourceError(st.loc, f"a for-generate of {abs(hi - lo) + 1} iterations: at most {MAX_ITERATIONS}")
    return list(range(lo, hi - 1, -1) if st.downto else range(lo, hi + 1))


def generated(ev: Evaluator, scope: Scope, st: ast.Generate) -> list[tuple[str, Scope, Evaluator]]:
    """Per copy of a generate's statements: the prefix of what it declares, its scope (with the generate
    parameter) and an evaluator in that scope."""
    out = []
    for k in generate_values(ev, st):
        inner = Scope(scope)
        if st.var is not None and k is not None:
            inner.declare(st.var, Value(sy.const(float(k)), "integer", "loop", st.loc), st.loc)
        sub = copy.copy(ev)
        sub.scope = inner
        out.append((st.label if k is None else f"{st.label}__{k}", inner, sub))
    return out


def generate(
    el: ConcurrentStatements, m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Generate | ast.CaseGenerate, top: bool
) -> None:
    """`if`/`for`/`case` generate: its declarations and statements once (if the static condition holds, the
    alternative the static selector chooses) or once per value of the static range; what it declares is named
    <label>__[<value>__]<name> in the netlist."""
    if isinstance(st, ast.CaseGenerate):
        st = chosen(ev, st)
    for prefix, inner, sub in generated(ev, scope, st):
        for d in st.decls:
            names = {f: getattr(d, f) for f in ("name", "across", "through") if getattr(d, f, None)}
            declare(m, inner, sub, dataclasses.replace(d, **{f: f"{prefix}__{n}" for f, n in names.items()}))
            for n in names.values():
                inner.names[n] = inner.names.pop(f"{prefix}__{n}")
        for s in labelled(st.stmts, prefix):
            el.statement(m, inner, sub, s, top)


def labelled(stmts: list, prefix: str) -> list:
    """A generate's statements with the labels of its instances and generates prefixed (unique per copy)."""
    return [
        dataclasses.replace(s, label=f"{prefix}__{s.label}")
        if isinstance(s, (ast.Instance, ast.Generate, ast.CaseGenerate))
        else s
        for s in stmts
    ]


def _assigned(stmts: list) -> list[str]:
    """The targets of the variable assignments in `stmts` (in order, with repeats)."""
    return [s.target for s, _ in ast.nested(stmts) if isinstance(s, ast.VarAssign)]
