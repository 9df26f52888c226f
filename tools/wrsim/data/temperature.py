"""The ambient temperature of a parameter set: the rules that scale a 20 degC set to another temperature within
-40 .. 85 degC (thesis 4.1.1.4, 4.1.2.7, 4.1.3, 4.2.1.2, 5.3.1, chapter 6), applied to a set's `[ambient]
temperature` by `at_temperature` (every run, in `data.params.resolve_params`) and written out as a derived set by
`wrsim identify temperature` (identify.paramset.temperature_set). docs/door-physics.md gives each rule's source.

Every rule is a factor on a 20 degC value (the bowden's friction coefficient is a value):

* drive (5.3.1: at 80 degC "no-load speed increases for about 20% to 30% and maximal torque decreases for about
  30%"): flux ke, kt x(1 + ALPHA_FLUX*dT) and resistance ra x(1 + ALPHA_RA*dT), linear in dT, with the two
  coefficients solved from the statement on an ideal motor (no-load speed ~ 1/ke: x1.25, the middle of 20-30 %;
  stall torque ~ kt/ra: x0.70). The cold end follows the same lines: the "flat" line of 5.3.1 at -40 degC;
* gear grease (4.1.4: grease traction is part of the housing friction m_gc): m_gc x2**(-dT/GREASE_DOUBLING_K),
  an assumption; the mesh efficiency eta, which decides self-locking, is held;
* seals (5.3.1: sealing friction "increases greatly, as rubber turns harder" in the cold and "becomes less" at
  80 degC): [seal_friction] forces and [top_frame_seal] frictions x SEAL_FACTORS (piecewise linear), an
  assumption bounded by those statements;
* rubber damper (4.1.3, Fig. 4.33: "quite stiff" at -40 degC, a little softer at 80 degC): x DAMPER_FACTORS,
  an assumption;
* bowden (4.2.1.2, Fig. 4.50, measured): mu 0.08 from 20 to 80 degC, 0.20 at -30 degC, linear in between (an
  assumption), held at 0.20 below -30 degC and at its 20 degC value above 20 degC;
* the PWM ECU's MOSFETs (not in the thesis): on-resistance r_ds_on x(1 + ALPHA_RDS_ON*dT), the slope of the
  normalized on-resistance of automotive trench MOSFETs' datasheets (about x1.6 from 25 to 150 degC), with the
  junction at the ambient temperature (no self-heating).
"""

from __future__ import annotations

import dataclasses

import numpy as np

from wrsim.data.params import Param, ParamSet
from wrsim.errors import WrsimError

__all__ = [
    "T_REF",
    "T_RANGE",
    "ALPHA_FLUX",
    "ALPHA_RA",
    "GREASE_DOUBLING_K",
    "SEAL_FACTORS",
    "DAMPER_FACTORS",
    "BOWDEN_MU",
    "ALPHA_RDS_ON",
    "temperature_rules",
    "at_temperature",
]

T_REF = 20.0  # degC, temperature of the identified set (room temperature, 4.1.1.4)
T_RANGE = (-40.0, 85.0)  # degC, the range the rules cover (5.3.1: -40 .. 80 degC; 85 degC: automotive grade)
# The drive at 80 degC as 5.3.1 states it (no-load speed x1.25, maximal torque x0.70), on an ideal motor.
_NO_LOAD_80, _STALL_80 = 1.25, 0.70
ALPHA_FLUX = (1.0 / _NO_LOAD_80 - 1.0) / (80.0 - T_REF)  # 1/K: -3.33e-3
ALPHA_RA = (1.0 / _NO_LOAD_80 / _STALL_80 - 1.0) / (80.0 - T_REF)  # 1/K: +2.38e-3
GREASE_DOUBLING_K = 60.0  # K: the gear's housing friction doubles every 60 K colder (assumption)
SEAL_FACTORS = ((-40.0, 2.0), (20.0, 1.0), (85.0, 0.8))  # seal friction (assumption, bounded by 5.3.1)
DAMPER_FACTORS = ((-40.0, 2.0), (20.0, 1.0), (85.0, 0.9))  # rubber-damper stiffness (assumption, Fig. 4.33)
BOWDEN_MU = ((-30.0, 0.20), (20.0, 0.08))  # thesis 4.2.1.2, Fig. 4.50 (measured)
ALPHA_RDS_ON = 0.005  # 1/K: a MOSFET's on-resistance (datasheet curves, about x1.6 from 25 to 150 degC)

Rules = dict[tuple[str, str], tuple[float, str]]


def _interp(table: tuple[tuple[float, float], ...], celsius: float) -> float:
    ts, fs = zip(*table)
    return float(np.interp(celsius, ts, fs))


def temperature_rules(pset: ParamSet, celsius: float, what: str) -> tuple[Rules, float | None, float]:
    """The scaling of the 20 degC set `pset` at `celsius`: factors (entity, key) -> (factor, why), the bowden
    friction coefficient below 20 degC (None above) and its 20 degC value. `what` names the input in errors."""
    if not T_RANGE[0] <= celsius <= T_RANGE[1]:
        raise WrsimError(
            f"{what}: {celsius:g} degC is outside {T_RANGE[0]:g} .. {T_RANGE[1]:g} degC, the range the rules cover"
        )
    dt = celsius - T_REF
    f_r, f_k = 1.0 + ALPHA_RA * dt, 1.0 + ALPHA_FLUX * dt
    f_g = 2.0 ** (-dt / GREASE_DOUBLING_K)
    f_s, f_c = _interp(SEAL_FACTORS, celsius), _interp(DAMPER_FACTORS, celsius)
    flux = f"flux x(1 {ALPHA_FLUX * 100:+.3f} %/K*({dt:+g} K)) = x{f_k:.4f} (5.3.1 at 80 degC)"
    seal = f"seal x{f_s:.3g} (assumption bounded by 5.3.1: rubber harder in the cold)"
    rules = {
        ("dcpm_motor", "ra"): (f_r, f"resistance x(1 {ALPHA_RA * 100:+.3f} %/K*({dt:+g} K)) = x{f_r:.4f} (5.3.1)"),
        ("dcpm_motor", "ke"): (f_k, flux),
        ("dcpm_motor", "kt"): (f_k, flux),
        ("drive", "m_gc"): (f_g, f"grease x2**({-dt:+g} K/{GREASE_DOUBLING_K:g} K) = x{f_g:.4f} (assumption)"),
        ("seal_friction", "forces"): (f_s, seal),
        ("top_frame_seal", "frictions"): (f_s, seal),
        ("rubber_damper", "stiffness"): (f_c, f"damper x{f_c:.3g} (assumption, Fig. 4.33 qualitative)"),
        ("h_bridge", "r_ds_on"): (
            1.0 + ALPHA_RDS_ON * dt,
            f"on-resistance x(1 {ALPHA_RDS_ON * 100:+.2f} %/K*({dt:+g} K)) (MOSFET datasheets)",
        ),
    }
    mu20 = pset.number_in("bowden", "mu", "1") if "mu" in pset.sections.get("bowden", {}) else BOWDEN_MU[1][1]
    mu = (
        float(np.interp(celsius, [BOWDEN_MU[0][0], T_REF], [BOWDEN_MU[0][1], mu20], left=BOWDEN_MU[0][1]))
        if celsius < T_REF
        else None
    )
    return rules, mu, mu20


def at_temperature(pset: ParamSet) -> ParamSet:
    """`pset` with its `[ambient] temperature` applied by `temperature_rules` (the values scaled from the 20 degC
    ones the set holds) and the section removed; `pset` itself when it has no [ambient] section."""
    ambient = pset.sections.get("ambient")
    if ambient is None:
        return pset
    unknown = [k for k in ambient if k != "temperature"]
    if unknown:
        p = ambient[unknown[0]]
        raise WrsimError(f"{p.file}:{p.line}: [ambient] {unknown[0]}: unknown key (the section holds temperature)")
    celsius = pset.number_in("ambient", "temperature", "degC") if "temperature" in ambient else None
    sections = {e: dict(keys) for e, keys in pset.sections.items() if e != "ambient"}
    pset = dataclasses.replace(
        pset, sections=sections, tolerances={e: t for e, t in pset.tolerances.items() if e != "ambient"}
    )
    if celsius is None:
        return pset
    p = ambient["temperature"]
    rules, mu, _ = temperature_rules(pset, celsius, f"{p.file}:{p.line}: [ambient] temperature")
    for (entity, key), (factor, _) in rules.items():
        given = sections.get(entity, {}).get(key)
        if given is not None:
            value = [v * factor for v in given.value] if isinstance(given.value, list) else given.value * factor
            sections[entity][key] = dataclasses.replace(given, value=value)
    if mu is not None:
        sections.setdefault("bowden", {})["mu"] = Param(mu, "1", p.file, p.line)
    return pset
