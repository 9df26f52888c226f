"""The HTML pages of a results folder: the dashboard (index.html, one row per bench), a bench's page (verdict,
metrics as a table, heat maps of its test matrices, interactive waveforms) and a table's own page. Every text that
reaches HTML is escaped here (descriptions from parameter files and VHDL comments, identifiers, file names)."""

from __future__ import annotations

import html
import math
import os
from pathlib import Path
from typing import Any
from urllib.parse import quote

from wrsim import paths
from wrsim.report import interactive
from wrsim.results import Grid, Plot

__all__ = [
    "verdict",
    "value_text",
    "requirement_text",
    "bench_page",
    "plots_page",
    "index_page",
    "grid_page",
    "grid_table",
]

esc = html.escape

INDEX_HTML = "index.html"


def verdict(passed: object, known: object = False) -> str:
    """PASS, KNOWN (a failing metric, or a bench whose only failures, the docs explain) or FAIL."""
    if passed is True:
        return "KNOWN" if known else "PASS"
    return "KNOWN" if known else "FAIL"


def _fmt(x: object) -> str:
    return "n/a" if not isinstance(x, int | float) or not math.isfinite(x) else f"{x:.4g}"


def value_text(m: dict[str, Any]) -> str:
    """A metric's value with its unit once: `47.6 N`, a flag as yes / no."""
    if m.get("kind") == "flag":
        return "n/a" if m.get("value") is None else "yes" if m["value"] >= 0.5 else "no"
    unit = m.get("unit") or ""
    return _fmt(m.get("value")) + (f" {unit}" if unit and unit != "1" else "")


def requirement_text(m: dict[str, Any], measured: bool = False) -> str:
    """What a metric is held to: `<= 100 N` (a limit), `yes` (a flag), `50 +- 7.5 N`; with `measured` (the
    reference is a measurement) also the deviation from it in %."""
    unit = m.get("unit") or ""
    unit = f" {unit}" if unit and unit != "1" else ""
    reference, tolerance = m.get("reference"), m.get("tolerance")
    if m.get("kind") == "flag":
        return "n/a" if reference is None else "yes" if reference >= 0.5 else "no"
    if m.get("kind") == "limit" and reference is not None and tolerance is not None:
        return f"<= {_fmt(reference + tolerance)}{unit}"
    text = f"{_fmt(reference)} +- {_fmt(tolerance)}{unit}"
    value = m.get("value")
    if measured and isinstance(value, int | float) and isinstance(reference, int | float) and reference:
        text += f" ({(value / reference - 1.0) * 100.0:+.1f} %)"
    return text


def _known_html(root: Path, known: str) -> str:
    """A known deviation's reason with a link to the doc that explains it (relative to the results folder)."""
    reason, _, doc = known.rpartition(" (")
    doc = doc.removesuffix(")")
    file, _, anchor = doc.partition("#")
    href = quote(os.path.relpath(paths.ROOT / file, root)) + (f"#{anchor}" if anchor else "")
    return f'KNOWN: {esc(reason)} (<a href="{esc(href)}">{esc(doc)}</a>)'


def _metric_rows(folder: Path, data: dict[str, Any]) -> str:
    """The metrics of a result as table rows: name, value, requirement, verdict, note (a known deviation links its
    doc, relative to `folder`)."""
    measured = bool(data.get("measurement"))
    rows = []
    for name, m in data.get("metrics", {}).items():
        v = verdict(m.get("pass"), m.get("known"))
        note = esc(m.get("note") or "")
        if m.get("known") and not m.get("pass"):
            note = (note + "<br>" if note else "") + _known_html(folder, m["known"])
        rows.append(
            f'<tr><td>{esc(name)}</td><td class="num">{esc(value_text(m))}</td>'
            f'<td class="req">{esc(requirement_text(m, measured))}</td>'
            f'<td class="{v.lower()}">{v}</td><td><small>{note}</small></td></tr>'
        )
    return "\n".join(rows)


def _shade(margin: float | None, scale: float) -> str:
    """A cell's background for a margin: red below 0, white at 0, green at `scale` and above."""
    if margin is None or not math.isfinite(margin):
        return ""
    if margin < 0:
        return "background:#f4a6a6"
    g = min(margin / scale, 1.0) if scale > 0 else 1.0
    r, gr, b = (round(255 - (255 - c) * g) for c in (120, 200, 120))
    return f"background:rgb({r},{gr},{b})"


def grid_table(grid: Grid) -> str:
    """A table as HTML: a heat map of its margins when it has them; cells that start with FAIL are marked (a
    thick red frame over any colour), INFO cells greyed."""
    head = "".join(f"<th>{esc(c)}</th>" for c in grid.columns)
    body = []
    for k, row in enumerate(grid.rows):
        cells = []
        for j, cell in enumerate(row):
            text = str(cell)
            margin = grid.margins[k][j] if grid.margins else None
            css = "fail" if text.startswith("FAIL") else "info" if text.startswith("INFO") else ""
            style = _shade(margin, grid.scale)
            link = grid.links[k][j] if grid.links else None
            shown = f'<a href="{esc(quote(link))}">{esc(text)}</a>' if link else esc(text)
            cells.append(f'<td class="{css}"' + (f' style="{style}"' if style else "") + f">{shown}</td>")
        body.append("<tr>" + "".join(cells) + "</tr>")
    legend = (
        f'<p class="legend">colour: the margin to the limit, red below 0, green from {grid.scale:g} up; '
        "a red frame: FAIL; grey: information</p>"
        if grid.margins
        else ""
    )
    return f'<table class="grid"><tr>{head}</tr>\n' + "\n".join(body) + f"</table>{legend}"


def grid_page(grid: Grid) -> str:
    """A table's own page (<name>.html beside its CSV)."""
    return (
        f'<!DOCTYPE html><html lang="en"><head><meta charset="utf-8"><title>{esc(grid.title)}</title>'
        f"<style>{_STYLE}</style></head><body><h1>{esc(grid.title)}</h1>{grid_table(grid)}</body></html>\n"
    )


def bench_page(folder: Path, root: Path, data: dict[str, Any], plots: list[Plot | Grid]) -> str:
    """<bench>/index.html: the verdict, the metrics, each table (as a heat map when it has margins) and each plot
    interactive (its PNG linked), and the files. `folder` holds the files (the page's until it is published),
    `root` is the results folder."""
    v = verdict(data.get("passed"), data.get("known"))
    sections = []
    for k, p in enumerate(plots):
        if isinstance(p, Plot) and p.page:
            continue  # on its own page, which the bench's tables link
        if isinstance(p, Grid):
            sections.append(
                f"<h2>{esc(p.title)}</h2>{grid_table(p)}"
                f'<p><a href="{esc(quote(p.filename))}">CSV</a> | <a href="{esc(quote(p.html_name))}">own page</a></p>'
            )
        else:
            sections.append(
                f"<h2>{esc(p.title)}</h2>{interactive.figure_html(p, f'plot{k}')}"
                f'<p><a href="{esc(quote(p.filename))}">PNG</a></p>'
            )
    files = [(f, f) for f in ("waveforms.csv", "waveforms.mf4", "result.json") if (folder / f).exists()]
    links = " | ".join(f'<a href="{esc(quote(f))}">{esc(t)}</a>' for t, f in files)
    metrics = _metric_rows(root / str(data["bench"]), data)  # links from where the page ends up
    table = (
        f"<table><tr><th>metric</th><th>value</th><th>required</th><th>result</th><th>note</th></tr>\n{metrics}</table>"
        if metrics
        else ""
    )
    if table and any(isinstance(p, Grid) for p in plots):  # the matrix says it at a glance; each metric a click away
        table = f"<details><summary>the {len(data.get('metrics', {}))} metrics one by one</summary>{table}</details>"
    measurement = f"<p>measured reference: {esc(str(data['measurement']))}</p>" if data.get("measurement") else ""
    script = interactive.script_tag(1) if any(isinstance(p, Plot) and not p.page for p in plots) else ""
    return (
        f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n'
        f"<title>{esc(str(data['bench']))}: wrsim result</title>\n<style>{_STYLE}</style>\n{script}\n</head>\n<body>\n"
        f'<p><a href="../{INDEX_HTML}">all results</a></p>\n'
        f'<h1>{esc(str(data["bench"]))}: <span class="{v.lower()}">{v}</span></h1>\n'
        f"<p>{esc(str(data.get('description') or ''))}</p>\n{measurement}{table}\n<p>{links}</p>\n"
        + "\n".join(sections)
        + "\n</body>\n</html>\n"
    )


def plots_page(bench: str, plots: list[Plot]) -> str:
    """A page of its own beside a bench's page (in its folder): `plots`, interactive."""
    title = esc(plots[0].page.removesuffix(".html"))
    figures = "\n".join(f"<h2>{esc(p.title)}</h2>{interactive.figure_html(p, f'plot{k}')}" for k, p in enumerate(plots))
    return (
        f'<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>{esc(bench)}: {title}</title>\n'
        f"<style>{_STYLE}</style>\n{interactive.script_tag(1)}\n</head>\n<body>\n"
        f'<p><a href="{INDEX_HTML}">{esc(bench)}</a> | <a href="../{INDEX_HTML}">all results</a></p>\n'
        f"<h1>{esc(bench)}: {title}</h1>\n{figures}\n</body>\n</html>\n"
    )


def _index_row(root: Path, data: dict[str, Any]) -> str:
    """One bench on the dashboard: name and description, verdict, counts of its metrics by verdict, its headline
    numbers (three metrics, failing and known ones first), the time it took, and the latest failure."""
    bench = str(data["bench"])
    metrics = data.get("metrics", {})
    counts = {k: 0 for k in ("PASS", "KNOWN", "FAIL")}
    for m in metrics.values():
        counts[verdict(m.get("pass"), m.get("known"))] += 1
    first = sorted(metrics.items(), key=lambda item: verdict(item[1].get("pass"), item[1].get("known")) == "PASS")
    headline = "<br>".join(  # the failing and known metrics first
        f'<span class="{verdict(m.get("pass"), m.get("known")).lower()}">{esc(name)}: {esc(value_text(m))}</span>'
        for name, m in first[:3]
    )
    problems = []
    if data.get("failure"):
        failure = data["failure"]
        problems.append(
            f"the latest run ({esc(str(failure.get('time', '')))}) failed, the numbers are the last good result: "
            f"<pre>{esc(str(failure.get('error')))}</pre>"
        )
    elif data.get("error"):
        problems.append(f"<pre>{esc(str(data['error']))}</pre>")
    timings = data.get("timings") or {}
    seconds = sum(t for t in timings.values() if isinstance(t, int | float))
    v = verdict(data.get("passed"), data.get("known"))
    page = root / bench / INDEX_HTML
    title = f'<a href="{esc(quote(bench))}/{INDEX_HTML}">{esc(bench)}</a>' if page.exists() else esc(bench)
    return (
        f"<tr><td><b>{title}</b><br><small>{esc(str(data.get('description') or ''))}</small></td>"
        f'<td class="{v.lower()}"><b>{v}</b></td>'
        f'<td class="num"><span class="pass">{counts["PASS"]}</span> / <span class="known">{counts["KNOWN"]}</span>'
        f' / <span class="fail">{counts["FAIL"]}</span></td>'
        f"<td>{headline}{''.join(problems)}</td>"
        f'<td class="num">{f"{seconds:.1f} s" if seconds else ""}</td></tr>'
    )


def index_page(root: Path, results: list[dict[str, Any]]) -> str:
    """The dashboard of a results folder: a summary and one row per bench, details one click away."""
    tally = {k: 0 for k in ("PASS", "KNOWN", "FAIL")}
    for data in results:
        tally[verdict(data.get("passed"), data.get("known"))] += 1
    summary = ", ".join(f'<span class="{k.lower()}">{n} {k}</span>' for k, n in tally.items())
    rows = "\n".join(_index_row(root, data) for data in results)
    return (
        '<!DOCTYPE html>\n<html lang="en">\n<head>\n<meta charset="utf-8">\n<title>wrsim results</title>\n'
        f"<style>{_STYLE}</style>\n</head>\n<body>\n<h1>wrsim results</h1>\n<p>{len(results)} benches: {summary}</p>\n"
        "<table>\n<tr><th>bench</th><th>result</th><th>metrics PASS / KNOWN / FAIL</th><th>headline</th>"
        f"<th>time</th></tr>\n{rows}\n</table>\n</body>\n</html>\n"
    )


_STYLE = """
body { font-family: sans-serif; margin: 1em 2em; }
table { border-collapse: collapse; margin: 0.5em 0; }
td, th { border: 1px solid #ccc; padding: 3px 8px; vertical-align: top; text-align: left; }
th { background: #f3f3f3; }
td.num { text-align: right; white-space: nowrap; }
td.req { white-space: nowrap; }
pre { white-space: pre-wrap; margin: 0.3em 0; }
.pass { color: #070; }
.fail { color: #b00; }
.known { color: #a60; }
table.grid td.fail { outline: 3px solid #b00; outline-offset: -3px; color: inherit; font-weight: bold; }
table.grid td.info { color: #777; }
.legend { font-size: small; color: #555; }
.plot { width: 100%; max-width: 1200px; }
"""
