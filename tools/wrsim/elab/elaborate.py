"""Elaboration: library loading, name resolution, symbolic evaluation of expressions and functions, the
instance tree with concrete generic values (assertions, parameter sets), and one equation system per
architecture for the backend.

Two passes share one evaluator:
- the static pass (`instances`) walks the instance tree with concrete generic values (`Const`): it checks
  assertions and parameter sets and reports bad generics with the instance path;
- the model pass builds, once per architecture (and per length of its vector generics), the unknowns and
  residual equations with generics left symbolic (`Param`), which the backend turns into one `.subckt`. This
  module holds its driver: the architecture's generics and ports, then its declarations (`declare`) and its
  concurrent statements by kind (`simultaneous`, `events`, `compound`, `instantiate`).
"""

from __future__ import annotations

import math
import re

from wrsim.elab import compound, events
from wrsim.elab import symbolic as sy
from wrsim.elab.attributes import system_attribute
from wrsim.elab.context import nature_of
from wrsim.elab.declare import declare, free_quantity
from wrsim.elab.design import AdcElem, ArchModel, Crossing, Derivative, Design, Equation, Integral, Unknown
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.instances import check_param_set
from wrsim.elab.instantiate import Instantiation
from wrsim.elab.library import Library
from wrsim.elab.pairing import pair_model
from wrsim.elab.scope import Quantity, Scope, Signal, Terminal, Value, base_type, new_signal
from wrsim.elab.simultaneous import break_statement, involved, quiescent_dots, simultaneous
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError, WrsimError
from wrsim.frontend import ast

__all__ = ["elaborate", "check_param_set"]


class _Elaborator(Instantiation):
    """The model pass: one equation system per architecture (and per shape of its integer and vector generics),
    with the generics left symbolic."""

    # -------------------------------------------------------------- model pass
    def model(
        self, ent: ast.Entity, arch: ast.Architecture, shape: dict[str, float | str], top_values=None
    ) -> ArchModel:
        """The equation system of `arch`. `shape` fixes what VHDL needs statically and a .subckt parameter
        cannot carry: the length of every real_vector generic and the value of every integer, boolean and string
        generic (loop bounds, case selectors, string comparisons); each distinct shape is its own .subckt."""
        key = ent.name if top_values is None else "top"
        archs = self.lib.archs.get(ent.name, [])
        if top_values is None:
            if len(archs) > 1 and archs[-1] is not arch:
                key += "__" + arch.name
            key += "".join(f"__{n}{_shape_tag(v)}" for n, v in sorted(shape.items()))
            if key in self.models:
                return self.models[key]
        defaults = self.generic_defaults(ent)
        indices = self.generic_indices(ent)
        scope = Scope(self.entity_scope(ent))
        params: dict[str, float] = {}
        for g in ent.generics:
            dflt, t = defaults[g.name]
            if top_values is not None:
                s = top_values.get(g.name, dflt)
                scope.declare(g.name, Value(s, t, "generic", g.loc, indices[g.name]), g.loc)
            elif t == "string":  # static, like an integer: each value is a .subckt of its own
                scope.declare(g.name, Value(sy.Text(str(shape[g.name])), t, "generic", g.loc), g.loc)
            elif t in ("integer", "boolean"):
                v = float(shape[g.name])
                scope.declare(
                    g.name, Value(sy.const(v) if t == "integer" else sy.const(bool(v)), t, "generic", g.loc), g.loc
                )
            elif t == "real_vector":
                n = int(shape[g.name])
                items = tuple(sy.Param(f"{g.name}_{k}") for k in range(n))
                for k in range(n):
                    params[f"{g.name}_{k}"] = (
                        sy.value(sy.items(dflt)[k]) if dflt is not None and k < len(sy.items(dflt)) else 0.0
                    )
                scope.declare(g.name, Value(sy.vec(items), t, "generic", g.loc, indices[g.name]), g.loc)
            else:
                params[g.name] = sy.value(dflt) if dflt is not None else 0.0
                scope.declare(g.name, Value(sy.Param(g.name), t, "generic", g.loc), g.loc)
        m = ArchModel(key, ent, arch, [], params, {}, [], {}, [], {}, {}, [], set(), [])
        for p in ent.ports:
            if isinstance(p, ast.TerminalPort):
                nat = nature_of(scope, p.nature, p.loc)
                scope.declare(p.name, Terminal(p.name, nat.decl.name, p.loc), p.loc)
                m.natures.add(nat.decl.name)
                m.ports.append(p.name)
            elif isinstance(p, ast.SignalPort):
                sig = new_signal(p.name, p.type_mark, p.width, p.mode, p.loc)
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

        def on_dot(q: Quantity, loc: Loc, order: int = 1) -> S:
            if order == 2:  # q'dot'dot: the 'dot of a hidden free quantity q__dot == q'dot
                name = f"{q.name}__dot"
                if name not in m.quantities:
                    free_quantity(m, name, None, loc)
                    res = sy.op("-", sy.Node(name), on_dot(q, loc))
                    m.equations.append(Equation(res, loc, [], involved(m, res)))
                q = m.quantities[name]
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

        def on_above(q: S, level: S, loc: Loc) -> None:
            guard = sy.op("-", q, level)
            if all(c.guard != guard for c in m.crossings):
                m.crossings.append(Crossing(f"above__{len(m.crossings) + 1}", guard, sy.op(">", q, level), loc))

        def on_system(attr: str, u: S, args: list[tuple[S, str]], loc: Loc) -> S:
            return system_attribute(
                m,
                attr,
                u,
                args,
                loc,
                lambda name, at: free_quantity(m, name, None, at).s,
                lambda name, at: on_dot(m.quantities[name], at),
                lambda res, at: m.equations.append(Equation(res, at, [], involved(m, res))),
            )

        ev = Evaluator(arch_scope, on_dot, on_integ, on_signal=on_signal, on_above=on_above, on_system=on_system)
        held = events.assigned_signals(arch.stmts)
        for d in arch.decls:
            if isinstance(d, ast.SignalDecl) and (  # a type no digital unit connects to: a held value
                d.name in held
                or (
                    d.width is None
                    and base_type(d.type_mark, arch_scope, d.loc) not in ("std_logic", "integer", "boolean")
                )
            ):
                events.held_signal(m, arch_scope, ev, d)
            else:
                declare(m, arch_scope, ev, d)
        for st in arch.stmts:
            self.statement(m, arch_scope, ev, st, top=top_values is not None)
        quiescent_dots(m)
        events.fold_initial_runs(m)
        for unit in m.digital:  # what digital units drive is also recorded as a 0/1 waveform
            for node in unit.outputs:
                if node not in m.dacs:
                    m.recorded.add(node)
                m.dacs.setdefault(node, f"{node}__a")
        for h in m.holds.values():
            if h.quantity is not None and h.quantity not in m.derivatives:
                raise SourceError(
                    h.loc,
                    f"unsupported construct: break list on '{h.quantity}', whose 'dot this "
                    f"architecture does not take (only an integrated state restarts)",
                )
        if top_values is None:
            self.models[key] = m
        self.order.append(m)
        return m

    def statement(self, m: ArchModel, scope: Scope, ev: Evaluator, st, top: bool = False) -> None:
        """A concurrent statement of `m` (`top`: of the bench itself), by kind."""
        if isinstance(st, (ast.SimpleSimultaneous, ast.SimultaneousIf, ast.SimultaneousCase)):
            simultaneous(m, ev, st)
        elif isinstance(st, ast.SimultaneousNull):
            pass
        elif isinstance(st, ast.Break):
            break_statement(m, scope, ev, st, top)
        elif isinstance(st, ast.Process):
            try:
                events.process(m, scope, ev, st)
            except sy.FoldError as ex:  # arithmetic on the process's static values (its waits' times, ...)
                raise SourceError(st.loc, f"process{f' {st.label}' if st.label else ''}: {ex}") from None
        elif isinstance(st, ast.Procedural):
            compound.procedural(m, scope, ev, st)
        elif isinstance(st, (ast.Generate, ast.CaseGenerate)):
            compound.generate(self, m, scope, ev, st, top)
        elif isinstance(st, ast.Assertion):
            pass  # checked in the static pass with concrete generics
        elif isinstance(st, ast.SignalAssign):
            sig = scope.lookup(st.target)
            if not isinstance(sig, Signal) or sig.mode == "in":
                raise SourceError(st.loc, f"'{st.target}' is not an output signal of this model")
            if (st.index is None) != (sig.width is None or sig.type_mark in ("integer", "natural")) or (
                st.index is not None and not 0 <= st.index < len(sig.nodes)
            ):
                raise SourceError(
                    st.loc,
                    f"assign std_logic signals whole and vector signals bit by bit "
                    f"({st.target}(k), k in 0..{len(sig.nodes) - 1})",
                )
            node = sig.nodes[st.index or 0]
            if any(a.node == node for a in m.adcs):
                raise SourceError(st.loc, f"'{st.target}' already has a driver in this architecture")
            cond, t = ev.eval(st.cond)
            if t != "boolean":
                raise SourceError(st.cond.loc, f"the condition of a signal assignment must be boolean, found {t}")
            m.adcs.append(AdcElem(node, f"{node}__lvl", cond, st.loc))
        elif isinstance(st, ast.Instance):
            self.instance(m, scope, ev, st)
        else:
            raise SourceError(st.loc, "unsupported construct: concurrent statement")


def _shape_tag(v: float | str) -> str:
    return re.sub(r"\W", "_", v) if isinstance(v, str) else str(int(v)).replace("-", "m")


def elaborate(lib: Library, top: str, params=None, overrides: dict[str, float | str] | None = None) -> Design:
    """Elaborate entity `top` (a bench without ports) with a parameter set and top-level generic overrides."""
    ent = lib.entity(top)
    arch = lib.architecture(top, None, None)
    if any(True for _ in ent.ports):
        raise WrsimError(f"{ent.loc}: top-level entity '{top}' must not have ports (it is a bench)")
    if isinstance(arch, ast.DigitalArchitecture):
        raise WrsimError(
            f"{arch.loc}: top-level entity '{top}' is digital VHDL: GHDL runs it, not the analog elaboration"
        )
    el = _Elaborator(lib, params)
    if params is not None:
        check_param_set(lib, params)
    defaults = el.generic_defaults(ent)
    actuals: dict[str, S] = {}
    for k, v in (overrides or {}).items():
        if k not in defaults:
            raise WrsimError(f"bench {top} has no generic '{k}' (it has: {', '.join(defaults) or 'none'})")
        if not isinstance(v, str) and not math.isfinite(v):
            raise WrsimError(f"bench {top}: generic '{k}' = {v}: not a finite number")
        actuals[k] = sy.Text(v) if isinstance(v, str) else sy.const(v)
    tree = el.static_instance(ent, arch, top, actuals, None)
    top_values = {g.name: actuals.get(g.name, defaults[g.name][0]) for g in ent.generics}
    topm = el.model(ent, arch, {}, top_values)
    natures = set()
    for mm in el.order:
        natures |= mm.natures
    for mm in el.order:  # the pairing pass: 1076.1 equation count, one unknown per equation
        pair_model(mm)
    models = [mm for mm in el.order if mm is not topm]
    return Design(
        topm,
        models,
        tree,
        natures,
        lib.digital_files(list(dict.fromkeys(d.entity.name for mm in el.order for d in mm.digital))),
    )
