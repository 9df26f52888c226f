"""The elaborated design, between elaboration and the backends: one equation system per architecture (`ArchModel`,
with symbolic generics), the instance tree with concrete generic values (`InstanceInfo`), `QUIESCENT` (the test the
design's quiescent-domain switches are written with), and the walks over a design (every instance with its
netlist-wide names, the generic values per instance, an instance by label path)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from wrsim.elab import symbolic as sy
from wrsim.elab.scope import INTEGER_HIGH, INTEGER_LOW, Quantity, Signal
from wrsim.elab.symbolic import S, substitute
from wrsim.errors import Loc, WrsimError
from wrsim.frontend import ast

__all__ = [
    "QUIESCENT",
    "Unknown",
    "Equation",
    "BranchElem",
    "Derivative",
    "Integral",
    "AdcElem",
    "Crossing",
    "Hold",
    "HoldEvent",
    "Element",
    "DigitalChild",
    "ChildInstance",
    "ArchModel",
    "Generics",
    "InstanceInfo",
    "Design",
    "instances",
    "generic_values",
    "numbers",
    "instance",
]

# `domain = quiescent_domain` holds exactly at the DC operating point (time 0); from the first time step on
# the time-domain equations apply, so the switch falls on a step boundary.
QUIESCENT = sy.Op("<=", (sy.Time(), sy.Const(0.0)))


@dataclass
class Unknown:
    node: str
    role: str  # through, free, out
    unit: str | None
    loc: Loc


@dataclass
class Equation:
    residual: S
    loc: Loc
    alternatives: list[Loc]  # an if-use/case-use equation: the equation of every branch, in order
    unknowns: set[str]  # unknowns it involves (for the structural pairing)
    paired: str = ""  # the unknown whose node carries this equation


@dataclass
class BranchElem:
    through: str
    plus: str
    minus: str
    loc: Loc


@dataclass
class Derivative:
    quantity: str
    source: S  # Node or Diff being differentiated
    element: str  # name of the 0 V source whose current is the derivative


@dataclass
class Integral:
    quantity: str
    source: S
    node: str


@dataclass
class AdcElem:
    """A->D: the digital `node` follows the 0/1 analog `level` = cond."""

    node: str
    level: str
    cond: S
    loc: Loc


@dataclass
class Crossing:
    """A `q'above(e)`: the guard node `node` = q - e, whose zero crossings the runner makes analog time points
    (IEEE 1076.1: an 'above event happens at the crossing, not at the next solver step)."""

    node: str
    guard: S
    test: S  # the boolean q > e that the model uses
    loc: Loc


@dataclass
class Hold:
    """A value the simulator holds between events (the event side of 1076.1's mixed-signal cycle), the node of an
    external source: a signal a process assigns, a sample of 'zoh, or, with `quantity`, the re-initialisation
    offset of a quantity a break list sets (its 'dot capacitor is referenced to the held node, so the integrated
    state stays and the quantity jumps by the change of the offset)."""

    node: str
    initial: S
    loc: Loc
    quantity: str | None = None
    name: str | None = None  # the signal or process variable it holds (a waveform of the run)
    integer: bool = False  # of an integer type: a value past integer'high or below integer'low is none


@dataclass
class HoldEvent:
    """When holds change: at every crossing of one of `guards` ('above guard nodes, either way), at a change of one
    of the held values `changes` (a delta cycle later; once however many of them changed), at `offset` + k *
    `period`, when the time reaches the value of hold `at`, or (`first`) at the first time point; if `cond` holds
    there, each (hold node, value) of `sets` takes the value evaluated at that point, all at once. The set at
    position j of `sets` in `delays` takes it that long later (a signal assignment `after` a delay; a delay < 0
    means the run assigned nothing to it), replacing the values pending at or after it and those within its pulse
    rejection limit before it, but for a run of its own value (IEEE 1076 10.5.2.2): `limits[j]`, else the delay
    (inertial); 0 for transport and a waveform's later elements, which are sets of their hold after its first."""

    sets: list[tuple[str, S]]
    loc: Loc
    guards: list[str] = field(default_factory=list)
    changes: list[str] = field(default_factory=list)
    cond: S | None = None
    period: S | None = None
    offset: S | None = None
    first: bool = False
    delays: dict[int, S] = field(default_factory=dict)
    limits: dict[int, S] = field(default_factory=dict)
    at: str | None = None  # also when the time reaches the value of this hold (a `wait for` entered)

    def mechanism(self, j: int) -> str:
        """How set j arrives: "" at once, "inertial" (its limit is the delay), "transport" (limit 0), or "reject"
        (a limit of its own, `limits[j]`)."""
        if j not in self.delays:
            return ""
        limit = self.limits.get(j)
        if limit is None:
            return "inertial"
        return "transport" if isinstance(limit, sy.Const) and limit.value == 0.0 else "reject"

    def fault(self, j: int, holds: dict[str, Hold]) -> S:
        """Where set j's value has none (boolean; const(False) when it always has one): what sy.undefined finds,
        and, for a hold of an integer type, a value outside integer'low .. integer'high (IEEE 1076 5.2.3: an
        error, not a wrap). Every backend stops the run at an event whose value has none."""
        held, target = self.sets[j]
        out = sy.undefined(target)
        if holds[held].integer:
            outside = sy.op("or", sy.op("<", target, sy.const(INTEGER_LOW)), sy.op(">", target, sy.const(INTEGER_HIGH)))
            out = sy.op("or", out, outside)
        return out


@dataclass
class Element:
    """An element an attribute needs beyond behavioural sources, its output `node` driven by `source`: 'delayed
    (a lossless line, args: the delay), 'slew (XSPICE slew, args: rising and falling slope), 'ramp (a ramp of a
    held value by the crossing driver, args: rise and fall time), 'last (S'last_value: the crossing driver keeps
    the held value's value before its last change) or 'flag (S'event of a signal in a process sensitive to
    several: the crossing driver sets it to 1 at the delta cycle that sees a change of the held value, else 0)."""

    kind: str
    node: str
    source: S
    args: tuple[S, ...]
    loc: Loc


@dataclass
class DigitalChild:
    """An instance of a digital unit (GHDL) in an architecture: one d_cosim element per instance of that
    architecture, its nodes named as in the architecture (the netlist names them netlist-wide)."""

    label: str
    entity: ast.Entity
    arch: ast.DigitalArchitecture
    generics: dict[str, int | bool | str]
    inputs: list[str]  # digital nodes, port by port in declaration order, bit 0 first
    outputs: list[str]
    loc: Loc


@dataclass
class ChildInstance:
    label: str
    model: ArchModel
    ports: list[str]  # actual nodes in the order of the child's ports
    params: dict[str, S]  # explicitly mapped generics (vector generics expanded as name_k)
    loc: Loc


@dataclass
class ArchModel:
    """One architecture with symbolic generics: becomes one .subckt."""

    key: str  # subckt name
    entity: ast.Entity
    arch: ast.Architecture
    ports: list[str]
    params: dict[str, float]  # default value per scalar parameter (after the parameter set)
    quantities: dict[str, Quantity]
    branches: list[BranchElem]
    unknowns: dict[str, Unknown]
    equations: list[Equation]
    derivatives: dict[str, Derivative]
    integrals: dict[str, Integral]
    children: list[ChildInstance]
    natures: set[str]
    breaks: list[Loc]
    signals: dict[str, Signal] = field(default_factory=dict)
    dacs: dict[str, str] = field(default_factory=dict)  # digital node -> its 0/1 analog level node
    adcs: list[AdcElem] = field(default_factory=list)
    digital: list[DigitalChild] = field(default_factory=list)
    recorded: set[str] = field(default_factory=set)  # D->A nodes only recorded, read by no equation
    crossings: list[Crossing] = field(default_factory=list)  # one per distinct q'above(e)
    eliminated: dict[str, S] = field(default_factory=dict)  # free quantity -> its expression (elimination pass)
    initial: list[tuple[str, float, Loc]] = field(default_factory=list)  # `break q => v;`: q's node, its value at 0
    initial_dots: list[tuple[S, float]] = field(default_factory=list)  # `break q'dot => v;`: q'dot, its value at 0
    ac_sources: dict[str, tuple[S, S]] = field(default_factory=dict)  # spectrum source quantity -> magnitude, phase
    noise_sources: dict[str, S] = field(default_factory=dict)  # noise source quantity -> its power density
    holds: dict[str, Hold] = field(default_factory=dict)
    hold_events: list[HoldEvent] = field(default_factory=list)
    elements: list[Element] = field(default_factory=list)
    limits: list[S] = field(default_factory=list)  # `limit ... with step`: the analysis's step at most this
    notes: list[str] = field(default_factory=list)  # what the lowering accepted and left out (a note to the user)

    def initial_dot(self, d: Derivative) -> float | None:
        """The value a break list at t = 0 gives derivative `d` at the quiescent point (None: none, so 0)."""
        return next((v for dot, v in self.initial_dots if dot == sy.Branch(d.element)), None)


class Generics:
    """An instance's generic values: `g["name"]` for a scalar (real, integer, boolean as 0/1), `g.vector("name")`
    for a real_vector; a generic of the other kind is an internal error of the caller."""

    def __init__(self, values: dict[str, float | list[float] | str]):
        self.values = values

    def __getitem__(self, name: str) -> float:
        v = self.values[name]
        if isinstance(v, (list, str)):
            raise WrsimError(f"internal: generic '{name}' is not a number")
        return v

    def vector(self, name: str) -> list[float]:
        v = self.values[name]
        if not isinstance(v, list):
            raise WrsimError(f"internal: generic '{name}' is a scalar")
        return v

    def __contains__(self, name: object) -> bool:
        return name in self.values

    def __repr__(self) -> str:
        return f"Generics({self.values!r})"


@dataclass
class InstanceInfo:
    """An instance in the elaborated tree, with its concrete generic values."""

    path: str
    entity: str
    arch: str
    generics: Generics
    loc: Loc | None
    children: list[InstanceInfo]


@dataclass
class Design:
    """An elaborated bench: one model per architecture (children first), the instance tree, the natures used,
    and the digital files GHDL analyses for the digital units."""

    top: ArchModel
    models: list[ArchModel]  # children first, top last
    tree: InstanceInfo
    natures: set[str]
    digital_files: list[Path] = field(default_factory=list)  # what GHDL analyses for the digital units

    def unknowns(self) -> tuple[int, int]:
        """(unknowns, eliminated quantities), summed over every instance of the bench."""

        def count(m: ArchModel) -> tuple[int, int]:
            below = [count(c.model) for c in m.children]
            return len(m.unknowns) + sum(u for u, _ in below), len(m.eliminated) + sum(e for _, e in below)

        return count(self.top)

    def describe(self) -> str:
        """The unknowns of the whole bench, then unknowns, eliminated quantities, equations (with the unknown each is
        paired with) and instances per architecture."""
        unknowns, gone = self.unknowns()
        lines = [
            f"{unknowns} unknowns over all instances, {gone} quantities eliminated (explicit expressions); the "
            f"netlist adds helper nodes for 'dot, 'integ and 'above"
        ]
        for m in self.models + [self.top]:
            lines.append(f"== {m.key}: architecture {m.arch.name} of {m.entity.name} ({m.arch.loc})")
            lines += [f"  unknown {u.node} [{u.unit or '?'}] {u.role} ({u.loc})" for u in m.unknowns.values()]
            lines += [f"  eliminated {name} = {expr}" for name, expr in m.eliminated.items()]
            lines += [f"  equation {eq.loc} solved for {eq.paired}: {eq.residual}" for eq in m.equations]
            lines += [f"  instance {c.label}: {c.model.key} {c.ports} {c.params}" for c in m.children]
        return "\n".join(lines)


# ------------------------------------------------------------------------------------------------ design walks
def instances(
    m: ArchModel,
    visit: Callable[[ArchModel, Callable[[str], str], str], None],
    prefix: str = "",
    portmap: dict[str, str] | None = None,
    path: str = "",
) -> None:
    """Call visit(model, node, path) for every instance below and including `m`: node() maps a local node or
    element name to its netlist-wide (raw, lower case) name, path is the instance's VHDL-AMS label path."""
    portmap = portmap or {}

    def node(n: str) -> str:
        return "0" if n == "0" else portmap.get(n, f"{prefix}{n}".lower())

    visit(m, node, path)
    for c in m.children:
        instances(
            c.model,
            visit,
            f"{prefix}x_{c.label}.",
            {p: node(a) for p, a in zip(c.model.ports, c.ports)},
            f"{path}.{c.label}" if path else c.label,
        )


def generic_values(top: ArchModel) -> dict[str, dict[str, float]]:
    """The scalar generic values of every instance, by label path: the architecture's defaults (after the parameter
    set) overlaid with the values its instantiation maps."""
    out: dict[str, dict[str, float]] = {}

    def visit(m: ArchModel, values: dict[str, float], path: str) -> None:
        out[path] = values
        for c in m.children:
            mapped = {k: sy.value(numbers(e, values)) for k, e in c.params.items()}
            visit(c.model, {**c.model.params, **mapped}, f"{path}.{c.label}" if path else c.label)

    visit(top, dict(top.params), "")
    return out


def numbers(s: S, values: dict[str, float], node: Callable[[str], str] | None = None) -> S:
    """`s` with its generics replaced by their values and, with `node`, its nodes (and 'dot elements) by their
    netlist-wide names."""

    def leaf(x: S) -> S | None:
        if isinstance(x, sy.Param):
            return sy.const(values[x.name])
        if node is not None and isinstance(x, sy.Node):
            return sy.Node(node(x.name))
        if node is not None and isinstance(x, sy.Diff):
            return sy.Diff(node(x.plus), node(x.minus))
        if node is not None and isinstance(x, sy.Branch):
            return sy.Branch(node(x.name))
        return None

    return substitute(s, {}, leaf)


def instance(tree: InstanceInfo, path: str) -> InstanceInfo:
    """The instance at the label path `path` (e.g. "dut.motor") below `tree`."""
    node = tree
    for label in path.split("."):
        child = next((c for c in node.children if c.path.endswith("." + label)), None)
        if child is None:
            raise WrsimError(f"internal: no instance {path} in {tree.path}")
        node = child
    return node
