"""The one pint unit registry of wrsim, and unit conversion that reports problems as WrsimError.

Units are written in pint syntax (`N*m`, `V*s/rad`, `kg*m**2`, `rpm`, `Ohm`, `1` for dimensionless).
pint treats `rad` as dimensionless, so `rpm` converts to `rad/s` (and also to `1/s`).
"""

from __future__ import annotations

import functools
import math
import re
import sys
from typing import TYPE_CHECKING, overload

import numpy as np

from wrsim.errors import WrsimError

if TYPE_CHECKING:
    import pint

__all__ = ["registry", "check_unit", "convert", "parse_number"]


@functools.cache
def registry() -> pint.UnitRegistry:
    """The one pint registry, made at its first use (pint and its definitions take some 0.4 s to load, which a
    command that converts no unit, `wrsim list`, need not pay)."""
    import pint

    ureg: pint.UnitRegistry = pint.UnitRegistry()
    ureg.define("Ohm = ohm")  # the spelling used in the thesis and in VHDL comments
    pint.set_application_registry(ureg)
    return ureg


def parse_number(text: str, where: str) -> float:
    """The number written as `text`: finite, and not so small that it becomes 0 or loses digits (a written 1e-400 is
    no 0). One error naming `where` otherwise."""
    try:
        value = float(text)
    except ValueError:
        raise WrsimError(f"{where}: '{text}' is not a number") from None
    if not math.isfinite(value):
        raise WrsimError(f"{where}: '{text}' is not a finite number")
    written_nonzero = re.search(r"[1-9]", re.split(r"[eE]", text)[0]) is not None
    if 0.0 < abs(value) < sys.float_info.min or (value == 0.0 and written_nonzero):
        raise WrsimError(f"{where}: '{text}' is below the smallest number kept in full ({sys.float_info.min:.1e})")
    return value


def check_unit(unit: str) -> pint.Unit:
    """Parse a unit string; raise WrsimError if it is empty or not a unit pint knows."""
    if not unit.strip():
        raise WrsimError("empty unit (write 1 for a dimensionless value)")
    try:
        return registry().parse_units(unit)
    # pint's expression parser raises assorted exception types (TokenError, AssertionError,
    # ZeroDivisionError, ...) for malformed input; all of them mean "not a unit".
    except Exception as exc:  # noqa: BLE001
        detail = f": {exc}" if str(exc) else ""
        raise WrsimError(f"unknown unit '{unit}'{detail}") from exc


@overload
def convert(value: float, from_unit: str, to_unit: str) -> float: ...
@overload
def convert(value: np.ndarray, from_unit: str, to_unit: str) -> np.ndarray: ...


def convert(value: float | np.ndarray, from_unit: str, to_unit: str) -> float | np.ndarray:
    """Convert `value` (a number or a numpy array) from `from_unit` to `to_unit`.

    Returns a float for a scalar input and a float array for an array input. Raises WrsimError for
    an unknown unit or when the two units have different dimensions.
    """
    import pint

    src, dst = check_unit(from_unit), check_unit(to_unit)
    magnitude = np.asarray(value, dtype=float)
    try:
        with np.errstate(over="ignore", invalid="ignore"):  # a non-finite result is the caller's to report
            out = registry().Quantity(magnitude, src).to(dst).magnitude
    except pint.DimensionalityError as exc:
        raise WrsimError(f"cannot convert '{from_unit}' ({exc.dim1}) to '{to_unit}' ({exc.dim2})") from exc
    return float(out) if np.ndim(out) == 0 else np.asarray(out, dtype=float)
