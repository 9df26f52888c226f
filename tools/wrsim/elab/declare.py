"""Declarations of an architecture in the model pass: constants, subtypes, natures and the like go to the scope;
terminals (scalar and vector), free quantities (scalar and array), branch quantities (between scalar or vector
terminals), signals, limit and configuration specifications, and source quantities (0 in the time domain)."""

from __future__ import annotations

import dataclasses

from wrsim.elab import symbolic as sy
from wrsim.elab.context import declare_all, index_values, nature_of, reference_terminal
from wrsim.elab.design import ArchModel, BranchElem, Equation, Unknown
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.scope import GROUND, ArrayNature, Elements, Quantity, Scope, Terminal, base_type, new_signal
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast

__all__ = ["declare", "free_quantity", "branch", "terminal", "bind"]


def declare(m: ArchModel, scope: Scope, ev: Evaluator, d) -> None:
    """Declare an architecture's (or a generate's) declaration `d` in `scope`: what it adds to the equation system
    (unknowns, branches, natures, signals, limits) goes into `m`."""
    if isinstance(d, ast.NAME_DECLARATIONS):
        declare_all(scope, [d], Evaluator(scope, allow_quantities=False))
    elif isinstance(d, ast.LimitSpec):
        step, t = ev.eval(d.step)
        if t not in ("real", "time") or sy.nodes_of(step):
            raise SourceError(d.step.loc, f"a limit specification needs a static real step, found {t}")
        m.limits.append(step)
    elif isinstance(d, ast.ConfigSpec):
        bind(scope, d)
    elif isinstance(d, ast.FreeQuantityDecl) and d.source == "spectrum":  # 0 but in an AC analysis: a node
        magnitude, phase = (ev.real(e) for e in d.spectrum)  # driven by an independent source
        if sy.nodes_of(magnitude) or sy.nodes_of(phase):
            raise SourceError(d.loc, f"the spectrum of '{d.name}' must be static (constants and generics)")
        m.ac_sources[d.name] = (magnitude, phase)
        source = m.quantities[d.name] = Quantity(d.name, sy.Node(d.name), "source", d.unit, d.loc)
        scope.declare(d.name, source, d.loc)
    elif isinstance(d, ast.FreeQuantityDecl) and d.source == "noise":  # 0, with a noise current on its node
        (density,) = (ev.real(e) for e in d.spectrum)
        if sy.nodes_of(density):
            raise SourceError(d.loc, f"the noise density of '{d.name}' must be static (constants and generics)")
        m.noise_sources[d.name] = density
        noise = m.quantities[d.name] = Quantity(d.name, sy.Node(d.name), "source", d.unit, d.loc)
        m.unknowns[d.name] = Unknown(d.name, "free", d.unit, d.loc)
        m.equations.append(Equation(sy.Node(d.name), d.loc, [], {d.name}))  # n == 0
        scope.declare(d.name, noise, d.loc)
    elif isinstance(d, ast.SignalDecl):
        sig = new_signal(d.name, d.type_mark, d.width, "signal", d.loc)
        scope.declare(d.name, sig, d.loc)
        m.signals[d.name] = sig
    elif isinstance(d, ast.TerminalDecl):
        kind = scope.lookup(d.nature)
        if isinstance(kind, ArrayNature) or d.bounds is not None:  # a vector terminal: one node per element
            if not isinstance(kind, ArrayNature) or d.bounds is None:
                raise SourceError(d.loc, f"a vector terminal needs an array nature and an index range ('{d.nature}')")
            m.natures.add(kind.element)
            scope.declare(
                d.name,
                Elements(
                    d.name,
                    {k: Terminal(f"{d.name}__{k}", kind.element, d.loc) for k in index_values(ev, d.bounds, scope)},
                ),
                d.loc,
            )
            return
        nat = nature_of(scope, d.nature, d.loc)
        scope.declare(d.name, Terminal(d.name, nat.decl.name, d.loc), d.loc)
        m.natures.add(nat.decl.name)
    elif isinstance(d, ast.FreeQuantityDecl):
        t = base_type(d.type_mark, scope, d.loc)
        unit = d.unit or getattr(scope.lookup(d.type_mark), "unit", None)
        indices = (
            index_values(ev, d.bounds, scope)
            if d.bounds is not None
            else getattr(scope.lookup(d.type_mark), "indices", None)
        )
        if t == "real_vector" and indices is not None:  # an array quantity: one per element
            scope.declare(
                d.name, Elements(d.name, {k: free_quantity(m, f"{d.name}__{k}", unit, d.loc) for k in indices}), d.loc
            )
            return
        if t != "real":
            raise SourceError(d.loc, f"unsupported construct: quantity of type {t}")
        scope.declare(d.name, free_quantity(m, d.name, unit, d.loc), d.loc)
    elif isinstance(d, ast.BranchQuantityDecl):
        plus = terminal(scope, ev, d.plus, d.loc)
        minus = terminal(scope, ev, d.minus, d.loc) if d.minus is not None else None
        vector = plus if isinstance(plus, Elements) else minus
        if isinstance(vector, Elements):  # elementwise over vector terminals
            groups: dict[str, dict[int, Quantity | Terminal]] = {}
            for k in vector.items:
                pk = plus.items[k] if isinstance(plus, Elements) else plus
                mk = minus.items[k] if isinstance(minus, Elements) else minus
                if not isinstance(pk, Terminal) or not isinstance(mk, Terminal | None):
                    raise SourceError(d.loc, "a branch between vector terminals needs terminals on both ends")
                across, through = (f"{n}__{k}" if n else None for n in (d.across, d.through))
                branch(m, scope, dataclasses.replace(d, across=across, through=through), pk, mk)
                for name, element in ((d.across, across), (d.through, through)):
                    q = scope.names.pop(element) if name and element else None
                    if name and isinstance(q, Quantity):
                        groups.setdefault(name, {})[k] = q
            for name, items in groups.items():
                scope.declare(name, Elements(name, items), d.loc)
            return
        assert isinstance(plus, Terminal) and not isinstance(minus, Elements)  # (neither is a vector)
        branch(m, scope, d, plus, minus)
    else:
        raise SourceError(d.loc, "unsupported construct: declaration in an architecture")


def free_quantity(m: ArchModel, name: str, unit: str | None, loc: Loc) -> Quantity:
    """A new free quantity of `m` (an unknown)."""
    q = Quantity(name, sy.Node(name), "free", unit, loc)
    m.quantities[name] = q
    m.unknowns[name] = Unknown(name, "free", unit, loc)
    return q


def branch(m: ArchModel, scope: Scope, d: ast.BranchQuantityDecl, plus: Terminal, minus: Terminal | None) -> None:
    """Declare the across and through quantity of one branch between `plus` and `minus` (None: the reference)."""
    if minus is not None and minus.nature != plus.nature:
        raise SourceError(
            d.loc, f"nature mismatch: terminal '{d.plus}' is {plus.nature}, '{d.minus}' is {minus.nature}"
        )
    minus = minus or Terminal(GROUND, plus.nature, None)
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


def terminal(scope: Scope, ev: Evaluator, name: str | ast.Expr, loc: Loc) -> Terminal | Elements:
    """A terminal by name, N'reference, t(k) (an element of a vector terminal) or a whole vector terminal."""
    if isinstance(name, ast.Call):
        t = ev.element(name, scope)
    elif isinstance(name, str) and name.endswith("'reference"):
        return reference_terminal(scope, name, loc)
    else:
        t = scope.lookup(str(name))
    if isinstance(t, Elements) and all(isinstance(x, Terminal) for x in t.items.values()):
        return t
    if not isinstance(t, Terminal):
        raise SourceError(loc, f"unknown terminal '{name}'" if t is None else f"'{name}' is not a terminal")
    return t


def bind(scope: Scope, d: ast.ConfigSpec) -> None:
    """Declare the bindings of a configuration specification (`instances.InstanceTree.resolve_instance` reads
    them)."""
    for label in d.labels:
        scope.declare(f"{d.component}'binding" if label in ("all", "others") else f"{label}'binding", d, d.loc)
