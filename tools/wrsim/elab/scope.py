"""Scopes and what a name can be bound to: values, quantities, signals, terminals, functions, natures,
subtypes."""

from __future__ import annotations

from dataclasses import dataclass

from wrsim.elab import symbolic as sy
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, SourceError
from wrsim.frontend import ast

__all__ = [
    "Value",
    "Quantity",
    "Signal",
    "Terminal",
    "Function",
    "Nature",
    "Subtype",
    "Scope",
    "base_type",
    "BASE_TYPES",
    "GROUND",
    "INTEGER_HIGH",
    "INTEGER_LOW",
    "new_signal",
    "ArrayNature",
    "Elements",
]

GROUND = "0"
INTEGER_HIGH = 2147483647.0  # integer'high: 32-bit integers, as GHDL (the digital units) and the common simulators
INTEGER_LOW = -2147483648.0  # integer'low
BASE_TYPES = {
    "real": "real",
    "integer": "integer",
    "natural": "integer",
    "positive": "integer",
    "boolean": "boolean",
    "real_vector": "real_vector",
    "string": "string",
    "time": "time",
    "bit": "std_logic",
    "std_ulogic": "std_logic",
    "std_logic": "std_logic",
}


@dataclass
class Value:
    s: S
    typ: str  # real, integer, boolean, real_vector, string
    kind: str  # generic, constant, variable, loop, literal
    loc: Loc | None = None
    indices: tuple[int, ...] | None = None  # a real_vector's index values, left to right (None: 0, 1, ...)

    def position(self, index: int) -> int | None:
        """Where the element of index `index` is in the vector, None when the index is out of its range."""
        n = len(sy.items(self.s))
        if self.indices is None:
            return index if 0 <= index < n else None
        return self.indices.index(index) if index in self.indices else None

    def index_range(self) -> list[int]:
        """The index values, left to right."""
        return list(self.indices) if self.indices is not None else list(range(len(sy.items(self.s))))


@dataclass
class Quantity:
    name: str
    s: S  # Node or Diff
    role: str  # through, across, free, in, out
    unit: str | None
    loc: Loc
    branch_through: str | None = None  # for an across quantity: the through quantity of its branch


@dataclass
class Signal:
    name: str
    nodes: list[str]  # one digital node per bit, bit 0 (LSB) first
    type_mark: str
    width: int | None
    mode: str  # in, out, or "signal" (declared in the architecture)
    loc: Loc


def new_signal(name: str, type_mark: str, width: int | None, mode: str, loc: Loc) -> Signal:
    """A signal with one digital node per bit (bit 0 first), or one node for a scalar."""
    nodes = [name] if width is None else [f"{name}_{k}" for k in range(width)]
    return Signal(name, nodes, type_mark, width, mode, loc)


@dataclass
class Terminal:
    node: str
    nature: str  # base nature name
    loc: Loc | None


@dataclass
class Function:
    decl: ast.FunctionDecl
    scope: Scope


@dataclass
class Nature:
    decl: ast.NatureDecl
    units: tuple[str | None, str | None]


@dataclass
class Subtype:
    base: str
    unit: str | None
    indices: tuple[int, ...] | None = None  # a constrained array subtype: its index values, left to right


@dataclass
class ArrayNature:
    """`nature n is array (natural range <>) of element;`"""

    element: str
    loc: Loc | None


@dataclass
class Elements:
    """An array quantity or a vector terminal: its elements (Quantity or Terminal) by index."""

    name: str
    items: dict[int, Quantity | Terminal]


class Scope:
    def __init__(self, parent: Scope | None = None):
        self.parent = parent
        self.names: dict[str, object] = {}

    def lookup(self, name: str):
        s: Scope | None = self
        while s is not None:
            if name in s.names:
                return s.names[name]
            s = s.parent
        return None

    def declare(self, name: str, binding, loc: Loc) -> None:
        """Bind `name`; a second declaration, or an integer value outside integer'low .. integer'high, is one
        error at `loc`."""
        if name in self.names:
            prev = self.names[name]
            where = getattr(prev, "loc", None) or getattr(getattr(prev, "decl", None), "loc", None)
            raise SourceError(loc, f"'{name}' is already declared" + (f" at {where}" if where else ""))
        if (
            isinstance(binding, Value)
            and binding.typ == "integer"
            and isinstance(binding.s, sy.Const)
            and not INTEGER_LOW <= binding.s.value <= INTEGER_HIGH
        ):
            raise SourceError(
                loc,
                f"'{name}' = {binding.s.value:.0f} is outside the integer range {INTEGER_LOW:.0f} .. "
                f"{INTEGER_HIGH:.0f} (integer'low .. integer'high: 32 bits, as GHDL and the common simulators)",
            )
        self.names[name] = binding


def base_type(type_mark: str, scope: Scope, loc: Loc) -> str:
    if type_mark in BASE_TYPES:
        return BASE_TYPES[type_mark]
    b = scope.lookup(type_mark)
    if isinstance(b, Subtype):
        return BASE_TYPES.get(b.base, b.base)
    raise SourceError(loc, f"unknown type '{type_mark}'")
