"""Parameter sets as standard VHDL for other 1076.1 simulators (Saber, SystemVision): the packages wr_params and
wr_digital_params with a set's values in place of the library's defaults.

Every generic of a library model reads its default from the constant `<entity>_<generic>` of one of these packages
(`PARAM_PACKAGES`, one constant per line). A parameter set replaces defaults too, for every instance whose generic
map leaves the generic alone; so a package with the set's values, analysed instead of the library's, gives another
simulator the design wrsim elaborates with the set laid over. The values are the ones the elaborator uses: in the
unit the generic declares, integers rounded, at the set's `[ambient] temperature`.

The digital package (the ECU software's calibration and the switch's settings) is also written as a C header
(`C_HEADERS`): `#define` lines of the same constants, so that ECU code built from the set carries the values the
simulated ECU ran with."""

from __future__ import annotations

import math
import re
import textwrap
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.data.atomic import write_text_atomic
from wrsim.data.params import ParamSet
from wrsim.elab import symbolic as sy
from wrsim.elab.instances import InstanceTree, check_param_set
from wrsim.elab.library import Library
from wrsim.errors import WrsimError

__all__ = ["ExportedFile", "export_params", "vhdl_literal", "c_header", "C_HEADERS"]

C_HEADERS = ("wr_digital_params",)  # the packages also written as a C header (<package>.h)

# `constant <name> : <type> := <value>;  -- comment`, the line form the packages keep
_CONSTANT = re.compile(
    r"^(?P<head>\s*constant\s+(?P<name>\w+)\s*:\s*(?P<type>\w+)\s*:=\s*)(?P<value>.*?);"
    r"(?P<tail>\s*--.*)?$",
    re.I,
)
_RANGES = {"natural": 0, "positive": 1}  # the lower bound of the integer subtypes generics use


@dataclass(frozen=True)
class ExportedFile:
    """One written package: where, and the constants that carry the set's values."""

    path: Path
    package: str
    changed: tuple[str, ...]


def vhdl_literal(value: float | list[float] | bool, type_mark: str) -> str:
    """`value` as a VHDL expression of type `type_mark`: an integer, `true`/`false`, a real literal with a point
    (`1.0e-5`, never `1e-05`), or a positional aggregate of them (`(0 => x)` for one element)."""
    if isinstance(value, list):
        items = [vhdl_literal(v, "real") for v in value]
        return f"(0 => {items[0]})" if len(items) == 1 else f"({', '.join(items)})"
    if type_mark == "boolean":
        return "true" if value else "false"
    if type_mark in ("integer", "natural", "positive"):
        return str(int(value))
    if not math.isfinite(value):
        raise WrsimError(f"{value}: not a finite number")
    text = repr(float(value))
    mantissa, e, exponent = text.partition("e")
    mantissa += "" if "." in mantissa else ".0"
    return f"{mantissa}e{int(exponent)}" if e else mantissa


def export_params(
    lib: Library, params: ParamSet, out: Path, header: list[str], packages: tuple[Path, ...] = paths.PARAM_PACKAGES
) -> list[ExportedFile]:
    """Write `packages` (the library's wr_params files) into folder `out` with the values of `params` (a set as
    the runs use it: overlays applied, at its temperature) and `header` (comment lines without `--`, wrapped; the
    first after `<package>: `) in place of the file's leading comment. Errors name the set's file:line and key; nothing
    is written then."""
    check_param_set(lib, params)
    tree = InstanceTree(lib, params)
    wanted = {
        f"{entity}_{key}": (entity, key, p) for entity, keys in params.sections.items() for key, p in keys.items()
    }
    texts: list[tuple[Path, str, str, list[str]]] = []
    for source in packages:
        lines = source.read_text(encoding="utf-8").splitlines()
        package = next(
            (m.group(1).lower() for line in lines if (m := re.match(r"\s*package\s+(\w+)\s+is", line, re.I))),
            source.stem,
        )
        changed = []
        for i, line in enumerate(lines):
            m = _CONSTANT.match(line)
            if m is None or m.group("name").lower() not in wanted:
                continue
            entity, key, p = wanted.pop(m.group("name").lower())
            value, _ = tree.generic_defaults(lib.entities[entity])[key]
            assert value is not None  # the set gives it
            type_mark = m.group("type").lower()
            number = [sy.value(v) for v in sy.items(value)] if isinstance(value, sy.Vec) else sy.value(value)
            if type_mark in _RANGES and not isinstance(number, list) and round(number) < _RANGES[type_mark]:
                raise WrsimError(
                    f"{p.file}:{p.line}: [{entity}] {key} = {number:g}: {entity}.{key} is {type_mark} "
                    f"(at least {_RANGES[type_mark]})"
                )
            comment = (m.group("tail") or "").strip().removeprefix("--").strip()
            lines[i] = (
                f"{m.group('head')}{vhdl_literal(number, type_mark)};  -- set: {paths.shown(p.file)}:{p.line}"
                + (f"; {comment}" if comment else "")
            )
            changed.append(m.group("name").lower())
        start = next(i for i, line in enumerate(lines) if not line.startswith("--"))
        told = [
            f"{package}: {header[0]} Analyse it into library WORK instead of {paths.shown(source)}, before the "
            f'models (README, "Import into Saber or SystemVision").',
            *header[1:],
        ]
        comment = [
            f"-- {w}"
            for h in told
            for w in textwrap.wrap(h, 112, break_long_words=False, subsequent_indent=_hanging(h))
        ]
        text = "\n".join([*comment, *lines[start:]]) + "\n"
        texts.append((out / source.name, package, text, changed))
    if wanted:
        entity, key, p = next(iter(wanted.values()))
        raise WrsimError(
            f"{p.file}:{p.line}: [{entity}] {key}: no constant {entity}_{key} in "
            f"{', '.join(s.name for s in packages)}; a testbench's generic is set in the simulator, "
            f"on the top-level entity, not by a package"
        )
    files = [(path, text) for path, _, text, _ in texts]  # every text made before the first is written
    files += [
        (path.with_suffix(".h"), c_header(text, package)) for path, package, text, _ in texts if package in C_HEADERS
    ]
    for path, text in files:
        write_text_atomic(path, text)
    return [ExportedFile(path, package, tuple(changed)) for path, package, _, changed in texts]


def c_header(package_text: str, package: str) -> str:
    """The constants of a parameter package (its VHDL text, as `export_params` writes it) as a C header: one
    `#define WR_<NAME> <value>` per constant (the names carry their entity: WR_ECU_SOFTWARE_ALGORITHM), integers as
    they are, booleans as 1 / 0, reals as C doubles, strings as C string literals; each with its VHDL comment (the
    unit, and `set:` where the set gave it)."""
    guard = f"{package.upper()}_H"
    lines = [
        f"/* {package}.h: the constants of {package}.vhd as C (written with it by `wrsim export`; do not edit). */",
        f"#ifndef {guard}",
        f"#define {guard}",
        "",
    ]
    for line in package_text.splitlines():
        m = _CONSTANT.match(line)
        if m is None:
            continue
        type_mark, value = m.group("type").lower(), m.group("value").strip()
        if type_mark == "boolean":
            value = "1" if value.lower() == "true" else "0"
        elif type_mark == "string":
            value = '"' + value[1:-1].replace('""', '"').replace("\\", "\\\\").replace('"', '\\"') + '"'
        elif type_mark not in ("integer", "natural", "positive", "real"):
            raise WrsimError(f"{package}: constant {m.group('name')} of type {type_mark} has no C form")
        comment = (m.group("tail") or "").strip().removeprefix("--").strip().replace("*/", "* /")
        lines.append(f"#define WR_{m.group('name').upper()} {value}" + (f"  /* {comment} */" if comment else ""))
    return "\n".join([*lines, "", f"#endif /* {guard} */", ""])


def _hanging(line: str) -> str:
    """The indent of a wrapped header line's continuation: an indented line (a list item) hangs by two more."""
    indent = len(line) - len(line.lstrip())
    return " " * (indent + 2 if indent else 0)
