"""Acceptance fixtures: run a registered bench end to end (elaborate, lower, ngspice, judge)."""
from __future__ import annotations

import pytest

from wrsim.benches import BENCHES, run_bench
from wrsim.cli import _library, _params
from wrsim.runner import NgspiceBatch


@pytest.fixture(scope="session")
def lib():
    return _library()


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
