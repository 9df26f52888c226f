"""Interactive waveforms in the HTML report: each Plot becomes a plotly.js figure (zoom, pan, several signals on a
shared time axis, a cursor that reads every signal's value, measured points as markers, the legend from the
signals' names and units) inlined in its page as JSON. The JavaScript is the copy bundled in the `plotly` Python
package, written once into a results folder's `_static/` and loaded from there, so pages open from file:// without
network. Long runs are decimated for display (the smallest and largest value of each pixel column, in time
order); the CSV and MDF4 files keep every point."""

from __future__ import annotations

import html
import importlib.resources
import json
import math
from pathlib import Path
from typing import Any

import numpy as np

from wrsim.data.atomic import write_bytes_atomic
from wrsim.results import Plot, Signal

__all__ = ["STATIC", "PLOTLY_JS", "COLUMNS", "install_script", "script_tag", "figure", "figure_html", "decimate"]

STATIC = "_static"  # the results folder's subfolder of shared page resources
PLOTLY_JS = "plotly.min.js"
COLUMNS = 1200  # pixel columns a trace is decimated to (two points each)
_COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf", "#bcbd22", "#7f7f7f"]
_MARKERS = ["circle", "square", "diamond", "triangle-up", "triangle-down", "x", "cross"]


def install_script(results_root: Path) -> Path:
    """Write plotly.js (the `plotly` package's bundled copy) to results_root/_static/ unless the same is there."""
    source = importlib.resources.files("plotly") / "package_data" / PLOTLY_JS
    data = source.read_bytes()
    target = Path(results_root) / STATIC / PLOTLY_JS
    if not (target.is_file() and target.stat().st_size == len(data) and target.read_bytes() == data):
        target.parent.mkdir(parents=True, exist_ok=True)
        write_bytes_atomic(target, data)
    return target


def script_tag(depth: int) -> str:
    """The <script> element that loads plotly.js from a page `depth` folders below the results folder."""
    return f'<script src="{"../" * depth}{STATIC}/{PLOTLY_JS}"></script>'


def decimate(x: np.ndarray, y: np.ndarray, columns: int = COLUMNS) -> tuple[np.ndarray, np.ndarray]:
    """`x`, `y` with at most 2 * `columns` points: per column of equal x width, the points of the smallest and the
    largest y, in x order (every point when there are fewer). A column of only non-finite values keeps one of them
    (a gap in the line)."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    if len(x) <= 2 * columns or not np.all(np.isfinite(x)) or x[-1] <= x[0]:
        return x, y
    bucket = np.minimum(((x - x[0]) / (x[-1] - x[0]) * columns).astype(int), columns - 1)
    starts = np.flatnonzero(np.r_[True, bucket[1:] != bucket[:-1]])
    ends = np.r_[starts[1:], len(x)]
    finite = np.where(np.isfinite(y), y, np.nan)
    keep = [0, len(x) - 1]
    for a, b in zip(starts.tolist(), ends.tolist()):
        part = finite[a:b]
        if np.all(np.isnan(part)):
            keep.append(a)
            continue
        keep += [a + int(np.nanargmin(part)), a + int(np.nanargmax(part))]
    index = np.unique(keep)
    return x[index], y[index]


def _values(a: np.ndarray) -> list[float | None]:
    """JSON numbers, None (a gap) for a non-finite value."""
    return [float(v) if math.isfinite(v) else None for v in np.asarray(a, dtype=float)]


def _trace(x: Signal, y: Signal, axis: str, color: str, marker: str | None = None, name: str = "") -> dict[str, Any]:
    xs, ys = (x.values, y.values) if marker else decimate(x.values, y.values)
    trace: dict[str, Any] = {
        "type": "scattergl" if len(xs) > 5000 else "scatter",
        "x": _values(xs),
        "y": _values(ys),
        "name": html.escape(name or y.axis_label),  # plotly.js reads its texts as HTML
        "yaxis": "y2" if axis == "right" else "y",
        "hovertemplate": f"%{{y:.6g}} {html.escape(y.unit)}".rstrip() + "<extra>%{fullData.name}</extra>",
    }
    if marker:
        trace.update(mode="markers", marker={"symbol": marker, "size": 7, "color": color})
    else:
        trace.update(mode="lines", line={"color": color, "width": 1.5})
    return trace


def figure(plot: Plot) -> dict[str, Any]:
    """The plotly.js figure (data and layout) of `plot`: its signals as lines on the left and right axes, its
    overlays as markers, the x axis shared, a unified cursor over x."""
    colors = iter(_COLORS * 10)
    data = [
        _trace(plot.x, s, side, next(colors))
        for side, sigs in (("left", plot.left), ("right", plot.right))
        for s in sigs
    ]
    data += [
        _trace(ov.x, ov.y, ov.axis, next(colors), _MARKERS[k % len(_MARKERS)], ov.name)
        for k, ov in enumerate(plot.overlays)
    ]
    layout: dict[str, Any] = {
        "title": {"text": html.escape(plot.title)},
        "xaxis": {
            "title": {"text": html.escape(plot.x.axis_label)},
            "type": "log" if plot.logx else "linear",
            "showspikes": True,
            "spikemode": "across",
            "spikethickness": 1,
        },
        "yaxis": {"title": {"text": html.escape(", ".join(dict.fromkeys(s.axis_label for s in plot.left)))}},
        "hovermode": "x unified",
        "legend": {"orientation": "h", "y": -0.2},
        "margin": {"t": 50, "r": 60},
        "height": 480,
    }
    if plot.right or any(ov.axis == "right" for ov in plot.overlays):
        layout["yaxis2"] = {
            "title": {"text": html.escape(", ".join(dict.fromkeys(s.axis_label for s in plot.right)))},
            "overlaying": "y",
            "side": "right",
        }
    return {"data": data, "layout": layout}


def figure_html(plot: Plot, element_id: str) -> str:
    """A <div> and the script that draws `plot` in it (plotly.js must be loaded before: `script_tag`); the PNG of
    the same plot is linked below it."""
    spec = json.dumps(figure(plot), allow_nan=False, separators=(",", ":")).replace("</", "<\\/")
    config = json.dumps({"responsive": True, "scrollZoom": True, "displaylogo": False})
    return (
        f'<div class="plot" id="{html.escape(element_id)}"></div>'
        f"<script>(function(){{var f={spec};Plotly.newPlot({json.dumps(element_id)},f.data,f.layout,{config});}})();"
        f"</script>"
    )
