"""The static pass of elaboration: the instance tree with concrete generic values. Generic defaults after the
parameter set, generic maps, assertions on generics (reported with the instance path and the parameter-set line
that set a value), and the check that a parameter set names only entities and generics that exist."""

from __future__ import annotations

from wrsim.elab import symbolic as sy
from wrsim.elab.compound import chosen, generated, labelled
from wrsim.elab.context import Context, array_indices, declare_all
from wrsim.elab.declare import bind
from wrsim.elab.design import ArchModel, Generics, InstanceInfo
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.library import Library
from wrsim.elab.scope import Quantity, Scope, Value, base_type, new_signal
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError, WrsimError
from wrsim.frontend import ast

__all__ = ["InstanceTree", "check_param_set"]


class InstanceTree:
    """Generic values and the instance tree of a design (the static pass); the model pass builds on it."""

    def __init__(self, lib: Library, params=None):
        self.lib = lib
        self.ctx = Context(lib)
        self.params = params
        self.models: dict[str, ArchModel] = {}
        self.order: list[ArchModel] = []
        self.defaults_cache: dict[str, dict[str, tuple[S | None, str]]] = {}
        self.indices_cache: dict[str, dict[str, tuple[int, ...] | None]] = {}
        self.origins: dict[tuple[str, str], str] = {}  # (entity, generic) -> "file:line" of a parameter set

    # -------------------------------------------------------------- generic defaults
    def entity_scope(self, ent: ast.Entity) -> Scope:
        return self.ctx.unit_scope(ent.uses)

    def generic_defaults(self, ent: ast.Entity) -> dict[str, tuple[S | None, str]]:
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
                        raise WrsimError(
                            f"{given.file}:{given.line}: [{ent.name}] {g.name}: expected a list "
                            f"of values (generic is a real_vector)"
                        )
                    out[g.name] = (sy.vec(tuple(sy.const(v) for v in value)), t)
                else:
                    if isinstance(value, list):
                        raise WrsimError(
                            f"{given.file}:{given.line}: [{ent.name}] {g.name}: expected one value, got a list"
                        )
                    out[g.name] = (sy.const(float(round(value)) if t == "integer" else value), t)
            elif g.default is not None:
                s, vt = ev.eval(g.default)
                if vt != t and not (t == "real_vector" and vt == "real_vector"):
                    raise SourceError(g.loc, f"type mismatch: generic '{g.name}' is {t}, default is {vt}")
                if not _static(s):
                    raise SourceError(g.loc, f"the default of generic '{g.name}' must be static")
                out[g.name] = (s, t)
            else:
                out[g.name] = (None, t)
        self.defaults_cache[ent.name] = out
        return out

    def generic_indices(self, ent: ast.Entity) -> dict[str, tuple[int, ...] | None]:
        """The index values of each real_vector generic with an index constraint or a constrained subtype (None:
        unconstrained, from 0); a default of another length is one error."""
        if ent.name not in self.indices_cache:
            scope = self.entity_scope(ent)
            ev = Evaluator(scope, allow_quantities=False)
            defaults = self.generic_defaults(ent)
            self.indices_cache[ent.name] = {
                g.name: array_indices(
                    ev, g.bounds, g.type_mark, scope, defaults[g.name][0], f"generic '{g.name}'", g.loc
                )
                if defaults[g.name][1] == "real_vector"
                else None
                for g in ent.generics
            }
        return self.indices_cache[ent.name]

    # -------------------------------------------------------------- static pass
    def static_instance(
        self,
        ent: ast.Entity,
        arch: ast.Architecture | ast.DigitalArchitecture,
        path: str,
        actuals: dict[str, S],
        loc: Loc | None,
    ) -> InstanceInfo:
        defaults = self.generic_defaults(ent)
        scope = Scope(self.entity_scope(ent))
        values: dict[str, float | list[float] | str] = {}
        for g in ent.generics:
            s, t = (actuals[g.name], defaults[g.name][1]) if g.name in actuals else defaults[g.name]
            if s is None:
                raise SourceError(
                    loc or g.loc,
                    f"generic '{g.name}' of {ent.name} (instance {path}) has no value: map it or give it a default",
                )
            scope.declare(g.name, Value(s, t, "generic", g.loc), g.loc)
            values[g.name] = _static_value(s)
        if isinstance(arch, ast.DigitalArchitecture):
            return InstanceInfo(path, ent.name, arch.name, Generics(values), loc, [])
        arch_scope = Scope(scope)
        for u in arch.uses:
            self.ctx.apply_use(arch_scope, u)
        ev = Evaluator(arch_scope, allow_quantities=False)
        children: list[InstanceInfo] = []
        for d in arch.decls:
            if isinstance(d, ast.NAME_DECLARATIONS):
                declare_all(arch_scope, [d], ev)
            elif isinstance(d, ast.ConfigSpec):
                bind(arch_scope, d)
            elif isinstance(d, ast.SignalDecl):
                arch_scope.names.setdefault(d.name, new_signal(d.name, d.type_mark, d.width, "signal", d.loc))
            elif isinstance(d, (ast.FreeQuantityDecl, ast.BranchQuantityDecl)):
                for name in (getattr(d, "name", None), getattr(d, "across", None), getattr(d, "through", None)):
                    if name:  # known here only so that a non-static use is reported as such
                        arch_scope.names.setdefault(name, Quantity(name, sy.Node(name), "free", None, d.loc))
        for p in ent.ports:
            if isinstance(p, ast.QuantityPort):
                arch_scope.names.setdefault(p.name, Quantity(p.name, sy.Node(p.name), p.mode, None, p.loc))
        labels: dict[str, object] = {}
        work: list[tuple[object, Evaluator]] = [(st, ev) for st in list(ent.stmts) + list(arch.stmts)]
        while work:
            st, ev = work.pop(0)
            if isinstance(st, ast.CaseGenerate):
                st = chosen(ev, st)
            if isinstance(st, ast.Generate):  # its copies' instances and assertions (with the parameter's value)
                copies: list[tuple[object, Evaluator]] = []
                for prefix, inner, sub in generated(ev, ev.scope, st):
                    declare_all(inner, [d for d in st.decls if isinstance(d, ast.ConstantDecl)], sub)
                    copies += [(s, sub) for s in labelled(st.stmts, prefix)]
                work[:0] = copies
                continue
            if isinstance(st, ast.Instance):
                if st.label.lower() in labels:
                    raise SourceError(
                        st.loc,
                        f"label '{st.label}' is already used in this architecture (at "
                        f"{labels[st.label.lower()]}): instance labels must be unique",
                    )
                labels[st.label.lower()] = st.loc
            if isinstance(st, ast.Assertion):
                c, t = ev.eval(st.cond)
                if t != "boolean" or not isinstance(c, sy.Const):
                    raise SourceError(
                        st.loc, "an assertion condition must be a static boolean (generics and constants only)"
                    )
                if not c.value and st.severity in ("error", "failure"):
                    shown = ", ".join(f"{k} = {_fmt_value(v)}" for k, v in values.items())
                    named = {n.ident for n in _names(st.cond)}
                    sources = [
                        f"{self.origins[(ent.name, g)]}: [{ent.name}] {g} = {_fmt_value(values[g])}"
                        for g in values
                        if g in named and g not in actuals and (ent.name, g) in self.origins
                    ]
                    where = f"; set by the parameter set at {'; '.join(sources)}" if sources else ""
                    raise SourceError(st.loc, f"{st.report} (instance {path}: {shown}){where}")
            elif isinstance(st, ast.Instance):
                cent, carch = self.resolve_instance(st, arch_scope)
                cact = self.static_actuals(st, cent, ev)
                children.append(self.static_instance(cent, carch, f"{path}.{st.label}", cact, st.loc))
        return InstanceInfo(path, ent.name, arch.name, Generics(values), loc, children)

    def static_actuals(self, st: ast.Instance, cent: ast.Entity, ev: Evaluator) -> dict[str, S]:
        out: dict[str, S] = {}
        for name, actual in self.associate(st.generic_map, [g.name for g in cent.generics], st, "generic"):
            if actual is None:
                continue
            s, _ = ev.eval(actual)
            if not _static(s):
                raise SourceError(actual.loc, f"generic '{name}' must be static")
            out[name] = s
        return out

    # -------------------------------------------------------------- instances
    def resolve_instance(
        self, st: ast.Instance, scope: Scope
    ) -> tuple[ast.Entity, ast.Architecture | ast.DigitalArchitecture]:
        if st.kind == "component":
            comp = scope.lookup(st.unit)
            binding = scope.lookup(f"{st.label}'binding") or scope.lookup(f"{st.unit}'binding")
            if isinstance(binding, ast.ConfigSpec) and binding.component == st.unit:  # for ... use entity e(a)
                ent = self.lib.entity(binding.entity, binding.loc)
                if isinstance(comp, ast.ComponentDecl):
                    self.check_component(comp, ent)
                return ent, self.lib.architecture(ent.name, binding.arch, binding.loc)
            if not isinstance(comp, ast.ComponentDecl) and st.unit not in self.lib.entities:
                raise SourceError(st.loc, f"unknown component '{st.unit}'")
            ent = self.lib.entity(st.unit, st.loc)
            if isinstance(comp, ast.ComponentDecl):
                self.check_component(comp, ent)
        else:
            ent = self.lib.entity(st.unit, st.loc)
        return ent, self.lib.architecture(ent.name, st.arch, st.loc)

    @staticmethod
    def check_component(comp: ast.ComponentDecl, ent: ast.Entity) -> None:
        eports = {p.name: p for p in ent.ports}
        for p in comp.ports:
            ep = eports.get(p.name)
            if ep is None or type(ep) is not type(p) or getattr(ep, "nature", None) != getattr(p, "nature", None):
                raise SourceError(p.loc, f"component port '{p.name}' does not match entity {ent.name} ({ent.loc})")

    @staticmethod
    def associate(assocs: list[ast.Assoc], formals: list[str], st: ast.Instance, what: str):
        out: list[tuple[str, ast.Expr | None]] = []
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


def _names(e) -> list[ast.Name]:
    """Every simple name an expression mentions."""
    if isinstance(e, ast.Name):
        return [e]
    if isinstance(e, ast.Unary):
        return _names(e.operand)
    if isinstance(e, ast.Binary):
        return _names(e.left) + _names(e.right)
    if isinstance(e, ast.Call):
        return [ast.Name(e.name, e.loc)] + [n for a in e.args if a.actual is not None for n in _names(a.actual)]
    if isinstance(e, ast.Attr):
        return [ast.Name(e.prefix, e.loc)] + [n for a in e.args for n in _names(a)]
    if isinstance(e, ast.Aggregate):
        return [n for x in e.items for n in _names(x)]
    return []


def _static(s: S) -> bool:
    """A value known at elaboration: a number, a string, or a vector of numbers."""
    return isinstance(s, (sy.Const, sy.Text)) or (
        isinstance(s, sy.Vec) and all(isinstance(x, sy.Const) for x in s.items)
    )


def _static_value(s: S) -> float | list[float] | str:
    """A generic's concrete value: a number, the numbers of a real_vector, or a string."""
    if isinstance(s, sy.Vec):
        return [sy.value(x) for x in s.items]
    if isinstance(s, sy.Text):
        return s.value
    return sy.value(s)


def _fmt_value(v) -> str:
    if isinstance(v, str):
        return repr(v)
    if isinstance(v, list):
        return "(" + ", ".join(f"{x:g}" for x in v) + ")"
    return f"{v:g}"


def check_param_set(lib: Library, params) -> None:
    """Every section of a parameter set must name an entity and every key one of its generics (also for a key that
    has only a tolerance)."""
    for entity, keys in [*params.sections.items(), *params.tolerances.items()]:
        if entity not in lib.entities:
            where = next((f"{p.file}:{p.line}" for p in keys.values()), str(params.path))
            raise WrsimError(
                f"{where}: [{entity}] names no entity of the library (entities: {', '.join(sorted(lib.entities))})"
            )
        for key, p in keys.items():
            generics = [g.name for g in lib.entities[entity].generics]
            if key not in generics:
                raise WrsimError(
                    f"{p.file}:{p.line}: [{entity}] {key}: {entity} has no generic '{key}' "
                    f"(it has: {', '.join(generics)})"
                )
