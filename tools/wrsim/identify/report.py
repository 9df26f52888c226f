"""The validation report of an identification: parameters with their sources, group lines and channels,
validation tables, stiffness table (index.html and PNGs, published as one directory)."""

from __future__ import annotations

import html
import math
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from wrsim.data.publish import publish_directory
from wrsim.data.units import convert
from wrsim.identify.fit import DamperIdentification, Validation
from wrsim.identify.paramset import identified_sections

if TYPE_CHECKING:
    from matplotlib.figure import Figure

__all__ = ["write_report"]

# ================================================================================================
# validation report (HTML + PNGs)


def _working_range(ax, lo: float, hi: float) -> None:
    for x in (lo, hi):
        ax.axvline(x, color="0.4", linestyle=":", linewidth=1.2, label="working range" if x == lo else None)


def _curves_figure(ident, speed_name: str) -> Figure:
    """Raw curves and their fitted lines over the working range (Fig. 4.11/4.12, 4.38/4.39)."""
    from matplotlib.figure import Figure

    rpm = convert(1.0, "rad/s", "rpm")
    fig = Figure(figsize=(9, 7))
    ax_w, ax_i = fig.subplots(2, 1, sharex=True)
    for k, (c, f) in enumerate(zip(ident.curves, ident.group.fits)):
        color = f"C{k % 10}"
        ax_w.plot(c.torque, c.speed * rpm, color=color, linewidth=0.5, alpha=0.35)
        ax_i.plot(c.torque, c.current, color=color, linewidth=0.5, alpha=0.35)
        m = np.array([f.lo, f.hi])
        ax_w.plot(m, f.speed(m) * rpm, color=color, linewidth=2, label=f"{c.label} fit")
        ax_i.plot(m, f.current(m), color=color, linewidth=2)
    for ax in (ax_w, ax_i):
        _working_range(ax, ident.group.lo, ident.group.hi)
        ax.grid(True, alpha=0.3)
    ax_w.set_ylabel(f"{speed_name} [rpm]")
    ax_i.set_ylabel("current [A]")
    ax_i.set_xlabel("torque [N*m]")
    ax_w.set_title(f"{ident.kind}: raw curves (thin) and linear fits over each curve's working range")
    ax_w.legend(loc="best", fontsize="small", ncol=2)
    return fig


def _channel_figure(ident, validations: list[Validation], speed_name: str) -> Figure:
    """Boundaries, mean and middle line of the fits with the simulated lines (Fig. 4.13/4.14, 4.40/4.45)."""
    from matplotlib.figure import Figure

    rpm = convert(1.0, "rad/s", "rpm")
    g = ident.group
    fig = Figure(figsize=(9, 7))
    axes = fig.subplots(2, 1, sharex=True)
    for ax, lines, scale, grid_of in ((axes[0], g.speed, rpm, "grid_speed"), (axes[1], g.current, 1.0, "grid_current")):
        ax.fill_between(g.torque, lines["min"] * scale, lines["max"] * scale, color="0.85", label="channel (min..max)")
        ax.plot(g.torque, lines["min"] * scale, "k--", linewidth=1, label="min / max")
        ax.plot(g.torque, lines["max"] * scale, "k--", linewidth=1)
        ax.plot(g.torque, lines["mean"] * scale, color="C0", label="mean")
        ax.plot(g.torque, lines["middle"] * scale, color="C2", label="middle of boundaries")
        for k, v in enumerate(validations):
            ax.plot(g.torque, getattr(v, grid_of) * scale, color=f"C{3 + k}", linewidth=2.2, alpha=0.8, label=v.label)
        _working_range(ax, g.lo, g.hi)
        ax.grid(True, alpha=0.3)
    axes[0].set_ylabel(f"{speed_name} [rpm]")
    axes[1].set_ylabel("current [A]")
    axes[1].set_xlabel("torque [N*m]")
    axes[0].set_title(f"{ident.kind}: simulated lines in the channel of the measured fits")
    axes[0].legend(loc="best", fontsize="small")
    return fig


def _damper_figure(ident: DamperIdentification) -> Figure:
    """Secant stiffness of the samples and the identified table (Fig. 4.32), in deg and N*m/deg."""
    from matplotlib.figure import Figure

    per_deg = math.radians(1.0)
    fig = Figure(figsize=(8, 5), layout="constrained")
    ax = fig.add_subplot()
    for k, c in enumerate(ident.curves):
        keep = c.angle > ident.angles[1] / 4
        ax.plot(
            np.degrees(c.angle[keep]),
            c.torque[keep] / c.angle[keep] * per_deg,
            ".",
            markersize=2,
            color=f"C{k % 10}",
            alpha=0.4,
            label=f"{c.label} M/angle",
        )
    ax.plot(np.degrees(ident.angles), ident.stiffness * per_deg, "ko-", linewidth=2, label="identified table")
    ax.set_xlabel("angle change [deg]")
    ax.set_ylabel("stiffness [N*m/deg]")
    ax.set_title("rubber damper: secant stiffness of the samples and the identified table")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize="x-small", ncol=2)
    return fig


def _table(header: list[str], rows: list[list[str]]) -> str:
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{esc(c)}</td>" for c in row) + "</tr>" for row in rows)
    return f"<table><tr>{head}</tr>{body}</table>"


def _validation_html(v: Validation) -> str:
    rpm = convert(1.0, "rad/s", "rpm")
    rows = [
        [f"{m:.5g}", f"{w * rpm:.5g}", f"{rw * rpm:.5g}", f"{ew:.3f}", f"{i:.5g}", f"{ri:.5g}", f"{ei:.3f}"]
        for m, w, rw, ew, i, ri, ei in zip(
            v.torque, v.speed, v.ref_speed, v.speed_error, v.current, v.ref_current, v.current_error
        )
    ]
    inside = (
        "inside the channel"
        if v.speed_outside == 0 and v.current_outside == 0
        else f"OUTSIDE the channel by up to {v.speed_outside:.3g} % (speed), {v.current_outside:.3g} % (current)"
    )
    return (
        f"<h3>{html.escape(v.label)} vs {v.reference} line</h3>"
        + _table(
            [
                "torque [N*m]",
                "sim speed [rpm]",
                f"{v.reference} speed [rpm]",
                "difference [%]",
                "sim current [A]",
                f"{v.reference} current [A]",
                "difference [%]",
            ],
            rows,
        )
        + f"<p>Over the working range: max speed difference {v.max_speed_error:.3f} %, max current "
        f"difference {v.max_current_error:.3f} %; {inside}.</p>"
    )


def _fits_html(ident) -> str:
    rpm = convert(1.0, "rad/s", "rpm")
    rows = [
        [
            Path(f.name).stem,
            f"{f.direction:+d}",
            str(f.samples),
            f"{f.lo:.4g}-{f.hi:.4g}",
            f"{f.stall:.4g}",
            f"{f.speed_intercept * rpm:.5g}",
            f"{f.speed_slope * rpm:.5g}",
            f"{f.current_intercept:.4g}",
            f"{f.current_slope:.4g}",
            f"{f.torque_rate:.4g}",
            f"{f.voltage:.4g}",
        ]
        for f in ident.group.fits
    ]
    return _table(
        [
            "curve",
            "dir",
            "samples",
            "cut [N*m]",
            "stall [N*m]",
            "speed at 0 [rpm]",
            "speed slope [rpm/(N*m)]",
            "current at 0 [A]",
            "current slope [A/(N*m)]",
            "ramp [N*m/s]",
            "voltage [V]",
        ],
        rows,
    )


def write_report(directory: str | Path, ident, validations: list[Validation] | None = None) -> Path:
    """Write the validation report of an identification into `directory` (index.html and PNGs), replacing
    the directory as a whole. `validations` are the simulated lines to judge (motor, drive)."""
    directory = Path(directory)
    header, sections = identified_sections(ident)
    rows = [
        [
            f"[{entity}] {key}",
            repr(value) if not isinstance(value, list) else ", ".join(f"{x:.6g}" for x in value),
            unit,
            comment,
        ]
        for entity, entries in sections.items()
        for key, value, unit, comment in entries
    ]
    parts = [
        f"<h1>wrsim identification: {ident.kind}</h1>",
        "".join(f"<p>{html.escape(line)}</p>" for line in header),
        "<h2>Parameters</h2>",
        _table(["parameter", "value", "unit", "source"], rows),
    ]
    figures: dict[str, Figure] = {}
    if isinstance(ident, DamperIdentification):
        figures["stiffness.png"] = _damper_figure(ident)
        grid = [
            [f"{math.degrees(a):.4g}", f"{a:.6g}", f"{c:.5g}", f"{c * math.radians(1.0):.5g}"]
            for a, c in zip(ident.angles, ident.stiffness)
        ]
        parts += [
            "<h2>Stiffness table</h2>",
            _table(["angle [deg]", "angle [rad]", "stiffness [N*m/rad]", "stiffness [N*m/deg]"], grid),
        ]
    else:
        speed_name = "armature speed" if ident.kind == "motor" else "gear speed"
        figures["curves.png"] = _curves_figure(ident, speed_name)
        figures["channel.png"] = _channel_figure(ident, validations or [], speed_name)
        parts += [
            "<h2>Validation (working range marked in the plots)</h2>",
            *(_validation_html(v) for v in validations or []),
        ]
        parts += ["<h2>Curves</h2>", _fits_html(ident)]
    parts += [f'<p><img src="{name}" alt="{name}"></p>' for name in figures]
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8"><title>wrsim identification</title>'
        "<style>body{font-family:sans-serif} table{border-collapse:collapse}"
        "td,th{border:1px solid #ccc;padding:3px 6px;text-align:right}</style></head><body>\n"
        + "\n".join(parts)
        + "\n</body></html>\n"
    )
    with publish_directory(directory.parent, directory.name) as tmp:
        for name, fig in figures.items():
            fig.savefig(tmp / name, format="png", dpi=100)
        (tmp / "index.html").write_text(page, encoding="utf-8")
    return directory / "index.html"
