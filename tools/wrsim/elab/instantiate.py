"""Component and entity instances in the model pass: an analog child (its architecture's equation system for the
shape of its generics, generic and port maps) or, at any depth, a digital unit GHDL runs (static generics, signal
ports; the netlist hoists its d_cosim instance)."""

from __future__ import annotations

from abc import ABC, abstractmethod

from wrsim.elab import symbolic as sy
from wrsim.elab.context import nature_of
from wrsim.elab.design import ArchModel, ChildInstance, DigitalChild
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.instances import InstanceTree
from wrsim.elab.scope import Elements, Quantity, Scope, Signal, Terminal, base_type
from wrsim.elab.symbolic import S
from wrsim.errors import SourceError, WrsimError
from wrsim.frontend import ast

__all__ = ["Instantiation"]


class Instantiation(InstanceTree, ABC):
    """The instances of the model pass, on top of the static pass's resolution of instances and generic values."""

    @abstractmethod
    def model(
        self, ent: ast.Entity, arch: ast.Architecture, shape: dict[str, float | str], top_values=None
    ) -> ArchModel:
        """The equation system of `arch` for the `shape` of its generics (`elaborate._Elaborator.model`)."""

    def instance(self, m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Instance) -> None:
        """An instance statement of `m`: an analog child or a digital unit (at any depth: the netlist puts its
        d_cosim element at the top level)."""
        cent, carch = self.resolve_instance(st, scope)
        if isinstance(carch, ast.DigitalArchitecture):  # at any depth: the netlist hoists its d_cosim
            m.digital.append(self.digital_child(scope, ev, st, cent, carch))
        else:
            m.children.append(self.child(m, scope, ev, st))

    def empty_default(self, ent: ast.Entity, name: str) -> bool:
        """Whether generic `name` of `ent` defaults to the empty string."""
        g = next(g for g in ent.generics if g.name == name)
        if g.default is None:
            return False
        value, _ = Evaluator(self.entity_scope(ent), allow_quantities=False).eval(g.default)
        return isinstance(value, sy.Text) and value.value == ""

    def digital_child(
        self, scope: Scope, ev: Evaluator, st: ast.Instance, cent: ast.Entity, carch: ast.DigitalArchitecture
    ) -> DigitalChild:
        generics: dict[str, int | bool | str] = {}
        for name, actual in self.associate(st.generic_map, [g.name for g in cent.generics], st, "generic"):
            s, t = ev.eval(actual)
            if isinstance(s, sy.Text) and s.value == "":
                # GHDL's run option -gNAME= takes no empty value: an empty string is the unit's own default or an error
                if not self.empty_default(cent, name):
                    raise SourceError(
                        actual.loc,
                        f"generic '{name}' of digital unit {cent.name}: GHDL cannot set a "
                        f'string generic to "" (only leave it at an empty default)',
                    )
            elif isinstance(s, sy.Text):
                generics[name] = s.value
            elif isinstance(s, sy.Const) and t in ("integer", "boolean"):
                generics[name] = bool(s.value) if t == "boolean" else int(s.value)
            else:
                inner = any(isinstance(x, sy.Param) for x in sy.walk(s))  # a real generic of the enclosing model
                raise SourceError(
                    actual.loc,
                    f"generic '{name}' of digital unit {cent.name}: GHDL takes static "
                    f"integer, boolean or string generics only"
                    + (
                        " (inside a model, from the enclosing entity's integer, boolean "
                        "or string generics, not its real ones)"
                        if inner
                        else ""
                    ),
                )
        for g in cent.generics:  # the parameter set replaces the defaults the instance leaves alone
            given = self.params.sections.get(cent.name, {}).get(g.name) if self.params is not None else None
            if given is not None and g.name not in generics:
                self.origins[(cent.name, g.name)] = f"{given.file}:{given.line}"
                value, t = self.params.value_in(cent.name, g.name, g.unit or "1"), base_type(g.type_mark, scope, g.loc)
                if t not in ("integer", "boolean"):
                    raise WrsimError(
                        f"{given.file}:{given.line}: [{cent.name}] {g.name}: a digital unit takes "
                        f"integer or boolean values from a parameter set"
                    )
                generics[g.name] = bool(value) if t == "boolean" else int(round(value))
        mapped = dict(self.associate(st.port_map, [p.name for p in cent.ports], st, "port"))
        inputs: list[str] = []
        outputs: list[str] = []
        for p in cent.ports:
            actual = mapped.get(p.name)
            if not isinstance(p, ast.SignalPort):
                raise SourceError(p.loc, f"digital unit {cent.name} may only have signal ports")
            if p.mode == "in" and p.type_mark in ("integer", "natural"):
                raise SourceError(
                    p.loc,
                    f"input port '{p.name}' of digital unit {cent.name}: GHDL 2.0 cannot set "
                    f"integer inputs through VPI; use std_logic_vector",
                )
            if actual is None or not isinstance(actual, ast.Name):
                raise SourceError(st.loc, f"port '{p.name}' of {cent.name} must be connected to a signal")
            nodes = _connect_signal(p, scope.lookup(actual.ident), actual, cent)
            # d_cosim takes every port's bits left index first: MSB first for downto vectors and integers
            (inputs if p.mode == "in" else outputs).extend(reversed(nodes))
        return DigitalChild(st.label, cent, carch, generics, inputs, outputs, st.loc)

    def child(self, m: ArchModel, scope: Scope, ev: Evaluator, st: ast.Instance) -> ChildInstance:
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
                shape[g.name] = (
                    len(sy.items(d)) if gt == "real_vector" else d.value if isinstance(d, sy.Text) else sy.value(d)
                )
        for g in cent.generics:  # an index constraint: the number of elements
            indices = self.generic_indices(cent)[g.name]
            if indices is not None:
                n = len(indices)
                if shape.get(g.name, n) != n:
                    raise SourceError(
                        st.loc,
                        f"generic '{g.name}' of {cent.name} has {n} elements ({g.type_mark} constrained at "
                        f"{g.loc}), its value {int(shape[g.name])}",
                    )
        if isinstance(carch, ast.DigitalArchitecture):
            raise SourceError(st.loc, f"internal: digital unit {cent.name} reached the analog model pass")
        cm = self.model(cent, carch, shape)
        formals = [p for p in cent.ports]
        mapped = dict(self.associate(st.port_map, [p.name for p in formals], st, "port"))
        nodes = []
        for p in formals:
            actual = mapped.get(p.name)
            if actual is None:
                raise SourceError(st.loc, f"port '{p.name}' of {cent.name} is not connected (instance {st.label})")
            if isinstance(actual, ast.Call) and isinstance(scope.lookup(actual.name), Elements):
                b = ev.element(actual, scope)  # n(k): an element of a vector terminal or quantity
                actual = ast.Name(f"{actual.name}(...)", actual.loc)
            elif not isinstance(actual, ast.Name):
                raise SourceError(actual.loc, f"port '{p.name}' must be connected to a terminal or quantity name")
            else:
                b = scope.lookup(actual.ident)
            if b is None:
                raise SourceError(actual.loc, f"unknown name '{actual.ident}' in the port map of {st.label}")
            if isinstance(p, ast.SignalPort):
                nodes.extend(_connect_signal(p, b, actual, cent))
                continue
            if isinstance(p, ast.TerminalPort):
                pn = nature_of(self.entity_scope(cent), p.nature, p.loc).decl.name
                if not isinstance(b, Terminal):
                    raise SourceError(actual.loc, f"port '{p.name}' is a terminal; '{actual.ident}' is not a terminal")
                if b.nature != pn:
                    raise SourceError(
                        actual.loc,
                        f"nature mismatch: port '{p.name}' of {cent.name} is {pn}, "
                        f"terminal '{actual.ident}' is {b.nature}",
                    )
                nodes.append(b.node)
            else:
                if not isinstance(b, Quantity) or b.role == "across":
                    raise SourceError(actual.loc, f"port '{p.name}' is a quantity port; connect a free quantity")
                nodes.append(b.name)
                if p.mode == "out" and b.name in m.unknowns and b.role in ("free", "out"):
                    m.unknowns.pop(b.name)  # its equation lives in the child
        return ChildInstance(st.label, cm, nodes, params, st.loc)


def _connect_signal(p: ast.SignalPort, b, actual: ast.Name, ent: ast.Entity) -> list[str]:
    """The digital nodes a signal port is connected to (widths and kinds must match)."""
    if not isinstance(b, Signal):
        raise SourceError(actual.loc, f"port '{p.name}' of {ent.name} is a signal; '{actual.ident}' is not a signal")

    def kind(t):
        return "integer" if t in ("integer", "natural") else "std_logic" if t == "std_ulogic" else t

    if kind(b.type_mark) != kind(p.type_mark) or b.width != p.width:
        raise SourceError(
            actual.loc,
            f"signal '{actual.ident}' ({b.type_mark}{f'({b.width})' if b.width else ''}) "
            f"does not fit port '{p.name}' of {ent.name} ({p.type_mark}"
            f"{f'({p.width})' if p.width else ''})",
        )
    return list(b.nodes)


def _has_time(s: S) -> bool:
    return any(isinstance(x, sy.Time) for x in sy.walk(s))
