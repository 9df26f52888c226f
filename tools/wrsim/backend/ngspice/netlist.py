"""Backend: an elaborated design -> a readable ngspice netlist (docs/vhdl-ams-subset.md, "Lowering").

One `.subckt` per architecture, named after its entity; quantities keep their names as nodes; every element
group is preceded by the VHDL-AMS source it comes from. The netlist also carries the probe table (how to
read every quantity of every instance back from ngspice's vectors) and the source map the runner uses to
report ngspice failures in VHDL-AMS terms. The lines of each architecture come from
wrsim.backend.ngspice.elements."""

from __future__ import annotations

import contextlib
import math
import os
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path

from wrsim.backend.ghdl.cosim import instance_line
from wrsim.backend.ngspice import osdi
from wrsim.backend.ngspice.elements import (
    ADC_MODEL,
    DAC_MODEL,
    DRIVEN,
    HOLDS_FILE,
    body,
    digital_nodes,
    located,
    num,
    shown,
    source_line,
    subckt,
    wrap,
)
from wrsim.elab import symbolic as sy
from wrsim.elab.design import (
    ArchModel,
    Crossing,
    Design,
    DigitalChild,
    Hold,
    generic_values,
    instances,
    numbers,
)
from wrsim.elab.eliminate import eliminated, event_exprs
from wrsim.elab.symbolic import S
from wrsim.errors import Loc, WrsimError
from wrsim.frontend import ast

__all__ = [
    "Analysis",
    "Probe",
    "Netlist",
    "DigitalUse",
    "lower",
    "NATURE_TOLERANCES",
    "RAW_FILE",
    "EVENT_FILE",
    "HOLDS_FILE",
]

# nature -> (across unit, through unit, absolute tolerance across, absolute tolerance through)
NATURE_TOLERANCES = {
    "electrical": ("V", "A", 1e-6, 1e-9),
    "translational": ("m", "N", 1e-8, 1e-6),
    "translational_velocity": ("m/s", "N", 1e-8, 1e-6),
    "rotational": ("rad", "N*m", 1e-8, 1e-8),
    "rotational_velocity": ("rad/s", "N*m", 1e-8, 1e-8),
}
DEFAULT_TOLERANCE = ("1", "1", 1e-8, 1e-8)
RAW_FILE, EVENT_FILE = "waveforms.raw", "events.vcd"  # what the netlist's .control section writes
COMPILE_DEFAULT = "1"  # WRSIM_COMPILE when unset: compiled


def compiled_default() -> bool:
    """Whether analyses compile the equations (OSDI devices) by default: the setting WRSIM_COMPILE (1 or 0; the
    command line's --compile / --no-compile set it for the process and the workers it starts)."""
    return os.environ.get("WRSIM_COMPILE", COMPILE_DEFAULT) != "0"


@contextlib.contextmanager
def compiled_setting(compiled: bool) -> Iterator[None]:
    """WRSIM_COMPILE set to `compiled` inside the block (and for the processes it starts), as before after it."""
    before = os.environ.get("WRSIM_COMPILE")
    os.environ["WRSIM_COMPILE"] = "1" if compiled else "0"
    try:
        yield
    finally:
        if before is None:
            del os.environ["WRSIM_COMPILE"]
        else:
            os.environ["WRSIM_COMPILE"] = before


@dataclass
class Analysis:
    """A transient analysis. `max_step` bounds ngspice's step; `reltol` is its relative tolerance; `save` names
    the probes to write (all when empty): a long closed-loop run writes gigabytes otherwise."""

    stop: float
    max_step: float | None = None
    reltol: float = 1e-4
    method: str = "gear"
    save: tuple[str, ...] = ()
    exact_crossings: bool = True  # a time point at every 'above crossing something reads (runs through libngspice)
    compiled: bool = field(default_factory=compiled_default)  # the equations as one OSDI device (osdi.py)
    ac: tuple[float, float, int] | None = None  # instead: small-signal from FSTART to FSTOP [Hz], POINTS a decade
    # instead: the noise density of a quantity, frequencies as `ac`, and the spectrum source it is referred to
    noise: tuple[str, float, float, int, str | None] | None = None

    @property
    def step(self) -> float:
        """The largest step [s]: `max_step`, by default stop / 500 (every command and bench takes it from here)."""
        return self.max_step or self.stop / 500


@dataclass
class Probe:
    """How to read one quantity from ngspice vectors: value = v(plus) - v(minus) or the current i(branch)."""

    name: str  # hierarchical VHDL-AMS name, e.g. "dut.motor.omega"
    unit: str
    plus: str | None = None  # raw vector node names (lower case), "0" for ground
    minus: str | None = None
    branch: str | None = None
    bits: list[str] | None = None  # a signal: the 0/1 level node of each bit, bit 0 first
    signed: bool = False  # bits are a two's-complement integer
    expr: S | None = None  # an eliminated quantity: its expression over raw node names, generics as numbers


@dataclass
class DigitalUse:
    """A digital unit the runner must build with GHDL and describe in `include` (a d_cosim .model card)."""

    label: str
    entity: str
    model: str  # the .model name the instance line uses
    include: str  # file name (in the run directory) the netlist includes
    generics: dict[str, int | bool | str]
    ports: list  # ast.SignalPort of the entity, declaration order
    lazy: list[str] = field(default_factory=list)  # out ports no analog element reads (model_card's `lazy`)


@dataclass
class Netlist:
    text: str
    probes: dict[str, Probe]
    source_map: dict[str, str]  # raw node/element name -> "what it is, file:line:col"
    title: str = ""
    stop: float = 0.0  # end of the transient analysis [s]
    digital: list[DigitalUse] = field(default_factory=list)
    digital_files: list[Path] = field(default_factory=list)
    events: dict[str, str] = field(default_factory=dict)  # 0/1 level name -> digital node recorded in EVENT_FILE
    crossings: list[str] = field(default_factory=list)  # guard nodes of q'above(e): time points at their zeros
    holds: list[str] = field(default_factory=list)  # the crossing driver's table of held values (HOLDS_FILE)
    edge_only: set[str] = field(default_factory=set)  # those of them whose 'above no equation reads (digital edges)
    max_step: float = 0.0  # the transient analysis's largest step [s]
    devices: str = ""  # C source of the compiled device the netlist loads (osdi.LIBRARY_FILE), if any
    ac: bool = False  # a small-signal or noise analysis (the raw file's vectors are over frequency)
    initial: list[tuple[str, float, str]] = field(default_factory=list)  # break list at t = 0: node, value, source
    at_rest: list[tuple[str, float, str, str]] = field(default_factory=list)  # compiled: 'dot node, quiescent value,
    # its quantity and where it is declared

    def write(self, path: Path) -> None:
        """Write the netlist to `path` and, when it holds values, their table beside it (HOLDS_FILE)."""
        path.write_text(self.text, encoding="utf-8")
        if self.holds:
            (path.parent / HOLDS_FILE).write_text("\n".join(self.holds) + "\n", encoding="utf-8")


def lower(design: Design, analysis: Analysis, title: str) -> Netlist:
    """Lower an elaborated design to an ngspice netlist with a transient analysis (or the small-signal or noise
    analysis `analysis` asks for)."""
    if analysis.stop <= 0:
        raise WrsimError(f"simulation stop time must be > 0, got {analysis.stop}")
    small_signal = analysis.ac is not None or analysis.noise is not None
    if small_signal and _digital_instances(design.top):
        raise WrsimError(f"{title}: a small-signal (AC, noise) analysis needs a design without digital units")
    if small_signal:
        setters_of: list[tuple[Hold, Loc]] = []  # each held value and where an event sets it (a process, a break)

        def held(m: ArchModel, node, path: str) -> None:
            for h in m.holds.values():
                setters = (e.loc for e in m.hold_events if any(n == h.node for n, _ in e.sets))
                setters_of.append((h, next(setters, h.loc)))

        instances(design.top, held)
        if setters_of:  # the driver's held values (external sources) exist only in a transient analysis
            h, where = setters_of[0]
            what = f"'{h.name}'" if h.name else ("a break's re-initialisation" if h.quantity else "a sampled value")
            raise WrsimError(
                f"{located(where)}: a small-signal (AC, noise) analysis needs a design without events; here {what} "
                f"changes at one ({source_line(where).strip()}): run --op or a transient analysis"
            )
    if small_signal and not analysis.compiled:  # B-sources linearise the equations of the operating point
        raise WrsimError(
            f"{title}: a small-signal (AC, noise) analysis runs the compiled equations (1076.1 linearises the "
            f"frequency domain's equations at the quiescent point, behavioural sources the quiescent domain's; the "
            f"noise sources are the compiled device's): drop --no-compile"
        )
    design = design if small_signal else eliminated(design)  # small signal: every quantity on a node, linearised
    out = [
        f"* {title}",
        "* generated by wrsim from VHDL-AMS; do not edit (edit the .vhd files instead)",
        "* analogy (1 V and 1 A per SI unit):",
    ]
    for nat in sorted(design.natures):
        a, t, _, _ = NATURE_TOLERANCES.get(nat, DEFAULT_TOLERANCE)
        out.append(f"*   {nat}: across [{a}] -> node voltage, through [{t}] -> branch current")
    out.append("*   free quantity -> node voltage in its own unit")
    out += ["* domain = quiescent_domain is (time <= 0): true at the DC operating point only"]
    mixed = any(m.dacs or m.digital for m in design.models + [design.top])
    if mixed:
        out += [
            "* digital <-> analog: signals are XSPICE digital nodes; a signal's 0/1 level is the node <name>__a",
            f".model {ADC_MODEL} adc_bridge(in_low=0.4 in_high=0.6)",
            f".model {DAC_MODEL} dac_bridge(out_low=0 out_high=1 out_undef=0.5 t_rise=1e-6 t_fall=1e-6)",
        ]
    out.append("")
    levels: dict[str, str] = {}  # global digital node -> global analog node holding its 0/1 level
    units = _digital_instances(design.top)
    consumed: set[str] = {n for _, _, inputs, _ in units for n in inputs}
    instances(design.top, lambda m, node, _: digital_nodes(m, node, levels, consumed))
    bridged: dict[str, set[str]] = {}  # model -> A->D nodes some instance of it feeds to a digital consumer
    instances(
        design.top,
        lambda m, node, _: bridged.setdefault(m.key, set()).update(a.node for a in m.adcs if node(a.node) in consumed),
    )
    observed = {
        m.key: _observed(m, bridged.get(m.key, set())) if analysis.exact_crossings else []
        for m in design.models + [design.top]
    }
    values = generic_values(design.top)
    compiled = osdi.device(design.top, values, observed) if analysis.compiled else None
    dots = compiled.dots if compiled else {}
    if compiled:
        out += [
            f"* compiled models: every equation, branch, 'dot, 'integ and v = expression source of the design in "
            f"one OSDI device ({osdi.LIBRARY_FILE}), one instance below the bench",
            f".model {compiled.model} {compiled.name}",
            "",
        ]
    for m in design.models:
        out += subckt(m, bridged.get(m.key, set()), observed[m.key], dots.get(m.key) if compiled else None)
        out.append("")
    out.append(
        f"* bench: architecture {design.top.arch.name} of {design.top.entity.name} ({located(design.top.arch.loc)})"
    )
    # A digital unit's output that no equation reads is recorded by ngspice's event log (eprvcd), not by a D->A
    # bridge: every change of a bridge adds breakpoints to the analog step (the 32-bit position bus alone doubled
    # the steps of a closed loop). With a save list, only saved signals are recorded (by hierarchical name).
    saved: set[str] = set()
    instances(
        design.top,
        lambda m, node, path: saved.update(
            node(n)
            for s in m.signals.values()
            if (f"{path}.{s.name}" if path else s.name) in analysis.save
            for n in s.nodes
        ),
    )
    events: dict[str, str] = {}
    instances(
        design.top,
        lambda m, node, _: events.update(
            (node(m.dacs[n]), node(n)) for n in sorted(m.recorded) if not analysis.save or node(n) in saved
        ),
    )
    out += body(
        design.top,
        True,
        bridged.get(design.top.key, set()),
        observed[design.top.key],
        dots.get(design.top.key) if compiled else None,
    )
    if compiled:
        args = " ".join(f"{k}={num(v)}" for k, v in compiled.params.items())
        out.append(
            f"* the compiled equations of every instance ({len(compiled.terminals)} nodes; generics by instance)"
        )
        out += wrap(f"n_{compiled.name} {' '.join(compiled.terminals)} {compiled.model}" + (f" {args}" if args else ""))
    if design.unknowns()[0] == 0:  # every quantity is explicit: ngspice still needs a circuit to solve
        out += ["* every quantity is an explicit expression of time: one node for ngspice", "r_anchor anchor 0 1"]
    # A digital output that only digital units or the event log read need not cut the analog step at its change.
    analog_read: set[str] = set()  # digital nodes whose D->A bridge an equation reads
    instances(design.top, lambda m, node, _: analog_read.update(node(n) for n in m.dacs if n not in m.recorded))
    digital = []
    if any("." in path for path, *_ in units):
        out.append(
            "* digital units inside models: their d_cosim elements are here, on the nodes of their instance "
            "(x_<label>.<node>), each with its own model card"
        )
    for path, d, inputs, outputs in units:
        name = path.replace(".", "__")  # cl.ecu -> cl__ecu (no VHDL label has a double underscore)
        use = DigitalUse(
            name,
            d.entity.name,
            f"cosim_{name}",
            f"{name}.cosim",
            d.generics,
            [p for p in d.entity.ports],
            _lazy_outputs(d, outputs, analog_read),
        )
        digital.append(use)
        out += [
            f"* {located(d.loc)}: instance {path} of digital unit {d.entity.name} ({shown(str(d.arch.path))}), run "
            f"by GHDL through d_cosim; the runner writes its model card",
            f".include {use.include}",
        ]
        out += wrap(instance_line(f"_{name}", inputs, outputs, use.model))  # null: a unit without inputs
    out.append("")
    across_tol = min((NATURE_TOLERANCES.get(n, DEFAULT_TOLERANCE)[2] for n in design.natures), default=1e-6)
    through_tol = min((NATURE_TOLERANCES.get(n, DEFAULT_TOLERANCE)[3] for n in design.natures), default=1e-12)
    max_step = analysis.step
    limits: list[float] = []  # `limit q : real with step;`, honoured as the analysis's step
    instances(design.top, lambda m, node, path: limits.extend(sy.value(numbers(x, values[path])) for x in m.limits))
    if limits and min(limits) < max_step:
        out.append(f"* limit specifications: the step is at most {num(min(limits))} s")
        max_step = min(limits)
    # The 1 F derivative capacitors hold quantity values as charge: their truncation-error floor (chgtol) must be
    # the quantities' own absolute accuracy, not ngspice's 1e-14 C, or a state decaying to zero stalls the step.
    # XSPICE limits the change of a code model's analog input per Newton iteration to max(convstep*|v|,
    # convabsstep), 0.1 by default: the A->D bridges' inputs are 0/1 levels, so every edge cost some 8 extra
    # iterations (the closed loop needed 4.5 per time point instead of 2.5). A step of 1 lets a level switch at once.
    # Compiled, KLU's refactorization with ngspice's relative pivot threshold (1e-3) returned solutions that broke
    # linear equations at accepted points when the motor stopped under load (the gauge's force 1e7 N off its
    # deflection, 14 of 25 compliance runs, later peaks moved by up to 11 N); a threshold of 0.1 chose pivots more
    # by size and removed them. At 0.1 the relay's switch-off with the glass on the bottom stop still ended runs in
    # "timestep too small" at some tolerances (compliance at reltol 9e-4: the iterates cycled at 1e-9 s steps);
    # a threshold of 1 (pivots by size alone) passes there, with the same compliance peaks to the printed digits
    # and the same speed (docs/performance.md). The behavioural references were made with ngspice's default.
    out.append(  # ngspice's noise analysis runs on its other solver (not KLU)
        f".options {'klu ' if analysis.noise is None else ''}reltol={num(analysis.reltol)} vntol={num(across_tol)} "
        f"abstol={num(through_tol)} "
        f"chgtol={num(across_tol / analysis.reltol)} method={analysis.method}"
        + (" convabsstep=1" if mixed else "")
        + (" pivrel=1" if compiled else "")
    )
    probes: dict[str, Probe] = {}
    source_map: dict[str, str] = {}
    instances(design.top, lambda m, node, path: _collect(m, node, path, probes, source_map, levels, values[path]))
    spectra: dict[str, str] = {}  # spectrum source quantity (hierarchical name) -> its node
    instances(design.top, lambda m, node, path: spectra.update({_join(path, n): node(n) for n in m.ac_sources}))
    if analysis.ac is not None:  # around the quiescent point; the spectrum source quantities excite it
        fstart, fstop, points = analysis.ac
        out.append(f".ac dec {points} {num(fstart)} {num(fstop)}")
    elif analysis.noise is not None:  # the noise source quantities' noise at a quantity, referred to an input
        output, fstart, fstop, points, referred = analysis.noise
        p = probes.get(output)
        if p is None or p.plus is None:
            raise WrsimError(f"--noise {output}: no quantity '{output}' in {title} ({', '.join(sorted(probes))})")
        at = f"v({p.plus})" if p.minus in (None, "0") else f"v({p.plus},{p.minus})"
        if referred is None:  # ngspice needs an input source: one that excites nothing
            source = "v_noise_in"
            out += ["v_noise_in noise_in 0 dc 0 ac 1", "r_noise_in noise_in 0 1"]
        elif referred in spectra:  # the spectrum source's element; ngspice refers to it per unit of its value
            path, _, leaf = spectra[referred].rpartition(".")
            source = f"v.{path}.v_{leaf}__ac" if path else f"v_{leaf}__ac"
        else:
            raise WrsimError(
                f"--noise-input {referred}: no spectrum source quantity '{referred}' in {title} "
                f"({', '.join(sorted(spectra)) or 'it has none'})"
            )
        out.append(f".noise {at} {source} dec {points} {num(fstart)} {num(fstop)}")
    else:
        out.append(f".tran {num(min(max_step, analysis.stop / 1000))} {num(analysis.stop)} 0 {num(max_step)}")
    if compiled:
        source_map[f"n_{compiled.name}"] = f"the compiled equations ({osdi.LIBRARY_FILE}, device {compiled.name})"
    crossings: list[str] = []
    instances(design.top, lambda m, node, _: crossings.extend(node(c.node) for c in observed[m.key]))
    holds, read_by_events = _hold_table(design.top, values)
    initial: list[tuple[str, float, str]] = []
    instances(
        design.top,
        lambda m, node, _: initial.extend(
            (node(n).lower(), v, f"{located(loc)}: {source_line(loc)}") for n, v, loc in m.initial
        ),
    )
    at_rest: list[tuple[str, float, str, str]] = []  # 1076.1: every q'dot is 0 at the quiescent point, or a break's
    if compiled:
        instances(design.top, lambda m, node, _: at_rest.extend(_quiescent_dots(m, node)))
    edge_only: set[str] = set()
    instances(design.top, lambda m, node, _: edge_only.update(node(c.node) for c in _edge_only(m, observed[m.key])))
    if analysis.save:
        unknown = [n for n in analysis.save if n not in probes]
        if unknown:
            raise WrsimError(f"cannot save {', '.join(unknown)}: no such quantity or signal in {title}")
        vectors = list(
            dict.fromkeys(
                v
                for p in (probes[name] for name in analysis.save)
                for v in (
                    [f"i({p.branch})"]
                    if p.branch
                    else [f"v({n})" for n in (p.plus, p.minus, *(p.bits or ())) if n not in (None, "0")]
                    + [f"v({n})" for n in sorted(sy.nodes_of(p.expr) if p.expr else ()) if n != "0"]
                )
            )
        )
        vectors = [v for v in vectors if v[2:-1] not in events] + [f"v({n})" for n in crossings + read_by_events]
        out += [".save " + " ".join(vectors[k : k + 8]) for k in range(0, len(vectors), 8)]
    out += [
        "",
        "* the run: analog waveforms to the raw file, the recorded digital nodes to a value change dump",
        ".control",
        # ngspice evaluates OSDI devices in OpenMP tasks, 8 threads by default (spinit): on a small machine the
        # threads' synchronisation cost more than the devices (futex calls at every load); one thread each run
        *([f"pre_osdi {osdi.LIBRARY_FILE}", "set num_threads=1"] if compiled else []),
        "set no_mem_check",  # else ngspice reads /proc/meminfo at every accepted point (docs/performance.md)
        "run",
        *(["setplot noise1"] if analysis.noise is not None else []),  # the densities (noise2: their integrals)
        f"write {RAW_FILE}",
        "rusage all",
    ]
    # The digital nodes that equations read are recorded too: the reference solver (backend.reference_solver)
    # replays them.
    recorded = list(dict.fromkeys([*events.values(), *sorted(analog_read)]))
    if recorded:  # one line: a .control line has no continuation
        out.append(f"eprvcd {' '.join(recorded)} > {EVENT_FILE}")
    out += [".endc", ".end"]
    return Netlist(
        "\n".join(out) + "\n",
        probes,
        source_map,
        title,
        analysis.stop,
        digital,
        design.digital_files,
        events,
        crossings,
        holds,
        edge_only,
        max_step,
        osdi.library(compiled) if compiled else "",
        small_signal,
        initial,
        at_rest,
    )


def _quiescent_dots(m: ArchModel, node) -> list[tuple[str, float, str, str]]:
    """The compiled device's node of each q'dot of `m` (osdi.py names it q__dot), the value 1076.1 gives it at the
    quiescent point (0, or what a break list at t = 0 sets), the quantity and where it is declared."""
    out = []
    for d in m.derivatives.values():
        q = m.quantities.get(d.quantity)
        where = f" ({d.quantity} declared at {located(q.loc)})" if q is not None else ""
        out.append((node(f"{d.quantity}__dot").lower(), m.initial_dot(d) or 0.0, d.quantity, where))
    return out


# ------------------------------------------------------------------------------------------------
def _hold_table(top: ArchModel, values: dict[str, dict[str, float]]) -> tuple[list[str], list[str]]:
    """The crossing driver's table of held values and their events (tools/cosim/wrsim_ngspice.c) with
    netlist-wide names, and the nodes the driver reads."""
    lines: list[str] = []
    read: list[str] = []
    index: dict[str, int] = {}

    def visit(m: ArchModel, node, path: str) -> None:
        def number(s: S) -> float:
            return sy.value(numbers(s, values[path]))

        def source(held: str) -> str:  # the external source of `held`, as ngspice names it (v.x_u.v_n in a subckt)
            name = node(f"v_{held}")
            return name if name == f"v_{held}".lower() else f"v.{name}"

        for h in m.holds.values():
            index[node(h.node)] = len(index)
            q = node(f"{h.quantity}__d1") if h.quantity else "-"
            lines.append(f"hold {source(h.node)} {'offset' if h.quantity else 'set'} {q} {number(h.initial)!r}")
            read.extend([q] if h.quantity else [])
        for k, e in enumerate(m.hold_events):
            lines.append(f"# {located(e.loc)} ({path or 'the bench'}): {source_line(e.loc)}")
            cond = node(f"event{k}__c") if e.cond is not None else "-"
            mechanisms = [e.mechanism(j) for j in range(len(e.sets))]
            faulty = [e.fault(j, m.holds) != sy.const(False) for j in range(len(e.sets))]  # a value that can be none
            sets = " ".join(
                f"{index[node(h)]}={node(f'event{k}_{j}')}"
                + (f"{'~' if how == 'transport' else '@'}{node(f'event{k}_{j}__d')}" if how else "")
                + (f"^{node(f'event{k}_{j}__r')}" if how == "reject" else "")
                + (f"!{node(f'event{k}_{j}__f')}" if faulty[j] else "")
                for j, ((h, _), how) in enumerate(zip(e.sets, mechanisms))
            )
            read.extend(node(f"event{k}_{j}__f") for j in range(len(e.sets)) if faulty[j])
            read.extend([node(f"event{k}_{j}") for j in range(len(e.sets))] + ([cond] if e.cond is not None else []))
            read.extend(node(f"event{k}_{j}__d") for j in e.delays)
            read.extend(node(f"event{k}_{j}__r") for j, how in enumerate(mechanisms) if how == "reject")
            lines.extend(f"on {node(g)} any {cond} {sets}" for g in e.guards)
            if e.changes:
                lines.append(f"change {','.join(str(index[node(h)]) for h in e.changes)} {cond} {sets}")
            if e.period is not None:
                period, offset = number(e.period), number(e.offset or sy.const(0.0))
                if not (0.0 < period < math.inf and 0.0 <= offset < math.inf):
                    raise WrsimError(
                        f"{located(e.loc)}: a sampling period of {period:g} s from {offset:g} s "
                        f"({path or 'the bench'}: {source_line(e.loc).strip()}): the period must be > 0 and the "
                        "first sample at or after 0 s"
                    )
                lines.append(f"every {period!r} {offset!r} {cond} {sets}")
            if e.at is not None:
                lines.append(f"at {index[node(e.at)]} {cond} {sets}")
            if e.first:
                lines.append(f"init {cond} {sets}")
        for el in m.elements:
            if el.kind in DRIVEN and isinstance(el.source, sy.Node):
                times = f" {number(el.args[0])!r} {number(el.args[1])!r}" if el.kind == "ramp" else ""
                lines.append(f"{el.kind} {source(el.node)} {index[node(el.source.name)]}{times}")

    instances(top, visit)
    return lines, read


def _digital_instances(top: ArchModel) -> list[tuple[str, DigitalChild, list[str], list[str]]]:
    """Every digital unit instance of the bench, those of the bench itself first: its label path (`cl.ecu`), the
    unit, and its input and output nodes with netlist-wide names."""
    out: list[tuple[str, DigitalChild, list[str], list[str]]] = []
    instances(
        top,
        lambda m, node, path: out.extend(
            (f"{path}.{d.label}" if path else d.label, d, [node(n) for n in d.inputs], [node(n) for n in d.outputs])
            for d in m.digital
        ),
    )
    return out


LAZY_ATTRIBUTE = "wrsim_lazy"  # a digital unit's `attribute wrsim_lazy of <ports> : signal is true;`


def _lazy_outputs(d: DigitalChild, outputs: list[str], analog_read: set[str]) -> list[str]:
    """The out ports of digital instance `d` (its output nodes `outputs`, netlist-wide) none of whose bits an
    analog element reads, and those its entity declares lazy (LAZY_ATTRIBUTE: the unit changes them in reaction to
    its inputs, and the analog side may take a change at the end of the accepted step that holds it)."""
    marked = {
        n.lower()
        for a in d.entity.attributes
        if a.attr.lower() == LAZY_ATTRIBUTE and isinstance(a.value, ast.Name) and a.value.ident == "true"
        for n in a.names
    }
    lazy, k = [], 0
    for p in d.entity.ports:
        if isinstance(p, ast.SignalPort) and p.mode == "out":
            width = p.width or 1
            if p.name.lower() in marked or not analog_read.intersection(outputs[k : k + width]):
                lazy.append(p.name)
            k += width
    return lazy


def _observed(m: ArchModel, bridged: set[str]) -> list[Crossing]:
    """The crossings of `m` whose 'above something reads: an equation, an integral, or an A->D signal that a
    digital unit or a D->A input consumes. An 'above that only sets a recorded level needs no time point."""
    tests = _tests_in(_analog_readers(m) + [a.cond for a in m.adcs if a.node in bridged])
    triggers = {g for e in m.hold_events for g in e.guards}
    return [c for c in m.crossings if c.test in tests or c.node in triggers]


def _edge_only(m: ArchModel, crossings: list[Crossing]) -> list[Crossing]:
    """The crossings among `crossings` whose 'above no equation or integral of `m` reads: they only time an A->D
    edge, and landing on them is no discontinuity of the analog system."""
    tests = _tests_in(_analog_readers(m))
    return [c for c in crossings if c.test not in tests]


def _analog_readers(m: ArchModel) -> list[S]:
    """The expressions of `m` the analog solver evaluates: equation residuals, integrands, what events read."""
    return [eq.residual for eq in m.equations] + [it.source for it in m.integrals.values()] + event_exprs(m)


def _tests_in(exprs: list[S]) -> set[S]:
    """The comparisons q > e (the form of every 'above) inside `exprs`."""
    return {x for e in exprs for x in sy.walk(e) if isinstance(x, sy.Op) and x.name == ">"}


def _join(path: str, name: str) -> str:
    """The hierarchical name of `name` in the instance at `path` ("" the bench)."""
    return f"{path}.{name}" if path else name


def _collect(
    m: ArchModel,
    node,
    path: str,
    probes: dict[str, Probe],
    source_map: dict[str, str],
    levels: dict[str, str],
    values: dict[str, float],
) -> None:
    """Probe table and source map entries of one instance (raw names are lower case)."""
    for q in m.quantities.values():
        shown = re.sub(r"__(\d+)$", r"(\1)", q.name)  # an element of an array quantity: a(k)
        name = f"{path}.{shown}" if path else shown
        if isinstance(q.s, sy.Node) and q.s.name in m.eliminated:
            probes[name] = Probe(name, q.unit or "1", expr=numbers(m.eliminated[q.s.name], values, node))
        elif isinstance(q.s, sy.Diff):
            probes[name] = Probe(name, q.unit or "1", node(q.s.plus), node(q.s.minus))
        elif isinstance(q.s, sy.Node):
            probes[name] = Probe(name, q.unit or "1", node(q.s.name), "0")
    for sig in m.signals.values():
        if all(node(n) in levels for n in sig.nodes):
            name = f"{path}.{sig.name}" if path else sig.name
            probes[name] = Probe(
                name, "1", bits=[levels[node(n)] for n in sig.nodes], signed=sig.type_mark == "integer"
            )
    for h in m.holds.values():  # signals and variables of processes
        if h.name:
            name = f"{path}.{h.name}" if path else h.name
            probes[name] = Probe(name, "1", node(h.node), "0")
    for u in m.unknowns.values():
        eq = next((e for e in m.equations if e.paired == u.node), None)
        what = f"quantity {f'{path}.' if path else ''}{u.node} ({u.role}, declared at {located(u.loc)})"
        if eq is not None:
            what += f", solved by the equation at {located(eq.loc)}: {source_line(eq.loc)}"
            what += "".join(f" / {located(alt)}: {source_line(alt)}" for alt in eq.alternatives)
        source_map[node(u.node)] = what
        source_map[node(f"b_{u.node}__eq")] = what
    where = f"{path}." if path else ""
    for b in m.branches:
        source_map[node(f"b_{b.through}")] = f"branch of the through quantity {where}{b.through} ({located(b.loc)})"
    for d in m.derivatives.values():  # the elements that differentiate a quantity for its 'dot
        what = f"{where}{d.quantity}'dot, the derivative of quantity {where}{d.quantity}" + (
            f": {source_map[node(d.quantity)]}" if node(d.quantity) in source_map else ""
        )
        for name in (d.element, f"e_{d.quantity}__d", f"c_{d.quantity}__d", f"{d.quantity}__d1", f"{d.quantity}__d2"):
            source_map[node(name)] = what
    for it in m.integrals.values():
        what = f"{where}{it.quantity}'integ, the integral of quantity {where}{it.quantity}"
        source_map[node(f"b_{it.quantity}__i")] = source_map[node(it.node)] = what
    for c in m.crossings:
        source_map[node(c.node)] = source_map[node(f"b_{c.node}")] = f"'above at {located(c.loc)}: {source_line(c.loc)}"
