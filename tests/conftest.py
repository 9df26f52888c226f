"""Shared pytest helpers: build and simulate a VHDL-AMS bench entity (netlist, simulate), and run a registered
bench end to end (lib, bench_run).

`netlist(entity, stop, ...)` loads vhdl/ieee and vhdl/common plus `files` (default: tests/fixtures/analytic),
elaborates `entity` and lowers it; the `simulate` fixture also runs ngspice in the test's tmp_path and returns
the Waveforms (by hierarchical VHDL-AMS name)."""
from __future__ import annotations

import functools
import itertools
from collections.abc import Callable, Iterable
from pathlib import Path

import pytest

from wrsim.elaborate import Library, elaborate, load_library
from wrsim.ngspice import Analysis, Netlist, lower
from wrsim.benches import BENCHES, run_bench
from wrsim.cli import _library as project_library, _params
from wrsim.runner import NgspiceBatch, Waveforms

ROOT = Path(__file__).resolve().parents[1]
ANALYTIC = ROOT / "tests" / "fixtures" / "analytic"
_BASE = (ROOT / "vhdl" / "ieee", ROOT / "vhdl" / "common")


@functools.lru_cache(maxsize=8)
def _library(paths: tuple[Path, ...]) -> Library:
    return load_library([*_BASE, *paths])


def netlist(entity: str, stop: float, max_step: float | None = None, files: Iterable[str | Path] = (ANALYTIC,),
            overrides: dict[str, float] | None = None) -> Netlist:
    """Elaborate bench `entity` from vhdl/ieee, vhdl/common and `files` (relative to the repository) and lower
    it to a transient analysis up to `stop` [s] with ngspice's step bounded by `max_step` [s]."""
    lib = _library(tuple(ROOT / f for f in files))
    design = elaborate(lib, entity, None, overrides)
    return lower(design, Analysis(stop=stop, max_step=max_step), entity)


@pytest.fixture
def simulate(tmp_path: Path) -> Callable[..., Waveforms]:
    """`simulate(entity, stop, max_step=None, files=(tests/fixtures/analytic,), overrides=None)` -> Waveforms;
    each call runs ngspice in its own folder below the test's tmp_path."""
    runs = itertools.count()

    def run(entity: str, stop: float, max_step: float | None = None, files: Iterable[str | Path] = (ANALYTIC,),
            overrides: dict[str, float] | None = None) -> Waveforms:
        net = netlist(entity, stop, max_step, files, overrides)
        return NgspiceBatch().run(net, tmp_path / f"{entity}_{next(runs)}")

    return run


# ------------------------------------------------------------------------------------------------ benches
@pytest.fixture(scope="session")
def lib():
    """The project's library (vhdl/, testbenches/)."""
    return project_library()


@pytest.fixture
def bench_run(lib, tmp_path):
    """bench_run(name) -> (BenchResult, metrics by full name and by name without its "(...)" note)."""
    def run(name: str):
        bench = BENCHES[name]
        result = run_bench(bench, lib, _params(None, bench), NgspiceBatch(), tmp_path / "work")
        metrics = {m.name: m for m in result.metrics}
        metrics.update({m.name.split(" (")[0]: m for m in result.metrics})
        return result, metrics
    return run
