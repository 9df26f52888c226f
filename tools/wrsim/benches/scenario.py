"""Scenario files: closed-loop cases of the window-regulator system (testbenches/tb_closed_loop.vhd) as users write
them, in TOML (docs/scenarios.md): the parameter sets, how the run starts, the supply, the switch commands (glass
heights in metres of glass position), an obstacle, disturbances, the ambient temperature and what is expected.
`load_scenario` validates a file (errors name file:line), `scenario_run` makes it a bench run; `run_scenarios` runs
many side by side and publishes a page per scenario and a summary."""

from __future__ import annotations

import dataclasses
import functools
import re
import sys
import tomllib
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

from wrsim import paths
from wrsim.benches.core import Run, bench_params
from wrsim.data.params import Param, ParamSet, find_param_set, load_params
from wrsim.elab.generics import GenericValue, number
from wrsim.elab.library import Library
from wrsim.errors import WrsimError

__all__ = [
    "Scenario",
    "Command",
    "Learning",
    "load_scenario",
    "find_scenarios",
    "load_scenarios",
    "scenario_params",
    "own_sets",
    "scenario_run",
    "extra_generics",
    "write_sequence",
    "with_ecu",
    "concept_over",
    "check_ecu",
    "check_runs",
    "ECUS",
    "unit_table",
    "TESTBENCH",
    "SYSTEM_PARAMS",
    "RELTOL",
    "MAX_STEP",
]

TESTBENCH = "tb_closed_loop"  # the closed-loop system every scenario runs
SYSTEM_PARAMS = "rail_wr_8p5nm"  # its parameter set (the testbench header names it)
RELTOL = 1e-3  # ngspice's relative tolerance of every closed-loop run (why: benches.closed_loop's docstring)
MAX_STEP = 1e-3  # [s] ngspice's largest step of every closed-loop run
NOMINAL_V = 13.0  # [V] tb_closed_loop's u_nominal default
# The ECU concepts: name -> tb_closed_loop's generic `ecu_kind` and the set laid beneath a run's own (None: none)
ECUS: dict[str, tuple[int, Path | None]] = {"relay": (0, None), "pwm": (1, paths.ECUS / "pwm.txt")}

# section -> key -> (the testbench generic it sets, the unit of a bare number: the unit of the generic's subtype in
# testbenches/tb_closed_loop.vhd, checked by a test), or None: a key this module handles itself
_KEYS: dict[str, dict[str, tuple[str, str] | None]] = {
    "": {"purpose": None, "params": None, "stop": None, "ecu": None},
    "start": {"state": None, "glass": None},
    "supply": {"nominal": ("u_nominal", "V")},
    "switch": {"sequence": None, "units": None},
    "obstacle": {
        "stiffness": ("gauge_stiffness", "N/m"),
        "gap": None,
        "position": ("pinch_position", "m"),
        "travel": ("gauge_travel", "m"),
        "insert": ("gauge_insert", "s"),
    },
    "disturbance": {
        "road_accel": ("road_accel", "m/s**2"),
        "road_frequency": ("road_frequency", "Hz"),
        "road_band_high": ("road_band_high", "Hz"),
        "road_lines": ("road_lines", "1"),
        "road_seed": ("road_seed", "1"),
        "seal_change": ("seal_change", "N"),
        "on": ("disturbance_on", "s"),
    },
    "ambient": {"temperature": None},
    "generics": {},  # any top-level generic of the testbench, as `--set` writes it
    "solver": {"reltol": None, "max_step": None},
    "expect": {
        "closings": None,
        "reversal": None,
        "reopening": None,
        "peak_max": None,
        "glass": None,
        "glass_tolerance": None,
    },
}
# testbench generics a scenario's other keys set: [generics] may not give them
_OWNED = {
    "sequence_file": "written from [switch] (give [switch] sequence = the file)",
    "ecu_kind": "the ECU concept: give ecu = 'relay' or 'pwm'",
    "learned_file": "a warm start's learned state: [start] state = 'warm'",
    "start_position": "a warm start's counter: [start] glass",
    "glass_start": "a warm start's glass height: [start] glass",
}
_WARM_KEYS = ("learned_file", "start_position", "glass_start")  # set by a warm start only
_UNIT_KEYS = {"t": ("at", "command", "supply"), "p": ("glass", "supply", "timeout")}
_COMMANDS = {"stop": 0, "up": 1, "down": 2, "one-touch": 3}  # the switch's commands (3: one-touch up)


@dataclass(frozen=True)
class Command:
    """One switch unit: at a time (`at` [s]) a command, or a move of the glass to a height (`glass` [m]); the
    supply while it runs [V] (None: nominal); `timeout` [s] of a move; where it was written."""

    at: float | None
    command: int
    glass: float | None
    supply: float | None
    timeout: float
    where: str


@dataclass(frozen=True)
class Scenario:
    """A validated scenario file."""

    name: str  # the file's stem
    file: Path
    purpose: str
    ecu: str  # the ECU concept (ECUS): "relay", the thesis's, or "pwm"
    stop: float  # [s]
    params: tuple[Path, ...]  # parameter sets laid over the testbench's, in order
    warm: bool  # start normalized (a learned state from a normalization run)
    glass0: float  # [m] glass position at t = 0 (warm starts)
    sequence: Path | None  # a switch-sequence file as it is ...
    commands: tuple[Command, ...]  # ... or the units to write one from
    values: dict[str, float]  # testbench generics of the sections, in the generics' units
    generics: dict[str, GenericValue]  # [generics]: further testbench generics as written (elab.generics)
    gap: float | None  # [m] obstacle: gap below the top-frame sealing
    ambient: Param | None  # [ambient] temperature as a parameter
    reltol: float
    max_step: float
    closings: int | None  # expected runs up after the normalization (None: any)
    reversal: bool | None  # every closing reverses (True) or none does (False)
    reopening: bool | None  # every reversal reopens as FMVSS 118 S5(b) asks (None: judged with the PWM ECU only)
    peak_max: float | None  # [N] largest peak force of a closing
    glass_end: float | None  # [m] glass position at the end
    glass_tolerance: float  # [m]
    where: dict[str, str] = field(default_factory=dict)  # key -> "file:line" for errors found later


def unit_table() -> dict[str, str]:
    """Testbench generic -> the unit a bare number of its scenario key is in."""
    return {t[0]: t[1] for keys in _KEYS.values() for t in keys.values() if t}


def find_scenarios(targets: Sequence[str | Path]) -> list[Path]:
    """The scenario files named: files, or every *.toml in a folder and its subfolders (sorted); one error for a
    missing one."""
    out: list[Path] = []
    for t in targets:
        p = Path(t)
        if p.is_dir():
            found = sorted(p.rglob("*.toml"))
            if not found:
                raise WrsimError(f"{p}: no scenario files (*.toml) in this folder")
            out += found
        elif p.is_file():
            out.append(p)
        else:
            raise WrsimError(f"{p}: no such scenario file or folder")
    names = [p.stem for p in out]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise WrsimError(f"two scenarios are named {twice[0]} (the file's stem names its results)")
    return out


def load_scenarios(targets: Sequence[str | Path], ecu: str | None = None) -> list[Scenario]:
    """Every scenario file `targets` names (find_scenarios), each checked before any runs; with `ecu`, each run with
    that ECU concept (ECUS) instead of its own."""
    loaded = [load_scenario(f) for f in find_scenarios(targets)]
    return loaded if ecu is None else [dataclasses.replace(one, ecu=ecu) for one in loaded]


def _lines(text: str) -> dict[str, int]:
    """'section.key' -> line of its first assignment (TOML as scenario files use it: tables, arrays of tables,
    `key = value` lines)."""
    out: dict[str, int] = {}
    section = ""
    for n, raw in enumerate(text.splitlines(), start=1):
        line = raw.split("#", 1)[0].strip()
        m = re.match(r"\[\[?\s*([A-Za-z0-9_.]+)\s*\]\]?$", line)
        if m:
            section = m.group(1)
            out.setdefault(section, n)
            continue
        m = re.match(r"([A-Za-z0-9_]+)\s*=", line)
        if m:
            out.setdefault(f"{section}.{m.group(1)}" if section else m.group(1), n)
    return out


MAX_STOP_S = 2147.0  # [s] the longest run: the ECU software's 1 us timer (`now / 1 us`, a VHDL natural) to 2**31-1 us
_MAX_NESTING = 32  # [levels] of arrays and inline tables in a scenario file (tomllib recurses per level)


def _too_deep(text: str) -> tuple[int, int] | None:
    """Where (line, column) the values of a TOML text nest more than _MAX_NESTING arrays or inline tables deep,
    strings and comments aside; None if they do not (a table header's brackets are not values, but they never nest
    past 2)."""
    depth, line, col, k, quote = 0, 1, 0, 0, ""
    while k < len(text):
        c = text[k]
        col += 1
        if quote:
            if text.startswith(quote, k):
                k += len(quote) - 1
                col += len(quote) - 1
                quote = ""
            elif c == "\\" and quote in ('"', '"""'):
                k += 1
                col += 1
        elif c == "#":
            while k < len(text) and text[k] != "\n":
                k += 1
            continue
        elif c in "\"'":
            quote = c * 3 if text.startswith(c * 3, k) else c
            k += len(quote) - 1
            col += len(quote) - 1
        elif c in "[{":
            depth += 1
            if depth > _MAX_NESTING:
                return line, col
        elif c in "]}":
            depth = max(0, depth - 1)
        if k < len(text) and text[k] == "\n":
            line, col = line + 1, 0
        k += 1
    return None


def load_scenario(path: str | Path) -> Scenario:
    """Read and check a scenario file; every error names file:line and the key."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as e:
        raise WrsimError(f"{path}: cannot read: {e.strerror or e}") from None
    except UnicodeDecodeError as e:
        raise WrsimError(f"{path}: not a UTF-8 text file ({e.reason})") from None
    deep = _too_deep(text)
    if deep is not None:
        raise WrsimError(
            f"{path}:{deep[0]}:{deep[1]}: arrays and inline tables nested more than {_MAX_NESTING} deep (a scenario "
            "needs a few levels)"
        )
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as e:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(e))
        located = f"{path}:{m.group(1)}:{m.group(2)}" if m else str(path)
        raise WrsimError(f"{located}: not valid TOML: {re.sub(r' [(]at line.*', '', str(e))}") from None
    except ValueError:  # Python's bound on the digits of a whole number (sys.get_int_max_str_digits)
        long = re.search(rf"\d{{{sys.get_int_max_str_digits()},}}", text)
        row, col = (
            (text.count("\n", 0, long.start()) + 1, long.start() - text.rfind("\n", 0, long.start()))
            if long
            else (1, 1)
        )
        raise WrsimError(
            f"{path}:{row}:{col}: a whole number of more than {sys.get_int_max_str_digits()} digits"
        ) from None
    lines = _lines(text)

    def at(key: str) -> str:
        head = key.rsplit(".", 1)[0] if "." in key else ""
        return f"{path}:{lines.get(key, lines.get(head, 1))}"

    for section, value in data.items():
        if section not in _KEYS[""] and section not in _KEYS:
            raise WrsimError(
                f"{at(section)}: unknown key '{section}' (keys: {', '.join(k for k in _KEYS if k)}, "
                f"{', '.join(_KEYS[''])})"
            )
        if section in _KEYS and section:
            if not isinstance(value, dict):
                raise WrsimError(f"{at(section)}: '{section}' is a table ([{section}])")
            if section not in ("generics",):
                for key in value:
                    if key not in _KEYS[section]:
                        raise WrsimError(
                            f"{at(f'{section}.{key}')}: [{section}] unknown key '{key}' (keys: "
                            f"{', '.join(_KEYS[section])})"
                        )
    purpose = data.get("purpose")
    if not isinstance(purpose, str) or not purpose.strip() or "\n" in purpose.strip():
        raise WrsimError(f"{at('purpose')}: purpose: one line that says what the case checks")
    ecu = data.get("ecu", "relay")
    if ecu not in ECUS:
        raise WrsimError(f"{at('ecu')}: ecu: {' or '.join(repr(k) for k in ECUS)} (the ECU concept; got {ecu!r})")
    if "stop" not in data:
        raise WrsimError(f"{path}: stop: missing (the end of the run, e.g. stop = 12.0 for 12 s)")
    stop = _positive(data["stop"], "s", f"{at('stop')}: stop")
    if stop > MAX_STOP_S:
        raise WrsimError(
            f"{at('stop')}: stop = {stop:g} s: at most {MAX_STOP_S:g} s (the ECU's 1 us timer is a 32-bit integer)"
        )
    params = data.get("params", [])
    if not isinstance(params, list) or not all(isinstance(p, str) for p in params):
        raise WrsimError(f'{at("params")}: params: a list of parameter sets, e.g. ["antipinch/observer"]')
    sets = tuple(_param_file(p, path, at("params")) for p in params)

    start = data.get("start", {})
    state = start.get("state", "cold")
    if state not in ("cold", "warm"):
        raise WrsimError(f"{at('start.state')}: [start] state: 'cold' (the sequence normalizes the ECU) or 'warm'")
    glass0 = number(start.get("glass", 0.0), "m", f"{at('start.glass')}: [start] glass")
    if glass0 != 0.0 and state == "cold":
        raise WrsimError(
            f"{at('start.glass')}: [start] glass: a cold start begins at the bottom (the ECU learns "
            f'on its way up); give state = "warm" to start elsewhere'
        )

    values: dict[str, float] = {}
    generics: dict[str, GenericValue] = {}
    where: dict[str, str] = {}
    for section, keys in _KEYS.items():
        for key, target in keys.items():
            if target and section in data and key in data[section]:
                here = f"{at(f'{section}.{key}')}: [{section}] {key}"
                values[target[0]] = _real(data[section][key], target[1], here)
                where[target[0]] = here
    for key, value in data.get("generics", {}).items():
        generics[key.lower()] = value
        where[key.lower()] = f"{at(f'generics.{key}')}: [generics]"
        if key.lower() in values:
            raise WrsimError(f"{where[key.lower()]} {key}: set by its own key in this file already")
        if key.lower() in _OWNED and (state == "warm" or key.lower() not in _WARM_KEYS):
            raise WrsimError(f"{where[key.lower()]} {key}: {_OWNED[key.lower()]}")
    obstacle = data.get("obstacle", {})
    gap = None
    if "gap" in obstacle:
        if "position" in obstacle:
            raise WrsimError(f"{at('obstacle.gap')}: [obstacle] give gap or position, not both")
        gap = number(obstacle["gap"], "m", f"{at('obstacle.gap')}: [obstacle] gap")
    if obstacle and "stiffness" not in obstacle:
        raise WrsimError(f'{at("obstacle")}: [obstacle] stiffness: missing (e.g. stiffness = "10 N/mm")')
    if obstacle and gap is None and "position" not in obstacle:
        raise WrsimError(f"{at('obstacle')}: [obstacle] gap (below the top-frame sealing) or position: missing")

    switch = data.get("switch")
    if switch is None:
        raise WrsimError(f"{path}: [switch]: missing (a sequence file, or units)")
    sequence: Path | None = None
    commands: tuple[Command, ...] = ()
    if "sequence" in switch:
        if "units" in switch:
            raise WrsimError(f"{at('switch.sequence')}: [switch] give sequence or units, not both")
        sequence = _sequence_file(switch["sequence"], path, at("switch.sequence"))
    elif "units" in switch:
        first = lines.get("switch.units", 1)
        braces = [first + k for k, line in enumerate(text.splitlines()[first - 1 :]) if "{" in line.split("#")[0]]
        commands = _commands(switch["units"], at("switch.units"), [f"{path}:{n}" for n in braces])
    else:
        raise WrsimError(f"{at('switch')}: [switch] sequence (a switch-sequence file) or units (a list)")
    for c in commands:
        _offset(c, values.get("u_nominal", NOMINAL_V))

    ambient = None
    if "temperature" in data.get("ambient", {}):
        here = at("ambient.temperature")
        celsius = number(data["ambient"]["temperature"], "degC", f"{here}: [ambient] temperature")
        file, _, line = here.rpartition(":")
        ambient = Param(celsius, "degC", file, int(line))
    solver = data.get("solver", {})
    expect = data.get("expect", {})
    closings = expect.get("closings")
    if closings is not None and (not isinstance(closings, int) or isinstance(closings, bool) or closings < 0):
        raise WrsimError(f"{at('expect.closings')}: [expect] closings: a whole number >= 0")
    reversal = expect.get("reversal")
    if reversal is not None and not isinstance(reversal, bool):
        raise WrsimError(f"{at('expect.reversal')}: [expect] reversal: true (every closing reverses) or false (none)")
    reopening = expect.get("reopening")
    if reopening is not None and not isinstance(reopening, bool):
        raise WrsimError(
            f"{at('expect.reopening')}: [expect] reopening: true (every reversal reopens as FMVSS 118 S5(b) asks) "
            "or false (not judged)"
        )
    peak = expect.get("peak_max")
    glass_end = expect.get("glass")
    return Scenario(
        name=path.stem,
        file=path,
        purpose=purpose.strip(),
        ecu=ecu,
        stop=stop,
        params=sets,
        warm=state == "warm",
        glass0=glass0,
        sequence=sequence,
        commands=commands,
        values=values,
        generics=generics,
        gap=gap,
        ambient=ambient,
        reltol=_positive(solver.get("reltol", RELTOL), "1", f"{at('solver.reltol')}: [solver] reltol"),
        max_step=_max_step(solver.get("max_step", MAX_STEP), stop, f"{at('solver.max_step')}: [solver] max_step"),
        closings=closings,
        reversal=reversal,
        reopening=reopening,
        peak_max=None if peak is None else _positive(peak, "N", f"{at('expect.peak_max')}: [expect] peak_max"),
        glass_end=None if glass_end is None else number(glass_end, "m", f"{at('expect.glass')}: [expect] glass"),
        glass_tolerance=_positive(
            expect.get("glass_tolerance", "5 mm"), "m", f"{at('expect.glass_tolerance')}: [expect] glass_tolerance"
        ),
        where=where,
    )


def _real(value: Any, unit: str, where: str) -> float:
    """A number in `unit`, or a string of a number with a unit."""
    if not isinstance(value, (int, float, str)) or isinstance(value, bool):
        hint = "" if unit == "1" else f" (in {unit}, or a string with a unit, e.g. '9 V')"
        raise WrsimError(f"{where}: a number{hint}")
    return number(value, unit, where)


def _positive(value: Any, unit: str, where: str) -> float:
    v = _real(value, unit, where)
    if v <= 0.0:
        raise WrsimError(f"{where}: must be > 0")
    return v


def _max_step(value: Any, stop: float, where: str) -> float:
    """[s] a largest step: > 0 and at most the run's `stop` (ngspice gives up on a longer one at the first step)."""
    step = _positive(value, "s", where)
    if step > stop:
        raise WrsimError(f"{where} = {step:g} s: at most the run's stop, {stop:g} s")
    return step


def _param_file(name: str, scenario: Path, where: str) -> Path:
    """A parameter set a scenario names: a file relative to the scenario's folder, or a set of params/."""
    beside = scenario.resolve().parent / name
    named = beside.name not in ("", ".", "..")  # a folder ('.', '..') is no set and takes no suffix
    for candidate in (beside, beside.with_suffix(".txt")) if named else ():
        try:
            if candidate.is_file():
                return candidate
        except OSError as e:  # a name longer than the file system takes
            raise WrsimError(f"{where}: params: {name[:40]}...: {e.strerror}") from None
    try:
        return find_param_set(name)
    except WrsimError as e:
        raise WrsimError(f"{where}: params: {e}") from None


def _sequence_file(name: Any, scenario: Path, where: str) -> Path:
    """A switch-sequence file: relative to the scenario's folder, or a name of params/sequences/."""
    if not isinstance(name, str) or not name:
        raise WrsimError(f"{where}: [switch] sequence: a file name")
    for candidate in (scenario.parent / name, paths.SEQUENCES / name, paths.SEQUENCES / f"{name}.txt"):
        if candidate.is_file():
            return candidate.resolve()
    raise WrsimError(f"{where}: [switch] sequence: no file '{name}' beside the scenario or in {paths.SEQUENCES}")


def _commands(units: Any, where: str, each: list[str]) -> tuple[Command, ...]:
    """The switch units of a scenario: a list of inline tables, `{at = T, command = "up", supply = V}` (from time
    T) or `{glass = H, supply = V, timeout = S}` (move the glass to height H); `each`: where each unit is written
    (one per line, as the docs show), else `where`."""
    if not isinstance(units, list) or not units or not all(isinstance(u, dict) for u in units):
        raise WrsimError(
            f'{where}: [switch] units: a list of units, e.g. [{{at = 0.0, command = "up"}}, '
            f"{{glass = 0.2, timeout = 0.15}}]"
        )
    out = []
    last = -1.0
    for k, u in enumerate(units, start=1):
        here = f"{each[k - 1] if len(each) == len(units) else where}: [switch] unit {k}"
        kind = "p" if "glass" in u else "t"
        unknown = [key for key in u if key not in _UNIT_KEYS[kind]]
        if unknown:
            raise WrsimError(
                f"{here}: unknown key '{unknown[0]}' (a time unit has {', '.join(_UNIT_KEYS['t'])}; a "
                f"move has {', '.join(_UNIT_KEYS['p'])})"
            )
        supply = None if "supply" not in u else number(u["supply"], "V", f"{here}: supply")
        if kind == "t":
            if "at" not in u or "command" not in u:
                raise WrsimError(f"{here}: a time unit needs at and command (or glass, for a move)")
            t = number(u["at"], "s", f"{here}: at")
            if t < 0 or t <= last:
                raise WrsimError(f"{here}: at = {t:g} s: times must be >= 0 and rise")
            last = t
            if u["command"] not in _COMMANDS:
                raise WrsimError(f"{here}: command '{u['command']}': one of {', '.join(_COMMANDS)}")
            out.append(Command(t, _COMMANDS[u["command"]], None, supply, 0.0, here))
        else:
            h = number(u["glass"], "m", f"{here}: glass")
            timeout = _positive(u.get("timeout", 0.15), "s", f"{here}: timeout")
            out.append(Command(None, 0, h, supply, timeout, here))
    return tuple(out)


class Learning(Protocol):
    """What a normalization run tells a scenario (benches.scenario_run.WarmStart): the generics of a warm start, and
    where a glass height is on the scale of the ECU's counter."""

    def generics(self, s: Scenario, pset: ParamSet | None) -> dict[str, float | str]:
        """learned_file, start_position and glass_start of a warm start of `s`."""
        ...

    def below_top(self, s: Scenario, pset: ParamSet | None, glass: float) -> float:
        """[m] the switch's target (the ECU's position in the switch's metres) where the glass is at `glass`."""
        ...


def write_sequence(
    s: Scenario, pset: ParamSet | None, path: Path, below_top: Callable[[float], float] | None = None
) -> Path:
    """The switch sequence of `s` in the switch's own format (docs/switch-sequence.md): glass heights become
    electronic positions: by `below_top` (the counter of a normalization run against the glass, `Learning`), else
    the distance below the glass closed in the top frame (the top-frame sealing's position plus its ranges in
    `pset`); supplies become offsets from the nominal supply."""
    nominal = s.values.get("u_nominal", NOMINAL_V)
    top = _top(pset, s)
    lines = [f"# switch sequence of scenario {s.file} (written by wrsim; glass closed in the frame at {top:g} m)"]
    if s.commands and s.commands[0].glass is not None:
        # the switch reads the position before the ECU's first output as 0 (the top): a move waits for it
        lines += ["T 0.0 0   # the ECU's position arrives first", "T 0.05 0"]
    for c in s.commands:
        offset = _offset(c, nominal)
        if c.glass is None:
            lines.append(f"T {c.at!r} {c.command} {offset:.1f}")
        else:
            if not 0.0 <= c.glass <= top:
                raise WrsimError(f"{c.where}: glass {c.glass:g} m is outside the stroke 0 .. {top:g} m")
            target = top - c.glass if below_top is None else below_top(c.glass)
            lines.append(f"P {target!r} {offset:.1f} 0 {c.timeout!r}   # glass to {c.glass:g} m")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path


def _offset(c: Command, nominal: float) -> float:
    """[V] the supply of unit `c` as the switch's offset from the `nominal` supply (-12.8 .. 12.7 V)."""
    offset = 0.0 if c.supply is None else c.supply - nominal
    if not -12.8 <= offset <= 12.7:
        raise WrsimError(
            f"{c.where}: supply {c.supply:g} V is {offset:+.1f} V from the nominal {nominal:g} V; "
            f"the switch offsets the supply by -12.8 .. 12.7 V"
        )
    return offset


def _top(pset: ParamSet | None, s: Scenario) -> float:
    """[m] the glass position closed in the top frame: the top-frame sealing's contact plus its ranges."""
    if pset is None or "top_frame_seal" not in pset.sections:
        raise WrsimError(f"{s.file}: the parameter set has no [top_frame_seal] (glass heights need the system set)")
    return pset.number_in("top_frame_seal", "position", "m") + sum(pset.vector_in("top_frame_seal", "lengths", "m"))


def _seal(pset: ParamSet | None, s: Scenario) -> float:
    if pset is None or "top_frame_seal" not in pset.sections:
        raise WrsimError(f"{s.file}: the parameter set has no [top_frame_seal] (a gap needs the system set)")
    return pset.number_in("top_frame_seal", "position", "m")


def scenario_params(user: Sequence[str | Path] = (), door: str | Path | None = None) -> ParamSet:
    """The parameter set scenario runs start from (benches.core.bench_params): the testbench's system set with the
    user's sets over it; a scenario's own sets and ambient temperature are its run's own (`scenario_run`). `door`: a
    set laid over the system set but beneath each scenario's own sets, as a fleet lays its doors (a door's door.txt:
    the case runs as the fleet recorded it)."""
    pset = bench_params(SYSTEM_PARAMS, user)
    assert pset is not None
    return pset if door is None else pset.beneath(load_params(find_param_set(door)))


def own_sets(s: Scenario) -> tuple[Path | ParamSet, ...]:
    """A scenario's own parameter sets in order, its ambient temperature last."""
    if s.ambient is None:
        return s.params
    return (*s.params, ParamSet(s.name, s.file, {"ambient": {"temperature": s.ambient}}))


def extra_generics(s: Scenario) -> dict[str, float | str]:
    """The [generics] of `s`, typed and converted like `--set` (elab.generics)."""
    if not s.generics:
        return {}
    from wrsim.elab.generics import top_generics
    from wrsim.elab.library import load_library

    lib = load_library(paths.LIBRARY)
    out: dict[str, float | str] = {}
    for name, value in s.generics.items():
        out.update(top_generics(lib, TESTBENCH, {name: value}, where=s.where[name]))
    return out


def scenario_run(s: Scenario, pset: ParamSet | None, learning: Learning | None = None) -> Run:
    """The bench run of `s` (`pset`: the set it starts from, `scenario_params`, for the geometry of the top-frame
    sealing; the run lays its own sets, `own_sets`): the testbench generics; a sequence written from its units into
    the run's folder, glass heights on the scale `learning` measured when given; for a warm start, the generics
    `learning` gives (the ECU's learned state and its counter at the glass height, benches.scenario_run)."""
    values: dict[str, float | str | Callable[[Path], float | str]] = dict(s.values)
    if s.gap is not None:
        values["pinch_position"] = _seal(pset, s) - s.gap
    values.update(extra_generics(s))
    if s.warm:
        if learning is None:
            raise WrsimError(f"{s.file}: a warm start needs the learned state of a normalization run")
        values.update(learning.generics(s, pset))
    if s.sequence is not None:
        values["sequence_file"] = str(s.sequence)
    else:
        scale = None if learning is None else functools.partial(learning.below_top, s, pset)
        values["sequence_file"] = lambda folder: str(write_sequence(s, pset, folder / "sequence.txt", scale))
    return with_ecu(Run(s.name, values, own_sets(s) or None), s.ecu)


# The PWM ECU's profile (motor_controller) as `check_ecu` holds it: speeds [mm/s] that must be > 0, and those that
# may not exceed the closing speed
_SPEEDS = ("close_mm_s", "pinch_mm_s", "stop_mm_s", "open_mm_s", "start_mm_s")
_AT_MOST_CLOSING = ("pinch_mm_s", "stop_mm_s", "start_mm_s")


def check_runs(lib: Library, scenarios: Sequence[Scenario], base: ParamSet) -> None:
    """Every scenario's run set before anything runs: its own sets read (includes, cycles, a file that is no set),
    its ambient temperature within the rules' range, the ECU concept laid in and, with the PWM ECU, its profile
    (`check_ecu`); `base`: the set the runs start from (`scenario_params`)."""
    for s in scenarios:
        pset = with_ecu(Run(s.name, {}, own_sets(s) or None), s.ecu).parameters(base)
        if s.ecu == "pwm" and pset is not None:
            check_ecu(lib, pset, str(s.file))


def check_ecu(lib: Library, pset: ParamSet, what: str) -> None:
    """The PWM ECU's profile in `pset` (a run's set, the ECU concept's laid in) before anything runs: every speed, the
    ramp and the current limit > 0, the pinch-zone and soft-stop speeds at most the closing speed, and a closing speed
    the drive reaches at the nominal 13 V without load (its back-EMF, speed/rpm_per_volt, below 13 V). One error naming
    the key and where the set gives it; `what` names the run when the value is the model's default."""
    from wrsim.elab import symbolic as sy
    from wrsim.elab.instances import InstanceTree

    values = InstanceTree(lib, pset).generic_defaults(lib.entities["motor_controller"])
    given = pset.sections.get("motor_controller", {})

    def value(key: str) -> float:
        v = values[key][0]
        assert v is not None  # every generic of motor_controller has a default
        return float(sy.value(v))

    def fail(key: str, why: str) -> None:
        p = given.get(key)
        where = f"{p.file}:{p.line}" if p is not None else f"{what} (the default of vhdl/digital/motor_controller.vhd)"
        raise WrsimError(f"{where}: [motor_controller] {key} = {value(key):g}: {why}")

    for key in (*_SPEEDS, "ramp_mm_s2", "i_limit_ma", "idle_ms"):
        if value(key) <= 0:
            fail(key, "must be > 0")
    for key in _AT_MOST_CLOSING:
        if value(key) > value("close_mm_s"):
            fail(key, f"must not exceed the closing speed close_mm_s = {value('close_mm_s'):g} mm/s")
    rpm = value("close_mm_s") * value("edges_per_m") * 60.0 / 4.0 / 1000.0
    if rpm / value("rpm_per_volt") >= NOMINAL_V:
        fail(
            "close_mm_s",
            f"the drive does not reach it at {NOMINAL_V:g} V: {rpm:.0f} rpm of armature need a back-EMF of "
            f"{rpm / value('rpm_per_volt'):.1f} V (rpm_per_volt = {value('rpm_per_volt'):g} rpm/V)",
        )


def concept_over(pset: ParamSet, ecu: str) -> ParamSet:
    """`pset` with the ECU concept `ecu`'s set (ECUS) laid over it, as a scenario run with that ECU has it beneath
    its own sets."""
    concept = ECUS[ecu][1]
    return pset if concept is None else pset.beneath(load_params(concept))


def with_ecu(run: Run, ecu: str) -> Run:
    """`run` with the ECU concept `ecu` (ECUS): the testbench's generic and the concept's set beneath the run's own."""
    generic, pset = ECUS[ecu]
    if pset is None:
        return run
    return dataclasses.replace(run, generics={**run.generics, "ecu_kind": generic}, params=(pset, *run.layers))
