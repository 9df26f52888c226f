"""Measurement and result tables (CSV with units in the header).

Format::

    # source: Fig. 4.15 of the thesis, ...      <- leading comment lines start with '#'
    # any further comment
    torque[N*m],mean_speed[rpm],mean_current[A] <- one header row, every column written name[unit]
    0.042956,5238.3,3.245                       <- numeric rows, one field per column

A `# source: <where the numbers come from>` comment is mandatory for measurement files (read them
with `require_source=True`). Units use pint syntax (see wrsim.units). Errors name `file:line` (the
physical line in the file) and the column.
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim.data.atomic import read_text, write_text_atomic
from wrsim.data.units import check_unit, convert, parse_number
from wrsim.errors import WrsimError

__all__ = ["Table", "read_table", "write_table"]

_SOURCE_PREFIX = "source:"


@dataclass
class Table:
    """A table read from a CSV file: columns in file order, each with its unit."""

    path: Path
    source: str
    columns: dict[str, np.ndarray]
    units: dict[str, str]

    def column(self, name: str, unit: str | None = None) -> np.ndarray:
        """Column `name`, converted to `unit` when given (a copy either way)."""
        if name not in self.columns:
            raise WrsimError(f"{self.path}: no column '{name}'; available: {', '.join(self.columns)}")
        values = self.columns[name]
        if unit is None:
            return values.copy()
        try:
            return convert(values, self.units[name], unit)
        except WrsimError as exc:
            raise WrsimError(f"{self.path}: column '{name}': {exc}") from exc


def _read_lines(path: Path) -> list[str]:
    return read_text(path).splitlines()


def _parse_header(path: Path, lineno: int, line: str) -> tuple[list[str], list[str]]:
    names: list[str] = []
    units: list[str] = []
    for k, field in enumerate(next(csv.reader([line])), start=1):
        field = field.strip()
        where = f"{path}:{lineno}: header column {k} '{field}'"
        if not (field.endswith("]") and "[" in field):
            raise WrsimError(f"{where}: missing [unit]; write it as name[unit], e.g. torque[N*m]")
        name, unit = field[:-1].split("[", 1)
        name, unit = name.strip(), unit.strip()
        if not name:
            raise WrsimError(f"{where}: missing column name before [{unit}]")
        if name in names:
            raise WrsimError(f"{path}:{lineno}: duplicate column '{name}' in header")
        try:
            check_unit(unit)
        except WrsimError as exc:
            raise WrsimError(f"{where}: {exc}") from exc
        names.append(name)
        units.append(unit)
    return names, units


def read_table(
    path: str | Path,
    increasing: str | None = None,
    require_source: bool = False,
    columns: tuple[str, ...] = (),
    what: str = "this table",
) -> Table:
    """Read a table. `increasing` names a column that must rise strictly from row to row (ramps);
    `require_source` demands a `# source:` comment (measurement files); `columns` must all be present
    (checked first; the error names `what`, the kind of file expected)."""
    path = Path(path)
    lines = _read_lines(path)
    source = ""
    header_at = None
    for lineno, line in enumerate(lines, start=1):
        text = line.strip()
        if text.startswith("#"):
            body = text[1:].strip()
            if body.lower().startswith(_SOURCE_PREFIX) and not source:
                source = body[len(_SOURCE_PREFIX) :].strip()
        elif text:
            header_at = lineno
            break
    if require_source and not source:
        raise WrsimError(f"{path}:1: missing '# source: <thesis table/figure and conditions>' comment line")
    if header_at is None:
        raise WrsimError(f"{path}:{len(lines) + 1}: missing header row name[unit],name[unit],...")
    names, units = _parse_header(path, header_at, lines[header_at - 1])

    rows: list[list[float]] = []
    row_lines: list[int] = []
    for lineno in range(header_at + 1, len(lines) + 1):
        line = lines[lineno - 1]
        if not line.strip():
            continue
        fields = [f.strip() for f in next(csv.reader([line]))]
        if len(fields) != len(names):
            raise WrsimError(f"{path}:{lineno}: row has {len(fields)} fields, the header has {len(names)}")
        row = []
        for name, text in zip(names, fields):
            row.append(parse_number(text, f"{path}:{lineno}: column '{name}'"))
        rows.append(row)
        row_lines.append(lineno)
    if not rows:
        raise WrsimError(f"{path}:{header_at}: header without data rows")

    data = np.array(rows, dtype=float)
    table = Table(path, source, {n: data[:, k].copy() for k, n in enumerate(names)}, dict(zip(names, units)))
    missing = [n for n in columns if n not in table.columns]
    if missing:
        raise WrsimError(
            f"{path}: {what} needs the columns {', '.join(columns)}; missing: "
            f"{', '.join(missing)} (found: {', '.join(names)})"
        )
    if increasing is not None:
        values = table.column(increasing)
        falls = np.flatnonzero(np.diff(values) <= 0)
        if falls.size:
            k = falls[0]
            raise WrsimError(
                f"{path}:{row_lines[k + 1]}: column '{increasing}': {values[k + 1]:g} does not "
                f"increase (previous row {values[k]:g}); a ramp must rise strictly"
            )
    return table


def write_table(path: str | Path, columns: dict[str, np.ndarray], units: dict[str, str], comments: list[str]) -> None:
    """Write a table atomically; each comment becomes a `# ` line above the header."""
    path = Path(path)
    for name, values in columns.items():
        bad = np.flatnonzero(~np.isfinite(np.asarray(values, dtype=float)))
        if bad.size:
            raise WrsimError(
                f"{path}: column '{name}', row {bad[0] + 1}: {values[bad[0]]} is not a finite number; nothing written"
            )
    if set(units) != set(columns):
        raise WrsimError(f"{path}: units given for {sorted(units)} but columns are {sorted(columns)}")
    arrays = {name: np.asarray(col, dtype=float).ravel() for name, col in columns.items()}
    lengths = {name: len(col) for name, col in arrays.items()}
    if len(set(lengths.values())) > 1:
        raise WrsimError(f"{path}: columns differ in length: {lengths}")
    for name, unit in units.items():
        if not name or any(c in name for c in "[],#\n"):
            raise WrsimError(f"{path}: column name '{name}' cannot be written in a header")
        try:
            check_unit(unit)
        except WrsimError as exc:
            raise WrsimError(f"{path}: column '{name}': {exc}") from exc
    out = [f"# {line}".rstrip() for comment in comments for line in (comment.splitlines() or [""])]
    out.append(",".join(f"{name}[{units[name]}]" for name in arrays))
    out.extend(",".join(repr(float(v)) for v in row) for row in zip(*arrays.values()))
    write_text_atomic(path, "\n".join(out) + "\n")
