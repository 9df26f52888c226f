"""The front-end's intermediate representation: one dataclass per VHDL-AMS construct of the subset
(docs/vhdl-ams-subset.md). The parser builds it; checks, elaboration and the ngspice backend read it.
Every node carries `loc` (file:line:col). Identifiers are lower case (VHDL is case-insensitive)."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field

from wrsim.errors import Loc

__all__ = [
    "nested",
    "expressions",
    "NAME_DECLARATIONS",
    "Expr",
    "Num",
    "Str",
    "Char",
    "Name",
    "Call",
    "Attr",
    "Unary",
    "Binary",
    "Aggregate",
    "Assoc",
    "Generic",
    "TerminalPort",
    "QuantityPort",
    "SignalPort",
    "Port",
    "SignalDecl",
    "SignalAssign",
    "ConstantDecl",
    "VariableDecl",
    "SubtypeDecl",
    "NatureDecl",
    "SubnatureDecl",
    "TerminalDecl",
    "BranchQuantityDecl",
    "FreeQuantityDecl",
    "Param",
    "FunctionDecl",
    "ComponentDecl",
    "Decl",
    "SimpleSimultaneous",
    "SimultaneousIf",
    "SimultaneousCase",
    "SimultaneousNull",
    "Break",
    "Wait",
    "SeqSignalAssign",
    "Bounds",
    "ArrayNatureDecl",
    "Process",
    "Procedural",
    "Generate",
    "CaseGenerate",
    "LimitSpec",
    "ConfigSpec",
    "AttributeSpec",
    "Assertion",
    "Instance",
    "ConcurrentStmt",
    "VarAssign",
    "Return",
    "IfStmt",
    "ForLoop",
    "WhileLoop",
    "LoopExit",
    "NullStmt",
    "SeqStmt",
    "UseClause",
    "Entity",
    "Architecture",
    "DigitalArchitecture",
    "Package",
    "PackageBody",
    "DesignUnit",
    "DesignFile",
]


# ----------------------------------------------------------------------------------------------
# Expressions
@dataclass
class Num:
    value: float
    is_int: bool
    loc: Loc
    time: bool = False  # a time literal (`10 ms`), its value in seconds


@dataclass
class Str:
    value: str
    loc: Loc


@dataclass
class Char:
    value: str  # a character literal such as '1'
    loc: Loc


@dataclass
class Name:
    ident: str  # lower case; a selected name keeps its dots ("ieee.math_real.sin")
    loc: Loc


@dataclass
class Assoc:
    """`formal => actual` or a positional actual (formal is None). actual None means `open`."""

    formal: str | None
    actual: Expr | None
    loc: Loc


@dataclass
class Call:
    """`name(args)`: a function call or an index into a vector; elaboration decides which."""

    name: str
    args: list[Assoc]
    loc: Loc


@dataclass
class Bounds:
    """The index range `(low to high)` or `(high downto low)` of an array subtype."""

    left: Expr
    right: Expr
    downto: bool


@dataclass
class Attr:
    """`prefix'attr` or `prefix'attr(args)`; `prefix(index)'attr` has an `index`."""

    prefix: str
    attr: str
    args: list[Expr]
    loc: Loc
    index: Expr | None = None


@dataclass
class Unary:
    op: str  # "-", "+", "abs", "not"
    operand: Expr
    loc: Loc


@dataclass
class Binary:
    op: str  # "+ - * / ** = /= < <= > >= and or xor nand nor & mod rem"
    left: Expr
    right: Expr
    loc: Loc


@dataclass
class Aggregate:
    items: list[Expr]
    loc: Loc


Expr = Num | Str | Char | Name | Call | Attr | Unary | Binary | Aggregate


# ----------------------------------------------------------------------------------------------
# Interface and declarations
@dataclass
class Generic:
    name: str
    type_mark: str
    default: Expr | None
    unit: str | None  # from the subtype or a trailing `-- [unit]` comment
    comment: str
    loc: Loc
    bounds: Bounds | None = None  # an index constraint, `real_vector(1 to 3)`


@dataclass
class TerminalPort:
    name: str
    nature: str
    loc: Loc


@dataclass
class QuantityPort:
    name: str
    mode: str  # "in" or "out"
    type_mark: str
    unit: str | None
    loc: Loc


@dataclass
class SignalPort:
    """A digital port: std_logic (width None), std_logic_vector(width-1 downto 0), or integer (width 32)."""

    name: str
    mode: str  # "in" or "out"
    type_mark: str  # std_logic, std_logic_vector, integer, natural, boolean
    width: int | None
    loc: Loc


Port = TerminalPort | QuantityPort | SignalPort


@dataclass
class SignalDecl:
    name: str
    type_mark: str
    width: int | None
    loc: Loc
    value: Expr | None = None  # the initial value


@dataclass
class ConstantDecl:
    name: str
    type_mark: str
    value: Expr | None  # None: deferred constant in a package declaration
    loc: Loc
    bounds: Bounds | None = None


@dataclass
class VariableDecl:
    name: str
    type_mark: str
    value: Expr | None
    loc: Loc


@dataclass
class SubtypeDecl:
    name: str
    base: str
    tolerance: str | None
    unit: str | None
    loc: Loc
    bounds: Bounds | None = None


@dataclass
class NatureDecl:
    name: str
    across: str  # subtype of the across quantities
    through: str  # subtype of the through quantities
    reference: str  # name of the reference terminal
    loc: Loc


@dataclass
class SubnatureDecl:
    name: str
    base: str
    loc: Loc


@dataclass
class TerminalDecl:
    name: str
    nature: str
    loc: Loc
    bounds: Bounds | None = None  # a vector terminal (of an array nature)


@dataclass
class BranchQuantityDecl:
    across: str | None
    through: str | None
    plus: str | Expr  # a terminal name, N'reference, or t(k) (an element of a vector terminal, a Call)
    minus: str | Expr | None  # None: the nature's reference terminal
    unit_across: str | None
    unit_through: str | None
    loc: Loc


@dataclass
class FreeQuantityDecl:
    name: str
    type_mark: str
    init: Expr | None
    unit: str | None
    loc: Loc
    bounds: Bounds | None = None  # an array quantity
    source: str | None = None  # a frequency-domain source quantity: "spectrum" or "noise"
    spectrum: tuple[Expr, ...] = ()  # its magnitude and phase [rad] (spectrum), its power density (noise)


@dataclass
class Param:
    name: str
    type_mark: str
    loc: Loc


@dataclass
class FunctionDecl:
    name: str
    params: list[Param]
    return_type: str
    decls: list[VariableDecl | ConstantDecl] | None  # None: declaration only
    body: list[SeqStmt] | None
    loc: Loc


@dataclass
class AliasDecl:
    name: str
    target: str  # the aliased name (a nature, terminal, quantity, constant, subtype ..., N'reference)
    loc: Loc


@dataclass
class ArrayNatureDecl:
    """`nature n is array (natural range <>) of element;`"""

    name: str
    element: str
    loc: Loc


@dataclass
class AttributeSpec:
    """`attribute a of n1, n2 : class is value;` (a user-defined attribute: n'a reads the value)."""

    attr: str
    names: list[str]  # or ["all"] / ["others"]
    value: Expr
    loc: Loc


@dataclass
class LimitSpec:
    """`limit q, ... : type with step;`: the largest step the solver takes for these quantities."""

    step: Expr
    loc: Loc


@dataclass
class ConfigSpec:
    """`for u1, u2 | all | others : comp use entity lib.e[(a)];`"""

    labels: list[str]  # or ["all"] / ["others"]
    component: str
    entity: str
    arch: str | None
    loc: Loc


@dataclass
class ComponentDecl:
    name: str
    generics: list[Generic]
    ports: list[Port]
    loc: Loc


Decl = (
    ConstantDecl
    | SubtypeDecl
    | NatureDecl
    | SubnatureDecl
    | TerminalDecl
    | BranchQuantityDecl
    | FreeQuantityDecl
    | FunctionDecl
    | ComponentDecl
    | SignalDecl
)


# ----------------------------------------------------------------------------------------------
# Concurrent statements
@dataclass
class SimpleSimultaneous:
    lhs: Expr
    rhs: Expr
    label: str | None
    loc: Loc


@dataclass
class SimultaneousIf:
    branches: list[tuple[Expr | None, list[ConcurrentStmt]]]  # condition None = else
    label: str | None
    loc: Loc


@dataclass
class SimultaneousCase:
    selector: Expr
    alternatives: list[tuple[list[Expr] | None, list[ConcurrentStmt]]]  # choices None = others
    label: str | None
    loc: Loc


@dataclass
class SimultaneousNull:
    loc: Loc


@dataclass
class Break:
    on: list[Expr]
    loc: Loc
    sets: list[tuple[str, Expr]] = field(default_factory=list)  # break list: quantity => its new value
    cond: Expr | None = None


@dataclass
class Assertion:
    cond: Expr
    report: str
    severity: str
    loc: Loc


@dataclass
class Instance:
    label: str
    kind: str  # "entity" or "component"
    unit: str  # entity or component name (library prefix removed)
    arch: str | None
    generic_map: list[Assoc]
    port_map: list[Assoc]
    loc: Loc


@dataclass
class SignalAssign:
    """The A->D form `s <= '1' when cond else '0';` (or `s(k) <= ...`), cond built from 'above and signals."""

    target: str
    index: int | None
    cond: Expr
    loc: Loc


@dataclass
class Wait:
    """`wait [on s, ...] [until c] [for t];`"""

    on: list[Expr]
    until: Expr | None
    timeout: Expr | None
    loc: Loc


@dataclass
class SeqSignalAssign:
    """`s <= [transport | [reject r] inertial] e [after d] {, e after d};` in a process."""

    target: str
    value: Expr
    loc: Loc
    after: Expr | None = None  # the delay
    transport: bool = False  # the delay mechanism: transport, else inertial
    reject: Expr | None = None  # inertial's pulse rejection limit when given (else the delay)
    more: list[tuple[Expr, Expr | None]] = field(default_factory=list)  # the waveform's later elements, (e, d)


@dataclass
class Process:
    """`[label:] process [(s, ...) | (all)] [is] declarations begin statements end process;` in an AMS
    architecture."""

    label: str | None
    sensitivity: list[Expr]
    decls: list
    body: list
    loc: Loc
    implied: bool = False  # a concurrent signal assignment's or `process (all)`: its sensitivity is every name
    # read (elaboration keeps the signals and 'above among them)


@dataclass
class Procedural:
    """`procedural [is] declarations begin statements end procedural;`: the quantities it assigns (`q := e;`)."""

    decls: list
    body: list
    loc: Loc


@dataclass
class Generate:
    """`label: if cond generate ... end generate;` or `label: for i in a to b generate ... end generate;`; with
    neither a condition nor a parameter, the alternative of a case-generate (its statements once)."""

    label: str
    cond: Expr | None
    var: str | None
    low: Expr | None
    high: Expr | None
    downto: bool
    decls: list
    stmts: list
    loc: Loc


@dataclass
class CaseGenerate:
    """`label: case e generate when [alt:] c1 | c2 => ... when others => ... end generate [label];` (VHDL-2008):
    the choices of each alternative (None: others) and its body."""

    label: str
    selector: Expr
    alternatives: list[tuple[list[Expr] | None, Generate]]
    loc: Loc


ConcurrentStmt = (
    SimpleSimultaneous
    | SimultaneousIf
    | SimultaneousCase
    | SimultaneousNull
    | Break
    | Assertion
    | Instance
    | SignalAssign
    | Process
    | Procedural
    | Generate
    | CaseGenerate
)


# ----------------------------------------------------------------------------------------------
# Sequential statements (function bodies)
@dataclass
class VarAssign:
    target: str
    value: Expr
    loc: Loc


@dataclass
class Return:
    value: Expr
    loc: Loc


@dataclass
class IfStmt:
    branches: list[tuple[Expr | None, list[SeqStmt]]]
    loc: Loc


@dataclass
class ForLoop:
    var: str
    low: Expr | None  # None with `range_attr`: `for k in v'range loop`
    high: Expr | None
    downto: bool
    range_attr: Attr | None
    body: list[SeqStmt]
    loc: Loc


@dataclass
class WhileLoop:
    """`while cond loop ... end loop;`, or with `cond` None a plain `loop ... end loop;` (left by an exit)."""

    cond: Expr | None
    body: list[SeqStmt]
    loc: Loc


@dataclass
class LoopExit:
    """`exit;` (`kind` "exit") or `next;` ("next") of the innermost loop; `exit when c;` is an if around it."""

    kind: str
    loc: Loc


@dataclass
class NullStmt:
    loc: Loc


SeqStmt = VarAssign | Return | IfStmt | ForLoop | WhileLoop | LoopExit | NullStmt | Wait | SeqSignalAssign | Break


# ----------------------------------------------------------------------------------------------
# Design units
@dataclass
class UseClause:
    library: str
    package: str
    item: str  # "all" or one name
    loc: Loc


@dataclass
class Entity:
    name: str
    generics: list[Generic]
    ports: list[Port]
    stmts: list[Assertion]
    uses: list[UseClause]
    header: str  # comment block in front of the unit
    loc: Loc
    attributes: list[AttributeSpec] = field(default_factory=list)  # the entity declarative part's specifications


@dataclass
class Architecture:
    name: str
    entity: str
    decls: list[Decl]
    stmts: list[ConcurrentStmt]
    uses: list[UseClause]
    loc: Loc


@dataclass
class DigitalArchitecture:
    """An architecture of a digital file (no AMS): its body is GHDL's, wrsim only instantiates it."""

    name: str
    entity: str
    path: str
    loc: Loc


@dataclass
class Package:
    name: str
    decls: list[Decl]
    uses: list[UseClause]
    loc: Loc


@dataclass
class PackageBody:
    name: str
    decls: list[Decl]
    uses: list[UseClause]
    loc: Loc


DesignUnit = Entity | Architecture | DigitalArchitecture | Package | PackageBody


@dataclass
class DesignFile:
    path: str
    library: str
    units: list[DesignUnit] = field(default_factory=list)
    digital: bool = False  # no AMS construct: the whole file is analysed by GHDL


def nested(stmts: list, depth: int = 0) -> Iterator[tuple[SeqStmt, int]]:
    """Every statement of `stmts` and of the if branches and loop bodies inside them, with its depth (0: in
    `stmts` itself)."""
    for s in stmts:
        yield s, depth
        if isinstance(s, IfStmt):
            for _, body in s.branches:
                yield from nested(body, depth + 1)
        elif isinstance(s, (ForLoop, WhileLoop)):
            yield from nested(s.body, depth + 1)


def expressions(e: Expr | None) -> Iterator[Expr]:
    """`e` and every expression inside it (None: none)."""
    if e is None:
        return
    yield e
    if isinstance(e, Call):
        for a in e.args:
            yield from expressions(a.actual)
    elif isinstance(e, Attr):
        for x in [*e.args, e.index]:
            yield from expressions(x)
    elif isinstance(e, Unary):
        yield from expressions(e.operand)
    elif isinstance(e, Binary):
        yield from expressions(e.left)
        yield from expressions(e.right)
    elif isinstance(e, Aggregate):
        for x in e.items:
            yield from expressions(x)


# Declarations that only add names to a scope (constants, functions, subtypes, components, aliases, attributes,
# natures): the static pass and the model pass declare them alike.
NAME_DECLARATIONS = (
    ConstantDecl,
    FunctionDecl,
    SubtypeDecl,
    ComponentDecl,
    AliasDecl,
    AttributeSpec,
    ArrayNatureDecl,
    NatureDecl,
    SubnatureDecl,
)
