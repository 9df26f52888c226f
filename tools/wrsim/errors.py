"""User-facing errors. Every error wrsim reports to a user is a WrsimError; the CLI prints its text and
exits with status 2, never a traceback."""

from __future__ import annotations

import math
from dataclasses import dataclass
from numbers import Real

__all__ = ["Loc", "WrsimError", "SourceError", "finite", "positive", "non_negative"]


@dataclass(frozen=True)
class Loc:
    """A position in a source file (1-based line and column)."""

    file: str
    line: int
    col: int

    def __str__(self) -> str:
        return f"{self.file}:{self.line}:{self.col}"


class WrsimError(Exception):
    """An error whose message is complete and meant for the user as it is."""


class SourceError(WrsimError):
    """An error located in a source file: the message starts with file:line:col."""

    def __init__(self, loc: Loc, message: str):
        super().__init__(f"{loc}: {message}")
        self.loc = loc
        self.message = message


def finite(name: str, value: object) -> float:
    """`value` as a float; WrsimError naming `name` unless it is a finite real number."""
    if isinstance(value, bool) or not isinstance(value, Real):
        raise WrsimError(f"{name} must be a real number, got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise WrsimError(f"{name} must be finite, got {x!r}")
    return x


def positive(name: str, value: object) -> float:
    x = finite(name, value)
    if x <= 0.0:
        raise WrsimError(f"{name} must be > 0, got {x!r}")
    return x


def non_negative(name: str, value: object) -> float:
    x = finite(name, value)
    if x < 0.0:
        raise WrsimError(f"{name} must be >= 0, got {x!r}")
    return x
