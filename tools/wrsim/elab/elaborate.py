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

from wrsim.elab import symbolic as sy
from wrsim.elab.context import Context, declare_all, nature_of
from wrsim.elab.design import (
    AdcElem,
    ArchModel,
    BranchElem,
    ChildInstance,
    Derivative,
    Design,
    DigitalChild,
    Equation,
    Generics,
    InstanceInfo,
    Integral,
    Unknown,
)
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.library import Library
from wrsim.elab.pairing import pair_model
from wrsim.elab.scope import GROUND, Quantity, Scope, Signal, Terminal, Value, base_type
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError, WrsimError
from wrsim.frontend import ast as ir

__all__ = ["elaborate", "check_param_set"]



# ================================================================================================
class _Elaborator:
    def __init__(self, lib: Library, params=None):
        self.lib = lib
        self.ctx = Context(lib)
        self.params = params
        self.models: dict[str, ArchModel] = {}
        self.order: list[ArchModel] = []
        self.defaults_cache: dict[str, dict[str, tuple[S | None, str]]] = {}
        self.origins: dict[tuple[str, str], str] = {}    # (entity, generic) -> "file:line" of a parameter set

    # -------------------------------------------------------------- generic defaults
    def entity_scope(self, ent: ir.Entity) -> Scope:
        return self.ctx.unit_scope(ent.uses)

    def generic_defaults(self, ent: ir.Entity) -> dict[str, tuple[S | None, str]]:
        """Entity generic defaults after the parameter set: name -> (Const or Vec of Const, type)."""
        if ent.name in self.defaults_cache:
            return self.defaults_cache[ent.name]
        scope = self.entity_scope(ent)
        ev = Evaluator(scope, allow_quantities=False)
        out: dict[str, tuple[S | None, str]] = {}
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
                    out[g.name] = (sy.vec(tuple(sy.const(v) for v in value)), t)
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
    def static_instance(self, ent: ir.Entity, arch: ir.Architecture | ir.DigitalArchitecture, path: str,
                        actuals: dict[str, S],
                        loc: Loc | None) -> InstanceInfo:
        defaults = self.generic_defaults(ent)
        scope = Scope(self.entity_scope(ent))
        values: dict[str, float | list[float] | str] = {}
        for g in ent.generics:
            s, t = (actuals[g.name], defaults[g.name][1]) if g.name in actuals else defaults[g.name]
            if s is None:
                raise SourceError(loc or g.loc, f"generic '{g.name}' of {ent.name} (instance {path}) has no "
                                                f"value: map it or give it a default")
            scope.declare(g.name, Value(s, t, "generic", g.loc), g.loc)
            values[g.name] = _static_value(s)
        if isinstance(arch, ir.DigitalArchitecture):
            return InstanceInfo(path, ent.name, arch.name, Generics(values), loc, [])
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
        return InstanceInfo(path, ent.name, arch.name, Generics(values), loc, children)

    def static_actuals(self, st: ir.Instance, cent: ir.Entity, ev: Evaluator) -> dict[str, S]:
        out: dict[str, S] = {}
        for name, actual in self.associate(st.generic_map, [g.name for g in cent.generics], st, "generic"):
            if actual is None:
                continue
            s, _ = ev.eval(actual)
            if not isinstance(s, (sy.Const, sy.Vec, sy.Text)):
                raise SourceError(actual.loc, f"generic '{name}' must be static")
            out[name] = s
        return out

    # -------------------------------------------------------------- instances
    def resolve_instance(self, st: ir.Instance,
                         scope: Scope) -> tuple[ir.Entity, ir.Architecture | ir.DigitalArchitecture]:
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
                scope.declare(g.name,
                              Value(sy.const(shape[g.name]) if t == "integer" else sy.const(bool(shape[g.name])),
                                            t, "generic", g.loc), g.loc)
            elif t == "real_vector":
                n = int(shape[g.name])
                items = tuple(sy.Param(f"{g.name}_{k}") for k in range(n))
                for k in range(n):
                    params[f"{g.name}_{k}"] = sy.value(sy.items(dflt)[k]) if dflt is not None and \
                        k < len(sy.items(dflt)) else 0.0
                scope.declare(g.name, Value(sy.vec(items), t, "generic", g.loc), g.loc)
            else:
                params[g.name] = sy.value(dflt) if dflt is not None else 0.0
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
        for unit in m.digital:         # what digital units drive is also recorded as a 0/1 waveform
            for node in unit.outputs:
                if node not in m.dacs:
                    m.recorded.add(node)
                m.dacs.setdefault(node, f"{node}__a")
        if top_values is None:
            self.models[key] = m
        self.order.append(m)
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
        test: S
        if isinstance(st, ir.SimultaneousIf):
            arms = []
            for c, body in st.branches:
                test = sy.const(True)
                if c is not None:
                    test, t = ev.eval(c)
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
                    test = sy.const(True)
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
            raise SourceError(st.loc,
                              "the branches of this simultaneous "
                              f"{'if' if isinstance(st, ir.SimultaneousIf) else 'case'} "
                                      f"have different numbers of equations ({detail}); 1076.1 requires the same")
        n = counts.pop() if counts else 0
        out = []
        for k in range(n):
            res: S | None = None
            for test, eqs in reversed(arms):
                res = eqs[k][0] if res is None else sy.cond(test, eqs[k][0], res)
            if res is None:
                raise SourceError(st.loc, "internal: a simultaneous statement without branches")
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
                shape[g.name] = len(sy.items(d)) if gt == "real_vector" else sy.value(d)
        if isinstance(carch, ir.DigitalArchitecture):
            raise SourceError(st.loc, f"internal: digital unit {cent.name} reached the analog model pass")
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



def _signal(name: str, type_mark: str, width: int | None, mode: str, loc: Loc) -> Signal:
    nodes = [name] if width is None else [f"{name}_{k}" for k in range(width)]
    return Signal(name, nodes, type_mark, width, mode, loc)


def _connect_signal(p: ir.SignalPort, b, actual: ir.Name, ent: ir.Entity) -> list[str]:
    """The digital nodes a signal port is connected to (widths and kinds must match)."""
    if not isinstance(b, Signal):
        raise SourceError(actual.loc, f"port '{p.name}' of {ent.name} is a signal; '{actual.ident}' is not a signal")
    def kind(t):
        return "integer" if t in ("integer", "natural") else t
    if kind(b.type_mark) != kind(p.type_mark) or b.width != p.width:
        raise SourceError(actual.loc, f"signal '{actual.ident}' ({b.type_mark}{f'({b.width})' if b.width else ''}) "
                                      f"does not fit port '{p.name}' of {ent.name} ({p.type_mark}"
                                      f"{f'({p.width})' if p.width else ''})")
    return list(b.nodes)


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


def _static_value(s: S) -> float | list[float] | str:
    """A generic's concrete value: a number, the numbers of a real_vector, or a string."""
    if isinstance(s, sy.Vec):
        return [sy.value(x) for x in s.items]
    if isinstance(s, sy.Text):
        return s.value
    return sy.value(s)


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
    if isinstance(arch, ir.DigitalArchitecture):
        raise WrsimError(f"{arch.loc}: top-level entity '{top}' is digital VHDL: GHDL runs it, not the analog "
                         f"elaboration")
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
    for mm in el.order:          # the pairing pass: 1076.1 equation count, one unknown per equation
        pair_model(mm)
    models = [mm for mm in el.order if mm is not topm]
    return Design(topm, models, tree, natures, lib.digital_files([d.entity.name for d in topm.digital]))
