"""A tolerance study's statistics and its page: per output the percentiles, Cpk against its specification limits
(or, for a yes/no output such as a false reversal, the probability with its 95 % Clopper-Pearson interval), the
samples nearest to or beyond a limit (re-runnable by id), histograms, and for a sensitivity study the
one-at-a-time effects ranked (a tornado chart)."""

from __future__ import annotations

import html
import math
import shlex
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim.data.atomic import write_text_atomic
from wrsim.study.study import Study, effects_of

__all__ = ["OutputStats", "statistics", "write_study_page"]

PERCENTILES = (1, 5, 50, 95, 99)
_WORST = 5  # samples listed per output


@dataclass(frozen=True)
class OutputStats:
    """The distribution of one output over a study's samples that ran."""

    name: str
    unit: str
    n: int  # samples with a value
    mean: float
    std: float  # sample standard deviation
    minimum: float
    maximum: float
    percentiles: dict[int, float]
    lower: float | None  # specification limits
    upper: float | None
    outside: int  # samples beyond a limit
    cpk: float | None  # None: no limit, or a yes/no output
    probability: tuple[float, float, float] | None  # yes/no output: share of 1, 95 % interval
    worst: list[tuple[int, float]]  # (sample, value) nearest to or beyond a limit, else the extremes
    note: str


def _limits(study: Study, name: str) -> tuple[float | None, float | None]:
    given = {n: (lo, hi) for n, lo, hi in study.spec.limits}
    meta = study.outputs[name]
    return given.get(name, (meta["lower"], meta["upper"]))


def statistics(study: Study) -> list[OutputStats]:
    """Every output's statistics over the samples that produced it."""
    from scipy.stats import binomtest

    ids = np.array(sorted(study.rows))
    out = []
    for name, meta in study.outputs.items():
        values = study.values(name)
        ok = np.isfinite(values)
        v, vid = values[ok], ids[ok]
        if v.size == 0:
            continue
        lower, upper = _limits(study, name)
        std = float(np.std(v, ddof=1)) if v.size > 1 else 0.0
        mean = float(np.mean(v))
        binary = bool(np.all((v == 0.0) | (v == 1.0)))
        outside = int(np.sum((v < lower) if lower is not None else 0) + np.sum((v > upper) if upper is not None else 0))
        cpk = probability = None
        if binary:
            k = int(v.sum())
            ci = binomtest(k, v.size).proportion_ci(0.95)
            probability = (k / v.size, float(ci.low), float(ci.high))
        elif lower is not None or upper is not None:
            side = min(upper - mean if upper is not None else math.inf, mean - lower if lower is not None else math.inf)
            cpk = side / (3.0 * std) if std > 0 else math.inf
        if lower is not None or upper is not None:
            margin = np.minimum(upper - v if upper is not None else np.inf, v - lower if lower is not None else np.inf)
            order = np.argsort(margin, kind="stable")[:_WORST]
        else:
            order = np.unique([int(np.argmin(v)), int(np.argmax(v))])
        out.append(
            OutputStats(
                name,
                meta["unit"],
                int(v.size),
                mean,
                std,
                float(v.min()),
                float(v.max()),
                {p: float(np.percentile(v, p)) for p in PERCENTILES},
                lower,
                upper,
                outside,
                cpk,
                probability,
                [(int(vid[k]), float(v[k])) for k in order],
                meta["note"],
            )
        )
    return out


def _fmt(x: float | None) -> str:
    if x is None:
        return "-"
    if math.isinf(x):
        return "inf"
    return f"{x:.4g}"


def _histogram(path: Path, s: OutputStats, values: np.ndarray) -> None:
    from matplotlib.figure import Figure

    fig = Figure(figsize=(5.0, 3.2))
    ax = fig.add_subplot()
    ax.hist(values[np.isfinite(values)], bins=min(40, max(5, int(math.sqrt(s.n)))), color="#4a7ab5")
    for limit in (s.lower, s.upper):
        if limit is not None:
            ax.axvline(limit, color="#c0392b", linestyle="--")
    ax.set_xlabel(f"{s.name} [{s.unit}]")
    ax.set_ylabel("samples")
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def _tornado(path: Path, output: str, effects: dict[str, float], unit: str) -> None:
    from matplotlib.figure import Figure

    ranked = sorted(((abs(e), f, e) for f, e in effects.items() if math.isfinite(e)), reverse=True)[:15]
    fig = Figure(figsize=(6.0, 0.35 * len(ranked) + 1.2))
    ax = fig.add_subplot()
    ax.barh([f for _, f, _ in ranked][::-1], [e for _, _, e in ranked][::-1], color="#4a7ab5")
    ax.set_xlabel(f"{output}: high limit minus low limit [{unit}]")
    fig.tight_layout()
    fig.savefig(path, dpi=90)


def _rerun(study: Study, sample: int) -> str:
    spec = study.spec
    args = ["wrsim", "study", spec.bench, "--method", spec.method, "--seed", str(spec.seed), "--rerun", str(sample)]
    args += [a for p in spec.params for a in ("--params", p)] + [a for r in spec.runs for a in ("--run", r)]
    args += [a for g, v in spec.generics for a in ("--set", f"{g}={v:g}")]
    args += ["--stop", f"{spec.stop:g}"] if spec.stop else []
    args += ["--name", spec.name] if spec.name else []
    return shlex.join(args)


def write_study_page(study: Study) -> Path:
    """Write `study.html` with its images and `statistics.csv` into the study's folder; returns the page."""
    folder = study.folder
    folder.mkdir(parents=True, exist_ok=True)
    stats = statistics(study)
    spec = study.spec
    e = html.escape
    done = len(study.rows) - len(study.failed())
    parts = [
        f"<h1>Tolerance study {e(spec.folder_name)}</h1>",
        f"<p>bench <b>{e(spec.bench)}</b>{' (runs ' + e(', '.join(spec.runs)) + ')' if spec.runs else ''}; "
        f"method {e(spec.method)}; seed {spec.seed}; parameter sets laid over the bench's: "
        f"{e(', '.join(spec.params)) or 'none'}; top-level generics: "
        f"{e(', '.join(f'{g}={v:g}' for g, v in spec.generics)) or 'the bench' + chr(39) + 's'}; "
        f"{done} samples ran, {len(study.failed())} failed. Results: <a href='samples.parquet'>samples.parquet"
        f"</a> (one row per sample: factors in:..., outputs out:...).</p>",
        "<h2>Factors</h2><table><tr><th>factor</th><th>nominal</th><th>law</th><th>from</th></tr>",
    ]
    for f in study.factors:
        t = f.tolerance
        law = (
            f"normal, +-{t.deviation * 100 if t.relative else t.deviation:g} {'%' if t.relative else t.unit} = "
            f"{t.sigmas:g} sigma"
            if t.law == "normal"
            else f"uniform {t.limits[0]:g} .. {t.limits[1]:g} {t.unit}"
            if t.limits
            else f"uniform +-{t.deviation * 100 if t.relative else t.deviation:g} {'%' if t.relative else t.unit}"
            if t.law == "uniform"
            else f"rows of {t.source}"
        )
        group = f"; group {t.group} ({t.rho:g})" if t.group else ""
        parts.append(
            f"<tr><td>{e(f.name)}</td><td>{e(str(f.nominal))} {e(f.unit)}</td><td>{e(law + group)}</td>"
            f"<td>{e(t.file)}:{t.line}</td></tr>"
        )
    parts.append(
        "</table><h2>Outputs</h2><table><tr><th>output</th><th>unit</th><th>n</th><th>mean</th><th>std</th>"
        + "".join(f"<th>p{p}</th>" for p in PERCENTILES)
        + "<th>min</th><th>max</th><th>limits</th><th>outside</th><th>Cpk / P(1) [95 %]</th></tr>"
    )
    csv = [
        "output,unit,n,mean,std," + ",".join(f"p{p}" for p in PERCENTILES) + ",min,max,lower,upper,outside,cpk,"
        "probability,probability_low,probability_high"
    ]
    for s in stats:
        limits = f"{_fmt(s.lower)} .. {_fmt(s.upper)}"
        quality = (
            f"P = {s.probability[0]:.3f} [{s.probability[1]:.3f}, {s.probability[2]:.3f}]"
            if s.probability
            else _fmt(s.cpk)
        )
        bad = " class='fail'" if s.outside else ""
        parts.append(
            f"<tr{bad}><td><a href='#{e(_slug(s.name))}'>{e(s.name)}</a></td><td>{e(s.unit)}</td>"
            f"<td>{s.n}</td><td>{_fmt(s.mean)}</td><td>{_fmt(s.std)}</td>"
            + "".join(f"<td>{_fmt(s.percentiles[p])}</td>" for p in PERCENTILES)
            + f"<td>{_fmt(s.minimum)}</td><td>{_fmt(s.maximum)}</td><td>{e(limits)}</td>"
            f"<td>{s.outside}</td><td>{e(quality)}</td></tr>"
        )
        p = s.probability or (None, None, None)
        csv.append(
            ",".join(
                [_csv(s.name), _csv(s.unit), str(s.n)]
                + [_fmt(x) for x in (s.mean, s.std, *s.percentiles.values(), s.minimum, s.maximum, s.lower, s.upper)]
                + [str(s.outside), _fmt(s.cpk), _fmt(p[0]), _fmt(p[1]), _fmt(p[2])]
            )
        )
    parts.append("</table>")
    if spec.method != "montecarlo":
        parts += _sensitivity_section(study, folder)
    for s in stats:
        png = f"hist_{_slug(s.name)}.png"
        _histogram(folder / png, s, study.values(s.name))
        worst = "".join(
            f"<li>sample {k} ({e(study.rows[k]['label'])}): {_fmt(v)} {e(s.unit)} &mdash; "
            f"<code>{e(_rerun(study, k))}</code></li>"
            for k, v in s.worst
        )
        which = "nearest to the limits" if s.lower is not None or s.upper is not None else "extremes"
        parts.append(
            f"<h3 id='{e(_slug(s.name))}'>{e(s.name)}</h3><p>{e(s.note)}</p><img src='{png}' "
            f"alt='{e(s.name)}'><p>{which}:</p><ul>{worst}</ul>"
        )
    if study.failed():
        parts.append(
            "<h2>Failed samples</h2><ul>"
            + "".join(f"<li>sample {r['sample']} ({e(r['label'])}): {e(r['error'])}</li>" for r in study.failed())
            + "</ul>"
        )
    style = (
        "body{font-family:sans-serif;margin:2em}table{border-collapse:collapse}td,th{border:1px solid #bbb;"
        "padding:2px 6px;text-align:right}td:first-child{text-align:left}tr.fail td{background:#fbe3e1}"
    )
    page = folder / "study.html"
    write_text_atomic(folder / "statistics.csv", "\n".join(csv) + "\n")
    write_text_atomic(
        page,
        f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{e(spec.folder_name)}"
        f"</title><style>{style}</style></head><body>{''.join(parts)}</body></html>\n",
    )
    return page


def _sensitivity_section(study: Study, folder: Path) -> list[str]:
    effects = effects_of(study)
    parts = [
        "<h2>One-at-a-time sensitivity</h2><p>Each factor alone at its low and its high tolerance limit, the "
        "others nominal; the effect is the output at the high limit minus the output at the low one, ranked by "
        "size.</p>"
    ]
    for output, effect in effects.items():
        unit = study.outputs[output]["unit"]
        png = f"tornado_{_slug(output)}.png"
        _tornado(folder / png, output, effect, unit)
        parts.append(f"<h3>{html.escape(output)}</h3><img src='{png}' alt='{html.escape(output)} sensitivity'>")
    corners = [r for r in study.rows.values() if r["label"].endswith((" lowest", " highest"))]
    if corners:
        parts.append(
            "<h2>Worst-case corners</h2><p>Every factor at the limit that moves the output that way "
            "(from its one-at-a-time effect).</p><table><tr><th>corner</th><th>value</th></tr>"
        )
        for r in sorted(corners, key=lambda r: r["sample"]):
            output = r["label"].rsplit(" ", 1)[0]
            value = r["outputs"].get(output)
            parts.append(
                f"<tr><td>{html.escape(r['label'])}</td><td>"
                f"{html.escape(r['error']) if r['error'] else _fmt(value)}</td></tr>"
            )
        parts.append("</table>")
    return parts


def _slug(name: str) -> str:
    return "".join(c if c.isalnum() else "_" for c in name).strip("_")[:60]


def _csv(text: str) -> str:
    return f'"{text}"' if "," in text or '"' in text else text
