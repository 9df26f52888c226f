"""Bench results on disk: build/results/<bench>/{waveforms.csv, result.json, *.png} and index.html (the result
types are in wrsim.results).

A bench's directory is assembled in a hidden temporary sibling and renamed into place at the end, so
a result directory is always either the complete previous one or the complete new one.
"""

from __future__ import annotations

import csv
import html
import itertools
import json
import math
import os
import re
import time
from pathlib import Path
from typing import Any
from urllib.parse import quote

import numpy as np
from matplotlib.figure import Figure

from wrsim import paths
from wrsim.data.atomic import write_text_atomic
from wrsim.data.publish import publish_directory
from wrsim.errors import WrsimError
from wrsim.report.mdf import write_mdf
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
INDEX_HTML = "index.html"
FAILURE_SUFFIX = ".failure.json"  # beside the result folder: the latest run failed

_BENCH_NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9_-]*")
_PLOT_FILE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*\.png")
_GRID_FILE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*\.csv")


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
            else:
                _write_plot(tmp / plot.filename, plot)
        _write_json(tmp / RESULT_JSON, result_dict(result))
        _bench_page(tmp, Path(results_root), result_dict(result))
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
    results = _load_results(root)
    passed = sum(data.get("passed") is True for data in results)
    known = sum(data.get("passed") is True and bool(data.get("known")) for data in results)
    page = _INDEX_TEMPLATE.format(
        verdict_styles=_VERDICT_STYLES,
        summary=html.escape(
            f"{passed} of {len(results)} benches passed"
            + (f" ({known} with known deviations from the thesis)" if known else "")
        ),
        rows="\n".join(_index_row(root, data) for data in results),
    )
    target = root / INDEX_HTML
    write_text_atomic(target, page)
    return target


def format_table(results: list[BenchResult | dict[str, Any]]) -> str:
    """The plain-text pass/fail table: one line per bench, then one indented line per metric.

    Dicts are taken in the result.json format.
    """
    header = ("bench / metric", "value", "reference", "tolerance", "result")
    lines: list[tuple[str, ...] | str] = [header]  # tuples are table rows, strings are printed as they are
    for item in results:
        data = result_dict(item) if isinstance(item, BenchResult) else item
        lines.append((str(data["bench"]), "", "", "", _verdict(data.get("passed"), data.get("known"))))
        if data.get("error"):
            lines.append("  error: " + str(data["error"]).replace("\n", "\n  "))
        for name, m in data.get("metrics", {}).items():
            unit = f" {m['unit']}" if m.get("unit") else ""
            lines.append(
                (
                    f"  {name}",
                    _fmt(m.get("value")) + unit,
                    _fmt(m.get("reference")) + unit,
                    "+/-" + _fmt(m.get("tolerance")) + unit,
                    _verdict(m.get("pass"), m.get("known")),
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


def _check_plot(plot: Plot, where: str) -> None:
    if not _PLOT_FILE.fullmatch(plot.filename):
        raise WrsimError(f"{where}: the file name must be a plain name ending in .png")
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
    esc = html.escape
    head = "".join(f"<th>{esc(c)}</th>" for c in grid.columns)
    body = "\n".join(
        "<tr>"
        + "".join(f'<td class="{"fail" if str(c).startswith("FAIL") else ""}">{esc(str(c))}</td>' for c in row)
        + "</tr>"
        for row in grid.rows
    )
    (folder / grid.html_name).write_text(
        f'<!DOCTYPE html><html><head><meta charset="utf-8"><title>{esc(grid.title)}</title><style>'
        "table{border-collapse:collapse}td,th{border:1px solid #999;padding:2px 6px}.fail{background:#fcc}"
        f"</style></head><body><h1>{esc(grid.title)}</h1><table><tr>{head}</tr>\n{body}</table></body></html>\n",
        encoding="utf-8",
    )


def _write_json(path: Path, data: dict[str, Any]) -> None:
    path.write_text(json.dumps(data, indent=2, allow_nan=False) + "\n", encoding="utf-8")


def _write_plot(path: Path, plot: Plot) -> None:
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
            }
            for m in result.metrics
        },
        "plots": [
            entry
            for p in result.plots
            for entry in (
                [{"title": p.title, "file": p.html_name}, {"title": f"{p.title} (CSV)", "file": p.filename}]
                if isinstance(p, Grid)
                else [{"title": p.title, "file": p.filename}]
            )
        ],
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


def _metric_items(folder: Path, data: dict[str, Any]) -> list[str]:
    """The metrics of a result as HTML list items (a known deviation links its doc, relative to `folder`)."""
    esc = html.escape
    items = []
    for name, m in data.get("metrics", {}).items():
        unit = esc(f" {m['unit']}" if m.get("unit") else "")
        items.append(
            f'<li class="{_verdict(m.get("pass"), m.get("known")).lower()}">{esc(name)}: {_fmt(m.get("value"))}{unit} '
            f"(reference {_fmt(m.get('reference'))}{unit} &plusmn; {_fmt(m.get('tolerance'))}{unit})"
            + (f" &mdash; {esc(m['note'])}" if m.get("note") else "")
            + (_known_html(folder, m["known"]) if m.get("known") and not m.get("pass") else "")
            + "</li>"
        )
    return items


def _bench_page(folder: Path, root: Path, data: dict[str, Any]) -> None:
    """<bench>/index.html: the verdict, the metrics, every plot and the files of one bench."""
    esc = html.escape
    verdict = _verdict(data.get("passed"), data.get("known"))
    images = "".join(
        f'<h3>{esc(p["title"])}</h3><img src="{esc(quote(p["file"]))}" alt="{esc(p["title"])}">'
        for p in data.get("plots", [])
        if p["file"].endswith(".png")
    )
    tables = [p for p in data.get("plots", []) if not p["file"].endswith(".png")]
    files = (
        [(p["title"], p["file"]) for p in tables]
        + [(f, f) for f in (WAVEFORMS_CSV, WAVEFORMS_MF4) if (folder / f).exists()]
        + [(RESULT_JSON, RESULT_JSON)]
    )
    links = " | ".join(f'<a href="{esc(quote(f))}">{esc(t)}</a>' for t, f in files)
    page = _BENCH_TEMPLATE.format(
        bench=esc(data["bench"]),
        verdict=verdict,
        css=verdict.lower(),
        verdict_styles=_VERDICT_STYLES,
        description=esc(str(data.get("description") or "")),
        metrics="".join(_metric_items(root / data["bench"], data)),
        images=images,
        links=links,
    )
    (folder / INDEX_HTML).write_text(page, encoding="utf-8")


def _index_row(root: Path, data: dict[str, Any]) -> str:
    bench = data["bench"]
    esc = html.escape
    metrics = _metric_items(root, data)
    if data.get("error"):
        metrics.append(f'<li class="fail"><pre>{esc(str(data["error"]))}</pre></li>')
    if data.get("failure"):
        failure = data["failure"]
        metrics.insert(
            0,
            f'<li class="fail">the latest run ({esc(str(failure.get("time", "")))}) failed; the metrics '
            f"below are the last good result:<pre>{esc(str(failure.get('error')))}</pre></li>",
        )
    files = [(p["title"] or p["file"], p["file"]) for p in data.get("plots", []) if p.get("file")]
    files += [(f, f) for f in (WAVEFORMS_CSV, WAVEFORMS_MF4) if (root / bench / f).exists()]
    files.append((RESULT_JSON, RESULT_JSON))
    links = "<br>".join(f'<a href="{esc(quote(bench))}/{esc(quote(f))}">{esc(t)}</a>' for t, f in files)
    verdict = _verdict(data.get("passed"), data.get("known"))
    description = esc(str(data.get("description") or ""))
    measurement = f"<br><small>vs. {esc(str(data['measurement']))}</small>" if data.get("measurement") else ""
    title = (
        f'<a href="{esc(quote(bench))}/{INDEX_HTML}">{esc(bench)}</a>'
        if (root / bench / INDEX_HTML).exists()
        else esc(bench)
    )
    return (
        f"<tr><td><b>{title}</b><br><small>{description}</small>{measurement}</td>"
        f'<td class="{verdict.lower()}">{verdict}</td>'
        f"<td><ul>{''.join(metrics)}</ul></td><td>{links}</td></tr>"
    )


def bench_verdict(result: BenchResult) -> str:
    """PASS, KNOWN or FAIL of a bench result, as the summary table and the index show it."""
    return _verdict(result.passed, any(m.known and not m.passed for m in result.metrics))


def _verdict(passed: object, known: object = False) -> str:
    """PASS, KNOWN (a failing metric, or a bench whose only failures, the docs explain) or FAIL."""
    if passed is True:
        return "KNOWN" if known else "PASS"
    return "KNOWN" if known else "FAIL"


def _known_html(root: Path, known: str) -> str:
    """A known deviation's reason with a link to the doc that explains it (relative to the results folder)."""
    reason, _, doc = known.rpartition(" (")
    doc = doc.removesuffix(")")
    file, _, anchor = doc.partition("#")
    href = quote(os.path.relpath(paths.ROOT / file, root)) + (f"#{anchor}" if anchor else "")
    return f' &mdash; KNOWN: {html.escape(reason)} (<a href="{html.escape(href)}">{html.escape(doc)}</a>)'


def _metadata(result: BenchResult) -> dict[str, str]:
    """What an MDF4 file of `result` says about itself (its header comment)."""
    return {
        "bench": result.bench,
        "description": " ".join(result.description.split()),
        "verdict": bench_verdict(result),
        "measurement": result.measurement or "",
        "program": "wrsim",
    }


def _fmt(x: object) -> str:
    return "n/a" if x is None else f"{x:.4g}"


_VERDICT_STYLES = ".pass { color: #070; }\n.fail { color: #b00; }\n.known { color: #a60; }"

_BENCH_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{bench}: wrsim bench result</title>
<style>
body {{ font-family: sans-serif; }}
img {{ max-width: 100%; }}
{verdict_styles}
</style>
</head>
<body>
<p><a href="../index.html">all benches</a></p>
<h1>{bench}: <span class="{css}">{verdict}</span></h1>
<p>{description}</p>
<ul>{metrics}</ul>
<p>{links}</p>
{images}
</body>
</html>
"""

_INDEX_TEMPLATE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>wrsim bench results</title>
<style>
body {{ font-family: sans-serif; }}
table {{ border-collapse: collapse; }}
td, th {{ border: 1px solid #ccc; padding: 4px 8px; vertical-align: top; text-align: left; }}
ul {{ margin: 0; padding-left: 1.2em; }}
{verdict_styles}
</style>
</head>
<body>
<h1>wrsim bench results</h1>
<p>{summary}</p>
<table>
<tr><th>bench</th><th>result</th><th>metrics (value, reference &plusmn; tolerance)</th><th>files</th></tr>
{rows}
</table>
</body>
</html>
"""
