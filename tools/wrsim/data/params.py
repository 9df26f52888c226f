"""Parameter sets: generic values for the VHDL-AMS models, kept apart from the model sources.

A parameter set is a text file under `params/` (its name is the file stem)::

    # comment lines and trailing comments start with '#'
    [dcpm_motor]                          # a section names a VHDL entity
    ke = 0.0204 V*s/rad  # where the value comes from
    laa = 0.09e-3 H
    [rubber_damper]
    angles = [0.0, 0.0349, 0.0698] rad    # a list sets a real_vector generic

Each `key = value unit` line sets generic `key` of the entity named by the section. The value REPLACES
the generic's default (the `:= ...` in the entity declaration; for the library's models the constant
`<entity>_<key>` of vhdl/common/wr_params.vhd or vhdl/digital/wr_digital_params.vhd, which `wrsim
export` writes with a set's values) for every instance of that entity in the design, except where an
instance's VHDL `generic map` sets that generic explicitly: the VHDL generic map wins. The unit is
mandatory and written in pint syntax (`V*s/rad`, `N*m`, `kg*m**2`, `N*m*s/rad`, `Ohm`, `H`, `1` for
dimensionless); the elaborator converts the value to the unit the generic declares, so `ke = 2.04e-2
V*s/rad` and `ke = 0.0204 V/(rad/s)` are the same. Entity, generic and key names are VHDL identifiers,
compared case-insensitively (stored in lower case). Whether an entity and generic exist is checked by
the elaborator, not here.

A set may build on others: `include FILE` lines before the first section lay the named sets (relative to the
including file's folder, `.txt` may be left out) beneath the file's own keys, in order::

    include ../rail_wr_8p5nm.txt          # the system set; the keys below replace or add to it
    [antipinch_gauge]
    stiffness = 65 N/mm

A cycle of includes, a chain of more than 32 files or a missing file is an error at the include line; a key given
twice in one file stays an error.

Tolerances (for `wrsim study`; every bench still uses the nominal value) follow the value, or stand alone on a
line without `=` to give the value of a set laid beneath a spread::

    ra = 0.55 Ohm +- 5 % normal 3sigma    # nominal 0.55 Ohm; +-5 % is three standard deviations (the default)
    mc +- 0.002 N*m uniform               # a spread only, in absolute units: the nominal comes from beneath
    kt +- 4 % group magnet                # one draw of the group `magnet` moves ke and kt together
    ke +- 4 % group magnet 0.9            # ... with correlation 0.9 to the group's common draw
    temperature = 20 degC in -30 .. 80 degC uniform   # a range given by its limits
    ra from motors.csv:ra group unit      # a row of a measured table (name[unit] CSV beside this file); the
                                          # same `group` picks the same row for every key that names it

The law is `normal [Ksigma]` (default: normal, the tolerance = 3 sigma) or `uniform`; a list value moves as a
whole (every element by the same relative or absolute deviation). A range followed by `calibrate` is no spread but
what `wrsim calibrate` may search (`threshold_rpm = 400 1 in 150 .. 600 1 calibrate`); studies leave it alone.
The section `[ambient]` holds `temperature`: not a generic but the temperature at which the set is used (default
20 degC); the runs apply the rules of `wrsim identify temperature` (identify.paramset) to the set for it.
"""

from __future__ import annotations

import dataclasses
import math
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

from wrsim import paths
from wrsim.data.atomic import read_text, write_text_atomic
from wrsim.data.units import check_unit, convert, parse_number
from wrsim.errors import WrsimError

__all__ = ["Param", "ParamSet", "Tolerance", "load_params", "find_param_set", "save_params"]

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


@dataclass(frozen=True)
class Tolerance:
    """The spread of one value: `law` normal (`deviation` = `sigmas` standard deviations), uniform (nominal +-
    deviation, or between `limits`), or table (one of `values`, a column of the table `source`). Deviations
    are fractions of the nominal value when `relative`, else in `unit`. `group`: keys with the same group share a
    common standard-normal draw, each with correlation `rho` to it."""

    law: str
    deviation: float = 0.0
    relative: bool = False
    unit: str = "1"
    sigmas: float = 3.0
    limits: tuple[float, float] | None = None
    values: tuple[float, ...] = ()  # law table: the column's rows, in `unit`
    source: str = ""  # law table: file:column
    group: str | None = None
    rho: float = 1.0
    file: str = ""
    line: int = 0


@dataclass
class ParamSet:
    """A loaded parameter set: sections[entity][generic] -> Param; tolerances[entity][generic] -> Tolerance."""

    name: str
    path: Path
    sections: dict[str, dict[str, Param]] = field(default_factory=dict)
    user: ParamSet | None = None  # the set the user laid over last (`--params`); it stays on top (`beneath`)
    tolerances: dict[str, dict[str, Tolerance]] = field(default_factory=dict)

    def overlay(self, other: ParamSet, user: bool = False) -> ParamSet:
        """This set with every key of `other` replacing or adding to it (e.g. a temperature or identified
        motor set applied to a bench's own system set). `user`: `other` is the user's set, kept on top of any
        set laid `beneath` it later."""
        sections, tolerances = _merged(self.sections, other.sections), _merged(self.tolerances, other.tolerances)
        return ParamSet(f"{self.name}+{other.name}", other.path, sections, other if user else self.user, tolerances)

    def beneath(self, other: ParamSet) -> ParamSet:
        """`other` laid over this set but beneath the user's set (a bench run's own settings, e.g. the
        anti-pinch algorithm under test, which the user's `--params` still overrides)."""
        merged = ParamSet(self.name, self.path, self.sections, tolerances=self.tolerances).overlay(other)
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
            raise WrsimError(f"{self.path}: no section [{entity}]; sections: {', '.join(self.sections) or 'none'}")
        param = section.get(generic.lower())
        if param is None:
            raise WrsimError(f"{self.path}: [{entity}] has no key '{generic}'; keys: {', '.join(section)}")
        try:
            values = [
                convert(v, param.unit, unit) for v in (param.value if isinstance(param.value, list) else [param.value])
            ]
        except WrsimError as exc:
            raise WrsimError(f"{param.file}:{param.line}: [{entity}] {generic}: {exc}") from exc
        if not all(math.isfinite(v) for v in values):
            raise WrsimError(
                f"{param.file}:{param.line}: [{entity}] {generic}: {param.value} {param.unit} is not a "
                f"finite number in {unit}"
            )
        return values if isinstance(param.value, list) else values[0]


def _merged(below: dict[str, dict], above: dict[str, dict]) -> dict[str, dict]:
    out = {entity: dict(keys) for entity, keys in below.items()}
    for entity, keys in above.items():
        out.setdefault(entity, {}).update(keys)
    return out


def _parse_value(rest: str, where: str) -> tuple[Value, str]:
    """Split `value unit` into the value and the unit string."""
    if rest.startswith("["):
        close = rest.find("]")
        if close < 0:
            raise WrsimError(f"{where}: list value without closing ']'")
        items = [item.strip() for item in rest[1:close].split(",")]
        if items == [""]:
            raise WrsimError(f"{where}: empty list")
        return [parse_number(item, where) for item in items], rest[close + 1 :].strip()
    parts = rest.split(None, 1)
    if not parts:
        raise WrsimError(f"{where}: missing value after '='")
    return parse_number(parts[0], where), parts[1].strip() if len(parts) > 1 else ""


_TOLERANCE = re.compile(r"(?:^|\s)(\+-|in(?=\s+\S+\s*\.\.)|from)(?=\s)")
_SIGMAS = re.compile(r"(.+)sigma\Z")
SIGMAS = (0.5, 10.0)  # the standard deviations a normal law's tolerance may stand for


def _split_tolerance(rest: str) -> tuple[str, str, str]:
    """`value unit`, the tolerance keyword (`+-`, `in`, `from`, or ""), and the text after it."""
    m = _TOLERANCE.search(rest)
    if m is None:
        return rest, "", ""
    return rest[: m.start()].strip(), m.group(1), rest[m.end() :].strip()


def _parse_tolerance(keyword: str, text: str, where: str, base: Path) -> Tolerance:
    """The tolerance after `keyword` (see the module docstring); errors name `where`."""
    words = text.split()
    kw: dict = {}
    if keyword == "+-":
        if len(words) < 2:
            raise WrsimError(f"{where}: write '+- N %' or '+- N <unit>' (e.g. +- 5 %, +- 0.03 Ohm)")
        dev = parse_number(words[0], where)
        if dev <= 0.0:
            raise WrsimError(f"{where}: the tolerance {words[0]} must be > 0")
        relative = words[1] == "%"
        unit = "1" if relative else words[1]
        kw.update(deviation=dev / 100.0 if relative else dev, relative=relative, unit=unit, law="normal")
        words = words[2:]
    elif keyword == "in":
        if len(words) < 4 or words[1] != "..":
            raise WrsimError(f"{where}: write 'in LOW .. HIGH <unit>' (e.g. in -30 .. 80 degC)")
        lo, hi, unit = parse_number(words[0], where), parse_number(words[2], where), words[3]
        if not lo < hi:
            raise WrsimError(f"{where}: in {words[0]} .. {words[2]}: the lower limit must be below the upper")
        kw.update(limits=(lo, hi), unit=unit, law="uniform")
        words = words[4:]
    else:
        source, _, column = words[0].rpartition(":") if words else ("", "", "")
        if not source or not column:
            raise WrsimError(f"{where}: write 'from FILE.csv:COLUMN' (a name[unit] table beside this file)")
        from wrsim.data.measurements import read_table

        try:
            table = read_table(base / source)
            values = table.column(column)
        except (WrsimError, ValueError) as exc:  # ValueError: a path the OS cannot take (a NUL byte)
            raise WrsimError(f"{where}: {exc}") from None
        kw.update(
            law="table", values=tuple(float(v) for v in values), unit=table.units[column], source=f"{source}:{column}"
        )
        words = words[1:]
    if kw["unit"] != "1":
        try:
            check_unit(kw["unit"])
        except WrsimError as exc:
            raise WrsimError(f"{where}: tolerance: {exc}") from exc
    laws: list[str] = []  # the law words given (normal, uniform): one
    while words:
        word = words.pop(0)
        sigmas = _SIGMAS.match(word)
        if word == "calibrate" and kw.get("limits"):
            kw["law"] = "calibrate"
        elif word in ("normal", "uniform") and kw["law"] != "table":
            if laws:
                raise WrsimError(f"{where}: '{word}' after '{laws[0]}': a tolerance has one law")
            laws.append(word)
            if word == "normal" and kw.get("limits"):
                raise WrsimError(f"{where}: a range 'in LOW .. HIGH' is uniform (give +- for a normal law)")
            kw["law"] = word
        elif sigmas and kw["law"] == "normal":
            kw["sigmas"] = parse_number(sigmas.group(1), where)
            if not SIGMAS[0] <= kw["sigmas"] <= SIGMAS[1]:
                raise WrsimError(
                    f"{where}: '{word}': the tolerance is {SIGMAS[0]:g} .. {SIGMAS[1]:g} standard deviations (a "
                    "tolerance of a smaller number of them spreads the value far beyond it)"
                )
        elif word == "group" and words and _IDENT.match(words[0]):
            kw["group"] = words.pop(0).lower()
            if words and words[0][:1] in "-.0123456789":
                kw["rho"] = parse_number(words.pop(0), where)
                if not -1.0 <= kw["rho"] <= 1.0:
                    raise WrsimError(f"{where}: group correlation {kw['rho']:g} is outside -1 .. 1")
        else:
            raise WrsimError(
                f"{where}: '{word}' is not part of a tolerance (after the spread: normal [Ksigma], "
                f"uniform, group NAME [correlation]; after a range: calibrate)"
            )
    return Tolerance(**kw)


def _check_nominal(tol: Tolerance, value: Value, unit: str, where: str) -> None:
    """A tolerance fits the value it spreads: convertible units, a range around a scalar nominal value."""
    if tol.relative:
        return
    try:
        convert(1.0, tol.unit, unit)
    except WrsimError as exc:
        raise WrsimError(f"{where}: tolerance in '{tol.unit}' for a value in '{unit}': {exc}") from None
    if isinstance(value, list) and tol.law != "normal" and (tol.limits or tol.values):
        raise WrsimError(f"{where}: a list value takes a +- tolerance, not a range or a table")
    if tol.limits and not isinstance(value, list):
        lo, hi = (convert(v, tol.unit, unit) for v in tol.limits)
        if not lo <= value <= hi:
            raise WrsimError(
                f"{where}: the nominal {value:g} {unit} is outside the range {tol.limits[0]:g} .. "
                f"{tol.limits[1]:g} {tol.unit}"
            )


def load_params(path: str | Path, _including: tuple[Path, ...] = ()) -> ParamSet:
    """Read a parameter-set file, with the sets it includes laid beneath its own keys; errors name file:line and
    the key (`_including`: the files whose includes led here, for the cycle check)."""
    path = Path(path)
    lines = read_text(path).splitlines()

    pset = ParamSet(path.stem, path)
    below: ParamSet | None = None  # the included sets, laid in order
    section_lines: dict[str, int] = {}
    current: str | None = None
    for lineno, raw in enumerate(lines, start=1):
        text = raw.split("#", 1)[0].strip()
        if not text:
            continue
        if text.split(None, 1)[0] == "include" and "=" not in text:
            if current is not None:
                raise WrsimError(
                    f"{path}:{lineno}: include comes after section [{current}] (write the includes "
                    f"first: the included sets lie beneath every key of this file)"
                )
            one = load_params(_included(text, path, lineno, _including), (*_including, path.resolve()))
            below = one if below is None else below.overlay(one)
            continue
        header = _SECTION.match(text)
        if header:
            name = header.group(1)
            if not _IDENT.match(name):
                raise WrsimError(f"{path}:{lineno}: section [{name}] is not a VHDL entity name")
            current = name.lower()
            if current in section_lines:
                raise WrsimError(
                    f"{path}:{lineno}: duplicate section [{name}] (first on line {section_lines[current]})"
                )
            section_lines[current] = lineno
            pset.sections[current] = {}
            continue
        key, eq, rest = text.partition("=")
        if not eq:  # `key +- ...`: a tolerance for the value of a set beneath
            key, keyword, spread = _split_tolerance(text)
            rest = ""
            if not keyword or not key:
                raise WrsimError(f"{path}:{lineno}: '{text}': missing '=' (write key = value unit)")
        key = key.strip()
        if not _IDENT.match(key):
            raise WrsimError(f"{path}:{lineno}: '{key}' is not a VHDL generic name")
        if current is None:
            raise WrsimError(f"{path}:{lineno}: key '{key}' comes before any [entity] section")
        where = f"{path}:{lineno}: [{current}] {key}"
        if eq:
            rest, keyword, spread = _split_tolerance(rest.strip())
        tolerance = None
        if keyword:
            tolerance = _parse_tolerance(keyword, spread, where, path.parent)
            tolerance = dataclasses.replace(tolerance, file=str(path), line=lineno)
            known = pset.tolerances.setdefault(current, {})
            if key.lower() in known:
                raise WrsimError(f"{where}: duplicate tolerance (first on line {known[key.lower()].line})")
            known[key.lower()] = tolerance
        if not eq:
            continue
        value, unit = _parse_value(rest, where)
        if not unit:
            raise WrsimError(f"{where}: missing unit after the value (write 1 for dimensionless)")
        try:
            check_unit(unit)
        except WrsimError as exc:
            raise WrsimError(f"{where}: {exc}") from exc
        if tolerance is not None:
            _check_nominal(tolerance, value, unit, where)
        section = pset.sections[current]
        if key.lower() in section:
            raise WrsimError(f"{where}: duplicate key (first set on line {section[key.lower()].line})")
        section[key.lower()] = Param(value, unit, str(path), lineno)
    if below is None:
        return pset
    return dataclasses.replace(below.overlay(pset), name=pset.name)


MAX_INCLUDE_DEPTH = 32  # [files] a chain of `include` lines (each file read recursively)


def _included(text: str, path: Path, lineno: int, including: tuple[Path, ...]) -> Path:
    """The file an `include FILE` line of `path` names: relative to `path`'s folder, `.txt` optional."""
    where = f"{path}:{lineno}"
    parts = text.split()
    if len(parts) != 2:
        raise WrsimError(f"{where}: write 'include FILE' (a parameter set, relative to this file's folder)")
    target = Path(os.path.normpath(path.parent / parts[1]))
    if not target.is_file() and not target.suffix and target.with_suffix(".txt").is_file():
        target = target.with_suffix(".txt")
    if not target.is_file():
        raise WrsimError(f"{where}: include {parts[1]}: no such parameter set ({target})")
    if target.resolve() in (*including, path.resolve()):
        chain = " -> ".join(str(p) for p in (*including, path.resolve(), target.resolve()))
        raise WrsimError(f"{where}: include {parts[1]}: a cycle ({chain})")
    if len(including) + 1 >= MAX_INCLUDE_DEPTH:
        raise WrsimError(
            f"{where}: include {parts[1]}: includes nested more than {MAX_INCLUDE_DEPTH} deep (from {including[0]})"
        )
    return target


def find_param_set(name_or_path: str | Path, root: str | Path = paths.ROOT) -> Path:
    """Resolve a parameter-set name (file stem under `root`/params, or a path below it without .txt, e.g.
    antipinch/observer) or an existing file path."""
    candidate = Path(name_or_path)
    params_dir = Path(root) / "params"
    if candidate.suffix or len(candidate.parts) > 1:
        if candidate.is_file():
            return candidate
        if not candidate.suffix and (params_dir / f"{candidate}.txt").is_file():  # e.g. tolerances/production
            return params_dir / f"{candidate}.txt"
        raise WrsimError(f"{candidate}: parameter-set file not found")
    path = params_dir / f"{name_or_path}.txt"
    if not path.is_file():
        available = sorted(p.stem for p in params_dir.glob("*.txt"))
        raise WrsimError(
            f"unknown parameter set '{name_or_path}'; available in {params_dir}: {', '.join(available) or 'none'}"
        )
    return path


def _format_value(value: Value) -> str:
    if isinstance(value, list):
        return "[" + ", ".join(repr(float(v)) for v in value) + "]"
    return repr(float(value))


def save_params(
    path: str | Path, header_comments: list[str], sections: dict[str, list[tuple[str, Value, str, str]]]
) -> None:
    """Write a parameter set atomically: header comments, then per entity section the lines
    `key = value unit  # comment` (comments aligned; an empty comment is left out)."""
    path = Path(path)
    out = [f"# {line}".rstrip() for comment in header_comments for line in (comment.splitlines() or [""])]
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
