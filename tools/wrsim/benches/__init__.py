"""The benches, one module per thesis chapter: `drive` (4.1.1, 4.1.4), `worm_gear` (4.1.2), `two_mass` (3.1),
`system` (4.2, 5.1, 5.3.1, 5.3.3), `closed_loop` (5.2, 5.3.2), `identification` (Appendix B). Each module
contributes its `BENCHES` list; `core` says what a bench is and runs it."""

from __future__ import annotations

import importlib
import pkgutil

from wrsim.benches.core import (
    Bench,
    Judgement,
    Run,
    Simulated,
    measurement_of,
    run_bench,
    simulate_runs,
)
from wrsim.errors import WrsimError

__all__ = [
    "BENCHES",
    "select_benches",
    "Bench",
    "Judgement",
    "Run",
    "Simulated",
    "measurement_of",
    "run_bench",
    "simulate_runs",
]


# the modules that run, time, export, score and describe benches (not a chapter's benches)
_MACHINERY = ("core", "run", "timing", "export", "score", "known", "convergence", "scenario", "scenario_run", "replay")


def _registry() -> dict[str, Bench]:
    out: dict[str, Bench] = {}
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if info.name in _MACHINERY:
            continue
        for b in importlib.import_module(f"{__name__}.{info.name}").BENCHES:
            if b.name in out:
                raise WrsimError(f"internal: bench '{b.name}' is defined twice")
            out[b.name] = b
    return out


BENCHES: dict[str, Bench] = _registry()
"""Every bench by name."""


def select_benches(names: list[str] | None) -> list[Bench]:
    """The benches named (all when none); an unknown name is a WrsimError listing the known ones."""
    if not names:
        return list(BENCHES.values())
    unknown = [n for n in names if n not in BENCHES]
    if unknown:
        raise WrsimError(f"unknown bench '{unknown[0]}' (benches: {', '.join(BENCHES)})")
    return [BENCHES[n] for n in names]
