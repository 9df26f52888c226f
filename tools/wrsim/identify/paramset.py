"""Parameter sets from identifications: the identified sections with their sources (merged into a base set),
and temperature sets derived from the 20 degC set by physical scaling (thesis 4.1.1.4, 4.1.3, 5.3.1)."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

from wrsim.closed_form.motor import drive_line_summary, motor_from_set
from wrsim.data.params import load_params, save_params
from wrsim.data.temperature import BOWDEN_MU, T_REF, temperature_rules
from wrsim.data.units import convert
from wrsim.identify.calculator import THESIS_VOLTAGE, significant
from wrsim.identify.fit import DriveIdentification, MotorIdentification
from wrsim.identify.operating import ETA_RANGE, OperatingPointIdentification

__all__ = ["identified_sections", "write_identified_set", "temperature_set"]

# ================================================================================================
# parameter sets

Section = list[tuple[str, float | list[float], str, str]]


def _curves(n: int) -> str:
    return f"{n} curve{'' if n == 1 else 's'}"


def _files(curves: list) -> str:
    names = [c.label for c in curves]
    return ", ".join(names) if len(names) <= 4 else f"{names[0]} .. {names[-1]} ({len(names)} files)"


def identified_sections(ident) -> tuple[list[str], dict[str, Section]]:
    """Header lines and parameter sections ([entity] -> (key, value, unit, source)) of an identification."""
    rpm = convert(1.0, "rad/s", "rpm")
    if isinstance(ident, MotorIdentification):
        p, d, lsq = ident.params, ident.calculator_details, ident.least_squares_details
        lo, hi = ident.fractions
        n = _curves(len(ident.curves))
        how = (
            f"parameter calculator on the middle line of {n}"
            if ident.method == "calculator"
            else f"least squares over the cut samples of {n} ({lsq['case']})"
        )
        header = [
            f"Motor identified by `wrsim identify motor` from {_files(ident.curves)}.",
            f"Conditions (group means over the working ranges): {ident.voltage:.4g} V, "
            f"load ramp {ident.torque_rate:.4g} N*m/s.",
            f"Each curve cut to {lo:.0%}-{hi:.0%} of its own stall torque and fitted with lines; middle line of "
            f"the boundaries over {ident.group.lo:.4f}-{ident.group.hi:.4f} N*m (stall {ident.stall:.4f} N*m).",
            f"Parameter calculator (Eq. 4.2-4.8) at {d['points']['torque'][0]:.4f} and "
            f"{d['points']['torque'][1]:.4f} N*m of the middle line's fit: ke {ident.calculator.ke:.6g}, "
            f"kt {ident.calculator.kt:.6g}, ra {ident.calculator.ra:.6g}, visc {ident.calculator.visc:.4g}.",
            f"Least squares ({lsq['case']}): ke {ident.least_squares.ke:.6g}, kt {ident.least_squares.kt:.6g}, "
            f"ra {ident.least_squares.ra:.6g}, visc {ident.least_squares.visc:.4g}, mc {ident.least_squares.mc:.4g}"
            + (f"; {lsq['constraint']}." if lsq["constraint"] else "."),
            f"This set: {ident.method}.",
        ]
        src = f"{how}, 10-80 % of stall"
        mc_src = (
            "Eq. 4.8a: 0 by construction of the calculator (Coulomb friction folded into visc and kt)"
            if ident.method == "calculator"
            else src
        )
        return header, {
            "dcpm_motor": [
                ("ke", significant(p.ke), "V*s/rad", f"{'Eq. 4.4b, ' if ident.method == 'calculator' else ''}{src}"),
                ("kt", significant(p.kt), "N*m/A", f"{'Eq. 4.6b, ' if ident.method == 'calculator' else ''}{src}"),
                ("ra", significant(p.ra), "Ohm", f"{'Eq. 4.5b, ' if ident.method == 'calculator' else ''}{src}"),
                ("laa", p.laa, "H", "supplier value (Tab. 4.4), input of the identification"),
                ("j", p.j, "kg*m**2", "supplier value (Tab. 4.4), input of the identification"),
                (
                    "visc",
                    significant(p.visc),
                    "N*m*s/rad",
                    f"{'Eq. 4.7b, ' if ident.method == 'calculator' else ''}{src}",
                ),
                ("mc", significant(p.mc), "N*m", mc_src),
            ]
        }
    if isinstance(ident, DriveIdentification):
        header = [
            f"Worm gear and housing identified by `wrsim identify drive` from {_files(ident.curves)}.",
            f"Conditions (group means over {ident.group.lo:g}-{ident.group.hi:g} N*m): {ident.voltage:.4g} V, "
            f"load ramp {ident.torque_rate:.4g} N*m/s at the gear.",
            f"Eq. 4.35b: s_a = {ident.motor_slope * rpm:.2f} rpm/(N*m) (motor set, steady state), "
            f"s_d = {ident.drive_slope * rpm:.4f} rpm/(N*m) ({ident.reference} line of the drive fits), "
            f"ratio {ident.ratio:g} -> eta = {ident.eta:.6f}.",
            f"m_gc closes the mean speed gap between the drive model and that line: {ident.m_gc:.4f} N*m.",
        ]
        return header, {
            "worm_gear": [
                ("ratio", ident.ratio, "1", "gear ratio, input of the identification (design)"),
                (
                    "eta",
                    significant(ident.eta),
                    "1",
                    f"Eq. 4.35b, slopes of motor set and {ident.reference} drive line",
                ),
            ],
            "drive": [
                (
                    "m_gc",
                    significant(ident.m_gc),
                    "N*m",
                    f"gear-side housing friction, speed gap to the {ident.reference} drive line",
                )
            ],
        }
    if isinstance(ident, OperatingPointIdentification):
        return _operating_sections(ident)
    header = [
        f"Rubber damper identified by `wrsim identify damper` from {_files(ident.curves)}.",
        f"Stiffness table fitted by least squares to the torques with M = c(|dphi|)*dphi (Eq. 4.28, "
        f"piecewise linear c); rms residual {ident.rms:.4g} N*m.",
    ]
    return header, {
        "rubber_damper": [
            (
                "angles",
                [significant(a) for a in ident.angles],
                "rad",
                f"table grid, {math.degrees(ident.angles[1]):g} deg steps",
            ),
            (
                "stiffness",
                [significant(c) for c in ident.stiffness],
                "N*m/rad",
                "secant stiffness (Eq. 4.28), least squares",
            ),
        ]
    }


def _operating_sections(ident: OperatingPointIdentification) -> tuple[list[str], dict[str, Section]]:
    rpm = convert(1.0, "rad/s", "rpm")
    p, fam, src = ident.motor, ident.family.name, ident.source.name
    dw, di = ident.residuals()
    s, imp = ident.summary(), ident.implied
    points = "; ".join(
        f"{m:g} N*m: {w * rpm:.4g} rpm, {i:.4g} A" for m, w, i in zip(ident.torque, ident.speed, ident.current)
    )
    fitted = f"fitted to {src} (operating points, {ident.voltage:g} V)"
    header = [
        f"Drive identified by `wrsim identify operating-points {ident.source.as_posix()}",
        f"--base {ident.family.as_posix()}` (wrsim.identify.operating), operating points at {ident.voltage:g} V:",
        f"{points}.",
        "Fitted: ke, ra, visc, eta; held: kt = ke (energy), eta in "
        f"{ETA_RANGE[0]:g} .. {ETA_RANGE[1]:g} (thesis 4.1.2.7), ratio, laa, j, mc, m_gc from {fam}.",
        "Residuals: speed "
        + ", ".join(f"{v:+.2f} %" for v in dw)
        + "; current "
        + ", ".join(f"{v:+.2f} %" for v in di)
        + ".",
        f"Drive line at {ident.voltage:g} V: no load {s['no_load_rpm']:.2f} rpm, stall {s['stall']:.3f} N*m, "
        f"slope {s['slope_rpm']:.3f} rpm/(N*m).",
        f"The points' own lines: no load {imp['no_load_rpm']:.2f} rpm / {imp['no_load_current']:.3f} A, stall "
        f"{imp['stall']:.3f} N*m, {imp['current_slope']:.4f} A/(N*m); they need kt*eta/ke = "
        f"{imp['kt_eta_over_ke']:.4f}.",
    ]
    if ident.at_bound:
        header.append(f"On a bound: {', '.join(ident.at_bound)} (the points ask for more than the bound allows).")
    return header, {
        "dcpm_motor": [
            ("ke", significant(p.ke), "V*s/rad", fitted),
            ("kt", significant(p.kt), "N*m/A", "= ke (SI identity; kt > ke would create energy)"),
            ("ra", significant(p.ra), "Ohm", fitted),
            ("laa", p.laa, "H", f"family ({fam})"),
            ("j", p.j, "kg*m**2", f"family ({fam})"),
            ("visc", significant(p.visc), "N*m*s/rad", fitted),
            ("mc", p.mc, "N*m", f"family ({fam})"),
        ],
        "worm_gear": [
            ("ratio", ident.ratio, "1", f"family ({fam})"),
            (
                "eta",
                significant(ident.eta),
                "1",
                fitted + (" (on its upper bound, self-locking limit)" if "eta" in ident.at_bound else ""),
            ),
        ],
        "drive": [("m_gc", significant(ident.m_gc), "N*m", f"family ({fam})")],
    }


def _base_sections(base: Path) -> dict[str, Section]:
    """The sections of parameter set `base` (its includes resolved), each line's source kept and prefixed by the
    name of the file that gives it."""
    pset = load_params(base)
    lines: dict[str, list[str]] = {}
    out: dict[str, Section] = {}
    for entity, keys in pset.sections.items():
        out[entity] = []
        for key, p in keys.items():
            text = lines.setdefault(p.file, Path(p.file).read_text(encoding="utf-8").splitlines())
            comment = text[p.line - 1].partition("#")[2].strip()
            name = Path(p.file).name
            out[entity].append((key, p.value, p.unit, f"{name}: {comment}" if comment else f"{name}:{p.line}"))
    return out


def write_identified_set(out: str | Path, ident, base: str | Path | None = None) -> None:
    """Write the identified sections as a parameter set; with `base`, its other sections are carried over
    (identified sections replace the base's)."""
    header, sections = identified_sections(ident)
    merged = _base_sections(Path(base)) if base else {}
    merged.update(sections)
    lines = ["wrsim parameter set generated by wrsim.identify; do not edit.", *header]
    if base:
        text = Path(base).read_text(encoding="utf-8").splitlines()
        head = [
            line[1:].strip()
            for line in text[: next((k for k, t in enumerate(text) if not t.startswith("#")), len(text))]
        ]
        lines += [f"Other sections carried over from {base}, whose header reads:", *(f"  {h}" for h in head)]
    save_params(out, lines, merged)


# ================================================================================================
# temperature parameter sets (thesis 4.1.1.4, 4.1.3, 5.3.1, chapter 6; the rules: data.temperature)


def temperature_set(base: str | Path, celsius: float, out: str | Path, u: float = THESIS_VOLTAGE) -> dict:
    """Derive the parameter set at `celsius` from the 20 degC set `base` (its includes resolved) by the rules of
    `data.temperature` and write it to `out`, each scaled value with its rule. The header compares the drive's
    characteristic at `u` with the thesis's statements (5.3.1). Returns the summaries at 20 degC and at
    `celsius` and the relative changes."""
    base = Path(base)
    pset = load_params(base)
    sections = _base_sections(base)
    rules, mu, mu20 = temperature_rules(pset, celsius, "temperature set")
    for entity, entries in sections.items():
        for n, (key, value, unit, comment) in enumerate(entries):
            factor, why = rules.get((entity, key), (None, None))
            if factor is None:
                entries[n] = (key, value, unit, f"unchanged from 20 degC ({comment})")
            else:
                scaled = (
                    [significant(v * factor) for v in value] if isinstance(value, list) else significant(value * factor)
                )
                entries[n] = (key, scaled, unit, f"{why}; 20 degC: {comment}")
    if mu is not None:
        bowden = [e for e in sections.get("bowden", []) if e[0] != "mu"]
        held = " (held below -30 degC)" if celsius < BOWDEN_MU[0][0] else ""
        sections["bowden"] = bowden + [
            ("mu", significant(mu), "1", f"thesis 4.2.1.2, Fig. 4.50: 0.20 at -30 degC, {mu20:g} at 20 degC{held}")
        ]
    motor20 = motor_from_set(pset)
    f_r, f_k = rules[("dcpm_motor", "ra")][0], rules[("dcpm_motor", "ke")][0]
    motor = replace(motor20, ke=motor20.ke * f_k, kt=motor20.kt * f_k, ra=motor20.ra * f_r)
    ratio, eta = pset.number_in("worm_gear", "ratio", "1"), pset.number_in("worm_gear", "eta", "1")
    m_gc = pset.number_in("drive", "m_gc", "N*m")
    s20 = drive_line_summary(motor20, ratio, eta, m_gc, u)
    st = drive_line_summary(motor, ratio, eta, m_gc * rules[("drive", "m_gc")][0], u)
    change = {k: st[k] / s20[k] - 1.0 for k in s20}
    applied = sorted(f"[{e}] {k}" for (e, k) in rules if k in {key for key, *_ in sections.get(e, [])})
    header = [
        f"wrsim parameter set: {base.name} ({T_REF:g} degC) at {celsius:g} degC, by the temperature rules of",
        f"wrsim.data.temperature (`wrsim identify temperature --celsius {celsius:g}`, docs/door-physics.md); do not "
        "edit.",
        "Scaled: " + ", ".join(applied) + (", [bowden] mu" if mu is not None else "") + "; each line names its rule.",
        f"Drive at {u:g} V, steady state (closed form of Eq. 4.30/4.31), against {T_REF:g} degC: no-load speed",
        f"  {s20['no_load_rpm']:.2f} -> {st['no_load_rpm']:.2f} rpm ({change['no_load_rpm']:+.1%}), stall torque "
        f"{s20['stall']:.2f} -> {st['stall']:.2f} N*m ({change['stall']:+.1%}), slope x"
        f"{st['slope_rpm'] / s20['slope_rpm']:.2f} ({'steeper' if change['slope_rpm'] > 0 else 'flatter'}).",
        "  Thesis 5.3.1: at 80 degC steeper, no-load speed +20 .. 30 %, maximal torque about -30 %; at -40 degC",
        "  flat (Fig. 5.5, no numbers).",
    ]
    save_params(out, header, sections)
    return {"at_20": s20, "at_t": st, "change": change}
