"""What `use` clauses make visible: package scopes (built once) and the declarations of packages and
architectures."""

from __future__ import annotations

import math

from wrsim.elab import symbolic as sy
from wrsim.elab.evaluate import Evaluator
from wrsim.elab.evaluator_base import MAX_ITERATIONS
from wrsim.elab.library import Library
from wrsim.elab.scope import (
    BASE_TYPES,
    GROUND,
    ArrayNature,
    Function,
    Nature,
    Scope,
    Subtype,
    Terminal,
    Value,
    base_type,
)
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast

__all__ = ["Context", "declare_all", "nature_of", "reference_terminal", "index_values"]

_MATH_CONSTANTS = {
    "math_pi": math.pi,
    "math_2_pi": 2 * math.pi,
    "math_pi_over_2": math.pi / 2,
    "math_pi_over_4": math.pi / 4,
    "math_e": math.e,
    "math_1_over_pi": 1 / math.pi,
    "math_sqrt_2": math.sqrt(2),
    "math_deg_to_rad": math.pi / 180,
    "math_rad_to_deg": 180 / math.pi,
}


# ================================================================================================
# Package and unit scopes
class Context:
    """Builds the scopes that `use` clauses make visible; package scopes are built once."""

    def __init__(self, lib: Library):
        self.lib = lib
        self.pkg_scopes: dict[tuple[str, str], Scope] = {}
        self.root = Scope()
        for name in ("real", "integer", "natural", "positive", "boolean", "real_vector", "string", "time"):
            self.root.names[name] = Subtype(BASE_TYPES[name], None)

    def unit_scope(self, uses: list[ast.UseClause]) -> Scope:
        scope = Scope(self.root)
        for u in uses:
            self.apply_use(scope, u)
        return scope

    def apply_use(self, scope: Scope, u: ast.UseClause) -> None:
        library = self.lib.aliases.get(u.library, u.library)
        if library == "ieee" and u.package == "math_real":
            items: dict[str, object] = {k: Value(sy.const(v), "real", "constant") for k, v in _MATH_CONSTANTS.items()}
        elif library in ("std", "ieee") and u.package in ("standard", "std_logic_1164", "numeric_std", "textio", "env"):
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
        found = self.lib.package(lib, name)
        if found is None:
            known = ", ".join(f"{l}.{n}" for l, n in sorted(self.lib.packages)) or "none"
            raise SourceError(
                loc, f"unknown package {lib}.{name} (known: {known}, and ieee.math_real){self.lib.not_loaded()}"
            )
        key = found
        if key in self.pkg_scopes:
            return self.pkg_scopes[key]
        pkg = self.lib.packages[key]
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
                if isinstance(d, ast.ConstantDecl) and isinstance(own.names.get(d.name), ast.ConstantDecl):
                    declare_all(body_scope, [d], Evaluator(body_scope, allow_quantities=False))
                    own.names[d.name] = body_scope.names.pop(d.name)  # the value of a deferred constant
                elif isinstance(d, ast.FunctionDecl):
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
        if isinstance(d, ast.ConstantDecl):
            t = base_type(d.type_mark, scope, d.loc)
            if d.value is None:  # deferred: the package body gives the value
                scope.declare(d.name, d, d.loc)
                continue
            s, vt = ev.eval(d.value, scope)
            if vt != t and not (t == "real_vector" and vt == "real_vector"):
                raise SourceError(d.loc, f"type mismatch: constant '{d.name}' is {t}, value is {vt}")
            indices = array_indices(ev, d.bounds, d.type_mark, scope, s, f"constant '{d.name}'", d.loc)
            scope.declare(d.name, Value(s, t, "constant", d.loc, indices), d.loc)
        elif isinstance(d, ast.SubtypeDecl):
            indices = tuple(index_values(ev, d.bounds, scope)) if d.bounds is not None else None
            scope.declare(d.name, Subtype(BASE_TYPES.get(d.base, d.base), d.unit, indices), d.loc)
        elif isinstance(d, ast.ArrayNatureDecl):
            scope.declare(d.name, ArrayNature(nature_of(scope, d.element, d.loc).decl.name, d.loc), d.loc)
        elif isinstance(d, ast.NatureDecl):
            ua = scope.lookup(d.across)
            ut = scope.lookup(d.through)
            scope.declare(d.name, Nature(d, (getattr(ua, "unit", None), getattr(ut, "unit", None))), d.loc)
            scope.declare(d.reference, Terminal(GROUND, d.name, d.loc), d.loc)
        elif isinstance(d, ast.SubnatureDecl):
            base = scope.lookup(d.base)
            if not isinstance(base, Nature):
                raise SourceError(d.loc, f"'{d.base}' is not a nature")
            scope.declare(d.name, base, d.loc)
        elif isinstance(d, ast.FunctionDecl):
            existing = scope.names.get(d.name)
            if isinstance(existing, Function) and d.body is not None and existing.decl.body is None:
                existing.decl, existing.scope = d, scope
            else:
                scope.declare(d.name, Function(d, scope), d.loc)
        elif isinstance(d, ast.ComponentDecl):
            scope.declare(d.name, d, d.loc)
        elif isinstance(d, ast.AttributeSpec):  # n'attr reads the value (static)
            value, t = ev.eval(d.value, scope)
            for name in d.names:
                scope.names[f"{name}'{d.attr}"] = Value(value, t, "constant", d.loc)
        elif isinstance(d, ast.AliasDecl):  # another name for the same nature, terminal, quantity, constant ...
            target = (
                reference_terminal(scope, d.target, d.loc)
                if d.target.endswith("'reference")
                else scope.lookup(d.target)
            )
            if target is None:
                raise SourceError(d.loc, f"alias {d.name}: unknown name '{d.target}'")
            scope.declare(d.name, target, d.loc)
        else:
            raise SourceError(d.loc, "this declaration is not allowed in a package")


def array_indices(
    ev: Evaluator, bounds: ast.Bounds | None, type_mark: str, scope: Scope, value: S | None, what: str, loc: Loc
) -> tuple[int, ...] | None:
    """The index values of a real_vector constant or generic from its index constraint or its constrained subtype
    (None: unconstrained, 0 up); one error when `value` has another number of elements."""
    subtype = scope.lookup(type_mark)
    indices = (
        tuple(index_values(ev, bounds, scope))
        if bounds is not None
        else subtype.indices
        if isinstance(subtype, Subtype)
        else None
    )
    if indices is not None and isinstance(value, sy.Vec) and len(value.items) != len(indices):
        raise SourceError(loc, f"{what} has {len(indices)} elements (its index range), its value {len(value.items)}")
    return indices


def index_values(ev: Evaluator, bounds: ast.Bounds, scope: Scope) -> list[int]:
    """The index values of `(a to b)` / `(a downto b)`, left to right (static integers)."""
    ends = []
    for e in (bounds.left, bounds.right):
        s, t = ev.eval(e, scope)
        if t != "integer" or not isinstance(s, sy.Const):
            raise SourceError(e.loc, "an index bound must be a static integer")
        ends.append(int(s.value))
    a, b = ends
    if abs(b - a) >= MAX_ITERATIONS:
        raise SourceError(bounds.left.loc, f"an index range of {abs(b - a) + 1} elements: at most {MAX_ITERATIONS}")
    return list(range(a, b - 1, -1)) if bounds.downto else list(range(a, b + 1))


def reference_terminal(scope: Scope, name: str, loc: Loc) -> Terminal:
    """N'reference: the reference terminal of nature N."""
    return Terminal(GROUND, nature_of(scope, name.split("'")[0], loc).decl.name, loc)


def nature_of(scope: Scope, name: str, loc: Loc) -> Nature:
    n = scope.lookup(name)
    if not isinstance(n, Nature):
        raise SourceError(loc, f"unknown nature '{name}'")
    return n


# ================================================================================================
