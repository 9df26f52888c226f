"""Symbolic evaluation of VHDL-AMS expressions and function bodies: static parts fold to numbers, branches
on quantities become conditional expressions, loops unroll. `Evaluator` puts the parts together: literals and
operators (`operators`), names and attributes (`names`), calls and function bodies (`calls`)."""

from __future__ import annotations

from wrsim.elab import symbolic as sy
from wrsim.elab.calls import CallsAndBodies
from wrsim.elab.evaluator_base import MAX_INTEGER
from wrsim.elab.names import NamesAndAttributes
from wrsim.elab.operators import binary, literal, unary
from wrsim.elab.scope import Scope
from wrsim.elab.symbolic import S
from wrsim.errors import SourceError
from wrsim.frontend import ast

__all__ = ["Evaluator"]


class Evaluator(NamesAndAttributes, CallsAndBodies):
    """VHDL-AMS expression -> (symbolic value, type), in a scope; see `EvaluatorBase` for the callbacks of the
    model pass."""

    def eval(self, e: ast.Expr, scope: Scope | None = None) -> tuple[S, str]:
        """The symbolic value and type of `e`; an operation on constants without a finite result, an integer out of
        range or an expression too deep is a SourceError at the operation."""
        try:
            s, t = self.evaluate(e, scope or self.scope)
        except sy.FoldError as ex:
            raise SourceError(e.loc, str(ex)) from None
        if t == "integer" and isinstance(s, sy.Const) and abs(s.value) > MAX_INTEGER:
            raise SourceError(e.loc, f"integer {s.value:g} is out of the integer range")
        return s, t

    def evaluate(self, e: ast.Expr, scope: Scope) -> tuple[S, str]:
        """`eval` without the checks of the result: dispatch on the kind of expression."""
        if isinstance(e, (ast.Num, ast.Str, ast.Char)):
            return literal(e)
        if isinstance(e, ast.Name):
            return self.name(e, scope)
        if isinstance(e, ast.Unary):
            return unary(e, *self.eval(e.operand, scope))
        if isinstance(e, ast.Binary):
            return binary(e, *self.eval(e.left, scope), *self.eval(e.right, scope))
        if isinstance(e, ast.Call):
            return self.call(e, scope)
        if isinstance(e, ast.Attr):
            return self.attribute(e, scope)
        if isinstance(e, ast.Aggregate):
            items = tuple(self.real(x, scope) for x in e.items)
            return sy.vec(items), "real_vector"
        raise SourceError(e.loc, "unsupported construct: expression")
