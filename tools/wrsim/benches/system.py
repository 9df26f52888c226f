"""Open-loop window-regulator system benches (thesis 5.1, 5.3.1, 5.3.3; 4.2.2): battery, drive, rail
mechanism and door at a fixed voltage, no electronics. Parameter set: params/rail_wr_8p5nm.txt.

* stroke: full up stroke at 13 V from fully open (Fig. 5.7-5.9): drum torque, drive speed and current at the
  bottom and entering the top sealing, stroke time, tension distribution;
* drum-diameter-sweep: the stroke with drum diameters 40 .. 48 mm (Table 5.1: stroke time, drum revolutions);
  the cases are simulated concurrently by run_bench;
* startup: start upwards from the tension state a downward / an upward stroke leaves (Fig. 4.61/4.64);
* stiffness: pinch on the 10 N/mm gauge, resultant stiffness from the motor rotation (Fig. 4.60, Eq. 4.42);
* `select_drive`: the drive-class choice of 5.3.1 (working point <= 40 % of the class torque, also with the
  class torque 15 % low) on the simulated load, for `wrsim select-drive`.

The glass oscillates on the mechanism's stiffness during the whole stroke (little damping: Coulomb friction
does not damp it), so every operating point is a time mean over a window of glass positions that spans
several oscillation periods."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.benches.core import (
    Bench,
    Judgement,
    Output,
    Run,
    Session,
    Simulated,
    instance,
    measured,
    metric,
    resampled,
    simulate_runs,
)
from wrsim.closed_form.friction import (
    resultant_stiffness,
    system_stiffness_from_resultant,
    translational_stiffness,
)
from wrsim.data.measurements import Table, read_table
from wrsim.data.units import convert
from wrsim.elab.library import Library
from wrsim.errors import WrsimError
from wrsim.results import Metric, Overlay, Plot, Signal
from wrsim.runner import Runner

__all__ = [
    "BENCHES",
    "DRIVE_CLASSES",
    "DriveChoice",
    "select_drive",
    "format_selection",
    "drive_selection",
    "stroke_points",
    "StrokePoints",
]

SYSTEM_PARAMS = "rail_wr_8p5nm"
TABLE_5_1 = paths.MEASUREMENTS / "table5_1_drum_diameter.csv"
DRIVE_CLASSES = (8.5, 10.0, 12.0, 13.75)  # [N*m] power classes of 5.3.1
WORKING_LIMIT = 0.40  # working point <= 40 % of the maximal torque (5.3.1)
PRODUCTION_TOLERANCE = 0.15  # maximal torque up to 15 % below the class value (5.3.1)
_WINDOW = 0.04  # [m] glass travel of an operating-point window (several periods)
_CLOSED = 0.5e-3  # [m] the window counts as closed this close to the metal frame


# ------------------------------------------------------------------------------------------------
# operating points of a stroke
@dataclass(frozen=True)
class StrokePoints:
    """Time means over the bottom window (glass 10 .. 50 mm) and the top window (the last 40 mm before the
    top-frame sealing), stroke time (switch-on to the metal frame) and drum revolutions at that moment."""

    bottom: dict[str, float]
    top: dict[str, float]
    bottom_span: tuple[float, float]  # [s]
    top_span: tuple[float, float]  # [s]
    seal: float  # [m] glass position of the top-frame sealing
    frame: float  # [m] glass position of the metal frame
    stroke_time: float  # [s]
    revolutions: float  # [1]


_POINT_SIGNALS = {
    "torque": "plant.mechanism.drum.torque",
    "speed": "plant.dut.speed_rpm",
    "current": "plant.dut.motor.ia",
}


def _span(t: np.ndarray, pos: np.ndarray, lo: float, hi: float) -> tuple[float, float]:
    """Times at which the glass first passes lo and hi."""
    if pos.max() < hi:
        raise WrsimError(
            f"the glass never reaches {hi:.3f} m within the simulated time (highest "
            f"{pos.max():.3f} m): the drive cannot lift it with this parameter set"
        )
    return float(t[np.argmax(pos >= lo)]), float(t[np.argmax(pos >= hi)])


def _mean(t: np.ndarray, y: np.ndarray, span: tuple[float, float]) -> float:
    grid = np.linspace(span[0], span[1], 2001)
    return float(np.mean(np.interp(grid, t, y)))


def stroke_points(s: Simulated, prefix: str = "") -> StrokePoints:
    """Operating points of an up stroke simulated with tb_stroke (`prefix` = "study." inside tb_drum_diameter)."""
    w, t = s.waves, s.waves.time
    seal = instance(s.design.tree, f"{prefix}plant.door.top_seal").generics
    frame = seal["position"] + float(np.sum(seal.vector("lengths")))
    pos = w[f"{prefix}plant.door.pane.pos"]
    bottom_span = _span(t, pos, 0.01, 0.01 + _WINDOW)
    top_span = _span(t, pos, seal["position"] - _WINDOW, seal["position"])
    closed = _span(t, pos, 0.0, frame - _CLOSED)[1]
    angle = w[f"{prefix}plant.mechanism.drum.angle"]

    def means(span):
        return {k: _mean(t, w[f"{prefix}{q}"], span) for k, q in _POINT_SIGNALS.items()}

    return StrokePoints(
        means(bottom_span),
        means(top_span),
        bottom_span,
        top_span,
        seal["position"],
        frame,
        closed,
        float(np.interp(closed, t, angle)) / (2.0 * math.pi),
    )


_WINDOWS = {"bottom": "mean over glass 10-50 mm", "top": "mean over the last 40 mm before the top sealing"}


def _pct(value: float, reference: float) -> float:
    return (value / reference - 1.0) * 100.0


# ------------------------------------------------------------------------------------------------
# stroke (5.3.1, Fig. 5.7-5.9)
STROKE_TIME = (3.5, 4.5)  # [s] passenger-car requirement on the stroke time (5.3.1)


def _stroke_outputs(bench: Bench, sims: list[Simulated]) -> list[Output]:
    """A stroke's operating points for a tolerance study, the stroke time held to 5.3.1's requirement and the drum
    torque entering the top sealing to 40 % of the 8.5 N*m class (the working limit of 5.3.1). A glass that does
    not reach the metal frame within the run (the drive stalls in the sealing, or the run is too short) has only
    `closes` = 0, its highest position and its speed at the end."""
    s = sims[0]
    seal = instance(s.design.tree, "plant.door.top_seal").generics
    highest = float(s.waves["plant.door.pane.pos"].max())
    closes = highest >= seal["position"] + float(np.sum(seal.vector("lengths"))) - _CLOSED
    out = [Output("closes", float(closes), "1", 0.5, None, "the glass reaches the metal frame within the run")]
    if not closes:
        return out + [
            Output("highest glass position", highest * 1e3, "mm", note="of a glass that does not close"),
            Output(
                "glass speed at the end",
                float(s.waves["plant.door.pane.v"][-1]) * 1e3,
                "mm/s",
                note="of a glass that does not close: about 0 when it stalls, else the run is too short",
            ),
        ]
    p = stroke_points(s)
    load_limit = WORKING_LIMIT * DRIVE_CLASSES[0]
    return out + [
        Output("stroke time", p.stroke_time, "s", *STROKE_TIME, "passenger-car requirement (5.3.1)"),
        Output(
            "drum torque top",
            p.top["torque"],
            "N*m",
            None,
            load_limit,
            f"40 % of the {DRIVE_CLASSES[0]:g} N*m class (5.3.1)",
        ),
        Output("drum torque bottom", p.bottom["torque"], "N*m"),
        Output("current top", p.top["current"], "A"),
        Output("current bottom", p.bottom["current"], "A"),
        Output("drive speed top", p.top["speed"], "rpm"),
    ]


def _judge_stroke(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    table = measured(bench, table)
    s = sims[0]
    p = stroke_points(s)
    ref = {
        k: table.column(c, u)
        for k, c, u in (
            ("torque", "drum_torque", "N*m"),
            ("speed", "drive_speed", "rpm"),
            ("current", "drive_current", "A"),
        )
    }
    where = ("bottom", p.bottom), ("top", p.top)
    # Tolerances [%]: the thesis states none for these points, so 10 % each. The drive is identified from these
    # very points (params/drive_8p5nm.txt), so speed and current check the system's drum torque through the
    # drive line, not the drive itself; the drum torque is the mechanism's and the door's.
    tol = {"torque": 10.0, "speed": 10.0, "current": 10.0}
    notes = {
        "torque": f"vs Fig. 5.7 ({table.path.name}); 44 mm drum",
        "speed": "vs Fig. 5.8 (the drive's identification points)",
        "current": "vs Fig. 5.8 (the drive's identification points)",
    }
    metrics: list[Metric] = []
    for k, (label, values) in enumerate(where):
        for q, unit in (("torque", "N*m"), ("speed", "rpm"), ("current", "A")):
            metrics.append(
                metric(
                    f"{q} {label} deviation",
                    _pct(values[q], ref[q][k]),
                    0.0,
                    tol[q],
                    "%",
                    f"{values[q]:.3g} {unit} ({_WINDOWS[label]}) {notes[q]}",
                )
            )
    t51 = read_table(TABLE_5_1, require_source=True)
    d = instance(s.design.tree, "plant.mechanism").generics["drum_diameter"]
    row = np.flatnonzero(np.isclose(t51.column("drum_diameter", "m"), d))
    if row.size:
        ref_t = float(t51.column("stroke_time", "s")[row[0]])
        metrics.append(
            metric(
                "stroke time deviation",
                _pct(p.stroke_time, ref_t),
                0.0,
                5.0,
                "%",
                f"{p.stroke_time:.3f} s to the metal frame vs Table 5.1 ({ref_t} s at {d * 1e3:.0f} mm); "
                f"the passenger-car requirement of 5.3.1 (3.5-4.5 s) is met neither by the model nor "
                f"by Table 5.1 itself",
            )
        )
    down = s.waves["plant.mechanism.spring_down.tension"]
    before_seal = s.waves.time < p.top_span[1]
    metrics.append(
        metric(
            "lower spring tension min before the sealing",
            float(down[before_seal].min()),
            25.0,
            24.0,
            "N",
            "1 .. 49 N: the lower compressing spring stays compressed while lifting (4.2.2.2 a)",
        )
    )
    up_c = instance(s.design.tree, "plant.mechanism.spring_up").generics
    blocked = s.waves["plant.mechanism.spring_up.compression"][(s.waves.time > p.bottom_span[0]) & before_seal]
    metrics.append(
        metric(
            "upper spring in block while lifting",
            float(np.mean(blocked >= up_c["travel_block"])) * 100.0,
            100.0,
            5.0,
            "%",
            "share of the stroke with the upper spring in block (Fig. 4.62)",
        )
    )
    return Judgement(
        metrics=metrics, plots=_stroke_plots(bench, s, p, table), waveforms=_stroke_signals(sims, bench.stop)
    )


def _stroke_signals(sims: list[Simulated], stop: float, prefix: str = "") -> list[Signal]:
    return resampled(
        sims,
        {
            "speed": ("rpm", lambda s: s.waves[f"{prefix}plant.dut.speed_rpm"]),
            "current": ("A", lambda s: s.waves[f"{prefix}plant.dut.motor.ia"]),
            "drum_torque": ("N*m", lambda s: s.waves[f"{prefix}plant.mechanism.drum.torque"]),
            "drum_angle": ("rad", lambda s: s.waves[f"{prefix}plant.mechanism.drum.angle"]),
            "glass_position": ("m", lambda s: s.waves[f"{prefix}plant.door.pane.pos"]),
            "tension_upper": ("N", lambda s: s.waves[f"{prefix}plant.mechanism.spring_up.tension"]),
            "tension_lower": ("N", lambda s: s.waves[f"{prefix}plant.mechanism.spring_down.tension"]),
        },
        stop,
    )


def _stroke_plots(bench: Bench, s: Simulated, p: StrokePoints, table: Table) -> list[Plot]:
    grid = np.linspace(0.0, bench.stop, 4001)
    w = s.waves

    def on(name: str) -> np.ndarray:
        return np.interp(grid, w.time, w[name])

    mid = np.array([sum(p.bottom_span) / 2.0, sum(p.top_span) / 2.0])
    angle_mid = np.interp(mid, w.time, w["plant.mechanism.drum.angle"])
    return [
        Plot(
            f"{bench.name}: drive speed and current (Fig. 5.8/5.9)",
            Signal("time", "s", grid),
            [Signal("drive speed", "rpm", on("plant.dut.speed_rpm"))],
            [Signal("motor current", "A", on("plant.dut.motor.ia"))],
            [
                Overlay(
                    "Fig. 5.8 speed",
                    Signal("time", "s", mid),
                    Signal("speed", "rpm", table.column("drive_speed", "rpm")),
                    "left",
                ),
                Overlay(
                    "Fig. 5.8 current",
                    Signal("time", "s", mid),
                    Signal("current", "A", table.column("drive_current", "A")),
                    "right",
                ),
            ],
            "speed_current.png",
        ),
        Plot(
            f"{bench.name}: drum torque over drum angle (Fig. 5.7)",
            Signal("drum angle", "rad", on("plant.mechanism.drum.angle")),
            [Signal("drum torque", "N*m", on("plant.mechanism.drum.torque"))],
            [],
            [
                Overlay(
                    "Fig. 5.7",
                    Signal("drum angle", "rad", angle_mid),
                    Signal("torque", "N*m", table.column("drum_torque", "N*m")),
                    "left",
                )
            ],
            "drum_torque.png",
        ),
        Plot(
            f"{bench.name}: tension distribution (Fig. 4.62)",
            Signal("time", "s", grid),
            [
                Signal("upper spring", "N", on("plant.mechanism.spring_up.tension")),
                Signal("lower spring", "N", on("plant.mechanism.spring_down.tension")),
            ],
            [Signal("glass position", "m", on("plant.door.pane.pos"))],
            [],
            "tension.png",
        ),
    ]


# ------------------------------------------------------------------------------------------------
# drum-diameter study (5.3.3, Table 5.1)
# [%] per quantity: 5 % (the thesis's simulation is the reference; no tolerance stated).
_SWEEP_TOLERANCE = {
    "stroke time": (5.0, ""),
    "drum revolutions": (5.0, "; includes the springs' deflection under the lifting tension"),
}


def _judge_sweep(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    table = measured(bench, table)
    ref_d = table.column("drum_diameter", "m")
    points = [(instance(s.design.tree, "study").generics["drum_diameter"], stroke_points(s, "study.")) for s in sims]
    metrics: list[Metric] = []
    for d, p in points:
        k = int(np.argmin(np.abs(ref_d - d)))
        for name, value, col, unit in (
            ("stroke time", p.stroke_time, "stroke_time", "s"),
            ("drum revolutions", p.revolutions, "drum_revolutions", "1"),
        ):
            ref = float(table.column(col, unit)[k])
            tol, why = _SWEEP_TOLERANCE[name]
            metrics.append(
                metric(
                    f"{name} deviation {d * 1e3:.0f} mm",
                    _pct(value, ref),
                    0.0,
                    tol,
                    "%",
                    f"{value:.3f} {unit} vs Table 5.1 {ref:g} {unit}{why}",
                )
            )
    d_mm = np.array([d for d, _ in points]) * 1e3
    plot = Plot(
        f"{bench.name}: stroke time and drum revolutions (Table 5.1)",
        Signal("drum diameter", "mm", d_mm),
        [Signal("stroke time", "s", np.array([p.stroke_time for _, p in points]))],
        [Signal("drum revolutions", "1", np.array([p.revolutions for _, p in points]))],
        [
            Overlay(
                "Table 5.1 stroke time",
                Signal("drum diameter", "mm", convert(ref_d, "m", "mm")),
                Signal("stroke time", "s", table.column("stroke_time", "s")),
                "left",
            ),
            Overlay(
                "Table 5.1 revolutions",
                Signal("drum diameter", "mm", convert(ref_d, "m", "mm")),
                Signal("drum revolutions", "1", table.column("drum_revolutions", "1")),
                "right",
            ),
        ],
        "table5_1.png",
    )
    return Judgement(metrics=metrics, plots=[plot], waveforms=_stroke_signals(sims, bench.stop, "study."))


# ------------------------------------------------------------------------------------------------
# start-up from the same / the opposite direction (4.2.2.2 c, Fig. 4.61/4.64)
_RUNNING = (0.3, 0.6)  # [s] window of the running speed, after the start-up


def _first_peak(s: Simulated) -> tuple[float, float, float]:
    """(highest drive speed before the glass moves [rpm], running mean speed [rpm], time the glass starts [s])."""
    w, t = s.waves, s.waves.time
    start = float(t[np.argmax(w["plant.door.pane.v"] > 0.01)])
    before = t <= start
    return float(w["plant.dut.speed_rpm"][before].max()), _mean(t, w["plant.dut.speed_rpm"], _RUNNING), start


def _bound(name: str, value: float, lo: float, hi: float, unit: str, note: str) -> Metric:
    """A metric that passes inside [lo, hi] (reference = the middle, tolerance = the half width)."""
    return metric(name, value, 0.5 * (lo + hi), 0.5 * (hi - lo), unit, note)


def _judge_startup(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    metrics: list[Metric] = []
    for s in sims:
        peak, running, start = _first_peak(s)
        where = f"{peak:.1f} rpm before the glass moves at {start * 1e3:.0f} ms, running {running:.1f} rpm"
        if s.run.number("tension_state") < 0:
            metrics.append(
                _bound(
                    "first peak / running speed, opposite direction",
                    peak / running,
                    1.05,
                    1.5,
                    "1",
                    f"{where}: the drive spins up while the tension redistributes, a first peak "
                    f"above the running speed (Fig. 4.61 top); criterion > 1.05",
                )
            )
        else:
            metrics.append(
                _bound(
                    "first peak / running speed, same direction",
                    peak / running,
                    0.0,
                    1.0,
                    "1",
                    f"{where}: the drive meets the load at once, the speed rises slowly, no "
                    f"first peak (Fig. 4.61 bottom); criterion < 1",
                )
            )
    opposite, same = (next(s for s in sims if s.run.number("tension_state") == v) for v in (-1.0, 1.0))
    spring = instance(opposite.design.tree, "plant.mechanism.spring_up").generics
    r = instance(opposite.design.tree, "plant.mechanism.drum").generics["r_cd"]
    shift = 2.0 * (spring["travel_block"] - spring["spacer"])  # cable moved from the lower to the upper spring
    turned = [
        float(np.interp(_first_peak(x)[2], x.waves.time, x.waves["plant.mechanism.drum.angle"]))
        for x in (opposite, same)
    ]
    metrics.append(
        metric(
            "extra drum angle before the glass moves, opposite vs same",
            turned[0] - turned[1],
            shift / r,
            0.3 * shift / r,
            "rad",
            f"the loop's redistribution: {shift * 1e3:.1f} mm of cable from the lower to the upper "
            f"spring = {shift / r:.2f} rad of drum (Fig. 4.64)",
        )
    )
    grid = np.linspace(0.0, bench.stop, 3001)
    speeds = [
        Signal(f"speed {s.run.label}", "rpm", np.interp(grid, s.waves.time, s.waves["plant.dut.speed_rpm"]))
        for s in sims
    ]
    springs = [
        Signal(f"{name} {s.run.label}", "mm", convert(np.interp(grid, s.waves.time, s.waves[q]), "m", "mm"))
        for s in sims
        for name, q in (
            ("upper spring", "plant.mechanism.spring_up.compression"),
            ("lower spring", "plant.mechanism.spring_down.compression"),
        )
    ]
    plots = [
        Plot(
            f"{bench.name}: drive speed at start-up (Fig. 4.61)", Signal("time", "s", grid), speeds, [], [], "speed.png"
        ),
        Plot(
            f"{bench.name}: spring compressions (Fig. 4.64)", Signal("time", "s", grid), springs, [], [], "springs.png"
        ),
    ]
    signals = resampled(
        sims,
        {
            "speed": ("rpm", lambda s: s.waves["plant.dut.speed_rpm"]),
            "current": ("A", lambda s: s.waves["plant.dut.motor.ia"]),
            "glass_velocity": ("m/s", lambda s: s.waves["plant.door.pane.v"]),
            "upper_compression": ("m", lambda s: s.waves["plant.mechanism.spring_up.compression"]),
            "lower_compression": ("m", lambda s: s.waves["plant.mechanism.spring_down.compression"]),
        },
        bench.stop,
    )
    return Judgement(metrics=metrics, plots=plots, waveforms=signals)


# ------------------------------------------------------------------------------------------------
# system stiffness from a pinch (4.2.2.1, Fig. 4.60, Eq. 4.42)
_FIT = (50.0, 100.0)  # [N] trapping-force range of the fit (4.2.2.1: best linearity)


def _judge_stiffness(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    s = sims[0]
    w, tree = s.waves, s.design.tree
    force = w["pinch_force"]
    r = instance(tree, "plant.mechanism.drum").generics["r_cd"]
    ratio = instance(tree, "plant.dut.gear").generics["ratio"]
    displacement = w["plant.dut.motor.angle"] / ratio * r  # thesis: motor rotation, gear ratio, drum radius
    rising = np.arange(len(force)) <= np.argmax(force)
    fit = rising & (force >= _FIT[0]) & (force <= _FIT[1])
    resultant = float(np.polyfit(displacement[fit], force[fit], 1)[0])
    gauge = tree.generics["gauge_stiffness"]
    block = instance(tree, "plant.mechanism.spring_up").generics["k_block"]
    damper_rot = instance(tree, "plant.dut.damper").generics.vector("stiffness")[0]
    damper = translational_stiffness(damper_rot, r)
    eq_4_42 = resultant_stiffness(gauge, block, damper)
    c_wr = system_stiffness_from_resultant(resultant, gauge, damper)
    metrics = [
        metric(
            "resultant stiffness deviation",
            _pct(resultant, eq_4_42),
            0.0,
            10.0,
            "%",
            f"{resultant / 1e3:.3f} N/mm from the motor rotation, {_FIT[0]:g}-{_FIT[1]:g} N, vs Eq. 4.42 with "
            f"gauge {gauge / 1e3:g}, system {block / 1e3:g}, damper {damper / 1e3:.1f} N/mm: "
            f"{eq_4_42 / 1e3:.3f} N/mm (thesis 6.9 N/mm); Eq. 4.42 neglects the friction between the pressed "
            f"spring and the glass, which softens the model's apparent mechanism",
        ),
        metric(
            "system stiffness back from Eq. 4.42 deviation",
            _pct(c_wr, block),
            0.0,
            35.0,
            "%",
            f"{c_wr / 1e3:.1f} N/mm identified the thesis's way vs the block stiffness {block / 1e3:g} N/mm set "
            f"in the model; thesis range 20-40 N/mm",
        ),
    ]
    plots = [
        Plot(
            f"{bench.name}: trapping force over glass displacement (Fig. 4.60)",
            Signal("displacement from motor rotation", "mm", convert(displacement[rising], "m", "mm")),
            [Signal("trapping force", "N", force[rising])],
            [],
            [],
            "force_displacement.png",
        )
    ]
    signals = resampled(
        sims,
        {
            "pinch_force": ("N", lambda s: s.waves["pinch_force"]),
            "motor_angle": ("rad", lambda s: s.waves["plant.dut.motor.angle"]),
            "glass_position": ("m", lambda s: s.waves["plant.door.pane.pos"]),
        },
        bench.stop,
    )
    return Judgement(metrics=metrics, plots=plots, waveforms=signals)


# ------------------------------------------------------------------------------------------------
# drive selection (5.3.1)
@dataclass(frozen=True)
class DriveChoice:
    """One power class against the working point: the 40 % limits of the nominal and the worst-case torque."""

    torque_class: float  # [N*m]
    limit_nominal: float  # [N*m] 40 % of the class torque
    limit_worst: float  # [N*m] 40 % of the class torque minus the production tolerance
    suitable: bool


def select_drive(
    working_point: float, classes=DRIVE_CLASSES, limit: float = WORKING_LIMIT, tolerance: float = PRODUCTION_TOLERANCE
) -> tuple[list[DriveChoice], float | None]:
    """The classes judged against `working_point` [N*m] and the smallest suitable one (None if none is)."""
    rows = [
        DriveChoice(c, limit * c, limit * (1.0 - tolerance) * c, working_point <= limit * (1.0 - tolerance) * c)
        for c in sorted(classes)
    ]
    return rows, next((r.torque_class for r in rows if r.suitable), None)


def format_selection(working_point: float, rows: list[DriveChoice], chosen: float | None, source: str) -> str:
    lines = [
        f"working point: {working_point:.2f} N*m drum torque just before the top-frame sealing ({source})",
        f"{'class [N*m]':>12s} {'40 % [N*m]':>11s} {'40 % of -15 % [N*m]':>20s}  verdict",
    ]
    for r in rows:
        lines.append(
            f"{r.torque_class:12.2f} {r.limit_nominal:11.2f} {r.limit_worst:20.2f}  "
            f"{'suitable' if r.suitable else 'too weak'}"
        )
    if chosen is None:
        lines.append("no class keeps the working point below 40 % of its worst-case torque")
    else:
        lines.append(
            f"choice: {chosen:g} N*m, the smallest class whose maximal torque, even 15 % below its class "
            f"value, keeps the working point below 40 % (room for -40 .. 80 degC, 5.3.1); larger classes "
            f"cost more and are heavier"
        )
    return "\n".join(lines)


def drive_selection(lib: Library, params, runner: Runner, workdir: Path, classes=DRIVE_CLASSES) -> str:
    """Simulate the stroke bench with `params` and choose the power class for its load (5.3.1): the working
    point is the mean drum torque just before the top-frame sealing, the "2.5 N*m taken as driving load" of
    Fig. 5.7."""
    bench = next(b for b in BENCHES if b.name == "stroke")
    sims, _ = simulate_runs(bench, lib, params, runner, workdir)
    load = stroke_points(sims[0]).top["torque"]
    rows, chosen = select_drive(load, classes)
    return format_selection(load, rows, chosen, f"stroke bench, parameter set {params.name}")


# ------------------------------------------------------------------------------------------------
_DIAMETERS = (0.040, 0.042, 0.044, 0.046, 0.048)  # [m] Table 5.1

BENCHES = [
    Bench(
        name="stroke",
        entity="tb_stroke",
        description="Open-loop up stroke at 13 V from fully open, 44 mm drum (thesis 5.3.1, Fig. 5.7-5.9): drum "
        "torque, "
        "drive speed and current, stroke time, tension distribution",
        stop=3.8,
        max_step=1e-3,
        runs=(Run("up", {}),),
        judge=_judge_stroke,
        params=SYSTEM_PARAMS,
        outputs=_stroke_outputs,
    ),
    Bench(
        name="drum-diameter-sweep",
        entity="tb_drum_diameter",
        description="Up stroke at 13 V with drum diameters 40-48 mm (thesis 5.3.3, Table 5.1): stroke time, drum "
        "revolutions",
        stop=3.9,
        max_step=1e-3,
        runs=tuple(Run(f"d{d * 1e3:.0f}", {"drum_diameter": d}) for d in _DIAMETERS),
        judge=_judge_sweep,
        params=SYSTEM_PARAMS,
    ),
    Bench(
        name="startup",
        entity="tb_startup",
        description="Start upwards from the tension state of a downward (opposite) or upward (same) stroke (thesis "
        "4.2.2.2, "
        "Fig. 4.61/4.64): first speed peak",
        stop=0.6,
        max_step=5e-4,
        runs=(Run("opposite", {"tension_state": -1.0}), Run("same", {"tension_state": 1.0})),
        judge=_judge_startup,
        params=SYSTEM_PARAMS,
    ),
    Bench(
        name="stiffness",
        entity="tb_stiffness",
        description="Pinch on the 10 N/mm gauge, 20 mm drum radius, 0.8 N*m/deg damper (thesis 4.2.2.1, Fig. 4.60, "
        "Eq. 4.42): resultant and system stiffness",
        stop=1.2,
        max_step=5e-4,
        runs=(Run("pinch", {}),),
        judge=_judge_stiffness,
        params=SYSTEM_PARAMS,
    ),
]
