"""Mutation fuzzing of every user input path: VHDL-AMS files (lexer, parser, elaboration, lowering) and data files
(parameter sets and their includes, tolerance laws, measurement tables, raw test-stand curves, CAN DBC and ASC logs,
scenario files as `wrsim scenario` checks them, replay records).

A case is (file, seed): the seed picks the mutations, so a failing case is reproduced by its seed alone. A case
passes when the reader either succeeds or raises WrsimError; anything else (an uncaught exception, more than
`SECONDS` of CPU, more than `MEMORY` bytes) is a finding. `python tests/fuzz/fuzzer.py` runs many cases in worker
processes with those limits and prints the counts; tests/fuzz/test_fuzz.py runs a short budget in `make test`."""

from __future__ import annotations

import argparse
import functools
import importlib.util
import multiprocessing
import os
import random
import re
import resource
import signal
import subprocess
import sys
import tempfile
import time
import traceback
from collections import Counter
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

import wrsim
from wrsim import paths
from wrsim.benches.core import bench_params
from wrsim.data.can import decode_log, load_dbc
from wrsim.data.curves import read_characteristic, read_torque_angle
from wrsim.data.measurements import read_table
from wrsim.data.params import load_params
from wrsim.elab import Library
from wrsim.errors import WrsimError
from wrsim.frontend import parse_text

SECONDS = 10  # CPU seconds one case may take
MEMORY = 1 << 30  # bytes of address space a worker may grow by

# Literals and fragments that stress number conversion, widths, loops and recursion.
NASTY = [
    "1.0e999",
    "1e400",
    "10.0 ** 400",
    "1.0e-999",
    "37#1#",
    "2#102#",
    "16#_#",
    "16#FF_#",
    "2#" + "1" * 5000 + "#",
    "9" * 5000,
    "0.0",
    "0",
    "-1",
    "7.0",
    "1000000",
    "100000000",
    "2147483648",
    "nan",
    "inf",
    "open",
    "'1'",
    '"x"',
    "(" * 200 + "1.0" + ")" * 200,
    " + ".join(["1.0"] * 600),
    "real'high",
    "real'low",
    "x'dot'dot",
    "now",
    "std_logic_vector(1000000 downto 0)",
    "std_logic_vector(7.0 downto 0)",
    "f(open, 1.0)",
    "abs",
    "**",
    "--",
    "\x00",
    "\ufeff",
    "é",
    "/*",
    "*/",
    "#",
    "\\",
    "''",
    "'",
    '"',
    ";",
    "(",
    ")",
    "=>",
    ":=",
    "<=",
    "==",
]
NUMBERS = [
    "0",
    "0.0",
    "-1",
    "-1.0",
    "1",
    "7.0",
    "1.0e-300",
    "1.0e300",
    "1.0e308",
    "2147483648",
    "100000",
    "10000000",
    "1.5",
    "(0.0 / 0.0)",
    "(1.0e300 * 1.0e300)",
    "(10.0 ** 400)",
    "(2 ** 80)",
    "real'high",
]
WORD = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|\d[\d._#eE+-]*|\S")
NUMBER = re.compile(r"(?<![A-Za-z_])\d[\d_]*(\.\d[\d_]*)?([eE][+-]?\d+)?")
IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def mutate(text: str, rng: random.Random, rounds: int | None = None) -> str:
    """`text` with 1-4 random edits: half of them lexical (a nasty fragment in place of a token, a token deleted,
    duplicated or swapped with another, a line deleted or duplicated, a byte flipped, a cut), half aimed at a
    construct of VHDL-AMS (CONSTRUCTS: time literals, waits, delays, breaks, attributes, processes); a construct
    edit that finds nothing to change falls back to a lexical one."""
    for _ in range(rounds or rng.randint(1, 4)):
        edited = rng.choice(CONSTRUCTS)(text, rng) if rng.random() < 0.5 else None
        text = edited if edited is not None else _lexical(text, rng)
    return text


def _lexical(text: str, rng: random.Random) -> str:
    tokens = [m.span() for m in WORD.finditer(text)] or [(0, 0)]
    a, b = tokens[rng.randrange(len(tokens))]
    kind = rng.randrange(11)
    numbers = [m.span() for m in NUMBER.finditer(text)]
    names = [m.span() for m in IDENT.finditer(text)]
    if kind in (8, 9) and numbers:  # a number in the model's own context: overflow, zero, width
        a, b = numbers[rng.randrange(len(numbers))]
        return text[:a] + rng.choice(NUMBERS) + text[b:]
    if kind == 10 and names:  # a name in place of another: types, natures, kinds of binding
        a, b = names[rng.randrange(len(names))]
        c, d = names[rng.randrange(len(names))]
        return text[:a] + text[c:d] + text[b:]
    if kind == 0:
        return text[:a] + rng.choice(NASTY) + text[b:]
    if kind == 1:
        return text[:a] + text[b:]
    if kind == 2:
        c, d = tokens[rng.randrange(len(tokens))]
        return text[:a] + text[c:d] + text[b:]
    if kind == 3:
        return text[:b] + " " + text[a:b] + text[b:]
    if kind in (4, 5):
        lines = text.split("\n")
        k = rng.randrange(len(lines))
        lines[k : k + 1] = [] if kind == 4 else [lines[k], lines[k]]
        return "\n".join(lines)
    if kind == 6 and text:
        k = rng.randrange(len(text))
        return text[:k] + chr(rng.randrange(32, 127)) + text[k + 1 :]
    return text[: rng.randrange(len(text) + 1)]


# ------------------------------------------------------------------------------------------------ construct edits
# Each takes the text and the generator and returns the edited text, or None when the text has no such construct.
TIMES = [
    "0 ns",
    "1 fs",
    "1fs",
    "10ms",
    "0.5 fs",
    "1.0e-300 sec",
    "1.0e300 sec",
    "-1 ms",
    "1 hr",
    "time'high",
    "time'low",
    "time'val(1)",
    "now",
    "(1 ms / 0)",
    "(1 ms * 1.0e300)",
    "(1 sec / 1.0e300)",
    "(now / 2.0)",
    "1 ms / 2",
]
ATTRIBUTES = [
    "'dot",
    "'dot'dot'dot",
    "'integ",
    "'integ'integ",
    "'above(0.0)",
    "'above(1.0e300)",
    "'above(now)",
    "'delayed(1.0e-300)",
    "'delayed(0.0)",
    "'delayed(-1.0)",
    "'ltf((0 => 1.0), (1.0, 1.0e-300))",
    "'ltf((0 => 1.0), (1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0))",
    "'ltf((0 => 1.0), (0 => 0.0))",
    "'ztf((0 => 1.0), (1.0, 0.5), 1.0e-300)",
    "'ztf((0 => 1.0), (1.0, 0.5), 1.0e-3, -1.0)",
    "'zoh(1.0e-300)",
    "'zoh(0.0)",
    "'zoh(1.0e-3, 1.0e300)",
    "'slew(0.0)",
    "'slew(1.0e300, -1.0e-300)",
    "'ramp(0.0)",
    "'ramp(-1.0)",
    "'event",
    "'last_value",
    "'stable",
    "'stable(1 ms)",
    "'length",
    "'high",
    "'pos(now)",
    "'tolerance",
    "'reference",
    "'across",
    "'through",
    "'contribution",
]
WAITS = [
    "wait;",
    "wait for {time};",
    "wait on {signal};",
    "wait on {signal} for {time};",
    "wait until {signal} = {signal};",
    "wait until {quantity}'above({number});",
    "wait until {quantity}'above({number}) for {time};",
    "wait until false;",
    "if {quantity}'above(0.0) then wait for {time}; end if;",
    "for k in 1 to {number} loop wait for {time}; end loop;",
]
CONCURRENT = [
    "break {quantity} => {number};",
    "break {quantity}'dot => {number};",
    "break on {signal};",
    "break when {quantity}'above({number});",
    "break {quantity} => -{quantity} when not {quantity}'above({number});",
    "break {quantity} => {number} on {signal} when {quantity}'above(0.0);",
    "break for {quantity} use {quantity} => 0.0;",
    "{signal} <= not {signal} after {time};",
    "{signal} <= {signal} after {time} when {quantity}'above({number}) else {signal};",
    "fz: process begin {signal} <= {signal}; wait for {time}; end process fz;",
    "fz: process ({signal}) begin {signal} <= {signal} after {time}; end process fz;",
    "fz: process (all) begin {signal} <= {signal}; end process fz;",
    "fz: process begin wait until {quantity}'above({number}); {signal} <= {signal} after {time}; end process fz;",
    "fq: {quantity} == {quantity}'zoh({number});",
    "fq: {quantity}'dot == {quantity};",
]
PROCESS = re.compile(r"\bprocess\b.*?\bend\s+process\b", re.S | re.I)
ASSIGN = re.compile(r"<=\s*(?:transport\s+|inertial\s+)?([^;]*?)(\s+after\s+[^;,]*)?;", re.S)
TIME_LITERAL = re.compile(r"\b\d[\d_.eE+-]*\s*(?:fs|ps|ns|us|ms|sec|min|hr)\b", re.I)
ATTRIBUTE = re.compile(r"'[A-Za-z_]\w*(?:\([^()]*\))?")
DECLARED = re.compile(r"\b(signal|quantity)\s+([A-Za-z_]\w*(?:\s*,\s*[A-Za-z_]\w*)*)\s*:", re.I)


def _fill(template: str, text: str, rng: random.Random) -> str:
    """`template` with {signal}, {quantity} from the text's declarations (or any name), {time}, {number}."""
    names: dict[str, list[str]] = {"signal": [], "quantity": []}
    for kind, listed in DECLARED.findall(text):
        names[kind.lower()] += [n.strip() for n in listed.split(",")]
    anyname = IDENT.findall(text) or ["x"]
    return re.sub(
        r"\{(\w+)\}",
        lambda m: rng.choice(TIMES if m[1] == "time" else NUMBERS if m[1] == "number" else names.get(m[1]) or anyname),
        template,
    )


def _time_literal(text: str, rng: random.Random) -> str | None:
    spans = [m.span() for m in TIME_LITERAL.finditer(text)]
    if not spans:
        return None
    a, b = rng.choice(spans)
    return text[:a] + rng.choice(TIMES) + text[b:]


def _wait(text: str, rng: random.Random) -> str | None:
    """A wait of any kind inserted after a statement of a process, or a wait there replaced."""
    bodies = [m.span() for m in PROCESS.finditer(text)]
    if not bodies:
        return None
    a, b = rng.choice(bodies)
    ends = [a + m.end() for m in re.finditer(";", text[a:b])] or [b]
    k = rng.choice(ends)
    wait = _fill(rng.choice(WAITS), text, rng)
    old = re.compile(r"\s*wait\b[^;]*;", re.I).match(text, k)
    return text[:k] + " " + wait + (text[old.end() :] if old and rng.random() < 0.5 else text[k:])


def _delay(text: str, rng: random.Random) -> str | None:
    """A signal assignment's delay mechanism, delay or waveform changed."""
    found = list(ASSIGN.finditer(text))
    if not found:
        return None
    m = rng.choice(found)
    value, time_ = m[1], rng.choice(TIMES)
    form = rng.choice(
        [
            f"<= {value} after {time_};",
            f"<= transport {value} after {time_};",
            f"<= inertial {value} after {time_};",
            f"<= reject {rng.choice(TIMES)} inertial {value} after {time_};",
            f"<= {value}, {value} after {time_};",
            f"<= transport {value} after {time_}, {value} after {rng.choice(TIMES)};",
            f"<= {value} after {time_} when {value} = {value} else {value};",
            "<= unaffected;",
        ]
    )
    return text[: m.start()] + form + text[m.end() :]


def _concurrent(text: str, rng: random.Random) -> str | None:
    """A break, a process or a simultaneous statement added to an architecture's statements."""
    ends = [m.start() for m in re.finditer(r"\bend\s+architecture\b", text, re.I)]
    if not ends:
        return None
    k = rng.choice(ends)
    return text[:k] + "  " + _fill(rng.choice(CONCURRENT), text, rng) + "\n" + text[k:]


def _attribute(text: str, rng: random.Random) -> str | None:
    """An attribute replaced by another, or one appended to a quantity's or signal's name."""
    spans = [m.span() for m in ATTRIBUTE.finditer(text)]
    if spans and rng.random() < 0.6:
        a, b = rng.choice(spans)
        return text[:a] + rng.choice(ATTRIBUTES) + text[b:]
    name = _fill(rng.choice(["{quantity}", "{signal}"]), text, rng)
    uses = [m.end() for m in re.finditer(rf"\b{re.escape(name)}\b", text)]
    if not uses:
        return None
    k = rng.choice(uses)
    return text[:k] + rng.choice(ATTRIBUTES) + text[k:]


def _sensitivity(text: str, rng: random.Random) -> str | None:
    """A process's sensitivity list replaced: all, empty of signals, a quantity, every declared signal."""
    lists = [m.span(1) for m in re.finditer(r"\bprocess\s*\(([^)]*)\)", text, re.I)]
    if not lists:
        return None
    a, b = rng.choice(lists)
    return (
        text[:a]
        + _fill(rng.choice(["all", "{quantity}", "{signal}, {signal}", "{quantity}'above(0.0)"]), text, rng)
        + text[b:]
    )


CONSTRUCTS: list[Callable[[str, random.Random], str | None]] = [
    _time_literal,
    _wait,
    _delay,
    _concurrent,
    _attribute,
    _sensitivity,
]


# ------------------------------------------------------------------------------------------------ VHDL-AMS
CORPUS = paths.ROOT / "tests" / "corpus"


@functools.cache
def project() -> tuple[dict[Path, str], Library, dict[str, str]]:
    """The library's files and their text, the parsed library, and for each design unit a bench entity that
    elaborates it (a testbench elaborates itself)."""
    files = sorted(p for root in paths.LIBRARY for p in root.rglob("*.vhd"))
    lib = wrsim.load_library()
    bench_of: dict[str, str] = {}
    for bench in wrsim.BENCHES.values():
        design = wrsim.elaborate(lib, bench.entity, bench_params(bench), _overrides(bench))
        stack = [design.tree]
        while stack:
            node = stack.pop()
            bench_of.setdefault(node.entity, bench.entity)
            stack.extend(node.children)
    files += sorted(CORPUS.rglob("*.vhd"))  # the models users bring: every construct of the subset
    return {p: p.read_text(encoding="utf-8") for p in files}, lib, bench_of


def _lower_alone(design_file, top: str) -> None:
    """Elaborate and lower the testbench `top` of `design_file` against the IEEE packages alone, as `wrsim run`."""
    alone = Library()
    for f in project()[1].files:
        if Path(f.path).parent.name == "ieee":
            alone.add(f)
    alone.add(design_file)
    wrsim.lower(wrsim.elaborate(alone, top), wrsim.Analysis(stop=1e-3, max_step=1e-5), top)


def _overrides(bench) -> dict:
    return {k: v for k, v in bench.runs[0].generics.items() if not callable(v)} if bench.runs else {}


def vhdl_case(path: Path, seed: int) -> None:
    """Mutate `path`, put it in place of the original in the library, and elaborate and lower the bench that uses
    it (or every bench's first entity for a package). Raises what the pipeline raises."""
    texts, lib, bench_of = project()
    text = mutate(texts[path], random.Random(seed))
    design_file = parse_text(text, str(path), "ieee" if path.parent.name == "ieee" else "work")
    if CORPUS in path.parents:  # a corpus model: its own testbench against the IEEE packages
        _lower_alone(design_file, path.stem)
        return
    own = [u.name for u in design_file.units if hasattr(u, "name")]
    mutated = Library()
    for f in lib.files:
        mutated.add(design_file if f.path == str(path) else f)
    entity = next((bench_of[n] for n in own if n in bench_of), "tb_stroke")
    bench = next((b for b in wrsim.BENCHES.values() if b.entity == entity), None)
    params = bench_params(bench) if bench else None
    design = wrsim.elaborate(mutated, entity, params, _overrides(bench) if bench else {})
    wrsim.lower(design, wrsim.Analysis(stop=1.0, max_step=1e-3), entity)


# ------------------------------------------------------------------------------------------------ data files
@functools.cache
def data_files() -> dict[Path, Callable[[Path], object]]:
    """Every data file a user hands wrsim, with its reader. Raw test-stand curves are written once from the
    synthetic stand."""
    from wrsim.identify.synthetic import Truth, write_group

    raw = Path(tempfile.mkdtemp(prefix="wrsim-fuzz-raw-"))
    group = write_group(raw, Truth.from_params(load_params(paths.PARAMS / "fpg2_12nm.txt")), count=1, seed=0)
    out: dict[Path, Callable[[Path], object]] = {p: load_params for p in sorted(paths.PARAMS.glob("*.txt"))}
    out.update({p: _sampled for p in sorted((paths.PARAMS / "tolerances").glob("*.txt"))})
    out.update({p: lambda q: read_table(q, require_source=True) for p in sorted(paths.MEASUREMENTS.glob("*.csv"))})
    out.update({group["motor"][0]: read_characteristic, group["damper"][0]: read_torque_angle})
    out.update({p: load_dbc for p in sorted(paths.CAN.glob("*.dbc"))})
    out.update({p: decode_log for p in sorted(paths.CAN.glob("*.asc"))})
    out.update({p: _scenario for p in sorted(paths.SCENARIOS.rglob("*.toml"))[::4]})  # a quarter: 40-odd files
    out.update({p: _record for p in sorted((paths.ROOT / "tests" / "fixtures" / "records").rglob("no_obstacle*.txt"))})
    return out


def _scenario(path: Path) -> object:
    """A scenario file as `wrsim scenario` checks it before anything runs: the file, then its run's sets."""
    from wrsim.benches.scenario import check_runs, load_scenario, scenario_params
    from wrsim.elab.library import load_library

    s = load_scenario(path)
    check_runs(load_library(paths.LIBRARY), [s], scenario_params())
    return s


def _record(path: Path) -> object:
    """An input record as `wrsim replay` checks it (wrsim.benches.replay.read_inputs)."""
    from wrsim.benches.replay import read_inputs

    return read_inputs(path, path.with_suffix(".checked"))


# Structural operators of the data files, beside `mutate`'s lexical ones: the constructs of each format a user can
# nest, chain or repeat (one is applied to half of the cases of its kind)
LAWS = ["normal", "uniform", "3sigma", "1e-300sigma", "0.1sigma", "1e300sigma", "calibrate", "group g", "group g 2"]


def _structural(path: Path, text: str, rng: random.Random) -> str:
    lines = text.splitlines()
    k = rng.randrange(len(lines) + 1)
    if path.suffix == ".toml":
        depth = rng.choice([2, 31, 33, 3000])
        pick = rng.choice(
            [
                f"x = {'[' * depth}1{']' * depth}",
                "[generics]\nsequence_file = 'x.txt'",
                f"[solver]\nmax_step = {rng.choice(['1e300', '0.0', '1e-400', '-1.0'])}",
                f"[ambient]\ntemperature = '{rng.choice(['500 degC', '-273.15 degC', '1e400 K', '85 degC'])}'",
                f"params = [{rng.choice(['.', '..', '/', 'x' * 300, ''])!r}]",
                f"stop = {rng.choice(['2147.0', '2148.0', '1e-300', '1e308'])}",
            ]
        )
        return "\n".join([*lines[:k], pick, *lines[k:]])
    if "tolerances" in path.parts:  # a tolerance line's law words, repeated and mixed
        rows = [i for i, line in enumerate(lines) if "+-" in line or " in " in line]
        if rows:
            i = rng.choice(rows)
            lines[i] = lines[i].split("#")[0] + " " + " ".join(rng.choices(LAWS, k=rng.randint(1, 3)))
        return "\n".join(lines)
    if path.suffix == ".txt" and path.parent == paths.PARAMS:  # includes: itself, a chain, a folder
        pick = rng.choice([f"include {path.name}", "include .", "include ..", "include /dev/null", "include x" * 40])
        return "\n".join([*lines[:k], pick, *lines[k:]])
    if path.name.startswith("no_obstacle"):  # equal times, repeated lines
        body = [i for i, line in enumerate(lines) if line and not line.startswith("#")]
        if body:
            i = rng.choice(body)
            lines[i + 1 : i + 1] = [lines[i]] * rng.choice([1, 12, 1000])
        return "\n".join(lines)
    return text


def _sampled(path: Path) -> object:
    """A set of spreads laid over the system set, one sample drawn and set to its temperature (wrsim study)."""
    from wrsim.data.temperature import at_temperature
    from wrsim.study import draw, factors, sample_set

    pset = load_params(paths.PARAMS / "rail_wr_8p5nm.txt").overlay(load_params(path), user=True)
    fs = factors(pset)
    return at_temperature(sample_set(pset, draw(fs, 1, 0), "fuzz"))


def data_mutant(path: Path, seed: int) -> str:
    """The data file `path` mutated for `seed`: a structural operator for half of the seeds, else lexical ones."""
    rng = random.Random(seed)
    text = path.read_text(encoding="utf-8")
    return _structural(path, text, rng) if rng.random() < 0.5 else mutate(text, rng)


def data_case(path: Path, seed: int) -> None:
    """Mutate the data file `path` into a temporary file of the same name and read it."""
    reader = data_files()[path]
    text = data_mutant(path, seed)
    with tempfile.TemporaryDirectory(prefix="wrsim-fuzz-") as tmp:
        copy = Path(tmp) / path.name
        copy.write_text(text, encoding="utf-8", errors="surrogateescape")
        reader(copy)


# ------------------------------------------------------------------------------------------------ end to end
RUN_BOUND = 120.0  # [s] the wall time `wrsim run` of a mutant may take (its --timeout): reaching it is a finding


@functools.cache
def corpus_runs() -> dict[Path, tuple[float, float]]:
    """Each corpus model's stop time and largest step, from tests/unit/test_corpus.py's cases."""
    sys.path.insert(0, str(paths.ROOT / "tests"))  # its conftest
    spec = importlib.util.spec_from_file_location("corpus_cases", paths.ROOT / "tests" / "unit" / "test_corpus.py")
    assert spec and spec.loader
    module = sys.modules.setdefault(spec.name, importlib.util.module_from_spec(spec))
    spec.loader.exec_module(module)
    return {CORPUS / c.file: (c.stop, c.max_step) for c in reversed(module.CASES)}


def accepted_mutant(path: Path, seed: int) -> str | None:
    """The mutant of corpus model `path` for `seed` when the front-end, elaboration and lowering accept it."""
    text = mutate(project()[0][path], random.Random(seed))
    try:
        _lower_alone(parse_text(text, str(path), "work"), path.stem)
    except WrsimError:
        return None
    return text


def _session(cmd: list[str], case: str, codes: tuple[int, ...]) -> tuple[Finding | None, int, str]:
    """Run the wrsim command `cmd` in its own session: it must end within RUN_BOUND (and a minute) with an exit
    status in `codes`, no traceback, and no process of its session left. The finding (None), the exit status and
    its standard output."""
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    try:
        out, err = proc.communicate(timeout=RUN_BOUND + 60.0)
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.communicate()
        return Finding("bound", case, f"wrsim {cmd[1]} did not end within {RUN_BOUND + 60.0:.0f} s"), -9, ""
    try:
        os.killpg(proc.pid, signal.SIGKILL)  # anything left of the session is a finding
        return Finding("orphan", case, f"a process of wrsim {cmd[1]} outlived it"), proc.returncode, out
    except ProcessLookupError:
        pass
    if "did not finish within" in err:
        return Finding("bound", case, err.strip().splitlines()[0][:200]), proc.returncode, out
    if proc.returncode not in codes or "Traceback" in err:
        last = (err.strip().splitlines() or [f"exit status {proc.returncode}"])[-1][:200]
        return Finding("traceback", case, last), proc.returncode, out
    return None, proc.returncode, out


def run_mutant(path: Path, seed: int, text: str) -> tuple[Finding | None, int]:
    """`wrsim run` of an accepted mutant to its corpus stop time: a result or one error (exit 2), as _session
    judges it. Returns the finding (None) and the exit status."""
    stop, max_step = corpus_runs()[path]
    with tempfile.TemporaryDirectory(prefix="wrsim-fuzz-run-") as tmp:
        model = Path(tmp) / path.name
        model.write_text(text, encoding="utf-8")
        cmd = [str(Path(sys.executable).with_name("wrsim")), "run", str(model), "--top", path.stem, "--stop"]
        cmd += [repr(stop), "--max-step", repr(max_step), "--timeout", repr(RUN_BOUND), "--results", tmp]
        found, code, _ = _session(cmd, f"run {path} {seed}", (0, 2))
    return found, code


def _end_to_end(
    files: list[Path],
    accept: Callable[[Path, int], str | None],
    run: Callable[[Path, int, str], tuple[Finding | None, int]],
    count: int,
    first_seed: int,
    workers: int,
) -> tuple[list[Finding], Counter[int], int]:
    """`count` mutants that `accept` lets through (the file for a seed: files[seed * 7919 mod len], spread over the
    folders) run by `run`, `workers` at a time: the findings, the exit statuses and the seeds tried."""
    accepted: list[tuple[Path, int, str]] = []
    seed = first_seed
    while len(accepted) < count:
        path = files[(seed * 7919) % len(files)]
        text = accept(path, seed)
        if text is not None:
            accepted.append((path, seed, text))
        seed += 1
    findings: list[Finding] = []
    status: Counter[int] = Counter()
    with ThreadPoolExecutor(workers) as pool:
        for found, code in pool.map(lambda job: run(*job), accepted):
            status[code] += 1
            if found:
                findings.append(found)
                print(f"{found.kind}: {found.case}: {found.detail}", flush=True)
    return findings, status, seed - first_seed


def run_mutants(count: int, first_seed: int, workers: int) -> list[Finding]:
    """`count` accepted mutants of the corpus models run end to end, `workers` at a time."""
    files = sorted(corpus_runs())
    findings, status, tried = _end_to_end(files, accepted_mutant, run_mutant, count, first_seed, workers)
    print(
        f"{count} accepted mutants of {tried} run end to end: {status[0]} results, {status[2]} errors",
        file=sys.stderr,
    )
    return findings


def accepted_scenario(path: Path, seed: int) -> str | None:
    """The mutant of scenario file `path` for `seed` (data_case's mutation) when `wrsim scenario`'s check before
    anything runs accepts it."""
    text = data_mutant(path, seed)
    with tempfile.TemporaryDirectory(prefix="wrsim-fuzz-") as tmp:
        copy = Path(tmp) / path.name
        copy.write_text(text, encoding="utf-8", errors="surrogateescape")
        try:
            _scenario(copy)
        except Exception:  # noqa: BLE001 - refused (or an internal error, which the data cases report)
            return None
    return text


def run_scenario(path: Path, seed: int, text: str) -> tuple[Finding | None, int]:
    """`wrsim scenario` of an accepted scenario mutant: verdicts (exit 0 or 1) with no ERROR row, since the check
    before the run found nothing (an ERROR is a *late* error: one the check should have found), or one error
    (exit 2), as _session judges it."""
    case = f"scenario {path.relative_to(paths.ROOT)} {seed}"
    with tempfile.TemporaryDirectory(prefix="wrsim-fuzz-scenario-") as tmp:
        copy = Path(tmp) / path.name
        copy.write_text(text, encoding="utf-8", errors="surrogateescape")
        cmd = [str(Path(sys.executable).with_name("wrsim")), "scenario", str(copy), "--results", tmp]
        found, code, out = _session(cmd, case, (0, 1, 2))
    late = [line for line in out.splitlines() if line.split()[1:2] == ["ERROR"]]
    if found is None and late:
        found = Finding("late", case, late[0][:200])
    return found, code


def run_scenarios(count: int, first_seed: int, workers: int) -> list[Finding]:
    """`count` accepted mutants of the repository's scenario files run end to end, `workers` at a time."""
    files = sorted(paths.SCENARIOS.rglob("*.toml"))
    findings, status, tried = _end_to_end(files, accepted_scenario, run_scenario, count, first_seed, workers)
    print(
        f"{count} accepted scenario mutants of {tried} run end to end: {status[0] + status[1]} with verdicts, "
        f"{status[2]} errors, {sum(f.kind == 'late' for f in findings)} late errors",
        file=sys.stderr,
    )
    return findings


# ------------------------------------------------------------------------------------------------ driver
@dataclass(frozen=True)
class Finding:
    kind: str  # "traceback", "timeout", "memory"; end to end: "bound", "orphan", "late" (a scenario's run-time error)
    case: str  # vhdl|data, file, seed
    detail: str  # exception type and the innermost frame


def _limits() -> None:
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    usage = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    resource.setrlimit(resource.RLIMIT_AS, (usage + MEMORY, hard))
    signal.signal(signal.SIGPROF, _cpu_exceeded)


def _cpu_exceeded(signum, frame):
    raise TimeoutError(f"more than {SECONDS} s of CPU")


def run_case(job: tuple[str, str, int]) -> Finding | None:
    kind, name, seed = job
    case = vhdl_case if kind == "vhdl" else data_case
    signal.setitimer(signal.ITIMER_PROF, SECONDS)  # CPU time of this case, user and system
    try:
        case(Path(name), seed)
    except WrsimError:
        return None
    except TimeoutError as e:
        return Finding("timeout", f"{kind} {name} {seed}", str(e))
    except MemoryError:
        return Finding("memory", f"{kind} {name} {seed}", "MemoryError")
    except BaseException as e:  # noqa: BLE001 - every other exception is the finding
        frame = traceback.extract_tb(e.__traceback__)[-1]
        return Finding(
            "traceback",
            f"{kind} {name} {seed}",
            f"{type(e).__name__} at {Path(frame.filename).name}:{frame.lineno}: {str(e)[:120]}",
        )
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
    return None


def jobs(kind: str, count: int, first_seed: int = 0) -> list[tuple[str, str, int]]:
    files = list(project()[0]) if kind == "vhdl" else list(data_files())
    return [(kind, str(files[k % len(files)]), first_seed + k) for k in range(count)]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--vhdl", type=int, default=100_000, help="mutated VHDL-AMS cases")
    ap.add_argument("--data", type=int, default=20_000, help="mutated data-file cases")
    ap.add_argument("--run", type=int, default=200, help="accepted corpus mutants run end to end by `wrsim run`")
    ap.add_argument("--scenarios", type=int, default=40, help="accepted scenario mutants run by `wrsim scenario`")
    ap.add_argument("--seed", type=int, default=0, help="first seed")
    ap.add_argument("--workers", type=int, default=None)
    args = ap.parse_args(argv)
    t0 = time.perf_counter()
    work = jobs("vhdl", args.vhdl, args.seed) + jobs("data", args.data, args.seed)
    findings: list[Finding] = []
    with multiprocessing.get_context("fork").Pool(args.workers, initializer=_limits, maxtasksperchild=500) as pool:
        for k, found in enumerate(pool.imap_unordered(run_case, work, chunksize=20), start=1):
            if found:
                findings.append(found)
                print(f"{found.kind}: {found.case}: {found.detail}", flush=True)
            if k % 5000 == 0:
                print(f"{k} cases, {len(findings)} findings, {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    findings += run_mutants(args.run, args.seed, args.workers or os.cpu_count() or 1) if args.run else []
    findings += run_scenarios(args.scenarios, args.seed, args.workers or os.cpu_count() or 1) if args.scenarios else []
    counts = Counter(f.kind for f in findings)
    print(
        f"fuzz: {args.vhdl} VHDL-AMS, {args.data} data-file, {args.run} end-to-end and {args.scenarios} scenario "
        f"cases in {time.perf_counter() - t0:.0f} s: {counts['traceback']} tracebacks, "
        f"{counts['timeout']} over {SECONDS} s, "
        f"{counts['memory']} over {MEMORY >> 20} MB, {counts['bound']} runs over {RUN_BOUND:.0f} s, "
        f"{counts['orphan']} left processes, {counts['late']} late errors"
    )
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
