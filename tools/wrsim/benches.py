"""The benches: which VHDL-AMS testbench entity to simulate, how long, with which top-level generics, and
how to judge the waveforms (metrics with references and tolerances, plots, the waveform table).

A bench's testbench entity names its measurement CSV in its header comment (`-- measurement: path`);
this module reads it from there, so the VHDL file stays the one place that says what it is compared with."""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import numpy as np

from . import identify
from .elaborate import Design, InstanceInfo, Library, elaborate
from .errors import WrsimError
from .measurements import Table, read_table
from .ngspice import Analysis, lower
from .report import BenchResult, Metric, Overlay, Plot, Signal
from .runner import Runner, Waveforms
from .units import convert

__all__ = ["Bench", "Run", "BENCHES", "run_bench", "measurement_of", "ROOT"]

ROOT = Path(__file__).resolve().parents[2]
RPM = convert(1.0, "rad/s", "rpm")


@dataclass(frozen=True)
class Run:
    """One simulation of a bench: a label and top-level generic values."""

    label: str
    generics: dict[str, float]


@dataclass
class Simulated:
    run: Run
    design: Design
    waves: Waveforms


@dataclass(frozen=True)
class Bench:
    name: str
    entity: str
    description: str
    stop: float                   # [s]
    max_step: float               # [s]
    runs: tuple[Run, ...]
    judge: Callable[["Bench", list[Simulated], Table | None], tuple[list[Metric], list[Plot], list[Signal]]]


def measurement_of(lib: Library, entity: str) -> Path | None:
    """The CSV named by `-- measurement: <path>` in the testbench's header comment."""
    for line in lib.entity(entity).header.splitlines():
        if line.lower().startswith("measurement:"):
            return ROOT / line.split(":", 1)[1].strip()
    return None


def run_bench(bench: Bench, lib: Library, params, runner: Runner, workdir: Path) -> BenchResult:
    """Elaborate, lower and simulate every run of `bench`, then judge the waveforms."""
    timings = {"lower": 0.0, "simulate": 0.0}
    sims = []
    for run in bench.runs:
        t0 = time.perf_counter()
        design = elaborate(lib, bench.entity, params, run.generics)
        netlist = lower(design, Analysis(bench.stop, bench.max_step), f"{bench.name} ({run.label})")
        timings["lower"] += time.perf_counter() - t0
        t0 = time.perf_counter()
        waves = runner.run(netlist, workdir / run.label)
        timings["simulate"] += time.perf_counter() - t0
        sims.append(Simulated(run, design, waves))
    csv = measurement_of(lib, bench.entity)
    table = read_table(csv, require_source=True) if csv else None
    metrics, plots, signals = bench.judge(bench, sims, table)
    return BenchResult(bench.name, bench.description, str(csv.relative_to(ROOT)) if csv else None, signals,
                       metrics, plots, timings, all(m.passed for m in metrics))


# ------------------------------------------------------------------------------------------------
# helpers shared by the judges
def instance(tree: InstanceInfo, path: str) -> InstanceInfo:
    node = tree
    for label in path.split("."):
        node = next((c for c in node.children if c.path.endswith("." + label)), None)
        if node is None:
            raise WrsimError(f"internal: no instance {path} in {tree.path}")
    return node


def motor_params(info: InstanceInfo) -> identify.MotorParams:
    g = info.generics
    return identify.MotorParams(g["ke"], g["kt"], g["ra"], g["laa"], g["j"], g["visc"], g["mc"])


def rel_error_pct(sim: np.ndarray, ref: np.ndarray) -> np.ndarray:
    return np.abs(sim / ref - 1.0) * 100.0


def on_load(torque: np.ndarray, values: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Values of a characteristic line at load torques `at` (torque rises monotonically over the ramp)."""
    return np.interp(at, torque, values)


def metric(name: str, value: float, reference: float, tolerance: float, unit: str, note: str = "") -> Metric:
    return Metric(name, float(value), float(reference), float(tolerance), unit,
                  bool(abs(value - reference) <= tolerance), note)


def resampled(sims: list[Simulated], columns: dict[str, tuple[str, Callable[[Simulated], np.ndarray]]],
              stop: float, points: int = 2001) -> list[Signal]:
    """The waveform table: every run resampled on one uniform time grid (runs have their own steps)."""
    t = np.linspace(0.0, stop, points)
    out = [Signal("time", "s", t)]
    for s in sims:
        for name, (unit, get) in columns.items():
            out.append(Signal(f"{name}_{s.run.label}", unit, np.interp(t, s.waves.time, get(s))))
    return out


# ------------------------------------------------------------------------------------------------
# characteristic lines (thesis 4.1.1.4 and 4.1.4.2)
def _characteristic(bench: Bench, sims: list[Simulated], table: Table | None, *, speed_of, current_of,
                    ref_speed: str, ref_current: str, window, tol_speed: float, tol_current: float,
                    closed_form) -> tuple[list[Metric], list[Plot]]:
    ref_m = table.column("torque", "N*m")
    lo, hi = window(ref_m, table)
    at = ref_m[(ref_m >= lo) & (ref_m <= hi)]
    ref_w = on_load(ref_m, table.column(ref_speed, "rpm"), at)
    ref_i = on_load(ref_m, table.column(ref_current, "A"), at)
    metrics: list[Metric] = []
    plots: list[Plot] = []
    for s in sims:
        d, tag = s.run.generics["direction"], s.run.label
        torque = s.waves["load.load_torque"]
        speed, current = d * speed_of(s) * RPM, d * current_of(s)
        sim_w, sim_i = on_load(torque, speed, at), on_load(torque, current, at)
        span = f"max over {lo:.3g}-{hi:.3g} N*m"
        metrics.append(metric(f"speed error {tag} ({span})", rel_error_pct(sim_w, ref_w).max(), 0.0, tol_speed, "%",
                              f"vs {ref_speed} of {table.path.name}"))
        metrics.append(metric(f"current error {tag} ({span})", rel_error_pct(sim_i, ref_i).max(), 0.0, tol_current,
                              "%", f"vs {ref_current} of {table.path.name}"))
        cf_w, cf_i = closed_form(s, at)
        worst = max(rel_error_pct(sim_w, cf_w * RPM).max(), rel_error_pct(sim_i, cf_i).max())
        metrics.append(metric(f"closed-form deviation {tag} ({span})", worst, 0.0, 0.1, "%",
                              "speed and current vs the exact ramp solution of the model's equations"))
        keep = torque <= ref_m.max() * 1.25
        plots.append(Plot(f"{bench.name}: {tag}", Signal("load torque", "N*m", torque[keep]),
                          [Signal(f"speed {tag}", "rpm", speed[keep])], [Signal(f"current {tag}", "A", current[keep])],
                          [Overlay(f"{ref_speed} ({table.path.name})", Signal("torque", "N*m", ref_m),
                                   Signal(ref_speed, "rpm", table.column(ref_speed, "rpm")), "left"),
                           Overlay(f"{ref_current} ({table.path.name})", Signal("torque", "N*m", ref_m),
                                   Signal(ref_current, "A", table.column(ref_current, "A")), "right")],
                          f"characteristic_{tag}.png"))
    return metrics, plots


def _judge_motor(bench: Bench, sims: list[Simulated], table: Table):
    def closed_form(s: Simulated, at):
        p = motor_params(instance(s.design.tree, "dut"))
        u = instance(s.design.tree, "supply").generics["u"] * s.run.generics["direction"]
        load = instance(s.design.tree, "load").generics
        return identify.motor_ramp_line(p, abs(u), load["torque_end"] / load["ramp_time"], at)

    def window(ref_m, table):
        slope, icpt = identify.line_fit(ref_m, table.column("mean_speed", "rpm"))
        stall = -icpt / slope
        return 0.1 * stall, 0.8 * stall

    metrics, plots = _characteristic(
        bench, sims, table, speed_of=lambda s: s.waves["dut.omega"], current_of=lambda s: s.waves["dut.ia"],
        ref_speed="mean_speed", ref_current="mean_current", window=window, tol_speed=2.0, tol_current=4.1,
        closed_form=closed_form)
    signals = resampled(sims, {"torque": ("N*m", lambda s: s.waves["load.load_torque"]),
                               "speed": ("rpm", lambda s: s.waves["dut.omega"] * RPM),
                               "current": ("A", lambda s: s.waves["dut.ia"])}, bench.stop)
    return metrics, plots, signals


def _judge_drive(bench: Bench, sims: list[Simulated], table: Table):
    def closed_form(s: Simulated, at):
        tree = s.design.tree
        p = motor_params(instance(tree, "dut.motor"))
        gear = instance(tree, "dut.gear").generics
        m_gc = instance(tree, "dut").generics["m_gc"]
        u = instance(tree, "supply").generics["u"]
        load = instance(tree, "load").generics
        return identify.drive_ramp_line(p, gear["ratio"], gear["eta"], m_gc, abs(u),
                                        load["torque_end"] / load["ramp_time"], at)

    metrics, plots = _characteristic(
        bench, sims, table, speed_of=lambda s: s.waves["dut.gear.omega_g"],
        current_of=lambda s: s.waves["dut.motor.ia"], ref_speed="fit_speed", ref_current="fit_current",
        window=lambda ref_m, t: (1.0, 5.0), tol_speed=0.3, tol_current=3.7, closed_form=closed_form)
    signals = resampled(sims, {"torque": ("N*m", lambda s: s.waves["load.load_torque"]),
                               "speed": ("rpm", lambda s: s.waves["dut.gear.omega_g"] * RPM),
                               "output_speed": ("rpm", lambda s: s.waves["dut.speed_rpm"]),
                               "current": ("A", lambda s: s.waves["dut.motor.ia"])}, bench.stop)
    return metrics, plots, signals


_BOTH = (Run("cw", {"direction": 1.0}), Run("ccw", {"direction": -1.0}))

BENCHES: dict[str, Bench] = {b.name: b for b in [
    Bench("motor-characteristic", "tb_motor_characteristic",
          "DCPM motor characteristic line at 13 V, load ramp 0-0.5 N*m in 3 s, both directions (thesis 4.1.1.4, "
          "Fig. 4.15)", 3.0, 1e-3, _BOTH, _judge_motor),
    Bench("drive-characteristic", "tb_drive_characteristic",
          "Drive characteristic line at 13 V, gear load ramp 0-13 N*m in 2 s, both directions (thesis 4.1.4.2, "
          "Fig. 4.44)", 2.0, 1e-3, _BOTH, _judge_drive),
]}
