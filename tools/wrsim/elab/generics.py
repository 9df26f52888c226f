"""Top-level generic values as users write them (`--set`, `wrsim study --set`, scenario files): a number with or
without a unit (`u_nominal=9V`, `pinch_position=320 mm`; without a unit the generic's own), an integer, a boolean
(`true`/`false`), a string (`sequence_file=my/seq.txt`). Each is checked against the generic's declared type and
converted to the unit of its subtype (IEEE 1076.1.1: `voltage` is in V, `displacement` in m); a string that names a
file relative to the directory the command was started in becomes that file's absolute path, since the simulator
runs elsewhere. A file a string generic names (a switch sequence the design reads with textio) is checked first:
a regular UTF-8 text file within the input limits (wrsim.data.atomic)."""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from pathlib import Path

from wrsim.data.atomic import check_lines
from wrsim.data.units import convert, parse_number
from wrsim.elab.context import Context
from wrsim.elab.library import Library
from wrsim.elab.scope import base_type
from wrsim.errors import WrsimError

__all__ = ["GenericValue", "top_generics", "number"]

GenericValue = float | str | bool
_NUMBER = re.compile(r"\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*?)\s*\Z")
_BOOLEANS = {"true": True, "false": False}


def top_generics(
    lib: Library, top: str, given: Mapping[str, GenericValue], where: str = "--set", cwd: Path | None = None
) -> dict[str, float | str]:
    """The values `given` (generic name -> text or value) for the top-level generics of entity `top`, checked and
    converted as the module says, plus every string generic left at a default that names a file relative to
    `cwd` (default: the working directory) as that file's absolute path. Errors name `where` and the generic."""
    cwd = cwd or Path.cwd()
    ent = lib.entity(top)
    scope = Context(lib).unit_scope(ent.uses)
    declared = {g.name: g for g in ent.generics}
    out: dict[str, float | str] = {}
    for raw_name, value in given.items():
        name = raw_name.strip().lower()
        g = declared.get(name)
        if g is None:
            raise WrsimError(
                f"{where} {raw_name}: {top} has no generic '{raw_name}' (it has: {', '.join(declared) or 'none'})"
            )
        kind = base_type(g.type_mark, scope, g.loc)
        unit = g.unit or getattr(scope.lookup(g.type_mark), "unit", None) or "1"
        out[name] = _value(kind, unit, value, f"{where} {name}={value}", cwd)
    for g in ent.generics:
        if g.name not in out and base_type(g.type_mark, scope, g.loc) == "string" and g.default is not None:
            text = getattr(g.default, "value", None)
            path = cwd / str(text)
            if isinstance(text, str) and text and not Path(text).is_absolute() and path.exists() and not path.is_dir():
                out[g.name] = _named_file(path)
    return out


def _named_file(path: Path) -> str:
    """The absolute path of an existing file a string generic names, checked (see the module docstring)."""
    check_lines(path)
    return str(path.resolve())


def _value(kind: str, unit: str, value: GenericValue, where: str, cwd: Path) -> float | str:
    """One generic's value of type `kind` in `unit` (see the module docstring)."""
    if kind == "string":
        if not isinstance(value, str):
            raise WrsimError(f"{where}: the generic is a string; write it as text")
        path = cwd / value  # an absolute value stays itself
        if value and path.exists() and not path.is_dir():
            try:
                return _named_file(path)
            except WrsimError as e:
                raise WrsimError(f"{where}: {e}") from None
        return value
    if kind == "boolean":
        if isinstance(value, bool):
            return value
        if isinstance(value, str) and value.strip().lower() in _BOOLEANS:
            return _BOOLEANS[value.strip().lower()]
        raise WrsimError(f"{where}: the generic is a boolean: write true or false")
    if kind not in ("real", "integer"):
        raise WrsimError(f"{where}: a {kind} generic cannot be set here (set it in a parameter set or the VHDL)")
    if isinstance(value, bool):
        raise WrsimError(
            f"{where}: the generic is a number ({kind}{'' if unit == '1' else f' in {unit}'}), not a boolean"
        )
    if isinstance(value, str):
        m = _NUMBER.match(value)
        if m is None and value.strip().lower().lstrip("+-") in ("inf", "infinity", "nan"):
            raise WrsimError(f"{where}: '{value.strip()}' is not a finite number")
        if m is None:
            raise WrsimError(
                f"{where}: the generic is a number ({kind}{'' if unit == '1' else f' in {unit}'}): "
                f"write a number, with or without a unit (e.g. 9V, 320 mm)"
            )
        number = parse_number(m.group(1), where)
        if m.group(2):
            try:
                number = convert(number, m.group(2), unit)
            except WrsimError as e:
                raise WrsimError(f"{where}: {e}") from None
        value = number
    if not math.isfinite(value):
        raise WrsimError(f"{where}: not a finite number")
    if kind == "integer":
        if value != round(value):
            raise WrsimError(f"{where}: the generic is an integer")
        return float(round(value))
    return float(value)


def number(value: GenericValue, unit: str, where: str) -> float:
    """A real value written as a generic is (a number in `unit`, or a number with a unit), in `unit`."""
    out = _value("real", unit, value, where, Path.cwd())
    assert isinstance(out, float)
    return out
