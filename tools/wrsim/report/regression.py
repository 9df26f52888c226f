"""Waveform regression: a bench's whole waveforms against its reference (testbenches/golden/<bench>.npz), each
inside a tolerance tube in time and value, the way Modelica's regression tests compare results (the funnel
algorithm, pyfunnel). A failing signal gets a page with the reference, the tube and the result, its violations
shaded and named by time range. `bless` replaces references only with a reason, recorded in
testbenches/golden/BLESSINGS.tsv.

The tube of a signal: TIME_TUBE of the bench's stop time along the time axis, VALUE_TUBE of the reference's
range (at least FLOOR of its largest magnitude, and at least RESOLUTION) along the value axis. References are
stored decimated (kept points reproduce every sample within DECIMATION of the value tube by linear interpolation)
and compressed."""

from __future__ import annotations

import csv
import datetime
import html
import json
import math
import os
import re
import subprocess
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import pyfunnel

from wrsim import paths
from wrsim.data.atomic import write_text_atomic
from wrsim.data.publish import publish_directory
from wrsim.errors import WrsimError
from wrsim.results import Signal

__all__ = [
    "TIME_TUBE",
    "VALUE_TUBE",
    "RESOLUTION",
    "Violation",
    "Regression",
    "reference_file",
    "compare",
    "bless",
    "decimate",
    "BLESSINGS",
]

TIME_TUBE = 2e-3  # of the bench's stop time
VALUE_TUBE = 5e-3  # of the reference's range
FLOOR = 1e-6  # of the reference's largest magnitude: the value tube of a constant signal
RESOLUTION = 1e-9  # [the signal's SI unit] the narrowest value tube: ngspice does not resolve less in wrsim's
# netlists (abstol 1e-9, vntol 1e-8 or more), and a signal that is 0 up to rounding (a gauge's force in a closing
# without an obstacle, +-3e-12 N) would otherwise compare its last bits, which another machine's libm may change
DECIMATION = 0.1  # of the value tube: how far the stored reference may stray from the simulated one
BLESSINGS = "BLESSINGS.tsv"


@dataclass(frozen=True)
class Violation:
    """Where a signal leaves its tube: from `start` to `end` [s], by at most `excess` (in the signal's unit)."""

    signal: str
    unit: str
    start: float
    end: float
    excess: float

    def __str__(self) -> str:
        how = (
            "defined where the reference is not, or the reverse"
            if math.isnan(self.excess)
            else f"by up to {self.excess:.3g} {self.unit}".rstrip()
        )
        return f"{self.signal}: outside its tube from {self.start:.4g} s to {self.end:.4g} s, {how}"


@dataclass
class Regression:
    """A bench's waveforms against its reference: signals compared, violations, reference signals the result
    lacks, and the page of every failing signal."""

    bench: str
    signals: int
    violations: list[Violation] = field(default_factory=list)
    missing: list[str] = field(default_factory=list)
    pages: list[Path] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return not self.violations and not self.missing

    def summary(self) -> str:
        if self.passed:
            return f"{self.bench}: {self.signals} signals within their tubes"
        lines = [
            f"{self.bench}: REGRESSION in {len({v.signal for v in self.violations}) + len(self.missing)} of "
            f"{self.signals} signals"
        ]
        lines += [f"  {v}" for v in self.violations]
        lines += [f"  {name}: in the reference, not in the result" for name in self.missing]
        lines += [f"  page: {p}" for p in self.pages]
        return "\n".join(lines)


def reference_file(bench: str, golden: Path = paths.GOLDEN) -> Path:
    return golden / f"{bench}.npz"


def decimate(t: np.ndarray, y: np.ndarray, tol: float) -> np.ndarray:
    """The indices of the samples to keep so that linear interpolation between them reproduces every sample
    within `tol` (Ramer-Douglas-Peucker on the values, first and last sample kept; NaN samples are kept)."""
    keep = np.zeros(len(t), dtype=bool)
    keep[[0, -1]] = True
    keep |= ~np.isfinite(y)
    stack = [(0, len(t) - 1)]
    while stack:
        a, b = stack.pop()
        if b - a < 2:
            continue
        seg = slice(a + 1, b)
        line = y[a] + (y[b] - y[a]) * (t[seg] - t[a]) / (t[b] - t[a]) if t[b] > t[a] else np.full(b - a - 1, y[a])
        err = np.abs(y[seg] - line)
        err[~np.isfinite(err)] = np.inf
        k = int(np.argmax(err))
        if err[k] > tol:
            keep[a + 1 + k] = True
            stack += [(a, a + 1 + k), (a + 1 + k, b)]
    return np.flatnonzero(keep)


def _tube(y: np.ndarray) -> float:
    finite = y[np.isfinite(y)]
    if finite.size == 0:
        return FLOOR
    return max(VALUE_TUBE * float(np.ptp(finite)), FLOOR * float(np.max(np.abs(finite))), RESOLUTION)


def bless(
    bench: str, waveforms: list[Signal], stop: float, reason: str, params: str = "", golden: Path = paths.GOLDEN
) -> Path:
    """Make `waveforms` the reference of `bench` and record why (`reason` must say it) in BLESSINGS.tsv."""
    if not reason.strip() or "\t" in reason or "\n" in reason:
        raise WrsimError("--bless needs a --reason: one line that says why the references change")
    if len(waveforms) < 2:
        raise WrsimError(f"bench {bench} has no waveforms to bless")
    t = np.asarray(waveforms[0].values, dtype=float)
    arrays: dict[str, Any] = {}
    signals = []
    for k, s in enumerate(waveforms[1:]):
        y = np.asarray(s.values, dtype=float)
        tube = _tube(y)
        idx = decimate(t, y, DECIMATION * tube)
        arrays[f"t{k}"], arrays[f"y{k}"] = t[idx], y[idx]
        signals.append({"name": s.name, "unit": s.unit, "tube": tube, "samples": int(len(t)), "kept": int(len(idx))})
    date, revision = datetime.date.today().isoformat(), _revision()
    meta = {
        "bench": bench,
        "stop": stop,
        "time_tube": TIME_TUBE * stop,
        "signals": signals,
        "revision": revision,
        "date": date,
        "params": params,
        "reason": reason,
    }
    golden.mkdir(parents=True, exist_ok=True)
    target = reference_file(bench, golden)
    with tempfile.NamedTemporaryFile(dir=golden, suffix=".npz", delete=False) as f:
        try:
            np.savez_compressed(f, meta=np.array(json.dumps(meta)), **arrays)
        except BaseException:
            Path(f.name).unlink(missing_ok=True)
            raise
    os.chmod(f.name, 0o644)
    Path(f.name).replace(target)
    log = golden / BLESSINGS
    old = log.read_text(encoding="utf-8") if log.exists() else "date\tbench\trevision\tparams\treason\n"
    write_text_atomic(log, old + "\t".join([date, bench, revision, params or "-", reason]) + "\n")
    return target


def _revision() -> str:
    try:
        out = subprocess.run(
            ["git", "-C", str(paths.ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True, timeout=10
        )
        return out.stdout.strip() or "-"
    except (OSError, subprocess.SubprocessError):
        return "-"


def _load(path: Path) -> tuple[dict, list[tuple[np.ndarray, np.ndarray]]]:
    try:
        with np.load(path) as data:
            meta = json.loads(str(data["meta"]))
            series = [(data[f"t{k}"], data[f"y{k}"]) for k in range(len(meta["signals"]))]
    except (OSError, KeyError, ValueError) as e:
        raise WrsimError(f"{path}: not a reference wrsim wrote ({e}); bless the bench again") from None
    return meta, series


def compare(bench: str, waveforms: list[Signal], out: Path, golden: Path = paths.GOLDEN) -> Regression | None:
    """`waveforms` of `bench` against its reference (None when it has none); the pages of failing signals go to
    out/<bench>/ (replaced as a whole; an index.html lists them)."""
    path = reference_file(bench, golden)
    if not path.exists():
        return None
    meta, series = _load(path)
    result = {s.name: s for s in waveforms[1:]}
    t = np.asarray(waveforms[0].values, dtype=float)
    reg = Regression(bench, len(meta["signals"]))
    failing = []
    for info, (tr, yr) in zip(meta["signals"], series):
        s = result.get(info["name"])
        if s is None:
            reg.missing.append(info["name"])
            continue
        y = np.asarray(s.values, dtype=float)
        lower, upper, errors = _funnel(tr, yr, t, y, meta["time_tube"], max(info["tube"], RESOLUTION))
        found = _violations(info["name"], info["unit"], *errors)
        if found:
            reg.violations += found
            failing.append((info, tr, yr, t, y, lower, upper, errors, found))
    if failing or (out / bench).exists():
        with publish_directory(out, bench) as tmp:
            for k, item in enumerate(failing):
                reg.pages.append(out / bench / _page(tmp, k, bench, meta, *item))
            _index(tmp, reg, meta)
    return reg


def _funnel(tr, yr, t, y, time_tube: float, tube: float):
    """pyfunnel's tube around the reference and the result's distance outside it: (lower, upper, errors), each a
    pair of arrays (x, values). Where one of the two is NaN (undefined) and the other is not within the time
    tube, the distance is NaN."""
    fin_r, fin = np.isfinite(yr), np.isfinite(y)
    mismatch = np.zeros(len(t), dtype=bool)
    if not fin_r.all() or not fin.all():
        nearest = np.clip(np.searchsorted(tr, t), 1, len(tr) - 1)
        nearest -= (t - tr[nearest - 1]) < (tr[nearest] - t)
        ref_nan = ~fin_r[nearest]
        lo, hi = np.searchsorted(t, t - time_tube), np.searchsorted(t, t + time_tube, side="right")
        nans = np.concatenate([[0], np.cumsum(ref_nan)])
        mismatch = (~fin & (nans[hi] - nans[lo] == 0)) | (fin & (nans[hi] - nans[lo] == hi - lo))
    if fin_r.sum() < 2 or fin.sum() < 2:
        return (tr, yr), (tr, yr), (t, np.where(mismatch, np.nan, 0.0))
    with tempfile.TemporaryDirectory(prefix="wrsim-funnel-") as d:
        pyfunnel.compareAndReport(
            list(tr[fin_r]), list(yr[fin_r]), list(t[fin]), list(y[fin]), d, atolx=time_tube, atoly=tube
        )
        lower, upper, (x, err) = (_xy(Path(d) / name) for name in ("lowerBound.csv", "upperBound.csv", "errors.csv"))
    if mismatch.any():
        x = np.concatenate([x, t[mismatch]])
        err = np.concatenate([err, np.full(int(mismatch.sum()), np.nan)])
        order = np.argsort(x, kind="stable")
        x, err = x[order], err[order]
    return lower, upper, (x, err)


def _xy(path: Path) -> tuple[np.ndarray, np.ndarray]:
    try:
        with path.open() as f:
            rows = list(csv.reader(f))[1:]
    except OSError as e:
        raise WrsimError(f"pyfunnel wrote no {path.name}: {e}") from None
    data = np.array(rows, dtype=float).reshape(-1, 2)
    return data[:, 0], data[:, 1]


def _violations(name: str, unit: str, x: np.ndarray, err: np.ndarray) -> list[Violation]:
    """The time ranges where `err` (the distance outside the tube) is above 0."""
    out = []
    bad = (np.abs(err) > 0.0) | np.isnan(err)
    k = 0
    while k < len(x):
        if not bad[k]:
            k += 1
            continue
        j = k
        while j + 1 < len(x) and bad[j + 1]:
            j += 1
        part = np.abs(err[k : j + 1])
        out.append(
            Violation(
                name, unit, float(x[k]), float(x[j]), float(np.nanmax(part)) if np.isfinite(part).any() else math.nan
            )
        )
        k = j + 1
    return out


def _page(
    folder: Path, k: int, bench: str, meta: dict, info: dict, tr, yr, t, y, lower, upper, errors, found: list[Violation]
) -> str:
    """One failing signal's page: a plot of reference, tube and result with the violations shaded, and beneath
    it how far the result is outside the tube."""
    from matplotlib.figure import Figure

    stem = f"{k:03d}_{re.sub(r'[^A-Za-z0-9_.-]+', '_', info['name'])}"
    fig = Figure(figsize=(10, 7.5))
    ax, below = fig.subplots(2, 1, sharex=True, gridspec_kw={"height_ratios": [3, 1]})
    ax.fill_between(
        lower[0],
        lower[1],
        np.interp(lower[0], upper[0], upper[1]),
        color="#9bd",
        alpha=0.5,
        label=f"tube (+-{meta['time_tube']:.3g} s, +-{info['tube']:.3g} {info['unit']})",
    )
    ax.plot(tr, yr, color="#036", lw=1.0, label="reference")
    ax.plot(t, y, color="#c60", lw=1.0, label="result")
    for v in found:
        ax.axvspan(v.start, max(v.end, v.start + 1e-3 * meta["stop"]), color="#d00", alpha=0.25)
    below.plot(errors[0], np.abs(errors[1]), color="#d00", lw=1.0)
    below.set_ylabel(f"outside by [{info['unit']}]" if info["unit"] else "outside by")
    below.set_xlabel("time [s]")
    below.grid(alpha=0.3)
    ax.set_ylabel(f"{info['name']} [{info['unit']}]" if info["unit"] else info["name"])
    ax.set_title(f"{bench}: {info['name']} leaves its tube (shaded red)")
    ax.legend(loc="best", fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(folder / f"{stem}.png", dpi=100)
    rows = "".join(f"<li>{html.escape(str(v))}</li>" for v in found)
    page = (
        f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{html.escape(bench)}: '
        f"{html.escape(info['name'])}</title></head><body>\n<h1>{html.escape(bench)}: "
        f'{html.escape(info["name"])}</h1>\n<ul>{rows}</ul>\n<img src="{stem}.png" alt="reference, tube and '
        f'result">\n<p>Reference blessed {html.escape(meta["date"])} at {html.escape(meta["revision"])}: '
        f'{html.escape(meta["reason"])}. <a href="index.html">All signals of {html.escape(bench)}</a></p>'
        f"\n</body></html>\n"
    )
    (folder / f"{stem}.html").write_text(page, encoding="utf-8")
    return f"{stem}.html"


def _index(folder: Path, reg: Regression, meta: dict) -> None:
    items = "".join(f'<li><a href="{p.name}">{html.escape(p.stem[4:])}</a></li>' for p in reg.pages)
    missing = "".join(f"<li>{html.escape(n)}: in the reference, not in the result</li>" for n in reg.missing)
    verdict = "all signals within their tubes" if reg.passed else "REGRESSION"
    (folder / "index.html").write_text(
        f'<!DOCTYPE html>\n<html><head><meta charset="utf-8"><title>{html.escape(reg.bench)}: waveform '
        f"regression</title></head><body>\n<h1>{html.escape(reg.bench)}: {verdict}</h1>\n<p>{reg.signals} signals "
        f"against the reference of {html.escape(meta['date'])} ({html.escape(meta['reason'])})</p>\n"
        f"<ul>{items}{missing}</ul>\n</body></html>\n",
        encoding="utf-8",
    )
