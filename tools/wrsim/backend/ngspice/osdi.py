"""Backend: a design's equations as compiled device code that ngspice loads through OSDI (`pre_osdi`).

The netlist's behavioural sources make ngspice evaluate every residual and the expression trees of its
derivatives at every Newton iteration. `device` turns what the architectures state as equations (simultaneous
statements, through-quantity branches, 'dot and 'integ) into one OSDI device for the whole netlist: C code that
evaluates each node's residual, split into a resistive part F(x, t) and a charge Q(x) whose time derivative ngspice
adds, with the Jacobian entries dF/dx and dQ/dx by forward differentiation of the same expressions. A 'dot gets a
node of its own (F = the 'dot, Q = -the quantity) where the behavioural netlist has a 1 F capacitor and a 0 V
source. The `v = expression` sources (A->D levels, 'above guards, the events' values and conditions, 'slew
inputs) become rows v(n) - e of the same device. Generics stay parameters of the instance, so one compiled library
serves every parameter set. The rest (held values, 'delayed lines and their inputs, the XSPICE bridges) stays in
the architectures' .subckt and reads a 'dot from its node. `library` writes the C file, `build` compiles it with
the system C compiler into a shared library, cached by the digest of its source.

Where C and ngspice's behavioural sources differ, the code follows ngspice: `x ** y` with a non-integer or large
exponent is |x| ** y, exp saturates at 1e99 above 227.96, ln(0) is -1e99, sin/cos/tan reduce their argument by
whole periods first, and every division (derivatives included) moves its divisor 1e-32 away from zero (without
it, 0.5 / sqrt(0) in the Jacobian of a cable angle made the closed loop's matrix infinite). The ABI is declared
in tools/cosim/wrsim_osdi.h."""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.backend.native import CC, compile_c, digest, staging
from wrsim.backend.ngspice import limiting
from wrsim.elab import symbolic as sy
from wrsim.elab.design import QUIESCENT, ArchModel, Crossing, instances
from wrsim.elab.symbolic import S
from wrsim.errors import WrsimError

__all__ = ["Device", "device", "library", "build", "LIBRARY_FILE"]

LIBRARY_FILE = "devices.osdi"  # the run folder's link to the compiled library (the netlist's pre_osdi)
DEVICE = "wrsim_equations"  # the device's name: the same for every netlist, so that the code depends on the structure
_HEADER = paths.COSIM / "wrsim_osdi.h"


@dataclass
class Device:
    """The compiled equations of a whole netlist: the OSDI device `name` and its `.model` card `model`, one instance
    at the top level whose nodes (`terminals`) are netlist-wide node names, its parameters (`params`: name ->
    value, every generic an equation reads, by instance), the node that carries each 'dot (by architecture: the 0 V
    source the behavioural netlist would have -> the local node) and the C code."""

    name: str
    model: str
    terminals: list[str]
    params: dict[str, float]
    dots: dict[str, dict[str, str]]
    code: str = ""


def device(
    top: ArchModel, values: dict[str, dict[str, float]], guards: dict[str, list[Crossing]] | None = None
) -> Device | None:
    """The OSDI device of every architecture instance's equations below `top` (generics: `values` by instance path,
    as design.generic_values gives them), or None when there are none. One device, so that ngspice evaluates all
    equations in one call per Newton iteration (each OSDI device type costs an OpenMP parallel region). Raises
    WrsimError naming the source line of an equation the backend cannot compile."""
    resist: dict[str, list[S]] = {}
    react: dict[str, list[S]] = {}
    rows: dict[str, list[str]] = {}
    params: dict[str, float] = {}
    names: dict[tuple[str, str], str] = {}
    dots: dict[str, dict[str, str]] = {}
    equations: set[str] = set()  # the nodes whose row is an equation's residual (its own node, nothing else on it)
    noise: list[tuple[str, S]] = []  # a noise source quantity's node and its density: a noise current into its row
    levels: set[str] = set()  # the nodes whose row sets the node to an expression (v = e: levels, guards, events)

    def visit(m: ArchModel, node: Callable[[str], str], path: str) -> None:
        local = {d.element: f"{d.quantity}__dot" for d in m.derivatives.values()}
        dots[m.key] = local
        where = f"{path or m.entity.name}"

        def param(name: str) -> sy.Param:
            if (path, name) not in names:
                base = "p_" + re.sub(r"\W", "_", f"{path}_{name}" if path else name).lower()
                key = base if base not in params else f"{base}_{len(params)}"
                names[(path, name)] = key
                params[key] = values[path][name]
            return sy.Param(names[(path, name)])

        def glob(s: S, loc: str) -> S:
            _check(s, local, loc)

            def leaf(x: S) -> S | None:
                if isinstance(x, sy.Param):
                    return param(x.name)
                if isinstance(x, sy.Node):
                    return sy.Node(node(x.name))
                if isinstance(x, sy.Diff):
                    return sy.Diff(node(x.plus), node(x.minus))
                if isinstance(x, sy.Branch):
                    return sy.Node(node(local[x.name]))
                return None

            return sy.substitute(s, {}, leaf)

        def add(table: dict[str, list[S]], at: str, s: S, what: str) -> None:
            if node(at) != "0":
                table.setdefault(node(at), []).append(s)
                rows.setdefault(node(at), []).append(f"{where}: {what}")

        for eq in m.equations:
            at = f"{paths.shown(eq.loc.file)}:{eq.loc.line}:{eq.loc.col}"
            add(resist, eq.paired, glob(eq.residual, at), at)
            equations.add(node(eq.paired))
        for b in m.branches:
            add(resist, b.plus, sy.Node(node(b.through)), f"branch {b.through} leaves")
            add(resist, b.minus, sy.op("neg", sy.Node(node(b.through))), f"branch {b.through} enters")
        for d in m.derivatives.values():
            ref = next((h.node for h in m.holds.values() if h.quantity == d.quantity), "0")
            quantity = glob(sy.op("-", d.source, sy.Node(ref)) if ref != "0" else d.source, f"{d.quantity}'dot")
            at = local[d.element]
            own: S = sy.Node(node(at))  # the row: q'dot's node - ddt(q); at the quiescent point 0, or a break's value
            at_rest = m.initial_dot(d)
            if at_rest is not None:
                own = sy.cond(QUIESCENT, sy.op("-", own, sy.const(at_rest)), own)
            add(resist, at, own, f"{d.quantity}'dot")
            add(react, at, sy.op("neg", quantity), f"{d.quantity}'dot")
        for it in m.integrals.values():
            src = sy.cond(QUIESCENT, sy.op("neg", sy.Node(node(it.node))), glob(it.source, f"{it.quantity}'integ"))
            add(resist, it.node, sy.op("neg", src), f"{it.quantity}'integ")
            add(react, it.node, sy.Node(node(it.node)), f"{it.quantity}'integ")

        def level(at: str, s: S, what: str) -> None:  # the node `at` = s: the behavioural netlist's B voltage source
            add(resist, at, sy.op("-", sy.Node(node(at)), glob(s, what)), what)
            levels.add(node(at))

        for a in m.adcs:
            level(a.level, sy.cond(a.cond, sy.const(1.0), sy.const(0.0)), f"the 0/1 level of {a.node}")
        for x in (guards or {}).get(m.key, []):
            level(x.node, x.guard, f"'above guard {x.node}")
        for k, e in enumerate(m.hold_events):
            for j, (held, target) in enumerate(e.sets):
                fault = e.fault(j, m.holds)  # where the value has none: 0 between events, the run stops at one
                level(f"event{k}_{j}", sy.cond(fault, sy.const(0.0), target), f"event {k}: the value for {held}")
                if fault != sy.const(False):
                    why = f"event {k}: {held} has no value"
                    level(f"event{k}_{j}__f", sy.cond(fault, sy.const(1.0), sy.const(0.0)), why)
                if j in e.delays:
                    level(f"event{k}_{j}__d", e.delays[j], f"event {k}: the delay for {held}")
                if e.mechanism(j) == "reject":
                    level(f"event{k}_{j}__r", e.limits[j], f"event {k}: the pulse rejection limit for {held}")
            if e.cond is not None:
                level(f"event{k}__c", sy.cond(e.cond, sy.const(1.0), sy.const(0.0)), f"event {k}: its condition")
        for name, density in m.noise_sources.items():  # its row is `n == 0` (1 S): the current's density is n's
            noise.append((node(name), glob(density, f"the noise density of {name}")))
        for el in m.elements:
            if el.kind == "slew":  # a 'delayed input feeds a lossless line, which draws current: it stays behavioural
                level(f"{el.node}__in", el.source, f"the input of {el.node}")

    instances(top, visit)
    if not resist and not react:
        return None
    read: set[str] = set()
    for table in (resist, react):
        for terms in table.values():
            for s in terms:
                read |= sy.nodes_of(s)
    terminals = list(dict.fromkeys([*resist, *react, *sorted(read - {"0"})]))
    dev = Device(DEVICE, DEVICE + "_m", terminals, params, dots)
    dev.code = _code(dev, resist, react, rows, equations, levels, noise)
    return dev


def library(dev: Device) -> str:
    """The C source of the library holding `dev` (the OSDI exports included)."""
    out = [
        "/* generated by wrsim from VHDL-AMS (wrsim.backend.ngspice.osdi); do not edit */",
        "#include <math.h>",
        "#include <stddef.h>",
        "#include <string.h>",
        '#include "wrsim_osdi.h"',
        "",
        "#define WRSIM_MOD(x, p) ((x) - (double)(int)((x) / (p)) * (p)) /* ngspice's argument reduction */",
        "static double wrsim_exp(double x) { return x > 227.9559242 ? 1e99 : exp(x); }",
        "static double wrsim_ln(double x) { return x > 0.0 ? log(x) : (x == 0.0 ? -1e99 : HUGE_VAL); }",
        "static double wrsim_sgn(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }",
        STEP_HELPER,
        "#define WRSIM_FLAGS 3 /* iterations at one time point an equation's residual may ask for */",
        "#define WRSIM_LIMITS 20 /* limited iterations at one time point */",
        limiting.C_HELPERS,
        "/* ngspice's division: the divisor moved 1e-32 away from 0 (gmin * 1e-20), so 0.5 / sqrt(0) stays finite */",
        "static double wrsim_div(double a, double b) { return a / (b >= 0.0 ? b + 1e-32 : b - 1e-32); }",
        "",
    ]
    out += [
        dev.code,
        "const uint32_t OSDI_VERSION_MAJOR = 0;",
        "const uint32_t OSDI_VERSION_MINOR = 3;",
        "const uint32_t OSDI_NUM_DESCRIPTORS = 1;",
        f"const wrsim_osdi_descriptor OSDI_DESCRIPTORS[] = {{{dev.name}_descriptor}};",
        "",
    ]
    return "\n".join(out)


def build(source: str, cache: Path) -> Path:
    """Compile the library `source` (cached in `cache` by the digest of the source and the ABI header); returns
    the shared library. A compiler failure is one WrsimError naming the kept C file."""
    header = _HEADER.read_text(encoding="utf-8")
    final = cache / "osdi" / digest(source, header)[:16]
    lib = final / LIBRARY_FILE
    if lib.is_file():
        return lib
    failed = cache / "osdi" / "failed.c"
    with staging(final) as tmp:
        c = tmp / "devices.c"
        c.write_text(source, encoding="utf-8")
        try:
            compile_c(
                [
                    CC,
                    "-O2",
                    "-fPIC",
                    "-shared",
                    "-fno-math-errno",
                    "-I",
                    str(paths.COSIM),
                    "-o",
                    str(tmp / LIBRARY_FILE),
                    str(c),
                    "-lm",
                ],
                "the compiled models",
            )
        except WrsimError as e:
            failed.parent.mkdir(parents=True, exist_ok=True)
            failed.write_text(source, encoding="utf-8")
            raise WrsimError(f"{str(e).replace(str(c), str(failed))}\n(the generated C file: {failed})") from None
    return lib


# ------------------------------------------------------------------------------------------------
def _check(s: S, dots: dict[str, str], where: str) -> None:
    for x in sy.walk(s):
        if isinstance(x, (sy.Vec, sy.Text)) or (isinstance(x, sy.Branch) and x.name not in dots):
            raise WrsimError(
                f"{where}: the compiled models (OSDI) cannot express {x} in an equation; "
                "run with the behavioural sources (--no-compile)"
            )
        if isinstance(x, sy.Fn) and x.name not in _DERIV:
            raise WrsimError(
                f"{where}: the compiled models (OSDI) have no function '{x.name}'; "
                "run with the behavioural sources (--no-compile)"
            )


def _num(v: float) -> str:
    if math.isnan(v):
        return "NAN"
    if abs(v) > 1e300:
        v = math.copysign(1e300, v)  # as the netlist writes it
    return repr(float(v))


class _Emitter:
    """Straight-line C for values and partial derivatives, common sub-expressions shared within a scope; the
    branches of a conditional are their own scopes (evaluated only when taken, as ngspice does)."""

    def __init__(self, index: dict[str, int], params: dict[str, int], prefix: str = "t", held: bool = False):
        self.index, self.params, self.prefix = index, params, prefix
        self.held = held  # a step function of the unknowns keeps its last iterate's value (x->held, STEP_HELPER)
        self.sites = 0  # the step functions so held, one x->held slot each
        self.lines: list[str] = []
        self.scopes: list[dict[S, tuple[str, dict[int, str]]]] = [{}]
        self.n = 0
        self.indent = 1

    def emit(self, line: str) -> None:
        self.lines.append("    " * self.indent + line)

    def temp(self) -> str:
        self.n += 1
        return f"{self.prefix}{self.n}"

    def value(self, s: S) -> tuple[str, dict[int, str]]:
        """C names of `s`'s value and of its derivative by each unknown it depends on."""
        for scope in reversed(self.scopes):
            if s in scope:
                return scope[s]
        got = self._value(s)
        self.scopes[-1][s] = got
        return got

    def _bind(self, expr: str, deriv: dict[int, str]) -> tuple[str, dict[int, str]]:
        v = self.temp()
        self.emit(f"const double {v} = {expr};")
        return v, self._bind_deriv(v, {k: e for k, e in deriv.items() if e != "0.0"})

    def _value(self, s: S) -> tuple[str, dict[int, str]]:
        if s == QUIESCENT:  # the domain: quiescent while ngspice solves the operating point, not in AC (eval)
            return "quiescent", {}
        if isinstance(s, sy.Const):
            return _num(s.value), {}
        if isinstance(s, sy.Param):
            return f"x->p[{self.params[s.name]}]", {}
        if isinstance(s, sy.Time):
            return "t", {}
        if isinstance(s, sy.Node):
            if s.name == "0":
                return "0.0", {}
            k = self.index[s.name]
            return f"v[{k}]", {k: "1.0"}
        if isinstance(s, sy.Diff):
            return self.value(sy.op("-", sy.Node(s.plus), sy.Node(s.minus)) if s.minus != "0" else sy.Node(s.plus))
        if isinstance(s, sy.Cond):
            return self._cond(s)
        if isinstance(s, sy.Op):
            return self._op(s)
        if isinstance(s, sy.Fn):
            return self._fn(s)
        raise WrsimError(f"internal: the OSDI backend cannot compile {s!r}")

    def _cond(self, s: sy.Cond) -> tuple[str, dict[int, str]]:
        test, _ = self.value(s.test)
        v = self.temp()
        branches = []
        self.emit(f"double {v};")
        deps: set[int] = set()
        for arm in (s.then, s.other):
            self.scopes.append({})
            self.indent += 1
            start = len(self.lines)
            got = self.value(arm)
            self.indent -= 1
            self.scopes.pop()
            branches.append((self.lines[start:], got))
            del self.lines[start:]
            deps |= set(got[1])
        for k in sorted(deps):
            self.emit(f"double {v}_{k};")
        for j, (lines, (val, der)) in enumerate(branches):
            self.emit(f"if ({test} != 0.0) {{" if j == 0 else "} else {")
            self.lines += lines
            self.emit(f"    {v} = {val};")
            for k in sorted(deps):
                self.emit(f"    {v}_{k} = {der.get(k, '0.0')};")
        self.emit("}")
        return v, {k: f"{v}_{k}" for k in sorted(deps)}

    def _op(self, s: sy.Op) -> tuple[str, dict[int, str]]:
        args = [self.value(a) for a in s.args]
        (a, da) = args[0]
        (b, db) = args[1] if len(args) > 1 else ("", {})
        keys = sorted(set(da) | set(db))

        def lin(fa: str, fb: str) -> dict[int, str]:  # fa * da + fb * db
            out = {}
            for k in keys:
                terms = ([f"{fa}{da[k]}"] if k in da else []) + ([f"{fb}{db[k]}"] if k in db else [])
                out[k] = " + ".join(terms).replace("+ -", "- ")
            return out

        n = s.name
        if n == "+":
            return self._bind(f"{a} + {b}", lin("", ""))
        if n == "-":
            return self._bind(f"{a} - {b}", lin("", "-"))
        if n == "neg":
            return self._bind(f"-{a}", {k: f"-{e}" for k, e in da.items()})
        if n == "*":
            return self._bind(f"{a} * {b}", lin(f"{b} * ", f"{a} * "))
        if n == "/":
            v, _ = self._bind(f"wrsim_div({a}, {b})", {})
            return v, self._bind_deriv(
                v, {k: f"wrsim_div({da.get(k, '0.0')} - {v} * {db.get(k, '0.0')}, {b})" for k in keys}
            )
        if n == "abs":
            return self._bind(f"fabs({a})", {k: f"wrsim_sgn({a}) * {e}" for k, e in da.items()})
        if n == "**":
            p = s.args[1]
            if isinstance(p, sy.Const) and p.value == int(p.value) and 0 < p.value <= 4:
                k_ = int(p.value)
                return self._bind(
                    " * ".join([a] * k_),
                    {k: f"{k_}.0 * {' * '.join([a] * (k_ - 1)) or '1.0'} * {e}" for k, e in da.items()},
                )
            v, _ = self._bind(f"pow(fabs({a}), {b})", {})
            der = {}
            for k in keys:
                terms = []
                if k in da:
                    # b * |a|**(b-1) * sgn(a) as b * |a|**b / a, guarded as sqrt's is (finite where a = 0)
                    terms.append(f"({da[k]} == 0.0 ? 0.0 : {b} * wrsim_div({v}, {a}) * {da[k]})")
                if k in db:
                    terms.append(f"({db[k]} == 0.0 || {v} == 0.0 ? 0.0 : {v} * log(fabs({a})) * {db[k]})")
                der[k] = " + ".join(terms)
            return v, self._bind_deriv(v, der)
        if n in _REL:
            return self._bind(f"({a} {_REL[n]} {b}) ? 1.0 : 0.0", {})
        if n == "and":
            return self._bind(f"({a} != 0.0 && {b} != 0.0) ? 1.0 : 0.0", {})
        if n == "or":
            return self._bind(f"({a} != 0.0 || {b} != 0.0) ? 1.0 : 0.0", {})
        if n == "not":
            return self._bind(f"({a} == 0.0) ? 1.0 : 0.0", {})
        raise WrsimError(f"internal: the OSDI backend has no operator '{n}'")

    def _bind_deriv(self, v: str, der: dict[int, str]) -> dict[int, str]:
        out = {}
        for k, e in der.items():
            self.emit(f"const double {v}_{k} = {e};")
            out[k] = f"{v}_{k}"
        return out

    def _fn(self, s: sy.Fn) -> tuple[str, dict[int, str]]:
        args = [self.value(a) for a in s.args]
        if s.name in ("min", "max"):
            (a, da), (b, db) = args
            keys = sorted(set(da) | set(db))
            pick = (
                f"{a} > {b}" if s.name == "max" else f"!({a} > {b})"
            )  # ngspice: max = a > b ? a : b, min = a > b ? b : a
            return self._bind(
                f"({pick}) ? {a} : {b}", {k: f"({pick}) ? {da.get(k, '0.0')} : {db.get(k, '0.0')}" for k in keys}
            )
        (a, da) = args[0]
        value, slope = _DERIV[s.name]
        if self.held and s.name in ("floor", "ceil") and da:
            v, _ = self._bind(f"wrsim_step_held({s.name}, {a}, &x->held[{self.sites}])", {})
            self.sites += 1
            return v, {}
        v, _ = self._bind(value.format(a=a), {})
        if slope is None:
            return v, {}
        # a zero change of the argument changes nothing, also where the slope is infinite (sqrt at 0)
        return v, self._bind_deriv(
            v, {k: f"{e} == 0.0 ? 0.0 : ({slope.format(a=a, v=v)}) * {e}" for k, e in da.items()}
        )


_REL = {"<": "<", "<=": "<=", ">": ">", ">=": ">=", "==": "==", "!=": "!="}
# A step function (floor, ceil) of the unknowns: within a millionth of its argument's magnitude (at least 1e-6) past
# an edge it keeps the value it had at the last iterate of the same time point. Else Newton's iterates that straddle
# an edge by their rounding flip it, and every 0/1 level made from it (an ADC register's bits), from one iteration
# to the next, and ngspice cuts the step to nothing ("timestep too small": a shunt's zero current on the edge of
# code 512, tests/unit/test_osdi.py). Each time point starts from the closed form: kept over several points, the
# value of an accumulating argument (a magnet's angle in turns) stood a whole band past its edge and moved a pinch
# peak by 10 N.
STEP_HELPER = """\
static double wrsim_step_held(double (*step)(double), double a, double *held) {
    const double tol = 1e-6 * fmax(1.0, fabs(a)), v = step(a);
    if (!isnan(*held) && *held != v && step(a - tol) <= *held && *held <= step(a + tol)) return *held;
    return *held = v;
}"""

# function -> (C value of argument {a}, its derivative by {a} given the value {v}; None: piecewise constant)
_DERIV: dict[str, tuple[str, str | None]] = {
    "sin": ("sin(WRSIM_MOD({a}, 2.0 * M_PI))", "cos({a})"),
    "cos": ("cos(WRSIM_MOD({a}, 2.0 * M_PI))", "-sin({a})"),
    "tan": ("tan(WRSIM_MOD({a}, M_PI))", "1.0 + {v} * {v}"),
    "atan": ("atan({a})", "wrsim_div(1.0, 1.0 + {a} * {a})"),
    "sqrt": ("({a}) < 0.0 ? HUGE_VAL : sqrt({a})", "wrsim_div(0.5, {v})"),
    "exp": ("wrsim_exp({a})", "{v}"),
    "ln": ("wrsim_ln({a})", "wrsim_div(1.0, {a})"),
    "sinh": ("sinh({a})", "cosh({a})"),
    "cosh": ("cosh({a})", "sinh({a})"),
    "tanh": ("tanh({a})", "1.0 - {v} * {v}"),
    "asin": ("asin({a})", "wrsim_div(1.0, sqrt(1.0 - {a} * {a}))"),
    "acos": ("acos({a})", "wrsim_div(-1.0, sqrt(1.0 - {a} * {a}))"),
    "abs": ("fabs({a})", "wrsim_sgn({a})"),
    "floor": ("floor({a})", None),
    "ceil": ("ceil({a})", None),
    "sgn": ("wrsim_sgn({a})", None),
    "min": ("", None),
    "max": ("", None),
}


def _code(
    dev: Device,
    resist: dict[str, list[S]],
    react: dict[str, list[S]],
    rows: dict[str, list[str]],
    equations: set[str],
    levels: set[str],
    noise: list[tuple[str, S]],
) -> str:
    """The instance layout, eval, the loaders and the descriptor of one device."""
    index = {n: k for k, n in enumerate(dev.terminals)}
    pindex = {p: k + 1 for k, p in enumerate(dev.params)}  # p[0]: $mfactor
    n, np_ = len(dev.terminals), len(dev.params) + 1
    em = _Emitter(index, pindex, held=True)
    jr: dict[tuple[int, int], list[str]] = {}
    jq: dict[tuple[int, int], list[str]] = {}
    f_rows: dict[int, str] = {}
    q_rows: dict[int, str] = {}
    _limiting(em, limiting.edges([t for table in (resist, react) for terms in table.values() for t in terms], index))
    for table, vals, jac in ((resist, f_rows, jr), (react, q_rows, jq)):
        for node, terms in table.items():
            row = index[node]
            em.emit(f"/* {node}: {'; '.join(rows[node])} */")
            total = terms[0]
            for t in terms[1:]:
                total = sy.op("+", total, t)
            v, der = em.value(total)
            vals[row] = v
            for col, d in der.items():
                jac.setdefault((row, col), []).append(d)
    entries = sorted(set(jr) | set(jq))
    ne = max(len(entries), 1)
    nq = [k for k, e in enumerate(entries) if e in jq]
    p = dev.name
    body = "\n".join(em.lines)
    out = [
        f"/* {dev.name}: {len(dev.terminals)} nodes, {len(dev.params)} parameters */",
        "typedef struct {",
        f"    uint32_t nm[{n}];",
        f"    double *jr[{ne}];",
        f"    double *jq[{ne}];",
        f"    double F[{n}], Q[{n}], JF[{ne}], JQ[{ne}];",
        f"    double reltol, abstol, vntol, t_before, last[{n}], older[{n}], at[{n}], held[{max(em.sites, 1)}];",
        "    uint32_t flagged, limited;",
        f"    double p[{np_}];",
        f"    bool given[{np_}];",
        "    bool collapsed[1];",
        "    uint32_t state[1];",
        f"}} {p}_inst;",
        f"static const uint32_t {p}_row[{ne}] = {{{', '.join(str(r) for r, _ in entries) or '0'}}};",
        f"static const uint32_t {p}_col[{ne}] = {{{', '.join(str(c) for _, c in entries) or '0'}}};",
        # $mfactor 1; the generics' values are on the instance line, never in the code: one library serves every
        # parameter set (a study's samples, a fleet's doors)
        f"static const double {p}_default[{np_}] = {{{', '.join(['1.0'] + ['0.0'] * (np_ - 1))}}};",
        "",
        f"static uint32_t {p}_eval(void *h, void *inst, const void *model, const wrsim_osdi_sim_info *info) {{",
        f"    {p}_inst *x = inst;",
        "    const double *s = info->prev_solve;",
        "    const double t = info->abstime;",
        f"    double v[{n}];",
        f"    for (int k = 0; k < {n}; k++) v[k] = x->nm[k] ? s[x->nm[k]] : 0.0;",
        "    if (t != x->t_before) { /* a new time point: no iterates to limit against yet */",
        f"        x->limited = 0; for (int k = 0; k < {n}; k++) x->older[k] = x->last[k] = NAN;",
        f"        for (int k = 0; k < {max(em.sites, 1)}; k++) x->held[k] = NAN; /* nor a step to keep */",
        "    }",
        "    uint32_t lim = 0; /* an unknown put back by Newton limiting (the first lines of the body) */",
        "    /* 1076.1: domain = quiescent_domain at the operating point (t = 0); a small-signal analysis",
        "       linearises the frequency domain's equations at that point (an evaluation with ANALYSIS_AC set) */",
        "    const double quiescent = (t <= 0.0 && !(info->flags & WRSIM_ANALYSIS_AC)) ? 1.0 : 0.0;",
        "    (void)quiescent;",
        body,
    ]
    for row in range(n):
        out.append(f"    x->F[{row}] = {f_rows.get(row, '0.0')};")
        out.append(f"    x->Q[{row}] = {q_rows.get(row, '0.0')};")
    # ngspice's behavioural sources take part in its convergence test: after a Newton solve, a source's value at the
    # new solution must be within reltol of its value at the last load (plus abstol). An equation's source carries
    # the residual on a node of its own, which the solve makes zero to first order, so that test asks for the
    # residual at the last load to be within abstol. OSDI has no such hook; the device asks for another iteration
    # (the limiting flag) while an equation's residual exceeds it: the same decision, in the same iteration. At
    # most WRSIM_FLAGS times per time point: at reltol 1e-4 an iterate crossing a kink again and again (the worm
    # gear's working modes tie at eta = 0.5) otherwise cut the step to nothing; then the node test decides.
    eq_rows = sorted(index[e] for e in equations)
    lv_rows = sorted(index[e] for e in levels)
    out += [
        "    uint32_t moved = 0;",
        f"    static const uint32_t equation_rows[{max(len(eq_rows), 1)}] = {{{', '.join(map(str, eq_rows)) or '0'}}};",
        f"    for (int j = 0; j < {len(eq_rows)}; j++) {{",
        "        const double r = fabs(x->F[equation_rows[j]]);",
        "        if (r > x->reltol * r + x->abstol) moved = 1;",
        "    }",
        f"    static const uint32_t level_rows[{max(len(lv_rows), 1)}] = {{{', '.join(map(str, lv_rows)) or '0'}}};",
        f"    for (int j = 0; j < {len(lv_rows)}; j++) {{  /* v = e: within reltol of v plus vntol */",
        "        const uint32_t k = level_rows[j];",
        "        if (fabs(x->F[k]) > x->reltol * fabs(v[k]) + x->vntol) moved = 1;",
        "    }",
        "    if (t != x->t_before) { x->t_before = t; x->flagged = 0; }",
        "    if (moved && ++x->flagged > WRSIM_FLAGS) moved = 0;",
        f"    for (int k = 0; k < {n}; k++) {{ x->older[k] = x->last[k]; x->at[k] = x->last[k] = v[k]; }}",
        "    if (lim) { x->limited++; moved = 1; }",
    ]
    for k, e in enumerate(entries):
        out.append(f"    x->JF[{k}] = {' + '.join(jr.get(e, ['0.0']))};")
        out.append(f"    x->JQ[{k}] = {' + '.join(jq.get(e, ['0.0']))};")
    out += ["    (void)h; (void)model; (void)t;", "    return moved;", "}", ""]
    out.append(
        _LOADERS.replace("PFX", p)
        .replace("NNODES", str(n))
        .replace("NENTRIES", str(len(entries)))
        .replace("NPARAMS", str(np_))
    )
    out += _noise(p, noise, index, pindex)
    out.append(f"static wrsim_osdi_node {p}_nodes[{n}] = {{")
    for row, name in enumerate(dev.terminals):
        charge = f"offsetof({p}_inst, Q) + {row} * sizeof(double)" if row in q_rows else "WRSIM_OSDI_NONE"
        out.append(
            f'    {{"{name}", "", "", offsetof({p}_inst, F) + {row} * sizeof(double), {charge}, '
            "WRSIM_OSDI_NONE, WRSIM_OSDI_NONE, false},"
        )
    out.append("};")
    out.append(f"static wrsim_osdi_jacobian_entry {p}_jac[{ne}] = {{")
    for k, (r, c) in enumerate(entries):
        react_off = f"offsetof({p}_inst, jq) + {k} * sizeof(double *)" if k in nq else "WRSIM_OSDI_NONE"
        flags = "WRSIM_JAC_RESIST" + (" | WRSIM_JAC_REACT" if k in nq else "")
        out.append(f"    {{{{{r}, {c}}}, {react_off}, {flags}}},")
    if not entries:
        out.append("    {{0, 0}, WRSIM_OSDI_NONE, 0},")
    out.append("};")
    out.append(f'static char *{p}_pname0[] = {{"$mfactor"}};')
    for k, q in enumerate(dev.params, start=1):
        out.append(f'static char *{p}_pname{k}[] = {{"{q}"}};')
    out.append(f"static wrsim_osdi_param {p}_params[{np_}] = {{")
    for k in range(np_):
        out.append(f'    {{{p}_pname{k}, 0, "", "", WRSIM_PARA_REAL | WRSIM_PARA_INST, 0}},')
    out.append("};")
    out.append(
        _DESCRIPTOR.replace("PFX", p)
        .replace("NNODES", str(n))
        .replace("NENTRIES", str(len(entries)))
        .replace("NPARAMS", str(np_))
        .replace("NOISE_SOURCES", f"{p}_noise_src" if noise else "NULL")
        .replace("NNOISE", str(len(noise)))
    )
    return "\n".join(out)


def _noise(p: str, noise: list[tuple[str, S]], index: dict[str, int], params: dict[str, int]) -> list[str]:
    """The noise sources (a current into the row of each noise source quantity's node, whose equation `n == 0`
    makes the node's noise density the current's) and `load_noise`, their densities from the parameters."""
    em = _Emitter(index, params, prefix="n")
    values = [em.value(density)[0] for _, density in noise]
    out = [
        f"static void {p}_noise(void *inst, void *model, double freq, double *dens) {{",
        f"    {p}_inst *x = inst; (void)x; (void)model; (void)freq;",
        *em.lines,
        *(f"    dens[{k}] = {v};" for k, v in enumerate(values)),
        "}",
    ]
    if noise:
        out.append(f"static wrsim_osdi_noise_source {p}_noise_src[{len(noise)}] = {{")
        out += [f'    {{"{node}", {{{index[node]}, WRSIM_OSDI_NONE}}}},' for node, _ in noise]
        out.append("};")
    return out


def _limiting(em: _Emitter, edges: dict[int, list[S]]) -> None:
    """The Newton limiting lines (ngspice.limiting) for each unknown with edges, emitted first in the body."""
    if not edges:
        return
    values = {k: [em.value(e)[0] for e in es] for k, es in sorted(edges.items())}  # before the block: shared temps
    em.emit("if (x->limited < WRSIM_LIMITS && !(info->flags & WRSIM_ANALYSIS_AC)) {")
    for k, vs in values.items():
        em.emit(f"    double edge{k}[{len(vs)}] = {{{', '.join(vs)}}};")
        em.emit(f"    lim |= wrsim_limit(&v[{k}], x->last[{k}], x->older[{k}], edge{k}, {len(vs)});")
    em.emit("}")


_LOADERS = """\
static void *PFX_access(void *inst, void *model, uint32_t id, uint32_t flags) {
    PFX_inst *x = inst;
    (void)model;
    if (x == NULL || id >= NPARAMS) return NULL;
    if (flags & WRSIM_ACCESS_SET) x->given[id] = true;
    return &x->p[id];
}
static void PFX_setup_model(void *h, void *model, wrsim_osdi_sim_paras *sp, wrsim_osdi_init_info *res) {
    (void)h; (void)model; (void)sp;
    res->flags = 0; res->num_errors = 0; res->errors = NULL;
}
static void PFX_setup_instance(void *h, void *inst, void *model, double temperature, uint32_t nt,
                               wrsim_osdi_sim_paras *sp, wrsim_osdi_init_info *res) {
    PFX_inst *x = inst;
    (void)h; (void)model; (void)temperature; (void)nt; (void)sp;
    for (int k = 0; k < NPARAMS; k++) if (!x->given[k]) x->p[k] = PFX_default[k];
    x->reltol = 1e-3; x->abstol = 1e-12; x->vntol = 1e-6;
    for (int k = 0; k < NNODES; k++) x->older[k] = x->last[k] = NAN; /* no iterates yet: nothing to limit */
    for (size_t k = 0; k < sizeof x->held / sizeof x->held[0]; k++) x->held[k] = NAN; /* nor a step to keep */
    for (int k = 0; sp && sp->names && sp->names[k]; k++) {
        if (strcmp(sp->names[k], "reltol") == 0) x->reltol = sp->vals[k];
        if (strcmp(sp->names[k], "abstol") == 0) x->abstol = sp->vals[k];
        if (strcmp(sp->names[k], "vntol") == 0) x->vntol = sp->vals[k];
    }
    res->flags = 0; res->num_errors = 0; res->errors = NULL;
}
static void PFX_residual_resist(void *inst, void *model, double *dst) {
    PFX_inst *x = inst; (void)model;
    for (int k = 0; k < NNODES; k++) if (x->nm[k]) dst[x->nm[k]] += x->F[k];
}
static void PFX_residual_react(void *inst, void *model, double *dst) {
    PFX_inst *x = inst; (void)model;
    for (int k = 0; k < NNODES; k++) if (x->nm[k]) dst[x->nm[k]] += x->Q[k];
}
static void PFX_no_limit(void *inst, void *model, double *dst) { (void)inst; (void)model; (void)dst; }
/* The right-hand side of the linearisation at the values eval used (x->at: the iterate, or where Newton limiting
   put an unknown back), not at ngspice's iterate `prev`. */
static void PFX_rhs_dc(void *inst, void *model, double *dst, double *prev) {
    PFX_inst *x = inst; (void)model; (void)prev;
    for (int k = 0; k < NNODES; k++) if (x->nm[k]) dst[x->nm[k]] -= x->F[k];
    for (int k = 0; k < NENTRIES; k++) {
        uint32_t r = x->nm[PFX_row[k]], c = x->nm[PFX_col[k]];
        if (r && c) dst[r] += x->JF[k] * x->at[PFX_col[k]];
    }
}
static void PFX_rhs_tran(void *inst, void *model, double *dst, double *prev, double alpha) {
    PFX_inst *x = inst; (void)model; (void)prev;
    for (int k = 0; k < NNODES; k++) if (x->nm[k]) dst[x->nm[k]] -= x->F[k];
    for (int k = 0; k < NENTRIES; k++) {
        uint32_t r = x->nm[PFX_row[k]], c = x->nm[PFX_col[k]];
        if (r && c) dst[r] += (x->JF[k] + alpha * x->JQ[k]) * x->at[PFX_col[k]];
    }
}
static void PFX_jacobian_resist(void *inst, void *model) {
    PFX_inst *x = inst; (void)model;
    for (int k = 0; k < NENTRIES; k++)
        if (x->nm[PFX_row[k]] && x->nm[PFX_col[k]]) *x->jr[k] += x->JF[k];
}
static void PFX_jacobian_react(void *inst, void *model, double alpha) {
    PFX_inst *x = inst; (void)model;
    for (int k = 0; k < NENTRIES; k++)
        if (x->nm[PFX_row[k]] && x->nm[PFX_col[k]] && x->jq[k]) *x->jq[k] += alpha * x->JQ[k];
}
static void PFX_jacobian_tran(void *inst, void *model, double alpha) {
    PFX_inst *x = inst; (void)model;
    for (int k = 0; k < NENTRIES; k++)
        if (x->nm[PFX_row[k]] && x->nm[PFX_col[k]]) *x->jr[k] += x->JF[k] + alpha * x->JQ[k];
}
"""

_DESCRIPTOR = """\
#define PFX_descriptor { \\
    .name = "PFX", .num_nodes = NNODES, .num_terminals = NNODES, .nodes = PFX_nodes, \\
    .num_jacobian_entries = NENTRIES, .jacobian_entries = PFX_jac, \\
    .num_collapsible = 0, .collapsible = NULL, .collapsed_offset = offsetof(PFX_inst, collapsed), \\
    .noise_sources = NOISE_SOURCES, .num_noise_src = NNOISE, \\
    .num_params = NPARAMS, .num_instance_params = NPARAMS, .num_opvars = 0, .param_opvar = PFX_params, \\
    .node_mapping_offset = offsetof(PFX_inst, nm), .jacobian_ptr_resist_offset = offsetof(PFX_inst, jr), \\
    .num_states = 0, .state_idx_off = offsetof(PFX_inst, state), .bound_step_offset = WRSIM_OSDI_NONE, \\
    .instance_size = sizeof(PFX_inst), .model_size = sizeof(double), \\
    .access = PFX_access, .setup_model = PFX_setup_model, .setup_instance = PFX_setup_instance, \\
    .eval = PFX_eval, .load_noise = PFX_noise, \\
    .load_residual_resist = PFX_residual_resist, .load_residual_react = PFX_residual_react, \\
    .load_limit_rhs_resist = PFX_no_limit, .load_limit_rhs_react = PFX_no_limit, \\
    .load_spice_rhs_dc = PFX_rhs_dc, .load_spice_rhs_tran = PFX_rhs_tran, \\
    .load_jacobian_resist = PFX_jacobian_resist, .load_jacobian_react = PFX_jacobian_react, \\
    .load_jacobian_tran = PFX_jacobian_tran }
"""
