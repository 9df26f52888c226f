"""The design library: every design unit of the analysed VHDL-AMS files, by library, and the order in which
GHDL must analyse the digital files a unit needs."""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from wrsim.errors import Loc, SourceError, WrsimError
from wrsim.frontend import ast
from wrsim.frontend.parser import parse_file

__all__ = ["Library", "load_library", "missing_units", "SUFFIXES"]


@dataclass
class Library:
    """Every design unit of the analysed files, by library."""

    files: list[ast.DesignFile] = field(default_factory=list)
    packages: dict[tuple[str, str], ast.Package] = field(default_factory=dict)
    bodies: dict[tuple[str, str], ast.PackageBody] = field(default_factory=dict)
    entities: dict[str, ast.Entity] = field(default_factory=dict)
    archs: dict[str, list[ast.Architecture | ast.DigitalArchitecture]] = field(default_factory=dict)
    broken: dict[str, str] = field(default_factory=dict)  # file -> why it did not parse (tolerant loading)
    aliases: dict[str, str] = field(default_factory=lambda: {"ieee_proposed": "ieee"})  # library -> the one it is

    def package(self, library: str, name: str) -> tuple[str, str] | None:
        """The key of package `library.name` (through `aliases`: IEEE_PROPOSED, the name the 1076.1.1 packages had
        before IEEE published them, is IEEE), None when no file provides it."""
        for lib in (library, self.aliases.get(library)):
            if lib is not None and (lib, name) in self.packages:
                return lib, name
        return None

    def not_loaded(self) -> str:
        """What tolerant loading set aside, for an error about a missing unit ("" when nothing was)."""
        return "".join(f"; not loaded: {e}" for e in self.broken.values())

    def digital_files(self, tops: list[str]) -> list[Path]:
        """The digital files the units `tops` need, each after the files it uses (`work.<unit>` references),
        in the order GHDL must analyse them. A package of constants only (wr_digital_params) is not a digital
        file to the parser, but GHDL needs it all the same."""
        provider = {
            u.name: f
            for f in self.files
            if f.library == "work"
            for u in f.units
            if isinstance(u, ast.Package) or (f.digital and isinstance(u, ast.Entity))
        }
        order: list[ast.DesignFile] = []

        def visit(f: ast.DesignFile, stack: tuple[str, ...]) -> None:
            if f in order:
                return
            if f.path in stack:
                raise WrsimError(f"{f.path}: circular work.* references between digital files ({' -> '.join(stack)})")
            for name in work_references(f.path):
                if name in provider and provider[name] is not f:
                    visit(provider[name], stack + (f.path,))
            order.append(f)

        for top in tops:
            visit(provider[top], ())
        return [Path(f.path) for f in order]

    def add(self, df: ast.DesignFile) -> None:
        self.files.append(df)
        for u in df.units:
            if isinstance(u, ast.Package):
                self._unique(self.packages, (df.library, u.name), u, "package")
            elif isinstance(u, ast.PackageBody):
                self._unique(self.bodies, (df.library, u.name), u, "package body")
            elif isinstance(u, ast.Entity):
                self._unique(self.entities, u.name, u, "entity")
            else:
                for other in self.archs.get(u.entity, []):
                    if other.name == u.name:
                        raise SourceError(
                            u.loc, f"architecture {u.name} of {u.entity} is already defined at {other.loc}"
                        )
                self.archs.setdefault(u.entity, []).append(u)

    def replace(self, df: ast.DesignFile) -> None:
        """Add `df`, its units replacing those of the same name, as analysing a unit again does in VHDL: a package
        drops the old one and its body, an entity the old one and its architectures."""
        for u in df.units:
            if isinstance(u, (ast.Package, ast.PackageBody)):
                for table in (self.packages, self.bodies):
                    table.pop((df.library, u.name), None)
            elif isinstance(u, ast.Entity):
                self.entities.pop(u.name, None)
                self.archs.pop(u.name, None)
            else:
                self.archs[u.entity] = [a for a in self.archs.get(u.entity, []) if a.name != u.name]
        current = {id(u) for t in (self.packages, self.bodies, self.entities) for u in t.values()}
        current |= {id(a) for archs in self.archs.values() for a in archs}
        for f in self.files:
            f.units[:] = [u for u in f.units if id(u) in current]
        self.add(df)

    @staticmethod
    def _unique(table: dict, key, unit, what: str) -> None:
        if key in table:
            raise SourceError(unit.loc, f"{what} {unit.name} is already defined at {table[key].loc}")
        table[key] = unit

    def entity(self, name: str, loc: Loc | None = None) -> ast.Entity:
        if name not in self.entities:
            known = ", ".join(sorted(self.entities)) or "none"
            msg = f"unknown entity '{name}' (known entities: {known}){self.not_loaded()}"
            raise SourceError(loc, msg) if loc else WrsimError(msg)
        return self.entities[name]

    def architecture(
        self, entity: str, name: str | None, loc: Loc | None
    ) -> ast.Architecture | ast.DigitalArchitecture:
        archs = self.archs.get(entity, [])
        if not archs:
            msg = f"entity '{entity}' has no architecture"
            raise SourceError(loc, msg) if loc else WrsimError(msg)
        if name is None:
            return archs[-1]  # the most recently analysed one, as in VHDL
        for a in archs:
            if a.name == name:
                return a
        msg = f"entity '{entity}' has no architecture '{name}' (it has: {', '.join(a.name for a in archs)})"
        raise SourceError(loc, msg) if loc else WrsimError(msg)


SUFFIXES = (".vhd", ".vhdl", ".ams", ".vha")  # what a folder's VHDL-AMS files end in


def load_library(
    paths: Sequence[str | Path],
    libraries: Mapping[str, Sequence[str | Path]] | None = None,
    tolerant: bool = False,
    over: Sequence[str | Path] = (),
) -> Library:
    """Parse every VHDL-AMS file (SUFFIXES) under `paths` into library WORK, except files in a folder named
    `ieee`, which go to library IEEE; `libraries` maps further library names to files or folders (e.g. a vendor
    library). `over`: files or folders parsed last into WORK, whose units replace those of the same name (e.g. a
    parameter package from `wrsim export`, or a user's version of a model). `tolerant`: a file that does not
    parse is set aside in `Library.broken` (its error) instead of stopping the load; a unit it would have provided
    is then reported missing, with that error."""
    lib = Library()
    replacing = Library()  # the `over` files among themselves: a unit twice there is still an error
    for name, where, target in [
        ("work", paths, lib),
        *((n, w, lib) for n, w in (libraries or {}).items()),
        ("work", over, replacing),
    ]:
        for f in _files(where):
            library = "ieee" if name == "work" and f.parent.name.lower() == "ieee" else name.lower()
            try:
                target.add(parse_file(f, library))
            except WrsimError as e:
                if not tolerant:
                    raise
                lib.broken[str(f)] = str(e)
    for df in replacing.files:
        lib.replace(df)
    return lib


def _files(paths: Sequence[str | Path]) -> list[Path]:
    files: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            files.extend(sorted(q for q in p.rglob("*") if q.suffix.lower() in SUFFIXES))
        elif p.is_file():
            files.append(p)
        else:
            raise WrsimError(f"{p}: no such VHDL-AMS file or folder")
    return files


def work_references(path: str) -> set[str]:
    """Units a digital file names as work.<unit> (use clauses, entity instantiations) or declares as a component
    (bound by default to the entity of its name)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as e:
        raise WrsimError(f"{path}: cannot read the digital file again (changed since it was loaded?): {e}") from None
    text = re.sub(r"--[^\n]*", "", text)
    return {(a or b).lower() for a, b in re.findall(r"\bwork\.(\w+)|\bcomponent\s+(\w+)", text, re.I)}


def missing_units(lib: Library) -> list[str]:
    """Every generic, quantity port and free quantity of the library that carries no unit (file:line:col)."""
    out = []
    subtypes_with_units = {
        d.name
        for f in lib.files
        for u in f.units
        if isinstance(u, ast.Package)
        for d in u.decls
        if isinstance(d, ast.SubtypeDecl) and d.unit
    }
    for f in lib.files:
        for u in f.units:
            items = []
            if isinstance(u, ast.Entity):
                items = [(g.name, g.unit, g.type_mark, g.loc) for g in u.generics]
                items += [(p.name, p.unit, p.type_mark, p.loc) for p in u.ports if isinstance(p, ast.QuantityPort)]
            elif isinstance(u, ast.Architecture):
                items = [(d.name, d.unit, d.type_mark, d.loc) for d in u.decls if isinstance(d, ast.FreeQuantityDecl)]
            for name, unit, type_mark, loc in items:
                if not unit and type_mark not in subtypes_with_units and type_mark != "boolean":
                    out.append(f"{loc}: '{name}' has no unit (use a unit subtype or a trailing `-- [unit]` comment)")
    return out
