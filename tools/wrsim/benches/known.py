"""Documented deviations (testbenches/known.toml): from the thesis, or of an anti-pinch algorithm on a case it was
not shaped on. A bench metric that fails for a reason the docs explain gets the verdict KNOWN instead of FAIL, with
the reason and the doc that says why. An entry may name the parameter sets it holds for (`params`: the `--params`
sets as given, their names joined by "+", or "default" for none); without it, it holds for every set."""

from __future__ import annotations

import dataclasses
import tomllib
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.errors import WrsimError
from wrsim.results import Metric

__all__ = ["DEFAULT_SETS", "Deviation", "deviations", "mark", "sets_label"]

_KEYS = ("bench", "metric", "reason", "doc")
_OPTIONAL = ("params",)
DEFAULT_SETS = "default"  # the label of a run without --params


@dataclass(frozen=True)
class Deviation:
    bench: str
    metric: str  # the metric's name in the bench's table
    reason: str  # one line
    doc: str  # the doc that explains it, relative to the repository (file#section)
    params: str | None = None  # the user's sets it holds for (sets_label); None: every set

    @property
    def text(self) -> str:
        return f"{self.reason} ({self.doc})"


def sets_label(user: Sequence[str | Path]) -> str:
    """How a deviation's `params` names the user's sets `user` (`--params`, in order): their names joined by "+"
    (a set's name is its file's stem, as ParamSet.name), DEFAULT_SETS for none."""
    return "+".join(Path(p).stem for p in user) or DEFAULT_SETS


def deviations(path: Path | None = None, sets: str = DEFAULT_SETS) -> dict[tuple[str, str], Deviation]:
    """The documented deviations of `path` (default paths.KNOWN) that hold for the user's sets `sets`
    (sets_label), by (bench, metric); a malformed file is one error naming the entry and key."""
    path = paths.KNOWN if path is None else path
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return {}
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as e:
        raise WrsimError(f"{path}: {e}") from None
    out: dict[tuple[str, str], Deviation] = {}
    entries: list[Deviation] = []
    for k, entry in enumerate(data.get("deviation", []), start=1):
        where = f"{path}: deviation {k}"
        if not isinstance(entry, dict):
            raise WrsimError(f"{where}: expected a [[deviation]] table")
        for key in _KEYS:
            if not isinstance(entry.get(key), str) or not entry[key].strip():
                raise WrsimError(f"{where}: '{key}' must be a non-empty string")
        unknown = sorted(set(entry) - set(_KEYS) - set(_OPTIONAL))
        if unknown:
            raise WrsimError(f"{where}: unknown key '{unknown[0]}' (keys: {', '.join(_KEYS + _OPTIONAL)})")
        if "params" in entry and (not isinstance(entry["params"], str) or not entry["params"].strip()):
            raise WrsimError(f"{where}: 'params' must be the sets' names joined by '+', or '{DEFAULT_SETS}'")
        doc = paths.ROOT / entry["doc"].split("#")[0]
        if not doc.is_file():
            raise WrsimError(f"{where}: 'doc' names {entry['doc']}, which does not exist")
        d = Deviation(entry["bench"], entry["metric"], entry["reason"], entry["doc"], entry.get("params"))
        if any((e.bench, e.metric, e.params) == (d.bench, d.metric, d.params) for e in entries):
            sets_named = f" ({d.params})" if d.params else ""
            raise WrsimError(f"{where}: a second entry for {d.bench}: {d.metric}{sets_named}")
        entries.append(d)
    for d in sorted(entries, key=lambda e: e.params is not None):  # an entry for these sets overrides one for all
        if d.params in (None, sets):
            out[(d.bench, d.metric)] = d
    return out


def mark(
    bench: str, metrics: list[Metric], sets: str = DEFAULT_SETS, known: dict[tuple[str, str], Deviation] | None = None
) -> list[Metric]:
    """`metrics` with every failing one that is a documented deviation for the user's sets `sets` (sets_label)
    marked known (its reason and doc)."""
    known = deviations(sets=sets) if known is None else known
    return [
        dataclasses.replace(m, known=known[(bench, m.name)].text) if not m.passed and (bench, m.name) in known else m
        for m in metrics
    ]
