"""User-facing errors. Every error wrsim reports to a user is a WrsimError; the CLI prints its text and
exits with status 2, never a traceback."""
from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Loc", "WrsimError", "SourceError"]


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
