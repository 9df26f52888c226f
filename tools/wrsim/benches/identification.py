"""The identification bench: synthetic test-stand group -> identification -> parameter set -> simulation.

The bench's runs simulate tb_drive_characteristic with the bench's parameter set (the "truth"; `--params`
chooses another, e.g. a temperature set). The judge then
1. writes a synthetic group made from that truth (wrsim.synthetic, seed 0: 5 units x 2 directions of
   motor, drive and rubber-damper files) to raw/ in the bench's work folder (build/work/identification/),
2. identifies motor, drive and damper from the files (wrsim.identify, the thesis's group procedure) and
   writes the parameter set identified.txt there (via motor.txt and drive.txt),
3. simulates tb_motor_characteristic and tb_drive_characteristic (both directions) with the identified
   set under the synthetic stand's conditions,
4. judges: recovered parameters against the truth (ke, kt, ra, eta within 2 %), the simulated lines
   against the measured channel and the group line (quantitative tables as Fig. 4.15/4.44), and the
   identified drive against the truth's simulation; writes the validation reports to
   {motor,drive,damper}_report/ there.
"""

from __future__ import annotations

import numpy as np

from wrsim.benches.core import (
    RPM,
    Bench,
    Judgement,
    Run,
    Session,
    Simulated,
    instance,
    metric,
    motor_params,
    on_load,
    rel_error_pct,
    resampled,
    simulate_runs,
)
from wrsim.data.curves import read_characteristic, read_torque_angle
from wrsim.data.measurements import Table
from wrsim.data.params import ParamSet, load_params
from wrsim.elab.design import InstanceInfo
from wrsim.identify.fit import (
    GroupLines,
    Validation,
    identify_damper,
    identify_drive,
    identify_motor,
    validate,
)
from wrsim.identify.paramset import write_identified_set
from wrsim.identify.report import write_report
from wrsim.identify.synthetic import DRIVE_STAND, MOTOR_STAND, Stand, Truth, write_group
from wrsim.results import Metric, Plot, Signal

_SEED = 0
_MOTOR_STOP = 3.0  # [s] motor testbench ramp (0.5 N*m at the stand's rate; covers 80 % of stall up to -30 degC)
_DRIVE_STOP = 2.0  # [s] drive testbench ramp (13 N*m at the stand's rate)


def _truth(tree: InstanceInfo) -> Truth:
    gear, damper = instance(tree, "dut.gear").generics, instance(tree, "dut.damper").generics
    return Truth(
        motor_params(instance(tree, "dut.motor")),
        gear["ratio"],
        gear["eta"],
        instance(tree, "dut").generics["m_gc"],
        tuple(damper.vector("angles")),
        tuple(damper.vector("stiffness")),
    )


def _simulate(session: Session, params: ParamSet, entity: str, stand: Stand, stop: float) -> list[Simulated]:
    """Both directions of the characteristic testbench `entity` with the identified set, on the stand's ramp."""
    bench = Bench(
        name=f"identification: {entity}",
        entity=entity,
        description="identified set",
        stop=stop,
        max_step=1e-3,
        runs=(),
        judge=_judge,
    )
    runs = tuple(
        Run(
            f"identified_{label}",
            {"direction": d, "u_supply": stand.voltage, "torque_end": stand.torque_rate * stop, "ramp_time": stop},
        )
        for d, label in ((1.0, "cw"), (-1.0, "ccw"))
    )
    return simulate_runs(bench, session.lib, params, session.runner, session.workdir / entity, runs)[0]


def _line(s: Simulated, speed: str, current: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Load torque, speed [rad/s] and current [A] of a run, by magnitude, on the rising part of the ramp."""
    d = s.run.number("direction")
    torque = s.waves["load.load_torque"]
    keep = np.concatenate([[False], np.diff(torque) > 0])
    return torque[keep], d * s.waves[speed][keep], d * s.waves[current][keep]


def _recovery(name: str, value: float, truth: float, tol: float, note: str) -> Metric:
    return metric(f"{name} recovered", (value / truth - 1.0) * 100.0, 0.0, tol, "%", note)


def _validation_metrics(
    kind: str, vals: list[Validation], tol_speed: float, tol_current: float, ref: str
) -> list[Metric]:
    out = []
    for v in vals:
        tag = f"{kind} {v.label.removeprefix('simulated ')}"
        out += [
            metric(
                f"{tag}: speed vs {v.reference} line",
                v.max_speed_error,
                0.0,
                tol_speed,
                "%",
                f"max over the working range, as {ref}",
            ),
            metric(
                f"{tag}: current vs {v.reference} line",
                v.max_current_error,
                0.0,
                tol_current,
                "%",
                f"max over the working range, as {ref}",
            ),
            metric(
                f"{tag}: speed outside the measured channel",
                v.speed_outside,
                0.0,
                0.0,
                "%",
                "largest distance outside min..max of the fits (0 = inside)",
            ),
            metric(
                f"{tag}: current outside the measured channel",
                v.current_outside,
                0.0,
                0.0,
                "%",
                "largest distance outside min..max of the fits (0 = inside)",
            ),
        ]
    return out


def _channel_plot(kind: str, group: GroupLines, reference: str, val: Validation) -> Plot:
    """Boundaries and reference line of the fits with the simulated line (speed left, current right)."""
    sides = []
    for q, unit, lines, scale, grid in (
        ("speed", "rpm", group.speed, RPM, val.grid_speed),
        ("current", "A", group.current, 1.0, val.grid_current),
    ):
        sides.append(
            [Signal(f"{q}: {name}", unit, lines[name] * scale) for name in ("min", "max", reference)]
            + [Signal(f"{q}: {val.label}", unit, grid * scale)]
        )
    return Plot(
        f"{kind}: simulation in the channel of the fits ({group.lo:.3g}-{group.hi:.3g} N*m)",
        Signal("torque", "N*m", group.torque),
        sides[0],
        sides[1],
        [],
        f"{kind}_channel.png",
    )


def _judge(bench: Bench, sims: list[Simulated], table: Table | None, session: Session) -> Judgement:
    out = session.workdir  # raw files, identified sets and validation reports beside the runs
    truth = _truth(sims[0].design.tree)
    files = write_group(out / "raw", truth, seed=_SEED)
    mot = identify_motor([read_characteristic(f) for f in files["motor"]], truth.motor.laa, truth.motor.j)
    drv = identify_drive([read_characteristic(f) for f in files["drive"]], mot.params, truth.ratio)
    dmp = identify_damper([read_torque_angle(f) for f in files["damper"]])
    write_identified_set(out / "motor.txt", mot)
    write_identified_set(out / "drive.txt", drv, out / "motor.txt")
    write_identified_set(out / "identified.txt", dmp, out / "drive.txt")
    params = load_params(out / "identified.txt")

    motor_sims = _simulate(session, params, "tb_motor_characteristic", MOTOR_STAND, _MOTOR_STOP)
    drive_sims = _simulate(session, params, "tb_drive_characteristic", DRIVE_STAND, _DRIVE_STOP)
    motor_vals = [
        validate(
            mot.group, "middle", f"simulated {s.run.label.split('_')[1]}", *_line(s, "dut.omega", "dut.ia"), points=7
        )
        for s in motor_sims
    ]
    drive_vals = [
        validate(
            drv.group,
            drv.reference,
            f"simulated {s.run.label.split('_')[1]}",
            *_line(s, "dut.gear.omega_g", "dut.motor.ia"),
            points=6,
        )
        for s in drive_sims
    ]
    write_report(out / "motor_report", mot, motor_vals)
    write_report(out / "drive_report", drv, drive_vals)
    write_report(out / "damper_report", dmp)

    group = "synthetic group of 5 units x 2 directions, seed 0; truth = the bench's parameter set"
    tm = truth.motor
    metrics = [
        _recovery(n, getattr(mot.params, n), getattr(tm, n), 2.0, f"parameter calculator, middle line; {group}")
        for n in ("ke", "kt", "ra")
    ]
    metrics += [
        _recovery(
            f"least squares {n}",
            getattr(mot.least_squares, n),
            getattr(tm, n),
            2.0,
            "electrical equation over the cut samples (kt is not separable at one voltage)",
        )
        for n in ("ke", "ra")
    ]
    metrics.append(_recovery("eta", drv.eta, truth.eta, 2.0, "Eq. 4.35b, motor set and mean drive line"))
    metrics.append(
        _recovery(
            "m_gc",
            drv.m_gc,
            truth.m_gc,
            40.0,
            "speed gap; inherits the motor set's error about 60-fold (seeds 0-9: -11 .. +39 %)",
        )
    )
    stiffness = np.interp(truth.damper_angles, dmp.angles, dmp.stiffness)
    metrics.append(
        metric(
            "damper stiffness recovered",
            float(np.max(rel_error_pct(stiffness, np.array(truth.damper_stiffness)))),
            0.0,
            2.0,
            "%",
            "max over the table",
        )
    )
    metrics += _validation_metrics("motor", motor_vals, 1.0, 1.0, "Fig. 4.15")
    metrics += _validation_metrics("drive", drive_vals, 0.3, 2.0, "Fig. 4.44")
    for truth_sim, ident_sim in zip(sims, drive_sims):
        t_m, t_w, t_i = _line(truth_sim, "dut.gear.omega_g", "dut.motor.ia")
        i_m, i_w, i_i = _line(ident_sim, "dut.gear.omega_g", "dut.motor.ia")
        at = drv.group.torque
        tag = truth_sim.run.label.removeprefix("truth_")
        metrics.append(
            metric(
                f"drive {tag}: identified vs truth simulation, speed",
                rel_error_pct(on_load(i_m, i_w, at), on_load(t_m, t_w, at)).max(),
                0.0,
                1.0,
                "%",
                "max over 1-6 N*m",
            )
        )
        metrics.append(
            metric(
                f"drive {tag}: identified vs truth simulation, current",
                rel_error_pct(on_load(i_m, i_i, at), on_load(t_m, t_i, at)).max(),
                0.0,
                2.0,
                "%",
                "max over 1-6 N*m",
            )
        )

    plots = [
        _channel_plot("motor", mot.group, "middle", motor_vals[0]),
        _channel_plot("drive", drv.group, drv.reference, drive_vals[0]),
    ]
    columns = {
        "torque": ("N*m", lambda s: s.waves["load.load_torque"]),
        "speed": ("rpm", lambda s: s.waves["dut.gear.omega_g"] * RPM),
        "current": ("A", lambda s: s.waves["dut.motor.ia"]),
    }
    return Judgement(metrics=metrics, plots=plots, waveforms=resampled(sims + drive_sims, columns, _DRIVE_STOP))


BENCHES = [
    Bench(
        name="identification",
        entity="tb_drive_characteristic",
        description="Synthetic test-stand group (5 units, both directions, ripple, noise) from the bench's "
        "parameter set -> "
        "identify motor, drive, damper -> simulate the characteristic testbenches with the identified set "
        "(thesis 4.1.1.4, 4.1.3, 4.1.4.2); reports in build/work/identification/",
        stop=_DRIVE_STOP,
        max_step=1e-3,
        runs=(Run("truth_cw", {"direction": 1.0}), Run("truth_ccw", {"direction": -1.0})),
        judge=_judge,
    ),
]
