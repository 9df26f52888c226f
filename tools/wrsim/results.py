"""What a bench run produces: named signals, checked metrics, plots and tables, and the bench result that holds
them. Benches, studies and identification build these; report.results writes them to disk."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["Signal", "Metric", "Overlay", "Plot", "Grid", "BenchResult"]


@dataclass(eq=False)
class Signal:
    """A named 1-D series of values in one unit."""

    name: str
    unit: str
    values: np.ndarray

    @property
    def label(self) -> str:
        """The CSV column name, `name[unit]`."""
        return f"{self.name}[{self.unit}]"

    @property
    def axis_label(self) -> str:
        """The plot axis label, `name [unit]` (just `name` when dimensionless)."""
        return f"{self.name} [{self.unit}]" if self.unit else self.name


@dataclass
class Metric:
    """One checked quantity; `tolerance` is absolute, in `unit`."""

    name: str
    value: float
    reference: float
    tolerance: float
    unit: str
    passed: bool
    note: str = ""
    known: str = ""  # a failing metric the docs explain (benches.known): why, and where
    kind: str = ""  # how the report states the requirement: "" reference +- tolerance, "limit" at most reference +
    # tolerance (the band starts at 0), "flag" a yes/no (value and reference 1 or 0)


@dataclass(eq=False)
class Overlay:
    """Measured or reference points drawn as markers on the "left" or "right" axis of a plot."""

    name: str
    x: Signal
    y: Signal
    axis: str


@dataclass(eq=False)
class Plot:
    """One PNG: `left` (and optionally `right`, on a twin axis) signals over `x`, plus overlays."""

    title: str
    x: Signal
    left: list[Signal]
    right: list[Signal]
    overlays: list[Overlay]
    filename: str
    logx: bool = False  # a logarithmic x axis (a frequency response)
    page: str = ""  # drawn on this page of its own beside the bench's (e.g. one per run), interactive only (no PNG)


@dataclass(eq=False)
class Grid:
    """A table written as `filename` (CSV) and the same name with .html, e.g. a test matrix with a verdict per
    cell; a cell that starts with FAIL is marked in the HTML, one that starts with INFO greyed. `margins` makes it
    a heat map: per cell a signed margin to a limit (None: no colour), green as it grows to `scale`, red below 0."""

    title: str
    columns: list[str]
    rows: list[list[str]]
    filename: str
    margins: list[list[float | None]] | None = None
    scale: float = 1.0  # the margin of the full green
    links: list[list[str | None]] | None = None  # per cell, a page of the bench's folder the cell opens

    @property
    def html_name(self) -> str:
        return self.filename[:-4] + ".html"


@dataclass(eq=False)
class BenchResult:
    """Everything a bench run produced; `waveforms[0]` is time[s], `passed` is all metrics passed or known."""

    bench: str
    description: str
    measurement: str | None
    waveforms: list[Signal]
    metrics: list[Metric]
    plots: list[Plot | Grid]
    timings: dict[str, float]
    passed: bool
