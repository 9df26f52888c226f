"""What every part of the expression evaluator shares: its state (the scope, the callbacks of the model pass, the
process run under way, the work done), the bounds of elaboration-time evaluation, and the methods the parts call on
one another (`Evaluator` in `evaluate` puts the parts together)."""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping

from wrsim.elab import symbolic as sy
from wrsim.elab.scope import Function, Scope
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast

__all__ = ["EvaluatorBase", "MAX_INTEGER", "MAX_ITERATIONS", "MAX_STEPS"]

MAX_INTEGER = 2.0**63 - 1  # VHDL-2008 integers are at most 64-bit
MAX_ITERATIONS = 10_000  # iterations of one loop unrolled at elaboration
MAX_STEPS = 1_000_000  # statements one evaluator executes in function bodies (nested loops included)


class EvaluatorBase(ABC):
    """The evaluator's state and the methods its parts call on one another. The model pass's callbacks: `on_dot` /
    `on_integ` for q'dot / q'integ, `on_signal` for a signal's 0/1 level, `on_above` for q'above, `on_system` for
    the attributes that are systems of their own and 'last_value; `allow_quantities` False: static values only."""

    def __init__(
        self,
        scope: Scope,
        on_dot=None,
        on_integ=None,
        allow_quantities: bool = True,
        on_signal=None,
        on_above=None,
        on_system=None,
    ):
        self.scope = scope
        self.on_dot = on_dot
        self.on_integ = on_integ
        self.on_signal = on_signal
        self.on_above = on_above
        self.on_system = on_system  # (attribute, prefix, [(argument, type)], loc) -> value, for SYSTEM_ATTRS
        self.on_effect: Callable[..., list[tuple[str, S]]] | None = None  # in a process: (signal assignment or
        # break, scope, the effects so far on this path) -> [(held node, value)]
        self.events: Mapping[str, S] | None = None  # in a process's run: the held nodes of the signals that may have
        # an event, each with the boolean that it has (true, or the read of its event flag); the others have none
        self.event_read = False  # whether the run read an event ('event, rising_edge)
        self.allow_quantities = allow_quantities
        self.depth = 0
        self.steps = 0  # statements executed in function bodies (bounded by MAX_STEPS)

    def event(self, signal: S, loc: Loc) -> S:
        """Whether the held signal `signal` has an event in the process run under way (`events`): a boolean."""
        nodes = sy.nodes_of(signal)
        if len(nodes) != 1 or self.events is None:
            raise SourceError(
                loc,
                "unsupported construct: an event of something other than a signal a process of "
                "this architecture assigns",
            )
        self.event_read = True
        return self.events.get(next(iter(nodes)), sy.const(False))

    def real(self, e: ast.Expr, scope: Scope | None = None) -> S:
        """The value of `e`, which must be real or integer."""
        s, t = self.eval(e, scope)
        if t not in ("real", "integer"):
            raise SourceError(e.loc, f"expected a real expression, found {t}")
        return s

    @abstractmethod
    def eval(self, e: ast.Expr, scope: Scope | None = None) -> tuple[S, str]:
        """The symbolic value and type of `e` (in `scope`, by default the evaluator's)."""

    @abstractmethod
    def name(self, e: ast.Name, scope: Scope) -> tuple[S, str]:
        """The value and type a simple name stands for."""

    @abstractmethod
    def element(self, e: ast.Call, scope: Scope):
        """The element `a(k)` of an array quantity or vector terminal, None when `a` is neither."""

    @abstractmethod
    def apply(self, f: Function, args: list[tuple[S, str]], loc: Loc) -> tuple[S, str]:
        """The value and type of a call of function `f` with evaluated arguments."""
