"""Characteristic-line benches of the motor and the drive (thesis 4.1.1.4, 4.1.4.2)."""

from __future__ import annotations

from wrsim.benches.core import (
    RPM,
    Bench,
    Judgement,
    Run,
    Session,
    Simulated,
    instance,
    measured,
    metric,
    motor_params,
    on_load,
    rel_error_pct,
    resampled,
)
from wrsim.closed_form.motor import drive_ramp_line, motor_ramp_line
from wrsim.data.measurements import Table
from wrsim.identify.calculator import line_fit
from wrsim.results import Metric, Overlay, Plot, Signal


# ------------------------------------------------------------------------------------------------
# characteristic lines (thesis 4.1.1.4 and 4.1.4.2)
def _characteristic(
    bench: Bench,
    sims: list[Simulated],
    table: Table | None,
    *,
    speed_of,
    current_of,
    ref_speed: str,
    ref_current: str,
    window,
    tol_speed: float,
    tol_current: float,
    closed_form,
) -> tuple[list[Metric], list[Plot]]:
    table = measured(bench, table)
    ref_m = table.column("torque", "N*m")
    lo, hi = window(ref_m, table)
    at = ref_m[(ref_m >= lo) & (ref_m <= hi)]
    ref_w = on_load(ref_m, table.column(ref_speed, "rpm"), at)
    ref_i = on_load(ref_m, table.column(ref_current, "A"), at)
    metrics: list[Metric] = []
    plots: list[Plot] = []
    for s in sims:
        d, tag = s.run.number("direction"), s.run.label
        torque = s.waves["load.load_torque"]
        speed, current = d * speed_of(s) * RPM, d * current_of(s)
        sim_w, sim_i = on_load(torque, speed, at), on_load(torque, current, at)
        span = f"max over {lo:.3g}-{hi:.3g} N*m"
        metrics.append(
            metric(
                f"speed error {tag} ({span})",
                rel_error_pct(sim_w, ref_w).max(),
                0.0,
                tol_speed,
                "%",
                f"vs {ref_speed} of {table.path.name}",
            )
        )
        metrics.append(
            metric(
                f"current error {tag} ({span})",
                rel_error_pct(sim_i, ref_i).max(),
                0.0,
                tol_current,
                "%",
                f"vs {ref_current} of {table.path.name}",
            )
        )
        cf_w, cf_i = closed_form(s, at)
        worst = max(rel_error_pct(sim_w, cf_w * RPM).max(), rel_error_pct(sim_i, cf_i).max())
        metrics.append(
            metric(
                f"closed-form deviation {tag} ({span})",
                worst,
                0.0,
                0.1,
                "%",
                "speed and current vs the exact ramp solution of the model's equations",
            )
        )
        keep = torque <= ref_m.max() * 1.25
        plots.append(
            Plot(
                f"{bench.name}: {tag}",
                Signal("load torque", "N*m", torque[keep]),
                [Signal(f"speed {tag}", "rpm", speed[keep])],
                [Signal(f"current {tag}", "A", current[keep])],
                [
                    Overlay(
                        f"{ref_speed} ({table.path.name})",
                        Signal("torque", "N*m", ref_m),
                        Signal(ref_speed, "rpm", table.column(ref_speed, "rpm")),
                        "left",
                    ),
                    Overlay(
                        f"{ref_current} ({table.path.name})",
                        Signal("torque", "N*m", ref_m),
                        Signal(ref_current, "A", table.column(ref_current, "A")),
                        "right",
                    ),
                ],
                f"characteristic_{tag}.png",
            )
        )
    return metrics, plots


def _judge_motor(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    def closed_form(s: Simulated, at):
        p = motor_params(instance(s.design.tree, "dut"))
        u = instance(s.design.tree, "supply").generics["u"] * s.run.number("direction")
        load = instance(s.design.tree, "load").generics
        return motor_ramp_line(p, abs(u), load["torque_end"] / load["ramp_time"], at)

    def window(ref_m, table):
        slope, icpt = line_fit(ref_m, table.column("mean_speed", "rpm"))
        stall = -icpt / slope
        return 0.1 * stall, 0.8 * stall

    metrics, plots = _characteristic(
        bench,
        sims,
        table,
        speed_of=lambda s: s.waves["dut.omega"],
        current_of=lambda s: s.waves["dut.ia"],
        ref_speed="mean_speed",
        ref_current="mean_current",
        window=window,
        tol_speed=2.0,
        tol_current=4.1,
        closed_form=closed_form,
    )
    signals = resampled(
        sims,
        {
            "torque": ("N*m", lambda s: s.waves["load.load_torque"]),
            "speed": ("rpm", lambda s: s.waves["dut.omega"] * RPM),
            "current": ("A", lambda s: s.waves["dut.ia"]),
        },
        bench.stop,
    )
    return Judgement(metrics=metrics, plots=plots, waveforms=signals)


def _judge_drive(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    def closed_form(s: Simulated, at):
        tree = s.design.tree
        p = motor_params(instance(tree, "dut.motor"))
        gear = instance(tree, "dut.gear").generics
        m_gc = instance(tree, "dut").generics["m_gc"]
        u = instance(tree, "supply").generics["u"]
        load = instance(tree, "load").generics
        return drive_ramp_line(p, gear["ratio"], gear["eta"], m_gc, abs(u), load["torque_end"] / load["ramp_time"], at)

    metrics, plots = _characteristic(
        bench,
        sims,
        table,
        speed_of=lambda s: s.waves["dut.gear.omega_g"],
        current_of=lambda s: s.waves["dut.motor.ia"],
        ref_speed="fit_speed",
        ref_current="fit_current",
        window=lambda ref_m, t: (1.0, 5.0),
        tol_speed=0.3,
        tol_current=3.7,
        closed_form=closed_form,
    )
    signals = resampled(
        sims,
        {
            "torque": ("N*m", lambda s: s.waves["load.load_torque"]),
            "speed": ("rpm", lambda s: s.waves["dut.gear.omega_g"] * RPM),
            "output_speed": ("rpm", lambda s: s.waves["dut.speed_rpm"]),
            "current": ("A", lambda s: s.waves["dut.motor.ia"]),
        },
        bench.stop,
    )
    return Judgement(metrics=metrics, plots=plots, waveforms=signals)


_BOTH = (Run("cw", {"direction": 1.0}), Run("ccw", {"direction": -1.0}))

BENCHES = [
    Bench(
        name="motor-characteristic",
        entity="tb_motor_characteristic",
        description="DCPM motor characteristic line at 13 V, load ramp 0-0.5 N*m in 3 s, both directions (thesis "
        "4.1.1.4, "
        "Fig. 4.15)",
        stop=3.0,
        max_step=1e-3,
        runs=_BOTH,
        judge=_judge_motor,
    ),
    Bench(
        name="drive-characteristic",
        entity="tb_drive_characteristic",
        description="Drive characteristic line at 13 V, gear load ramp 0-13 N*m in 2 s, both directions (thesis "
        "4.1.4.2, "
        "Fig. 4.44)",
        stop=2.0,
        max_step=1e-3,
        runs=_BOTH,
        judge=_judge_drive,
    ),
]
