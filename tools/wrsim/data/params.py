"""Parameter sets: generic values for the VHDL-AMS models, kept apart from the model sources.

A parameter set is a text file under `params/` (its name is the file stem)::

    # comment lines and trailing comments start with '#'
    [dcpm_motor]                          # a section names a VHDL entity
    ke = 0.0204 V*s/rad  # where the value comes from
    laa = 0.09e-3 H
    [rubber_damper]
    angles = [0.0, 0.0349, 0.0698] rad    # a list sets a real_vector generic

Each `key = value unit` line sets generic `key` of the entity named by the section. The value
REPLACES the generic's default (the `:= ...` in the entity declaration) for every instance of that
entity in the design, except where an instance's VHDL `generic map` sets that generic explicitly:
the VHDL generic map wins. The unit is mandatory and written in pint syntax (`V*s/rad`, `N*m`,
`kg*m**2`, `N*m*s/rad`, `Ohm`, `H`, `1` for dimensionless); the elaborator converts the value to
the unit the generic declares, so `ke = 2.04e-2 V*s/rad` and `ke = 0.0204 V/(rad/s)` are the same.
Entity, generic and key names are VHDL identifiers, compared case-insensitively (stored in lower
case). Whether an entity and generic exist is checked by the elaborator, not here.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from wrsim import paths
from wrsim.data.atomic import write_text_atomic
from wrsim.data.units import check_unit, convert
from wrsim.errors import WrsimError

__all__ = ["Param", "ParamSet", "load_params", "find_param_set", "save_params"]

_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_SECTION = re.compile(r"\[\s*(.*?)\s*\]\Z")
_ALIGN_MAX = 60  # save_params aligns trailing comments of lines up to this length

Value = float | list[float]


@dataclass(frozen=True)
class Param:
    """One `key = value unit` line: the value in its written unit and where it was written."""

    value: Value
    unit: str
    file: str
    line: int


@dataclass
class ParamSet:
    """A loaded parameter set: sections[entity][generic] -> Param."""

    name: str
    path: Path
    sections: dict[str, dict[str, Param]] = field(default_factory=dict)
    user: ParamSet | None = None   # the set the user laid over last (`--params`); it stays on top (`beneath`)

    def overlay(self, other: ParamSet, user: bool = False) -> ParamSet:
        """This set with every key of `other` replacing or adding to it (e.g. a temperature or identified
        motor set applied to a bench's own system set). `user`: `other` is the user's set, kept on top of any
        set laid `beneath` it later."""
        sections = {entity: dict(keys) for entity, keys in self.sections.items()}
        for entity, keys in other.sections.items():
            sections.setdefault(entity, {}).update(keys)
        return ParamSet(f"{self.name}+{other.name}", other.path, sections, other if user else self.user)

    def beneath(self, other: ParamSet) -> ParamSet:
        """`other` laid over this set but beneath the user's set (a bench run's own settings, e.g. the
        anti-pinch algorithm under test, which the user's `--params` still overrides)."""
        merged = ParamSet(self.name, self.path, self.sections).overlay(other)
        return merged.overlay(self.user, user=True) if self.user is not None else merged

    def number_in(self, entity: str, generic: str, unit: str) -> float:
        """The value of the scalar `[entity] generic` converted to `unit`."""
        value = self.value_in(entity, generic, unit)
        if isinstance(value, list):
            p = self.sections[entity.lower()][generic.lower()]
            raise WrsimError(f"{p.file}:{p.line}: [{entity}] {generic}: expected one value, got a list")
        return value

    def vector_in(self, entity: str, generic: str, unit: str) -> list[float]:
        """The values of the list `[entity] generic` converted to `unit`."""
        value = self.value_in(entity, generic, unit)
        if not isinstance(value, list):
            p = self.sections[entity.lower()][generic.lower()]
            raise WrsimError(f"{p.file}:{p.line}: [{entity}] {generic}: expected a list [a, b, ...]")
        return value

    def value_in(self, entity: str, generic: str, unit: str) -> Value:
        """The value of `[entity] generic` converted to `unit` (a float, or a list for lists)."""
        section = self.sections.get(entity.lower())
        if section is None:
            raise WrsimError(
                f"{self.path}: no section [{entity}]; sections: {', '.join(self.sections) or 'none'}"
            )
        param = section.get(generic.lower())
        if param is None:
            raise WrsimError(
                f"{self.path}: [{entity}] has no key '{generic}'; keys: {', '.join(section)}"
            )
        try:
            values = [convert(v, param.unit, unit) for v in
                      (param.value if isinstance(param.value, list) else [param.value])]
        except WrsimError as exc:
            raise WrsimError(f"{param.file}:{param.line}: [{entity}] {generic}: {exc}") from exc
        if not all(math.isfinite(v) for v in values):
            raise WrsimError(f"{param.file}:{param.line}: [{entity}] {generic}: {param.value} {param.unit} is not a "
                             f"finite number in {unit}")
        return values if isinstance(param.value, list) else values[0]


def _number(text: str, where: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise WrsimError(f"{where}: '{text}' is not a number") from None
    if not math.isfinite(value):
        raise WrsimError(f"{where}: '{text}' is not a finite number")
    return value


def _parse_value(rest: str, where: str) -> tuple[Value, str]:
    """Split `value unit` into the value and the unit string."""
    if rest.startswith("["):
        close = rest.find("]")
        if close < 0:
            raise WrsimError(f"{where}: list value without closing ']'")
        items = [item.strip() for item in rest[1:close].split(",")]
        if items == [""]:
            raise WrsimError(f"{where}: empty list")
        return [_number(item, where) for item in items], rest[close + 1:].strip()
    parts = rest.split(None, 1)
    if not parts:
        raise WrsimError(f"{where}: missing value after '='")
    return _number(parts[0], where), parts[1].strip() if len(parts) > 1 else ""


def load_params(path: str | Path) -> ParamSet:
    """Read a parameter-set file; errors name file:line and the key."""
    path = Path(path)
    try:
        lines = path.read_text(encoding="utf-8-sig").splitlines()
    except OSError as exc:
        raise WrsimError(f"{path}: cannot read: {exc.strerror or exc}") from exc
    except UnicodeDecodeError as exc:
        raise WrsimError(f"{path}: not a UTF-8 text file ({exc.reason})") from exc

    pset = ParamSet(path.stem, path)
    section_lines: dict[str, int] = {}
    current: str | None = None
    for lineno, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        header = _SECTION.match(text)
        if header:
            name = header.group(1)
            if not _IDENT.match(name):
                raise WrsimError(f"{path}:{lineno}: section [{name}] is not a VHDL entity name")
            current = name.lower()
            if current in section_lines:
                raise WrsimError(f"{path}:{lineno}: duplicate section [{name}] "
                                 f"(first on line {section_lines[current]})")
            section_lines[current] = lineno
            pset.sections[current] = {}
            continue
        key, eq, rest = text.partition("=")
        key = key.strip()
        if not eq:
            raise WrsimError(f"{path}:{lineno}: '{text}': missing '=' (write key = value unit)")
        if not _IDENT.match(key):
            raise WrsimError(f"{path}:{lineno}: '{key}' is not a VHDL generic name")
        if current is None:
            raise WrsimError(f"{path}:{lineno}: key '{key}' comes before any [entity] section")
        where = f"{path}:{lineno}: [{current}] {key}"
        value, unit = _parse_value(rest.strip(), where)
        if not unit:
            raise WrsimError(f"{where}: missing unit after the value (write 1 for dimensionless)")
        try:
            check_unit(unit)
        except WrsimError as exc:
            raise WrsimError(f"{where}: {exc}") from exc
        section = pset.sections[current]
        if key.lower() in section:
            raise WrsimError(f"{where}: duplicate key (first set on line {section[key.lower()].line})")
        section[key.lower()] = Param(value, unit, str(path), lineno)
    return pset


def find_param_set(name_or_path: str | Path, root: str | Path = paths.ROOT) -> Path:
    """Resolve a parameter-set name (file stem under `root`/params) or an existing file path."""
    candidate = Path(name_or_path)
    if candidate.suffix or len(candidate.parts) > 1:
        if not candidate.is_file():
            raise WrsimError(f"{candidate}: parameter-set file not found")
        return candidate
    params_dir = Path(root) / "params"
    path = params_dir / f"{name_or_path}.txt"
    if not path.is_file():
        available = sorted(p.stem for p in params_dir.glob("*.txt"))
        raise WrsimError(f"unknown parameter set '{name_or_path}'; available in {params_dir}: "
                         f"{', '.join(available) or 'none'}")
    return path


def _format_value(value: Value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(repr(float(v)) for v in value) + "]"
    return repr(float(value))


def save_params(path: str | Path, header_comments: list[str],
                sections: dict[str, list[tuple[str, Value, str, str]]]) -> None:
    """Write a parameter set atomically: header comments, then per entity section the lines
    `key = value unit  # comment` (comments aligned; an empty comment is left out)."""
    path = Path(path)
    out = [f"# {line}".rstrip() for comment in header_comments
           for line in (comment.splitlines() or [""])]
    for entity, entries in sections.items():
        if not _IDENT.match(entity):
            raise WrsimError(f"{path}: section [{entity}] is not a VHDL entity name")
        rows = []
        for key, value, unit, comment in entries:
            if not _IDENT.match(key):
                raise WrsimError(f"{path}: [{entity}] '{key}' is not a VHDL generic name")
            try:
                check_unit(unit)
            except WrsimError as exc:
                raise WrsimError(f"{path}: [{entity}] {key}: {exc}") from exc
            values = value if isinstance(value, list) else [value]
            if not all(isinstance(v, (int, float)) and math.isfinite(v) for v in values):
                raise WrsimError(f"{path}: [{entity}] {key} = {value}: not a finite number; nothing written")
            rows.append((f"{key} = {_format_value(value)} {unit}", comment))
        width = max((len(text) for text, _ in rows if len(text) <= _ALIGN_MAX), default=0)
        out += ["", f"[{entity}]"]
        out += [f"{text:<{width}}  # {comment}" if comment else text for text, comment in rows]
    write_text_atomic(path, "\n".join(out) + "\n")
