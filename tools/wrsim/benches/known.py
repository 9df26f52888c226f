"""Documented deviations (testbenches/known.toml): from the thesis, or of an anti-pinch algorithm on a case it was
not shaped on. A bench metric that fails for a reason the docs explain gets the verdict KNOWN instead of FAIL, with
the reason and the doc that says why."""

from __future__ import annotations

import dataclasses
import tomllib
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.errors import WrsimError
from wrsim.results import Metric

__all__ = ["Deviation", "deviations", "mark"]

_KEYS = ("bench", "metric", "reason", "doc")


@dataclass(frozen=True)
class Deviation:
    bench: str
    metric: str  # the metric's name in the bench's table
    reason: str  # one line
    doc: str  # the doc that explains it, relative to the repository (file#section)

    @property
    def text(self) -> str:
        return f"{self.reason} ({self.doc})"


def deviations(path: Path | None = None) -> dict[tuple[str, str], Deviation]:
    """The documented deviations by (bench, metric) of `path` (default paths.KNOWN); a malformed file is one
    error naming the entry and key."""
    path = paths.KNOWN if path is None else path
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return {}
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise WrsimError(f"{path}: {e}") from None
    out: dict[tuple[str, str], Deviation] = {}
    for k, entry in enumerate(data.get("deviation", []), start=1):
        where = f"{path}: deviation {k}"
        if not isinstance(entry, dict):
            raise WrsimError(f"{where}: expected a [[deviation]] table")
        for key in _KEYS:
            if not isinstance(entry.get(key), str) or not entry[key].strip():
                raise WrsimError(f"{where}: '{key}' must be a non-empty string")
        unknown = sorted(set(entry) - set(_KEYS))
        if unknown:
            raise WrsimError(f"{where}: unknown key '{unknown[0]}' (keys: {', '.join(_KEYS)})")
        doc = paths.ROOT / entry["doc"].split("#")[0]
        if not doc.is_file():
            raise WrsimError(f"{where}: 'doc' names {entry['doc']}, which does not exist")
        out[(entry["bench"], entry["metric"])] = Deviation(*(entry[key] for key in _KEYS))
    return out


def mark(bench: str, metrics: list[Metric], known: dict[tuple[str, str], Deviation] | None = None) -> list[Metric]:
    """`metrics` with every failing one that is a documented deviation marked known (its reason and doc)."""
    known = deviations() if known is None else known
    return [
        dataclasses.replace(m, known=known[(bench, m.name)].text) if not m.passed and (bench, m.name) in known else m
        for m in metrics
    ]
