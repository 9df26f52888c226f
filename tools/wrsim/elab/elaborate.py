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

import dataclasses
import math
import re

from wrsim.elab import compound, events
from wrsim.elab import symbolic as sy
from wrsim.elab.attributes import system_attribute
from wrsim.elab.context import declare_all, index_values, nature_of, reference_terminal
from wrsim.elab.design import (
    AdcElem,
    ArchModel,
    BranchElem,
    ChildInstance,
    Crossing,
    Derivative,
    Design,
    DigitalChild,
    Equation,
    Integral,
    Unknown,
)
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.instances import InstanceTree, check_param_set
from wrsim.elab.library import Library
from wrsim.elab.pairing import pair_model
from wrsim.elab.scope import (
    GROUND,
    ArrayNature,
    Elements,
    Quantity,
    Scope,
    Signal,
    Terminal,
    Value,
    base_type,
    new_signal,
)
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError, WrsimError
from wrsim.frontend import ast as ir

__all__ = ["elaborate", "check_param_set"]


class _Elaborator(InstanceTree):
    """The model pass: one equation system per architecture (and per shape of its integer and vector generics),
    with the generics left symbolic."""

    # -------------------------------------------------------------- model pass
    def model(self, ent: ir.Entity, arch: ir.Architecture, shape: dict[str, float | str],
              top_values=None) -> ArchModel:
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
        scope = Scope(self.entity_scope(ent))
        params: dict[str, float] = {}
        for g in ent.generics:
            dflt, t = defaults[g.name]
            if top_values is not None:
                s = top_values.get(g.name, dflt)
                scope.declare(g.name, Value(s, t, "generic", g.loc), g.loc)
            elif t == "string":          # static, like an integer: each value is a .subckt of its own
                scope.declare(g.name, Value(sy.Text(str(shape[g.name])), t, "generic", g.loc), g.loc)
            elif t in ("integer", "boolean"):
                v = float(shape[g.name])
                scope.declare(g.name, Value(sy.const(v) if t == "integer" else sy.const(bool(v)), t, "generic", g.loc),
                              g.loc)
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
            if order == 2:         # q'dot'dot: the 'dot of a hidden free quantity q__dot == q'dot
                name = f"{q.name}__dot"
                if name not in m.quantities:
                    self.free_quantity(m, name, None, loc)
                    res = sy.op("-", sy.Node(name), on_dot(q, loc))
                    m.equations.append(Equation(res, loc, [], self.involved(m, res)))
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
            return system_attribute(m, attr, u, args, loc, lambda name, at: self.free_quantity(m, name, None, at).s,
                                    lambda name, at: on_dot(m.quantities[name], at),
                                    lambda res, at: m.equations.append(Equation(res, at, [], self.involved(m, res))))

        ev = Evaluator(arch_scope, on_dot, on_integ, on_signal=on_signal, on_above=on_above, on_system=on_system)
        held = events.assigned_signals(arch.stmts)
        for d in arch.decls:
            if isinstance(d, ir.SignalDecl) and (d.name in held or d.type_mark == "real"):
                events.held_signal(m, arch_scope, ev, d)
            else:
                self.declare_arch_item(m, arch_scope, ev, d)
        for st in arch.stmts:
            self.statement(m, arch_scope, ev, st, top=top_values is not None)
        events.fold_initial_runs(m)
        for unit in m.digital:         # what digital units drive is also recorded as a 0/1 waveform
            for node in unit.outputs:
                if node not in m.dacs:
                    m.recorded.add(node)
                m.dacs.setdefault(node, f"{node}__a")
        for h in m.holds.values():
            if h.quantity is not None and h.quantity not in m.derivatives:
                raise SourceError(h.loc, f"unsupported construct: break list on '{h.quantity}', whose 'dot this "
                                         f"architecture does not take (only an integrated state restarts)")
        if top_values is None:
            self.models[key] = m
        self.order.append(m)
        return m

    def declare_arch_item(self, m: ArchModel, scope: Scope, ev: Evaluator, d) -> None:
        if isinstance(d, (ir.ConstantDecl, ir.FunctionDecl, ir.SubtypeDecl, ir.ComponentDecl, ir.AliasDecl,
                          ir.AttributeSpec, ir.ArrayNatureDecl, ir.NatureDecl, ir.SubnatureDecl)):
            declare_all(scope, [d], Evaluator(scope, allow_quantities=False))
        elif isinstance(d, ir.LimitSpec):
            step, t = ev.eval(d.step)
            if t not in ("real", "time") or sy.nodes_of(step):
                raise SourceError(d.step.loc, f"a limit specification needs a static real step, found {t}")
            m.limits.append(step)
        elif isinstance(d, ir.ConfigSpec):
            self.bind(scope, d)
        elif isinstance(d, ir.FreeQuantityDecl) and d.source is not None:
            scope.declare(d.name, Value(sy.const(0.0), "real", "constant", d.loc), d.loc)
            m.notes.append(f"{d.loc}: {d.source} source quantity '{d.name}' is 0 in the time domain (wrsim runs "
                           f"transient analyses)")
        elif isinstance(d, ir.SignalDecl):
            sig = new_signal(d.name, d.type_mark, d.width, "signal", d.loc)
            scope.declare(d.name, sig, d.loc)
            m.signals[d.name] = sig
        elif isinstance(d, ir.TerminalDecl):
            kind = scope.lookup(d.nature)
            if isinstance(kind, ArrayNature) or d.bounds is not None:    # a vector terminal: one node per element
                if not isinstance(kind, ArrayNature) or d.bounds is None:
                    raise SourceError(d.loc, f"a vector terminal needs an array nature and an index range "
                                             f"('{d.nature}')")
                m.natures.add(kind.element)
                scope.declare(d.name, Elements(d.name, {k: Terminal(f"{d.name}__{k}", kind.element, d.loc)
                                                        for k in index_values(ev, d.bounds, scope)}), d.loc)
                return
            nat = nature_of(scope, d.nature, d.loc)
            scope.declare(d.name, Terminal(d.name, nat.decl.name, d.loc), d.loc)
            m.natures.add(nat.decl.name)
        elif isinstance(d, ir.FreeQuantityDecl):
            t = base_type(d.type_mark, scope, d.loc)
            unit = d.unit or getattr(scope.lookup(d.type_mark), "unit", None)
            indices = index_values(ev, d.bounds, scope) if d.bounds is not None else \
                getattr(scope.lookup(d.type_mark), "indices", None)
            if t == "real_vector" and indices is not None:             # an array quantity: one per element
                scope.declare(d.name, Elements(d.name, {k: self.free_quantity(m, f"{d.name}__{k}", unit, d.loc)
                                                        for k in indices}), d.loc)
                return
            if t != "real":
                raise SourceError(d.loc, f"unsupported construct: quantity of type {t}")
            scope.declare(d.name, self.free_quantity(m, d.name, unit, d.loc), d.loc)
        elif isinstance(d, ir.BranchQuantityDecl):
            plus = self.terminal(scope, ev, d.plus, d.loc)
            minus = self.terminal(scope, ev, d.minus, d.loc) if d.minus is not None else None
            vector = plus if isinstance(plus, Elements) else minus
            if isinstance(vector, Elements):                   # elementwise over vector terminals
                groups: dict[str, dict[int, Quantity | Terminal]] = {}
                for k in vector.items:
                    pk = plus.items[k] if isinstance(plus, Elements) else plus
                    mk = minus.items[k] if isinstance(minus, Elements) else minus
                    if not isinstance(pk, Terminal) or not isinstance(mk, Terminal | None):
                        raise SourceError(d.loc, "a branch between vector terminals needs terminals on both ends")
                    across, through = (f"{n}__{k}" if n else None for n in (d.across, d.through))
                    self.branch(m, scope, dataclasses.replace(d, across=across, through=through), pk, mk)
                    for name, element in ((d.across, across), (d.through, through)):
                        q = scope.names.pop(element) if name and element else None
                        if name and isinstance(q, Quantity):
                            groups.setdefault(name, {})[k] = q
                for name, items in groups.items():
                    scope.declare(name, Elements(name, items), d.loc)
                return
            assert isinstance(plus, Terminal) and not isinstance(minus, Elements)     # (neither is a vector)
            self.branch(m, scope, d, plus, minus)
        else:
            raise SourceError(d.loc, "unsupported construct: declaration in an architecture")

    @staticmethod
    def free_quantity(m: ArchModel, name: str, unit: str | None, loc: Loc) -> Quantity:
        q = Quantity(name, sy.Node(name), "free", unit, loc)
        m.quantities[name] = q
        m.unknowns[name] = Unknown(name, "free", unit, loc)
        return q

    def branch(self, m: ArchModel, scope: Scope, d: ir.BranchQuantityDecl, plus: Terminal, minus: Terminal | None) \
            -> None:
        """Declare the across and through quantity of one branch between `plus` and `minus` (None: the reference)."""
        if minus is not None and minus.nature != plus.nature:
            raise SourceError(d.loc, f"nature mismatch: terminal '{d.plus}' is {plus.nature}, '{d.minus}' is "
                                     f"{minus.nature}")
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

    @staticmethod
    def terminal(scope: Scope, ev: Evaluator, name: str | ir.Expr, loc: Loc) -> Terminal | Elements:
        """A terminal by name, N'reference, t(k) (an element of a vector terminal) or a whole vector terminal."""
        if isinstance(name, ir.Call):
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

    def statement(self, m: ArchModel, scope: Scope, ev: Evaluator, st, top: bool = False) -> None:
        if isinstance(st, (ir.SimpleSimultaneous, ir.SimultaneousIf, ir.SimultaneousCase)):
            for res, locs in self.equations(st, ev):
                m.equations.append(Equation(res, locs[0], locs[1:], self.involved(m, res)))
        elif isinstance(st, ir.SimultaneousNull):
            pass
        elif isinstance(st, ir.Break):
            for e in [*st.on, *([st.cond] if st.cond is not None else [])]:
                ev.eval(e)                   # without a break list: a discontinuity, ngspice's step control sees it
            if st.sets and st.cond is None:  # runs once at initialisation, like its equivalent process
                self.initial_values(m, scope, ev, st, top, strict=not st.on)
            if st.sets and (st.on or st.cond is not None):
                events.reinitialisation(m, scope, ev, st)
            m.breaks.append(st.loc)
        elif isinstance(st, ir.Process):
            events.process(m, scope, ev, st)
        elif isinstance(st, ir.Procedural):
            compound.procedural(self, m, scope, ev, st)
        elif isinstance(st, ir.Generate):
            compound.generate(self, m, scope, ev, st, top)
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
            if isinstance(carch, ir.DigitalArchitecture):     # at any depth: the netlist hoists its d_cosim
                m.digital.append(self.digital_child(scope, ev, st, cent, carch))
            else:
                m.children.append(self.child(m, scope, ev, st))
        else:
            raise SourceError(st.loc, "unsupported construct: concurrent statement")

    @staticmethod
    def initial_values(m: ArchModel, scope: Scope, ev: Evaluator, st: ir.Break, top: bool, strict: bool) -> None:
        """A break list at initialisation: the quiescent point takes q = value instead of q'dot = 0 (1076.1). Not
        `strict` (a break on events): only what a plain break list could do is done, the rest is left out."""
        if not strict and (not top or any(not isinstance(ev.real(v, scope), sy.Const) for _, v in st.sets)):
            return
        for name, value in st.sets:
            q = scope.lookup(name)
            if not isinstance(q, Quantity):
                raise SourceError(st.loc, f"break list: '{name}' is not a quantity")
            v = ev.real(value, scope)
            if not top or not isinstance(v, sy.Const):
                raise SourceError(st.loc, "unsupported construct: break list at t = 0 " + (
                    "in an instantiated model (only in the testbench)" if not top else "with a value that is "
                    "not static"))
            if not isinstance(q.s, sy.Node) and not (isinstance(q.s, sy.Diff) and q.s.minus == GROUND):
                raise SourceError(st.loc, f"unsupported construct: break list on '{name}', an across quantity "
                                          f"between two terminals (only to the reference terminal)")
            node = q.s.name if isinstance(q.s, sy.Node) else q.s.plus
            m.initial = [i for i in m.initial if i[0] != node] + [(node, sy.value(v), st.loc)]

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
        ideal source's, is solved by its branch's through quantity, as in MNA; every branch on that node pair)."""
        names = set()
        by_source: dict[S, list[Quantity]] = {}
        for q in m.quantities.values():           # several branches may share a node pair (a source across a load)
            by_source.setdefault(q.s, []).append(q)
        derived = {d.element: d for d in m.derivatives.values()}
        for x in sy.walk(res):
            qs: list[Quantity] = []
            if isinstance(x, (sy.Node, sy.Diff)):
                qs = by_source.get(x, [])
            elif isinstance(x, sy.Branch) and x.name in derived:
                qs = [m.quantities[derived[x.name].quantity]] if derived[x.name].quantity in m.quantities else []
            for q in qs:
                if q.name in m.unknowns:
                    names.add(q.name)
                if q.branch_through:
                    names.add(q.branch_through)
        return names

    def empty_default(self, ent: ir.Entity, name: str) -> bool:
        """Whether generic `name` of `ent` defaults to the empty string."""
        g = next(g for g in ent.generics if g.name == name)
        if g.default is None:
            return False
        value, _ = Evaluator(self.entity_scope(ent), allow_quantities=False).eval(g.default)
        return isinstance(value, sy.Text) and value.value == ""

    def digital_child(self, scope: Scope, ev: Evaluator, st: ir.Instance, cent: ir.Entity,
                      carch: ir.DigitalArchitecture) -> DigitalChild:
        generics: dict[str, int | bool | str] = {}
        for name, actual in self.associate(st.generic_map, [g.name for g in cent.generics], st, "generic"):
            s, t = ev.eval(actual)
            if isinstance(s, sy.Text) and s.value == "":
                # GHDL's run option -gNAME= takes no empty value: an empty string is the unit's own default or an error
                if not self.empty_default(cent, name):
                    raise SourceError(actual.loc, f"generic '{name}' of digital unit {cent.name}: GHDL cannot set a "
                                                  f"string generic to \"\" (only leave it at an empty default)")
            elif isinstance(s, sy.Text):
                generics[name] = s.value
            elif isinstance(s, sy.Const) and t in ("integer", "boolean"):
                generics[name] = bool(s.value) if t == "boolean" else int(s.value)
            else:
                inner = any(isinstance(x, sy.Param) for x in sy.walk(s))     # a real generic of the enclosing model
                raise SourceError(actual.loc, f"generic '{name}' of digital unit {cent.name}: GHDL takes static "
                                              f"integer, boolean or string generics only" + (
                                                  " (inside a model, from the enclosing entity's integer, boolean "
                                                  "or string generics, not its real ones)" if inner else ""))
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
        shape: dict[str, float | str] = {}
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
            elif isinstance(s, sy.Text):
                shape[name] = s.value
            elif isinstance(s, sy.Vec):
                shape[name] = len(s.items)
                for k, item in enumerate(s.items):
                    params[f"{name}_{k}"] = item
            else:
                params[name] = s
        for g in cent.generics:
            d, gt = cdefaults[g.name]
            if gt in ("integer", "boolean", "real_vector", "string") and g.name not in shape:
                if d is None:
                    raise SourceError(st.loc, f"generic '{g.name}' of {cent.name} has no value")
                shape[g.name] = len(sy.items(d)) if gt == "real_vector" else d.value if isinstance(d, sy.Text) \
                    else sy.value(d)
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
            if isinstance(actual, ir.Call) and isinstance(scope.lookup(actual.name), Elements):
                b = ev.element(actual, scope)                   # n(k): an element of a vector terminal or quantity
                actual = ir.Name(f"{actual.name}(...)", actual.loc)
            elif not isinstance(actual, ir.Name):
                raise SourceError(actual.loc, f"port '{p.name}' must be connected to a terminal or quantity name")
            else:
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


def _shape_tag(v: float | str) -> str:
    return re.sub(r"\W", "_", v) if isinstance(v, str) else str(int(v)).replace("-", "m")


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


def _has_time(s: S) -> bool:
    return any(isinstance(x, sy.Time) for x in sy.walk(s))


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
    return Design(topm, models, tree, natures,
                  lib.digital_files(list(dict.fromkeys(d.entity.name for mm in el.order for d in mm.digital))))
