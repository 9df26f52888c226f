"""The ambient temperature of a parameter set: the rules that scale a 20 degC set to another temperature (thesis
4.1.1.4, 4.1.3, 5.3.1, chapter 6), applied to a set's `[ambient] temperature` by `at_temperature` (every run, in
`data.params.resolve_params`) and written out as a derived set by `wrsim identify temperature`
(identify.paramset.temperature_set)."""

from __future__ import annotations

import dataclasses

import numpy as np

from wrsim.data.params import Param, ParamSet
from wrsim.errors import WrsimError

__all__ = ["T_REF", "ALPHA_CU", "ALPHA_BR", "BOWDEN_MU", "temperature_rules", "at_temperature"]

T_REF = 20.0  # degC, temperature of the identified set (room temperature, 4.1.1.4)
ALPHA_CU = 3.93e-3  # 1/K, resistance of annealed copper at 20 degC (IEC 60028)
ALPHA_BR = -2.0e-3  # 1/K, remanence of hard ferrite magnets (typically -0.18 .. -0.20 %/K)
# Assumed rubber-damper stiffness factors: Fig. 4.33 shows the damper "quite stiff" at -40 degC and "softer,
# but not much" at 80 degC; its data is not in the text.
_DAMPER_FACTORS = ((-30.0, 2.0), (20.0, 1.0), (80.0, 0.9))
# Bowden friction coefficient (thesis 4.2.1.2, Fig. 4.50, thesis numbers): 0.20 at -30 degC, 0.08 from 20 to
# 80 degC; between -30 and 20 degC linear (assumption).
BOWDEN_MU = ((-30.0, 0.20), (20.0, 0.08))


def _damper_factor(celsius: float) -> float:
    ts, fs = zip(*_DAMPER_FACTORS)
    return float(np.interp(celsius, ts, fs))


def temperature_rules(
    pset: ParamSet, celsius: float, what: str
) -> tuple[dict[tuple[str, str], tuple[float, str]], float | None, float]:
    """The scaling of the 20 degC set `pset` at `celsius`: factors (entity, key) -> (factor, why), the bowden
    friction coefficient below 20 degC (None above) and its 20 degC value. `what` names the input in errors."""
    if not _DAMPER_FACTORS[0][0] <= celsius <= _DAMPER_FACTORS[-1][0]:
        raise WrsimError(
            f"{what}: {celsius:g} degC is outside {_DAMPER_FACTORS[0][0]:g} .. "
            f"{_DAMPER_FACTORS[-1][0]:g} degC, the range the scaling is documented for"
        )
    dt = celsius - T_REF
    f_r, f_k, f_c = 1.0 + ALPHA_CU * dt, 1.0 + ALPHA_BR * dt, _damper_factor(celsius)
    rules = {
        ("dcpm_motor", "ra"): (f_r, f"copper: x(1 + {ALPHA_CU:g}/K*({dt:+g} K)) = x{f_r:.4f}"),
        ("dcpm_motor", "ke"): (f_k, f"ferrite flux: x(1 {ALPHA_BR:+g}/K*({dt:+g} K)) = x{f_k:.4f}"),
        ("dcpm_motor", "kt"): (f_k, f"ferrite flux: x(1 {ALPHA_BR:+g}/K*({dt:+g} K)) = x{f_k:.4f}"),
        ("rubber_damper", "stiffness"): (f_c, f"assumed x{f_c:g} (Fig. 4.33 qualitative, no data)"),
    }
    mu20 = pset.number_in("bowden", "mu", "1") if "mu" in pset.sections.get("bowden", {}) else BOWDEN_MU[1][1]
    mu = float(np.interp(celsius, [BOWDEN_MU[0][0], T_REF], [BOWDEN_MU[0][1], mu20])) if celsius < T_REF else None
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
