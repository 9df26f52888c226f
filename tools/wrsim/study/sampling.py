"""What a study varies and how: the toleranced values of a parameter set (`factors`), reproducible Monte Carlo
draws (`draw`: sample `i` of seed `s` is the same whatever the study's size, worker or order), the corners of a
one-at-a-time sensitivity plan and of a worst case, and the set a sample runs with (`sample_set`).

Draws go through a Gaussian copula: every factor gets a standard-normal number z, made of its group's common
draw (correlation rho) and a draw of its own; the law turns z into a value (normal: the nominal plus
z * deviation / sigmas; uniform: the normal CDF of z spread over the range; table: the row at that quantile)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from wrsim.data.params import Param, ParamSet, Tolerance, Value
from wrsim.data.units import convert
from wrsim.errors import WrsimError

__all__ = ["Factor", "factors", "draw", "units", "sensitivity_plan", "worst_case_plan", "sample_set"]


@dataclass(frozen=True)
class Factor:
    """One toleranced value: `[entity] key`, its nominal value in `unit`, and its tolerance."""

    entity: str
    key: str
    nominal: Value
    unit: str
    tolerance: Tolerance

    @property
    def name(self) -> str:
        """`entity.key`, the column name in a study's results."""
        return f"{self.entity}.{self.key}"

    def _shift(self, nominal: float, fraction: float) -> float:
        """The nominal moved by `fraction` (-1 .. 1 at the tolerance limits) of the deviation."""
        t = self.tolerance
        if t.relative:
            return nominal * (1.0 + fraction * t.deviation)
        delta = convert(t.deviation, t.unit, self.unit) - convert(0.0, t.unit, self.unit)
        return nominal + fraction * delta

    def _range(self) -> tuple[float, float]:
        t = self.tolerance
        lo, hi = t.limits if t.limits else (min(t.values), max(t.values))
        return convert(lo, t.unit, self.unit), convert(hi, t.unit, self.unit)

    def at(self, z: float) -> Value:
        """The value at the standard-normal draw `z`."""
        from scipy.special import ndtr

        t = self.tolerance
        if t.law == "normal":
            return self._moved(z / t.sigmas)
        u = float(ndtr(z))
        if t.law == "table":
            return convert(t.values[min(int(u * len(t.values)), len(t.values) - 1)], t.unit, self.unit)
        if t.limits:
            lo, hi = self._range()
            return lo + (hi - lo) * u
        return self._moved(2.0 * u - 1.0)

    def limit(self, side: int) -> Value:
        """The value at the low (`side` -1) or high (+1) tolerance limit: nominal -+ deviation (for a normal law
        the deviation is `sigmas` standard deviations), the range's ends, the table's smallest or largest row."""
        t = self.tolerance
        if t.limits or t.law == "table":
            return self._range()[side > 0]
        return self._moved(float(side))

    def _moved(self, fraction: float) -> Value:
        if isinstance(self.nominal, list):
            return [self._shift(v, fraction) for v in self.nominal]
        return self._shift(self.nominal, fraction)


def factors(pset: ParamSet) -> list[Factor]:
    """The toleranced values of `pset`, sorted by name (the order of the draws). A tolerance whose value no set
    gives is an error naming the tolerance's line."""
    out = []
    for entity, keys in pset.tolerances.items():
        for key, t in keys.items():
            if t.law == "calibrate":  # a calibration's search range, not a spread
                continue
            p = pset.sections.get(entity, {}).get(key)
            if p is None:
                raise WrsimError(
                    f"{t.file}:{t.line}: [{entity}] {key}: a tolerance without a nominal value (no set "
                    f"beneath gives [{entity}] {key} = value unit)"
                )
            out.append(Factor(entity, key, p.value, p.unit, t))
    return sorted(out, key=lambda f: f.name)


def draw(fs: list[Factor], seed: int, sample: int) -> dict[str, Value]:
    """The values of Monte Carlo sample `sample` of the study with `seed`, by factor name."""
    groups = sorted({f.tolerance.group for f in fs if f.tolerance.group})
    rng = np.random.default_rng([seed, sample])
    common = dict(zip(groups, rng.standard_normal(len(groups))))
    own = rng.standard_normal(len(fs))
    out: dict[str, Value] = {}
    for f, e in zip(fs, own):
        t = f.tolerance
        z = t.rho * common[t.group] + math.sqrt(max(0.0, 1.0 - t.rho**2)) * e if t.group else e
        out[f.name] = f.at(float(z))
    return out


def units(fs: list[Factor]) -> list[tuple[str, list[tuple[Factor, int]]]]:
    """What a sensitivity moves as one: every factor of a group together (`group NAME`; a member with a negative
    correlation the other way), every other factor alone. (name, [(factor, direction)])."""
    out: dict[str, list[tuple[Factor, int]]] = {}
    for f in fs:
        t = f.tolerance
        out.setdefault(f"group {t.group}" if t.group else f.name, []).append((f, -1 if t.rho < 0 else 1))
    return list(out.items())


def _at(fs: list[Factor], moved: list[tuple[Factor, int]], side: int) -> dict[str, Value]:
    values = {f.name: f.nominal for f in fs}
    values.update({f.name: f.limit(side * direction) for f, direction in moved})
    return values


def sensitivity_plan(fs: list[Factor]) -> list[tuple[str, dict[str, Value]]]:
    """The nominal point, then every unit (`units`) alone at its low and at its high limit: (label, values)."""
    plan = [("nominal", _at(fs, [], 1))]
    for name, moved in units(fs):
        plan += [(f"{name} low", _at(fs, moved, -1)), (f"{name} high", _at(fs, moved, 1))]
    return plan


def worst_case_plan(fs: list[Factor], effects: dict[str, dict[str, float]]) -> list[tuple[str, dict[str, Value]]]:
    """For every output, the corner that pushes it lowest and the one that pushes it highest: each unit at the
    limit whose one-at-a-time effect (`effects[output][unit]` = high minus low) moves the output that way; a unit
    without a (finite, non-zero) effect stays nominal, an output without any gets no corners. (label, values)."""
    plan = []
    for output, effect in effects.items():
        moving = [
            (name, moved, math.copysign(1.0, effect[name]))
            for name, moved in units(fs)
            if math.isfinite(effect.get(name, math.nan)) and effect[name] != 0.0
        ]
        if not moving:
            continue
        for side, sign in (("lowest", -1), ("highest", 1)):
            values = {f.name: f.nominal for f in fs}
            for _, moved, slope in moving:
                values.update({f.name: f.limit(int(sign * slope) * direction) for f, direction in moved})
            plan.append((f"{output} {side}", values))
    return plan


def sample_set(pset: ParamSet, values: dict[str, Value], label: str) -> ParamSet:
    """`pset` with `values` (by factor name) in place of the nominal ones and no tolerances left; the user's set
    it carries (`ParamSet.user`, laid on top again beneath a run's own set) gets the same values."""
    sections = {e: dict(keys) for e, keys in pset.sections.items()}
    for name, value in values.items():
        entity, key = name.split(".", 1)
        p = sections.get(entity, {}).get(key)
        if p is not None:
            sections[entity][key] = Param(value, p.unit, p.file, p.line)
    user = None if pset.user is None else sample_set(pset.user, values, label)
    return dataclasses.replace(pset, name=f"{pset.name}@{label}", sections=sections, tolerances={}, user=user)
