"""The ngspice lines of one architecture: its `.subckt` (the bench's own elements go to the top level), and the
text every netlist line is made of: numbers, expressions, continuation lines and the VHDL-AMS source line each
element group comes from (wrsim.backend.ngspice.netlist puts them together)."""

from __future__ import annotations

import functools
import math
from pathlib import Path

from wrsim import paths
from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT, ArchModel, Crossing, Derivative
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, WrsimError

__all__ = [
    "ADC_MODEL",
    "DAC_MODEL",
    "DRIVEN",
    "HOLDS_FILE",
    "subckt",
    "body",
    "digital_nodes",
    "num",
    "param_value",
    "render",
    "wrap",
    "located",
    "shown",
    "source_line",
]

ADC_MODEL, DAC_MODEL = "wrsim_adc", "wrsim_dac"
HOLDS_FILE = "holds.txt"  # the held values and their events, for the crossing driver
DRIVEN = {  # the elements whose value the crossing driver gives (a `ramp`, `last` or `flag` line): what they are
    "ramp": "follows {} with ramps",
    "last": "follows {} one change behind ('last_value)",
    "flag": "is 1 at the delta cycle that sees a change of {}, else 0 ('event)",
}


def subckt(m: ArchModel, bridged: set[str], crossings: list[Crossing], dots: dict[str, str] | None) -> list[str]:
    """The `.subckt` of architecture `m` (its generics as parameters, its elements by `body`)."""
    head = f".subckt {m.key} {' '.join(m.ports)}"
    if m.params:
        head += " params: " + " ".join(f"{k}={num(v)}" for k, v in m.params.items())
    return [
        f"* architecture {m.arch.name} of {m.entity.name} ({located(m.arch.loc)})",
        *wrap(head),
        *body(m, False, bridged, crossings, dots),
        f".ends {m.key}",
    ]


def _control(d: Derivative) -> str:
    """The node pair whose voltage is the quantity `d` differentiates."""
    if isinstance(d.source, sy.Node):
        return f"{d.source.name} 0"
    if isinstance(d.source, sy.Diff):
        return f"{d.source.plus} {d.source.minus}"
    raise WrsimError(f"internal: 'dot of {d.source} (neither a node nor an across quantity)")


def digital_nodes(m: ArchModel, node, levels: dict[str, str], consumed: set[str]) -> None:
    """Record the analog level node of each digital node of `m` that is bridged (D->A, A->D) in `levels`, and the
    digital nodes a D->A bridge reads in `consumed`."""
    for d, level in m.dacs.items():
        levels.setdefault(node(d), node(level))
        consumed.add(node(d))
    for a in m.adcs:
        levels[node(a.node)] = node(a.level)


def body(
    m: ArchModel, top: bool, bridged: set[str], crossings: list[Crossing], dots: dict[str, str] | None = None
) -> list[str]:
    """The elements of `m`; a digital node only recorded (`m.recorded`, the event log's) gets no D->A bridge. With
    compiled models (`dots`: the node of each 'dot, osdi.Device.dots), the netlist's one compiled device holds the
    branches, 'dot and 'integ elements, the equations and the `v = expression` sources (their source lines stay
    here as comments) and the other elements read each 'dot from its node."""
    compiled = dots is not None
    r = functools.partial(render, top=top, dots=dots or {})
    lines: list[str] = []
    if compiled and (m.equations or m.branches or m.derivatives or m.integrals):
        lines.append("* the equations below, the branches and every 'dot and 'integ: in the compiled device")
        for eq in m.equations:
            lines.append(f"* {located(eq.loc)}: {source_line(eq.loc)}")
            lines += [f"* {located(alt)}: {source_line(alt)}" for alt in eq.alternatives]
        lines += [
            f"* {u} = {r(expr)}: explicit, substituted where it is read (no node)" for u, expr in m.eliminated.items()
        ]
        for d in m.derivatives.values():  # the crossing driver reads a re-initialised quantity on its node __d1
            if any(h.quantity == d.quantity for h in m.holds.values()):
                lines.append(f"e_{d.quantity}__d {d.quantity}__d1 0 {_control(d)} 1")
    for b in m.branches if not compiled else ():
        lines.append(f"* {located(b.loc)}: {source_line(b.loc)}")
        lines += wrap(f"b_{b.through} {b.plus} {b.minus} i = v({b.through})")
    for d in m.derivatives.values() if not compiled else ():
        ctrl = _control(d)
        q = d.quantity
        lines.append(f"* {q}'dot: ngspice integrates the 1 F capacitor, i({d.element}) = d({q})/dt")
        ref = next((h.node for h in m.holds.values() if h.quantity == q), "0")
        if ref != "0":
            lines.append(f"* a break list restarts {q}: the capacitor's reference is the held offset {ref}")
        lines += [f"e_{q}__d {q}__d1 0 {ctrl} 1", f"{d.element} {q}__d1 {q}__d2 0", f"c_{q}__d {q}__d2 {ref} 1"]
    for it in m.integrals.values() if not compiled else ():
        q = it.quantity
        lines.append(f"* {q}'integ: 1 F capacitor charged by {q}, held at 0 in the quiescent domain")
        lines += wrap(f"b_{q}__i 0 {it.node} i = ({r(QUIESCENT)} ? -v({it.node}) : {r(it.source)})")
        lines.append(f"c_{q}__i {it.node} 0 1")
    for eq in m.equations if not compiled else ():
        lines.append(f"* {located(eq.loc)}: {source_line(eq.loc)}")
        lines += [f"* {located(alt)}: {source_line(alt)}" for alt in eq.alternatives]
        lines += wrap(f"b_{eq.paired}__eq {eq.paired} 0 i = {r(eq.residual)}")
    for u, expr in m.eliminated.items() if not compiled else ():
        lines.append(f"* {u} = {r(expr)}: explicit, substituted where it is read (no node)")
    for node, level in m.dacs.items():
        if node not in m.recorded:
            lines += [f"* digital {node} -> 0/1 level {level}", f"a_{node}__dac [{node}] [{level}] {DAC_MODEL}"]
    if compiled and (m.adcs or crossings or m.hold_events or any(el.kind == "slew" for el in m.elements)):
        lines.append("* the levels, guards, event values and slew inputs below (v = ...): in the compiled device")
    for a in m.adcs:
        lines.append(f"* {located(a.loc)}: {source_line(a.loc)}")
        line = f"b_{a.node}__lvl {a.level} 0 v = ({r(a.cond)} ? 1 : 0)"
        lines += wrap(line) if not compiled else []
        if a.node in bridged:  # only where a digital unit or a D->A input reads the signal
            lines.append(f"a_{a.node}__adc [{a.level}] [{a.node}] {ADC_MODEL}")
    for x in crossings:
        lines.append(f"* {located(x.loc)}: {source_line(x.loc)}")
        lines.append(f"* 'above guard: the runner puts a time point where {x.node} crosses 0")
        lines += wrap(f"b_{x.node} {x.node} 0 v = {r(x.guard)}") if not compiled else []
    for h in m.holds.values():
        lines.append(f"* {located(h.loc)}: {source_line(h.loc)}")
        lines.append(f"* held between events by the crossing driver ({HOLDS_FILE})")
        lines.append(f"v_{h.node} {h.node} 0 dc 0 external")  # ngspice adds the dc value to the driver's
    for k, e in enumerate(m.hold_events):
        lines.append(f"* {located(e.loc)}: {source_line(e.loc)}")
        lines.append("* event: what the held values take, and when" + (" (the condition)" if e.cond else ""))
        for j, (_, target) in enumerate(e.sets if not compiled else ()):
            fault = e.fault(j, m.holds)  # where the value has none: 0 between events, the driver stops at one
            lines += wrap(f"b_event{k}_{j} event{k}_{j} 0 v = {r(sy.cond(fault, sy.const(0.0), target))}")
            if fault != sy.const(False):
                lines += wrap(f"b_event{k}_{j}__f event{k}_{j}__f 0 v = ({r(fault)} ? 1 : 0)")
            if j in e.delays:  # `after` a delay [s] (< 0: the run assigned nothing)
                lines += wrap(f"b_event{k}_{j}__d event{k}_{j}__d 0 v = {r(e.delays[j])}")
            if e.mechanism(j) == "reject":  # its pulse rejection limit [s]
                lines += wrap(f"b_event{k}_{j}__r event{k}_{j}__r 0 v = {r(e.limits[j])}")
        if e.cond is not None and not compiled:
            lines += wrap(f"b_event{k}__c event{k}__c 0 v = ({r(e.cond)} ? 1 : 0)")
    for el in m.elements:
        lines.append(f"* {located(el.loc)}: {source_line(el.loc)}")
        if el.kind in DRIVEN:
            lines.append(f"* {el.node} {DRIVEN[el.kind].format(r(el.source))} (the crossing driver, {HOLDS_FILE})")
            lines.append(f"v_{el.node} {el.node} 0 dc 0 external")
            continue
        if not compiled or el.kind == "delayed":
            lines += wrap(f"b_{el.node}__in {el.node}__in 0 v = {r(el.source)}")
        if el.kind == "delayed":
            lines.append(f"* {el.node} = the input {param_value(el.args[0])} s earlier: a matched lossless line")
            lines += [
                f"t_{el.node} {el.node}__in 0 {el.node} 0 z0=1 td={param_value(el.args[0])}",
                f"r_{el.node} {el.node} 0 1",
            ]
        else:
            lines.append(f"* {el.node} = the input with its slope limited (XSPICE slew)")
            lines += [
                f"a_{el.node} {el.node}__in {el.node} {el.node}__slew",
                f".model {el.node}__slew slew(rise_slope={param_value(el.args[0])} "
                f"fall_slope={param_value(sy.op('neg', el.args[1]))})",
            ]
    for brk in m.breaks:
        lines.append(f"* {brk}: break (ngspice's step control handles the discontinuity)")
    for name, (magnitude, phase) in m.ac_sources.items():  # 0 but in a small-signal analysis, which it excites
        if isinstance(phase, sy.Const):  # the same phase within one turn: its degrees stay finite
            phase = sy.const(math.remainder(phase.value, 2.0 * math.pi))
        degrees = sy.op("*", phase, sy.const(180.0 / math.pi))
        lines += [
            f"* {located(m.quantities[name].loc)}: spectrum source quantity {name}",
            f"v_{name}__ac {name} 0 dc 0 ac {param_value(magnitude)} {param_value(degrees)}",
        ]
    for node, value, loc in m.initial:  # the testbench's break list: the operating point holds the node at the value
        lines += [
            f"* {located(loc)}: {source_line(loc)}",
            f".ic v({node})={value!r}",  # KLU holds an .ic only on a node
            f"r_{node}__ic {node} 0 1e12",
        ]  # with a diagonal: 1e-12 S (gmin)
    for c in m.children:
        args = " ".join(f"{k}={param_value(v)}" for k, v in c.params.items())
        lines.append(f"* {located(c.loc)}: instance {c.label}")
        lines += wrap(f"x_{c.label} {' '.join(c.ports)} {c.model.key}" + (f" {args}" if args else ""))
    return lines


def num(v: float) -> str:
    """A number as the netlist writes it (12 significant digits)."""
    # ngspice's parser overflows near DBL_MAX; real'low/real'high (and values set to them) become +-1e300,
    # which keeps comparisons against them exact.
    if abs(v) > 1e300:
        v = math.copysign(1e300, v)
    return f"{v:.12g}"


def param_value(s: S) -> str:
    """A generic's actual as an instance parameter: a number, or a brace expression of generics."""
    if isinstance(s, sy.Const):
        return num(s.value)
    return "{" + render(s, top=False, in_param=True) + "}"


_INFIX = {
    "+": "+",
    "-": "-",
    "*": "*",
    "/": "/",
    "<": "<",
    "<=": "<=",
    ">": ">",
    ">=": ">=",
    "==": "==",
    "!=": "!=",
    "and": "&&",
    "or": "||",
}


def render(s: S, top: bool, in_param: bool = False, dots: dict[str, str] | None = None) -> str:
    """An expression in ngspice's behavioural-source syntax (`in_param`: a parameter expression of generics; `dots`:
    the compiled device's node of each 'dot)."""
    r = functools.partial(render, top=top, in_param=in_param, dots=dots)
    if isinstance(s, sy.Const):
        txt = num(s.value)
        return f"({txt})" if s.value < 0 else txt
    if isinstance(s, sy.Param):
        return s.name if in_param else "({" + s.name + "})"
    if in_param and not isinstance(s, sy.Op):
        raise WrsimError(f"unsupported construct: a generic actual must be arithmetic on generics ({s})")
    if isinstance(s, sy.Node):
        return f"v({s.name})"
    if isinstance(s, sy.Diff):
        return f"v({s.plus})" if s.minus == "0" else f"(v({s.plus}) - v({s.minus}))"
    if isinstance(s, sy.Branch):  # a 'dot: the 0 V source's current, or the compiled device's node
        return f"v({dots[s.name]})" if dots and s.name in dots else f"i({s.name})"
    if isinstance(s, sy.Time):
        return "time"
    if isinstance(s, sy.Op):
        a = s.args
        if s.name in _INFIX:
            return f"({r(a[0])} {_INFIX[s.name]} {r(a[1])})"
        if s.name == "neg":
            return f"(-{r(a[0])})"
        if s.name == "not":
            return f"(!{r(a[0])})"
        if s.name == "abs":
            return f"abs({r(a[0])})"
        if s.name == "**":
            if isinstance(a[1], sy.Const) and a[1].value == int(a[1].value) and 0 < a[1].value <= 4:
                return "(" + " * ".join([r(a[0])] * int(a[1].value)) + ")"
            return f"pow({r(a[0])}, {r(a[1])})"
    if isinstance(s, sy.Fn):
        return f"{s.name}({', '.join(r(x) for x in s.args)})"
    if isinstance(s, sy.Cond):
        return f"({r(s.test)} ? {r(s.then)} : {r(s.other)})"
    raise WrsimError(f"internal: cannot render {s!r}")


def wrap(line: str, width: int = 110) -> list[str]:
    """Split a long element line into ngspice continuation lines at spaces that follow an operator."""
    if len(line) <= width:
        return [line]
    out, cur = [], ""
    for tok in line.split(" "):
        if len(cur) + len(tok) + 1 > width and cur and cur.rstrip()[-1:] in "+-*/?:(,=&|<>":
            out.append(cur)
            cur = "+ " + tok
        else:
            cur = f"{cur} {tok}" if cur else tok
    out.append(cur)
    return out


def located(loc: Loc) -> str:
    """A source location as the netlist's comments give it: the file relative to the repository when inside it, so
    that the same design gives the same netlist however its files were named (`wrsim lower`, `wrsim run`)."""
    return f"{shown(loc.file)}:{loc.line}:{loc.col}"


@functools.lru_cache(maxsize=256)
def shown(file: str) -> str:
    return paths.shown(file)


@functools.lru_cache(maxsize=64)
def _file_lines(path: str) -> tuple[str, ...]:
    try:
        return tuple(Path(path).read_text(encoding="utf-8").splitlines())
    except OSError:
        return ()


def source_line(loc: Loc) -> str:
    """The VHDL-AMS source line at `loc`, stripped ("" when the file cannot be read)."""
    lines = _file_lines(loc.file)
    return lines[loc.line - 1].strip() if 0 < loc.line <= len(lines) else ""
