"""The convergence note of a bench: every metric at the bench's own solver tolerance and at a tighter one, side by
side. A peak force that sits one Hall edge from a limit can change its verdict with the tolerance (a closed-loop
peak moves by up to about 12 N between reltol 1e-3 and 1e-4); the note shows which verdicts rest on the solver setting.
`wrsim testbench --convergence RELTOL` (`make convergence`) adds it to a bench's page."""

from __future__ import annotations

import dataclasses

from wrsim.benches.core import Bench
from wrsim.errors import WrsimError
from wrsim.results import BenchResult, Grid, Metric

__all__ = ["tighter", "with_convergence"]


def tighter(bench: Bench, reltol: float) -> Bench:
    """`bench` at the tighter relative tolerance `reltol` (one error if it is not tighter than the bench's own)."""
    if not 0.0 < reltol < bench.reltol:
        raise WrsimError(
            f"--convergence {reltol:g}: the check needs a tolerance tighter than the bench's own "
            f"({bench.name}: reltol {bench.reltol:g})"
        )
    return dataclasses.replace(bench, reltol=reltol)


def _verdict(m: Metric) -> str:
    return "PASS" if m.passed else "KNOWN" if m.known else "FAIL"


def with_convergence(result: BenchResult, tight: BenchResult, own: float, reltol: float) -> BenchResult:
    """`result` (the bench at its own tolerance `own`) with the convergence table against `tight` (the same bench at
    `reltol`) and one metric: the verdicts that change at the tighter tolerance (none passes)."""
    at_tight = {m.name: m for m in tight.metrics}
    rows, flips = [], []
    for m in result.metrics:
        t = at_tight.get(m.name)
        if t is None:
            raise WrsimError(f"{result.bench}: metric '{m.name}' is missing at reltol {reltol:g}")
        before, after = _verdict(m), _verdict(t)
        if before != after:
            flips.append(m.name)
        rows.append(
            [
                m.name,
                m.unit,
                f"{m.value:.4g}",
                f"{t.value:.4g}",
                f"{t.value - m.value:+.3g}",
                before,
                after,
                "FAIL: it changes" if before != after else "yes",
            ]
        )
    table = Grid(
        f"convergence: every metric at the bench's reltol {own:g} and at {reltol:g} (FAIL: the verdict changes)",
        [
            "metric",
            "unit",
            f"reltol {own:g}",
            f"reltol {reltol:g}",
            "difference",
            f"verdict {own:g}",
            f"verdict {reltol:g}",
            "same verdict",
        ],
        rows,
        "convergence.csv",
    )
    flipped = Metric(
        f"verdicts that change at reltol {reltol:g}",
        float(len(flips)),
        0.0,
        0.0,
        "1",
        not flips,
        "; ".join(flips),
    )
    return dataclasses.replace(
        result,
        metrics=[*result.metrics, flipped],
        plots=[*result.plots, table],
        timings={**result.timings, **{f"{k} (reltol {reltol:g})": v for k, v in tight.timings.items()}},
        passed=result.passed and not flips,
    )
