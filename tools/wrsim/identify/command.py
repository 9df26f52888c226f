"""`wrsim identify motor|drive|damper|operating-points|temperature`: one identification from files, its parameter
set and report."""

from __future__ import annotations

import math
from pathlib import Path

from wrsim.closed_form.motor import motor_from_set
from wrsim.data.curves import read_characteristic, read_torque_angle
from wrsim.data.params import load_params
from wrsim.data.units import convert
from wrsim.errors import WrsimError
from wrsim.identify.calculator import THESIS_J, THESIS_LAA, THESIS_VOLTAGE
from wrsim.identify.fit import (
    DamperIdentification,
    DriveIdentification,
    MotorIdentification,
    identify_damper,
    identify_drive,
    identify_motor,
    validate,
)
from wrsim.identify.operating import identify_operating_points
from wrsim.identify.paramset import temperature_set, write_identified_set
from wrsim.identify.report import write_report

__all__ = ["identify_files"]

# ================================================================================================
# command line (`wrsim identify motor|drive|damper|temperature`)


def identify_files(
    what: str,
    files: list[Path],
    out: Path | None,
    base: Path | None = None,
    report: Path | None = None,
    ratio: float | None = None,
    method: str = "calculator",
    celsius: float | None = None,
    voltage: float = THESIS_VOLTAGE,
) -> list[str]:
    """Run one identification from files, write the parameter set `out` (and the report directory) and
    return the lines to print."""
    if out is None:
        raise WrsimError(f"identify {what}: give --out FILE for the parameter set")
    if what == "temperature":
        if base is None or celsius is None or files:
            raise WrsimError("identify temperature: give --base PARAMS --celsius T (and no files)")
        r = temperature_set(base, celsius, out)
        c = r["change"]
        return [
            f"drive at {celsius:g} degC vs 20 degC: no-load speed {c['no_load_rpm']:+.1%}, stall torque "
            f"{c['stall']:+.1%}, slope {c['slope_rpm']:+.1%}",
            f"wrote {out}",
        ]
    if what == "operating-points":
        if base is None or len(files) != 1 or report is not None:
            raise WrsimError(
                "identify operating-points: give one CSV of operating points and --base FAMILY (no --report: the "
                "residuals go into the set's header)"
            )
        op = identify_operating_points(files[0], base, voltage)
        write_identified_set(out, op)
        dw, dc = op.residuals()
        s = op.summary()
        return [
            f"drive: ke=kt={op.motor.ke:.6g} V*s/rad ra={op.motor.ra:.6g} Ohm visc={op.motor.visc:.4g} N*m*s/rad "
            f"eta={op.eta:.4g}" + (f" (on a bound: {', '.join(op.at_bound)})" if op.at_bound else ""),
            "residuals: speed "
            + ", ".join(f"{v:+.2f} %" for v in dw)
            + "; current "
            + ", ".join(f"{v:+.2f} %" for v in dc),
            f"line at {voltage:g} V: no load {s['no_load_rpm']:.2f} rpm, stall {s['stall']:.3f} N*m",
            f"wrote {out}",
        ]
    if not files:
        raise WrsimError(f"identify {what}: give one or more measurement files")
    pset = load_params(base) if base else None
    rpm = convert(1.0, "rad/s", "rpm")
    ident: MotorIdentification | DriveIdentification | DamperIdentification
    if what == "motor":
        known = pset.sections.get("dcpm_motor", {}) if pset else {}
        laa = pset.number_in("dcpm_motor", "laa", "H") if pset and "laa" in known else THESIS_LAA
        j = pset.number_in("dcpm_motor", "j", "kg*m**2") if pset and "j" in known else THESIS_J
        motor = identify_motor([read_characteristic(f) for f in files], laa, j, method=method)
        p, ident = motor.params, motor
        lines = [
            f"motor ({motor.method}): ke={p.ke:.6g} V*s/rad kt={p.kt:.6g} N*m/A ra={p.ra:.6g} Ohm "
            f"visc={p.visc:.6g} N*m*s/rad mc={p.mc:.3g} N*m"
        ]
    elif what == "drive":
        if pset is None or "dcpm_motor" not in pset.sections:
            raise WrsimError(
                "identify drive: needs the motor set: give --base PARAMS with a [dcpm_motor] section "
                "(e.g. the output of `wrsim identify motor`)"
            )
        if ratio is None:
            if "ratio" not in pset.sections.get("worm_gear", {}):
                raise WrsimError(f"identify drive: give --ratio (no [worm_gear] ratio in {base})")
            ratio = pset.number_in("worm_gear", "ratio", "1")
        drive = identify_drive([read_characteristic(f) for f in files], motor_from_set(pset), ratio)
        ident = drive
        lines = [
            f"drive: ratio={drive.ratio:g} eta={drive.eta:.6g} m_gc={drive.m_gc:.6g} N*m "
            f"(s_a={drive.motor_slope * rpm:.2f}, s_d={drive.drive_slope * rpm:.4f} rpm/(N*m))"
        ]
    elif what == "damper":
        damper = identify_damper([read_torque_angle(f) for f in files])
        ident = damper
        lines = [
            "damper: stiffness "
            + ", ".join(f"{c:.4g}" for c in damper.stiffness)
            + " N*m/rad at "
            + ", ".join(f"{math.degrees(a):g}" for a in damper.angles)
            + f" deg (rms {damper.rms:.3g} N*m)"
        ]
    else:
        raise WrsimError(
            f"identify: unknown kind '{what}' (motor, drive, damper, operating-points, temperature, default)"
        )
    write_identified_set(out, ident, base)
    lines.append(f"wrote {out}")
    if report:
        validations = []
        if not isinstance(ident, DamperIdentification):
            g = ident.group
            validations.append(
                validate(
                    g,
                    ident.reference,
                    "model (closed form)",
                    g.torque,
                    *ident.model_line(g.torque),
                    points=7 if what == "motor" else 6,
                )
            )
            v = validations[0]
            lines.insert(
                -1,
                f"model vs {v.reference} line: max speed difference {v.max_speed_error:.3f} %, current "
                f"{v.max_current_error:.3f} %; outside the channel: speed {v.speed_outside:.3g} %, "
                f"current {v.current_outside:.3g} %",
            )
        lines.append(f"report: {write_report(report, ident, validations)}")
    return lines
