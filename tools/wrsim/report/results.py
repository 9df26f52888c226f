"""Bench results on disk: build/results/<bench>/{waveforms.csv, result.json, *.png} and index.html (the result
types are in wrsim.results).

A bench's directory is assembled in a hidden temporary sibling and renamed into place at the end, so
a result directory is always either the complete previous one or the complete new one.
"""

from __future__ import annotations

import csv
import itertools
import json
import math
import re
import time
from pathlib import Path
from typing import Any

import numpy as np

from wrsim.data.atomic import write_text_atomic
from wrsim.data.publish import publish_directory
from wrsim.errors import WrsimError
from wrsim.report import interactive
from wrsim.report.mdf import write_mdf
from wrsim.report.pages import (
    INDEX_HTML,
    bench_page,
    grid_page,
    index_page,
    plots_page,
    requirement_text,
    value_text,
    verdict,
)
from wrsim.results import BenchResult, Grid, Plot, Signal

__all__ = [
    "write_bench_result",
    "write_failure",
    "write_index",
    "format_table",
    "result_dict",
    "bench_verdict",
]

WAVEFORMS_CSV = "waveforms.csv"
RESULT_JSON = "result.json"
WAVEFORMS_MF4 = "waveforms.mf4"  # the same table as ASAM MDF4 (CANape, INCA, asammdf), report.mdf
FAILURE_SUFFIX = ".failure.json"  # beside the result folder: the latest run failed

_BENCH_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*")
_PLOT_FILE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*\.png")
_GRID_FILE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*\.csv")
_PAGE_FILE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*\.html")


def write_bench_result(results_root: Path, result: BenchResult) -> Path:
    """Write `result` to results_root/<bench>/, replacing any previous result as a whole."""
    _check_result(result)
    with publish_directory(Path(results_root), result.bench) as tmp:
        if result.waveforms:
            _write_waveforms(tmp / WAVEFORMS_CSV, result.waveforms)
            write_mdf(tmp / WAVEFORMS_MF4, result.waveforms, _metadata(result))
        for plot in result.plots:
            if isinstance(plot, Grid):
                _write_grid(tmp, plot)
            elif not plot.page:
                _write_plot(tmp / plot.filename, plot)
        data = result_dict(result)
        _write_json(tmp / RESULT_JSON, data)
        if any(isinstance(p, Plot) for p in result.plots):
            interactive.install_script(Path(results_root))
        page = bench_page(tmp, Path(results_root), data, result.plots)
        (tmp / INDEX_HTML).write_text(page, encoding="utf-8")
        for name in dict.fromkeys(p.page for p in result.plots if isinstance(p, Plot) and p.page):
            own = [p for p in result.plots if isinstance(p, Plot) and p.page == name]
            (tmp / name).write_text(plots_page(result.bench, own), encoding="utf-8")
    (Path(results_root) / f"{result.bench}{FAILURE_SUFFIX}").unlink(missing_ok=True)
    return Path(results_root) / result.bench


def write_failure(results_root: Path, bench: str, message: str) -> Path:
    """Record that the latest run of `bench` failed, beside its last good result (which stays): results_root/
    <bench>.failure.json with the time and `message`. The next good result removes the record."""
    _check_bench_name(bench)
    path = Path(results_root) / f"{bench}{FAILURE_SUFFIX}"
    data = {"bench": bench, "passed": False, "error": message, "time": time.strftime("%Y-%m-%d %H:%M:%S")}
    try:
        Path(results_root).mkdir(parents=True, exist_ok=True)
        write_text_atomic(path, json.dumps(data, indent=2) + "\n")
    except OSError as e:
        raise WrsimError(f"cannot record the failure of bench {bench} in {results_root}: {e}") from e
    return path


def write_index(results_root: Path) -> Path:
    """Write results_root/index.html, a table of every results_root/*/result.json."""
    root = Path(results_root)
    target = root / INDEX_HTML
    write_text_atomic(target, index_page(root, _load_results(root)))
    return target


def format_table(results: list[BenchResult | dict[str, Any]]) -> str:
    """The plain-text pass/fail table: one line per bench, then one indented line per metric.

    Dicts are taken in the result.json format.
    """
    header = ("bench / metric", "value", "required", "result")
    lines: list[tuple[str, ...] | str] = [header]  # tuples are table rows, strings are printed as they are
    for item in results:
        data = result_dict(item) if isinstance(item, BenchResult) else item
        lines.append((str(data["bench"]), "", "", verdict(data.get("passed"), data.get("known"))))
        if data.get("error"):
            lines.append("  error: " + str(data["error"]).replace("\n", "\n  "))
        measured = bool(data.get("measurement"))
        for name, m in data.get("metrics", {}).items():
            lines.append(
                (
                    f"  {name}",
                    value_text(m),
                    requirement_text(m, measured),
                    verdict(m.get("pass"), m.get("known")),
                )
            )
            if m.get("known") and not m.get("pass"):
                lines.append(f"    known: {m['known']}")
    rows = [line for line in lines if isinstance(line, tuple)]
    widths = [max(len(row[i]) for row in rows) for i in range(len(header))]
    return "\n".join(
        line if isinstance(line, str) else "  ".join(c.ljust(w) for c, w in zip(line, widths)).rstrip()
        for line in lines
    )


# -- checks -------------------------------------------------------------------------------------


def _check_bench_name(bench: str) -> None:
    if not _BENCH_NAME.fullmatch(bench):
        raise WrsimError(f"invalid bench name {bench!r}: use letters, digits, '_' and '-'")


def _check_signal(sig: Signal, where: str) -> int:
    if re.search(r'[,"\n\r]', sig.label):
        raise WrsimError(f"{where}: signal name {sig.label!r} must not contain ',', '\"' or newlines")
    if np.ndim(sig.values) != 1:
        raise WrsimError(f"{where}: signal {sig.label} must be one-dimensional")
    return len(sig.values)


def _check_result(result: BenchResult) -> None:
    _check_bench_name(result.bench)
    where = f"bench {result.bench}"
    if result.waveforms and result.waveforms[0].label != "time[s]":
        raise WrsimError(f"{where}: the first waveform must be time[s]")
    lengths = {_check_signal(s, where) for s in result.waveforms}
    if len(lengths) > 1:
        raise WrsimError(f"{where}: waveforms have different lengths {sorted(lengths)}")
    labels = [s.label for s in result.waveforms]
    if len(set(labels)) != len(labels):
        raise WrsimError(f"{where}: duplicate waveform columns in {labels}")
    names = [m.name for m in result.metrics]
    if len(set(names)) != len(names):
        raise WrsimError(f"{where}: duplicate metric names in {names}")
    if result.passed != all(m.passed or m.known for m in result.metrics):
        raise WrsimError(f"{where}: passed={result.passed} disagrees with its metrics")
    files = [p.filename for p in result.plots]
    if len(set(files)) != len(files):
        raise WrsimError(f"{where}: duplicate plot file names in {files}")
    for plot in result.plots:
        if isinstance(plot, Grid):
            _check_grid(plot, f"{where}, table {plot.filename!r}")
        else:
            _check_plot(plot, f"{where}, plot {plot.filename!r}")


def _check_grid(grid: Grid, where: str) -> None:
    if not _GRID_FILE.fullmatch(grid.filename):
        raise WrsimError(f"{where}: the file name must be a plain name ending in .csv")
    for row in grid.rows:
        if len(row) != len(grid.columns):
            raise WrsimError(f"{where}: a row has {len(row)} cells for {len(grid.columns)} columns")
    for what, cells in (("margins", grid.margins), ("links", grid.links)):
        if cells is not None and [len(r) for r in cells] != [len(r) for r in grid.rows]:
            raise WrsimError(f"{where}: its {what} do not have the shape of its rows")


def _check_plot(plot: Plot, where: str) -> None:
    if not _PLOT_FILE.fullmatch(plot.filename):
        raise WrsimError(f"{where}: the file name must be a plain name ending in .png")
    if plot.page and (not _PAGE_FILE.fullmatch(plot.page) or plot.page == INDEX_HTML):
        raise WrsimError(f"{where}: its page must be a plain name ending in .html other than {INDEX_HTML}")
    if not plot.left:
        raise WrsimError(f"{where}: no signal for the left axis")
    n = _check_signal(plot.x, where)
    for sig in [*plot.left, *plot.right]:
        if _check_signal(sig, where) != n:
            raise WrsimError(f"{where}: {sig.label} has {len(sig.values)} values, {plot.x.label} {n}")
    for ov in plot.overlays:
        axis = {"left": plot.left, "right": plot.right}.get(ov.axis)
        if axis is None:
            raise WrsimError(f"{where}: overlay {ov.name!r} axis must be 'left' or 'right', not {ov.axis!r}")
        if _check_signal(ov.x, where) != _check_signal(ov.y, where):
            raise WrsimError(f"{where}: overlay {ov.name!r} has x and y of different lengths")
        if ov.x.unit != plot.x.unit:
            raise WrsimError(f"{where}: overlay {ov.name!r} x unit {ov.x.unit!r} is not {plot.x.unit!r}")
        units = {s.unit for s in axis}
        if units and ov.y.unit not in units:
            raise WrsimError(f"{where}: overlay {ov.name!r} y unit {ov.y.unit!r} is not on the {ov.axis} axis")


# -- writing ------------------------------------------------------------------------------------


def _write_waveforms(path: Path, waveforms: list[Signal]) -> None:
    table = np.column_stack([np.asarray(s.values, dtype=float) for s in waveforms])
    header = ",".join(s.label for s in waveforms)
    np.savetxt(path, table, fmt="%.12g", delimiter=",", header=header, comments="")


def _write_grid(folder: Path, grid: Grid) -> None:
    with open(folder / grid.filename, "w", newline="", encoding="utf-8") as f:
        writer = csv.writer(f)
        writer.writerow(grid.columns)
        writer.writerows(grid.rows)
    (folder / grid.html_name).write_text(grid_page(grid), encoding="utf-8")


def _write_json(path: Path, data: dict[str, Any]) -> None:
    path.write_text(json.dumps(data, indent=2, allow_nan=False) + "\n", encoding="utf-8")


def _write_plot(path: Path, plot: Plot) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8, 5), layout="constrained")
    left = fig.add_subplot()
    axes = {"left": left}
    if plot.right or any(ov.axis == "right" for ov in plot.overlays):
        axes["right"] = left.twinx()
    colors = itertools.cycle(f"C{i}" for i in range(10))
    for side, signals in (("left", plot.left), ("right", plot.right)):
        for sig in signals:
            axes[side].plot(plot.x.values, sig.values, color=next(colors), label=sig.name)
    for ov, marker in zip(plot.overlays, itertools.cycle("osD^vx+")):
        axes[ov.axis].plot(ov.x.values, ov.y.values, linestyle="none", marker=marker, color=next(colors), label=ov.name)
    left.set_xlabel(plot.x.axis_label)
    if plot.logx:
        left.set_xscale("log")
    left.set_title(plot.title)
    left.grid(True, alpha=0.3)
    for side, signals in (("left", plot.left), ("right", plot.right)):
        if side in axes:
            axes[side].set_ylabel(", ".join(dict.fromkeys(s.axis_label for s in signals)))
    handles, labels = [], []
    for ax in axes.values():
        h, lab = ax.get_legend_handles_labels()
        handles += h
        labels += lab
    left.legend(handles, labels, loc="best")
    fig.savefig(path, format="png", dpi=100)


def _num(x: float | None) -> float | None:
    """A float for JSON, None for a missing or non-finite value."""
    return float(x) if x is not None and math.isfinite(x) else None


def result_dict(result: BenchResult) -> dict[str, Any]:
    return {
        "bench": result.bench,
        "description": result.description,
        "measurement": None if result.measurement is None else str(result.measurement),
        "passed": bool(result.passed),
        "known": any(m.known and not m.passed for m in result.metrics),
        "error": None,
        "metrics": {
            m.name: {
                "value": _num(m.value),
                "reference": _num(m.reference),
                "tolerance": _num(m.tolerance),
                "unit": m.unit,
                "pass": bool(m.passed),
                "note": m.note,
                "known": m.known,
                "kind": m.kind,
            }
            for m in result.metrics
        },
        "plots": list(
            {  # a page of several plots once, by its name
                entry["file"]: entry
                for p in result.plots
                for entry in (
                    [{"title": p.title, "file": p.html_name}, {"title": f"{p.title} (CSV)", "file": p.filename}]
                    if isinstance(p, Grid)
                    else [
                        {"title": p.page.removesuffix(".html"), "file": p.page}
                        if p.page
                        else {"title": p.title, "file": p.filename}
                    ]
                )
            }.values()
        ),
        "timings": {k: _num(v) for k, v in result.timings.items()},
    }


# -- reading and the index ----------------------------------------------------------------------


def _load_results(root: Path) -> list[dict[str, Any]]:
    """Every bench's last good result, with the failure of a later run under "failure" (a bench that never
    produced a result: the failure alone)."""
    out: dict[str, dict[str, Any]] = {}
    for path in sorted(root.glob(f"*/{RESULT_JSON}")):
        bench = path.parent.name
        if bench.startswith("."):
            continue
        out[bench] = {**_read_json(path), "bench": bench}
    for path in sorted(root.glob(f"*{FAILURE_SUFFIX}")):
        bench = path.name.removesuffix(FAILURE_SUFFIX)
        failure = _read_json(path)
        if bench in out:
            out[bench]["failure"] = failure
            out[bench]["passed"] = False
        else:
            out[bench] = {"bench": bench, "passed": False, "error": failure.get("error"), "metrics": {}}
    return [out[k] for k in sorted(out)]


def _read_json(path: Path) -> dict[str, Any]:
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
        if not isinstance(data, dict):
            raise ValueError("not a JSON object")
        return data
    except (OSError, ValueError) as e:
        return {"passed": False, "error": f"unreadable {path.name}: {e}"}


def bench_verdict(result: BenchResult) -> str:
    """PASS, KNOWN or FAIL of a bench result, as the summary table and the index show it."""
    return verdict(result.passed, any(m.known and not m.passed for m in result.metrics))


def _metadata(result: BenchResult) -> dict[str, str]:
    """What an MDF4 file of `result` says about itself (its header comment)."""
    return {
        "bench": result.bench,
        "description": " ".join(result.description.split()),
        "verdict": bench_verdict(result),
        "measurement": result.measurement or "",
        "program": "wrsim",
    }
