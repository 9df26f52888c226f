"""Shared pytest helpers: build and simulate a VHDL-AMS bench entity (netlist, simulate), and run a registered
bench end to end (lib, bench_run).

`netlist(entity, stop, ...)` loads vhdl/ieee and vhdl/common plus `files` (default: tests/fixtures/analytic),
elaborates `entity` and lowers it; the `simulate` fixture also runs ngspice in the test's tmp_path and returns
the Waveforms (by hierarchical VHDL-AMS name)."""

from __future__ import annotations

import csv
import functools
import itertools
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
import pytest

from wrsim import (
    BENCHES,
    Analysis,
    Library,
    Netlist,
    NgspiceBatch,
    Waveforms,
    bench_params,
    elaborate,
    load_library,
    lower,
    paths,
    run_bench,
)

ROOT = paths.ROOT
ANALYTIC = ROOT / "tests" / "fixtures" / "analytic"
_BASE = (ROOT / "vhdl" / "ieee", ROOT / "vhdl" / "common")


def table(path: Path) -> tuple[list[str], np.ndarray]:
    """The header and the numbers of a CSV table wrsim wrote (waveforms.csv, op.csv, dc.csv, ac.csv, noise.csv)."""
    with path.open() as f:
        rows = list(csv.reader(f))
    return rows[0], np.array(rows[1:], dtype=float)


@functools.lru_cache(maxsize=8)
def _library(paths: tuple[Path, ...]) -> Library:
    return load_library([*_BASE, *paths])


def netlist(
    entity: str,
    stop: float,
    max_step: float | None = None,
    files: Iterable[str | Path] = (ANALYTIC,),
    overrides: dict[str, float] | None = None,
    compiled: bool = False,
) -> Netlist:
    """Elaborate bench `entity` from vhdl/ieee, vhdl/common and `files` (relative to the repository) and lower
    it to a transient analysis up to `stop` [s] with ngspice's step bounded by `max_step` [s]; behavioural sources
    (what the netlist tests read) unless `compiled`."""
    lib = _library(tuple(ROOT / f for f in files))
    design = elaborate(lib, entity, None, overrides)
    return lower(design, Analysis(stop=stop, max_step=max_step, compiled=compiled), entity)


@pytest.fixture
def simulate(tmp_path: Path) -> Callable[..., Waveforms]:
    """`simulate(entity, stop, max_step=None, files=(tests/fixtures/analytic,), overrides=None)` -> Waveforms;
    each call runs ngspice in its own folder below the test's tmp_path."""
    runs = itertools.count()

    def run(
        entity: str,
        stop: float,
        max_step: float | None = None,
        files: Iterable[str | Path] = (ANALYTIC,),
        overrides: dict[str, float] | None = None,
    ) -> Waveforms:
        net = netlist(entity, stop, max_step, files, overrides)
        folder, runner = tmp_path / f"{entity}_{next(runs)}", NgspiceBatch()
        runner.build(net, folder)
        return runner.run(net, folder)

    return run


# ------------------------------------------------------------------------------------------------ benches
@pytest.fixture(scope="session")
def lib():
    """The project's library (vhdl/, testbenches/)."""
    return load_library()


@pytest.fixture
def bench_run(lib, tmp_path):
    """bench_run(name, overlay=None) -> (BenchResult, metrics by full name and by name without its "(...)" note);
    `overlay` is a parameter-set file laid over the bench's own set."""
    runs = itertools.count()

    def run(name: str, overlay: Path | None = None):
        bench = BENCHES[name]
        result = run_bench(bench, lib, bench_params(bench, overlay), NgspiceBatch(), tmp_path / f"work{next(runs)}")
        metrics = {m.name: m for m in result.metrics}
        metrics.update({m.name.split(" (")[0]: m for m in result.metrics})
        return result, metrics

    return run


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    """Each test is marked by its folder: `unit`, `fuzz` or `acceptance` (declared in pyproject.toml), so that
    `pytest -m "not acceptance"` selects like the make targets do."""
    for item in items:
        folder = item.path.parent.name
        if folder in ("unit", "fuzz", "acceptance"):
            item.add_marker(folder)
