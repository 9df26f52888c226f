"""Digital units in GHDL, co-simulated inside ngspice through XSPICE `d_cosim` (docs/vhdl-ams-subset.md,
"Mixed signal").

One digital top entity becomes one shared library: its VHDL analysed and elaborated by `ghdl-llvm -e -shared`
with wrsim's VPI glue (tools/cosim/ngghdl_glue.c) linked in. ngspice loads it through tools/cosim/ngghdl_loader.c,
which gives every d_cosim instance (and every run) a private copy, so several instances of one design coexist.

The netlist contract, verified by tests/unit/test_ghdl.py:

- `instance_line` takes d_cosim's input list and output list. Inputs are the entity's `in` ports and outputs its
  `out` ports, each in declaration order (`DigitalBuild.inputs` / `.outputs`); a port of width W contributes W
  digital nodes, left index first: MSB first for `std_logic_vector(W-1 downto 0)`, bit 31 first for integers.
- Port types: std_logic, bit, boolean and their vectors both ways; integer/natural (32 bits, two's complement) as
  outputs only (GHDL 2.0 cannot set integer signals through VPI). No inout or buffer ports.
- Digital nodes meet the analog plant through `adc_bridge` / `dac_bridge`; d_cosim outputs start at '0' and change
  `delay` (default 1 us) after the VHDL event that caused them. d_cosim cuts the analog step back to the event
  time + delay/3 when an output changes, so a delay near ngspice's minimum step (1 ns) makes stiff plants fail with
  "timestep too small"; 1 us is invisible to a window regulator. VHDL-internal timing (clocks, timers) is exact;
  d_cosim hands inputs over only for accepted SPICE steps, so a reaction to an input event (even a combinational
  one) reaches SPICE at the end of the step that holds the event (bounded by max_step).
- Each d_cosim instance needs a unique `irreversible=` number (`uid` >= 1).
- ngspice lower-cases the strings on a `.model` line and its numparam mangles `=` inside them, so a model card
  names only lower-case files relative to the run folder (loader and library are linked there); GHDL's run
  options go into an args file instead.
- The runner passes `RUN_ENV` to ngspice, so that a VHDL `assert ... severity failure` ends the run with a non-zero
  status, and checks the log with `log_failure` (some d_cosim failures only print a message).
- Before a run, `preflight` loads the design with the run's generics in a separate process: GHDL's elaboration
  errors end the process they happen in, which must not be ngspice.
"""
from __future__ import annotations

import functools
import hashlib
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from .errors import Loc, SourceError, WrsimError

__all__ = ["DigitalPort", "DigitalBuild", "RUN_ENV", "check", "build", "preflight", "model_card", "instance_line",
           "log_failure"]

GHDL = "ghdl-llvm"
CC = "gcc"
GHDL_INCLUDE = Path("/usr/lib/ghdl/include/ghdl")
NGSPICE_INCLUDE = Path("/usr/share/ngspice/scripts/src")
COSIM_SOURCES = Path(__file__).resolve().parents[1] / "cosim"
RUN_ENV: dict[str, str] = {"NGGHDL_FATAL": "1", "NGGHDL_STATS": "1"}
"""Environment ngspice runs with: a failing VHDL simulation ends ngspice with its non-zero status, and each
digital unit writes its coupling counts to the log at the end (`wrsim bench` reports them)."""

_INSTALL = "install: make setup (apt-get install ghdl-llvm gcc)"
_CFLAGS = ["-O2", "-fPIC", "-Wall", "-Wextra", f"-I{GHDL_INCLUDE}", f"-I{NGSPICE_INCLUDE}"]
_LINK = ["-Wl,-Wl,-Bsymbolic", "-Wl,-lm"]
_IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")
_NODE = re.compile(r"[A-Za-z0-9_.#$]+\Z")
_SPICE_STRING_UNSAFE = re.compile(r'[A-Z\s"=\[\]{}]')
_TIMEOUT = 300.0


@dataclass(frozen=True)
class DigitalPort:
    """A port of a digital top entity: `width` bits (1 for std_logic, N for a vector, 32 for an integer)."""

    name: str
    direction: Literal["in", "out"]
    width: int = 1


@dataclass
class DigitalBuild:
    """A built digital top: the design library, the loader ngspice opens, and the ports in declaration order."""

    top: str
    library: Path
    loader: Path
    ports: list[DigitalPort]

    @property
    def inputs(self) -> list[DigitalPort]:
        """d_cosim's input list: the `in` ports in declaration order."""
        return [p for p in self.ports if p.direction == "in"]

    @property
    def outputs(self) -> list[DigitalPort]:
        """d_cosim's output list: the `out` ports in declaration order."""
        return [p for p in self.ports if p.direction == "out"]


def check() -> str:
    """GHDL's version line; raises WrsimError naming what to install when ghdl-llvm, gcc or a header is missing."""
    return _check()


@functools.cache
def _check() -> str:
    exe = shutil.which(GHDL)
    if exe is None:
        raise WrsimError(f"{GHDL} not found (GHDL with the LLVM back-end builds the digital units); {_INSTALL}")
    if shutil.which(CC) is None:
        raise WrsimError(f"{CC} not found (it compiles the co-simulation glue tools/cosim/*.c); {_INSTALL}")
    headers = {GHDL_INCLUDE / "vpi_user.h": "GHDL's VPI header (package ghdl-common, pulled in by ghdl-llvm)",
               NGSPICE_INCLUDE / "ngspice" / "cosim.h": "ngspice's d_cosim header (package ngspice >= 45)",
               NGSPICE_INCLUDE / "ngspice" / "cmtypes.h": "ngspice's code-model types (package ngspice >= 45)"}
    for path, what in headers.items():
        if not path.is_file():
            raise WrsimError(f"{path} missing: {what}; {_INSTALL}")
    out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
    if "llvm" not in out.lower():
        raise WrsimError(f"{exe} is not GHDL's LLVM back-end (needed for `-e -shared`); {_INSTALL}")
    return out.splitlines()[0].strip()


def build(top: str, files: list[Path], ports: list[DigitalPort], workdir: Path) -> DigitalBuild:
    """Analyse `files` (VHDL-2008, library work, in the caller's dependency order), compile the glue and the loader
    once per `workdir`, and elaborate `top` into a shared library. The result is cached in `workdir` by a hash of
    the sources, the glue and `top`: an unchanged second call runs no compiler. `ports` is the top's port list in
    declaration order (checked against the design by `preflight`)."""
    if not _IDENT.match(top):
        raise WrsimError(f"digital top '{top}' is not a VHDL identifier")
    _check_ports(top, ports)
    version = check()
    sources = []
    for f in files:
        try:
            sources.append((Path(f).resolve(), Path(f).read_bytes()))
        except OSError as e:
            raise WrsimError(f"{f}: cannot read VHDL source of digital unit '{top}': {e.strerror}") from None
    workdir.mkdir(parents=True, exist_ok=True)
    glue_o, loader = _glue(workdir.resolve(), version)
    key = _digest(version, top.lower(), glue_o.parent.name, *(text for _, text in sources))
    out = workdir.resolve() / f"{top.lower()}-{key[:16]}"
    library = out / f"{top.lower()}.so"
    if not library.is_file():
        with _staging(out) as tmp:
            work = tmp / "work"
            work.mkdir()
            _ghdl(["-a", "--std=08", f"--workdir={work}", *(str(p) for p, _ in sources)], tmp,
                  f"analysis of digital unit '{top}'")
            _ghdl(["-e", "--std=08", f"--workdir={work}", "-shared", f"-Wl,{glue_o}", *_LINK,
                   "-o", library.name, top], tmp, f"elaboration of digital unit '{top}'")
    return DigitalBuild(top, library, loader, list(ports))


def preflight(build: DigitalBuild, generics: dict[str, int | bool | str], workdir: Path) -> None:
    """Load `build` with `generics` the way ngspice will (loader, args file, glue) in a separate process and run
    VHDL time 0 with all inputs '0'. Unknown or out-of-range generics, elaboration errors and failing generic
    assertions raise WrsimError with GHDL's own message; so does a port map that differs from `build.ports`."""
    workdir.mkdir(parents=True, exist_ok=True)
    args = workdir / f"{build.top.lower()}.preflight.args"
    _write_args(args, generics, None)
    env = {**os.environ, **RUN_ENV, "NGGHDL_PORTS": "1"}
    try:
        proc = subprocess.run([sys.executable, "-I", "-S", "-c", _PROBE, str(build.loader), str(build.library),
                               build.top, f"@{args.resolve()}"], capture_output=True, text=True, env=env,
                              cwd=workdir, timeout=_TIMEOUT)
    except subprocess.TimeoutExpired:
        raise WrsimError(f"preflight of digital unit '{build.top}' did not finish within {_TIMEOUT:.0f} s") from None
    lines = [ln.rstrip() for ln in (proc.stderr + proc.stdout).splitlines() if ln.strip()]
    said = [ln for ln in lines if not _NOISE.match(ln)]
    if proc.returncode != 0:
        raise WrsimError(f"digital unit '{build.top}' with {_generics_text(generics)} fails before the simulation "
                         f"starts:\n  " + "\n  ".join(said or [f"exit status {proc.returncode}"]))
    port_lines = [re.match(r"ngghdl: (in|out) +(\S+) (\d+) ", ln + " ") for ln in lines]
    seen = [DigitalPort(m[2], m[1], int(m[3])) for m in port_lines if m]
    want = [DigitalPort(p.name.lower(), p.direction, p.width) for p in build.inputs + build.outputs]
    if seen != want:
        raise WrsimError(f"digital unit '{build.top}': GHDL sees the ports {_ports_text(seen)}, the netlist expects "
                         f"{_ports_text(want)} (in ports, then out ports, in declaration order)")


def model_card(build: DigitalBuild, model_name: str, generics: dict[str, int | bool | str], args_file: Path,
               uid: int, *, vcd: Path | None = None, delay: float = 1e-6) -> str:
    """Write GHDL's run options (generics as -gNAME=VALUE, optionally --vcd=FILE) to `args_file` and return the
    `.model` line of one d_cosim instance. `uid` is the instance's `irreversible=` number, unique in the netlist
    and >= 1; `delay` [s] is the delay d_cosim adds to every output change.

    ngspice lower-cases the strings of a .model line, so the card names no absolute path (the repository may
    live under /home/Alice): the loader and the design library are linked into the args file's folder, and
    every path on the card is relative to it. ngspice must run in that folder (the runner's work folder)."""
    if not _NODE.match(model_name):
        raise WrsimError(f"d_cosim model name '{model_name}' is not a plain SPICE name")
    if isinstance(uid, bool) or not isinstance(uid, int) or uid < 1:
        raise WrsimError(f"d_cosim model '{model_name}': irreversible number must be an integer >= 1, got {uid!r}")
    if not delay > 0:
        raise WrsimError(f"d_cosim model '{model_name}': output delay must be > 0 s, got {delay!r}")
    run_dir = args_file.parent
    names = {"loader": build.loader.name, "design library": f"{model_name}_{build.library.name}",
             "args file": args_file.name}
    for what, name in names.items():
        if _SPICE_STRING_UNSAFE.search(name):
            raise WrsimError(f"d_cosim model '{model_name}': {what} name {name} cannot go on a .model line (ngspice "
                             f"lower-cases it and mangles '=', quotes and blanks): use only lower-case letters, "
                             f"digits and ._-")
    _write_args(args_file, generics, vcd)
    for target, name in ((build.loader, names["loader"]), (build.library, names["design library"])):
        link = run_dir / name
        if link.is_symlink() or link.exists():
            link.unlink()
        link.symlink_to(target.resolve())
    return (f'.model {model_name} d_cosim(simulation="./{names["loader"]}" lib_args=["./{names["design library"]}"] '
            f'sim_args=["{build.top.lower()}" "@./{names["args file"]}"] delay={delay:.6g} irreversible={uid})')


def instance_line(name: str, inputs: list[str], outputs: list[str], model_name: str) -> str:
    """The d_cosim element line `a<name> [inputs] [outputs] <model_name>`: digital node names, one per bit, in the
    order of `DigitalBuild.inputs` / `.outputs` with each port's bits left index first (MSB first for
    `downto`). An empty list becomes `null`."""
    for node in (name, model_name, *inputs, *outputs):
        if not _NODE.match(node):
            raise WrsimError(f"d_cosim instance 'a{name}': '{node}' is not a plain SPICE name")
    vectors = [f"[{' '.join(nodes)}]" if nodes else "null" for nodes in (inputs, outputs)]
    return f"a{name} {vectors[0]} {vectors[1]} {model_name}"


def log_failure(log: str) -> str | None:
    """The co-simulation failure reported in an ngspice log (VHDL assertion failure, glue/loader error, d_cosim
    load error, port-count mismatch, duplicate irreversible number), or None. Some of these leave ngspice's exit
    status at 0."""
    lines = log.splitlines()
    vhdl = [ln.strip() for ln in lines if _VHDL_FAILURE.search(ln)]
    other = [ln.strip() for ln in lines if _COSIM_FAILURE.search(ln)]
    if vhdl:
        return "GHDL: " + "; ".join(vhdl[:3])
    return other[0] if other else None


# --- helpers ---------------------------------------------------------------------------------------------------

_NOISE = re.compile(r"loading VPI module |VPI module loaded!|ngghdl: (in|out) |ngghdl: VHDL simulation ended |"
                    r"ngghdl: error: VHDL simulation failed \(NGGHDL_FATAL")
_VHDL_FAILURE = re.compile(r":\((assertion|report) failure\):|^\S+:error: ")
_COSIM_FAILURE = re.compile(r"ngghdl(_loader)?: error: |d_cosim failed to load|no entry function in|"
                            r"mismatched XSPICE/co-simulator|Duplicate value \d+ in cm_irreversible|"
                            r"VHDL simulation ended at .* with status [1-9]")

# Runs in a fresh interpreter (python -I -S -c): loads the design through the loader exactly as d_cosim does
# (struct co_info of ngspice/cosim.h), drives every input bit '0', steps to t = 0 and shuts GHDL down.
# argv: loader, design library, then sim_args. The glue prints the port map (NGGHDL_PORTS) and, with
# NGGHDL_FATAL, exits non-zero if GHDL fails; GHDL itself exits on elaboration errors.
_PROBE = """
import ctypes, os, sys
class Digital(ctypes.Structure):
    _fields_ = [("state", ctypes.c_int), ("strength", ctypes.c_int)]
class CoInfo(ctypes.Structure):
    pass
Fn = ctypes.CFUNCTYPE(None, ctypes.POINTER(CoInfo))
IoFn = ctypes.CFUNCTYPE(None, ctypes.POINTER(CoInfo), ctypes.c_uint, ctypes.POINTER(Digital))
Argv = ctypes.POINTER(ctypes.c_char_p)
CoInfo._fields_ = [("in_count", ctypes.c_uint), ("out_count", ctypes.c_uint), ("inout_count", ctypes.c_uint),
                   ("cleanup", Fn), ("step", Fn), ("in_fn", IoFn), ("out_fn", IoFn), ("handle", ctypes.c_void_p),
                   ("vtime", ctypes.c_double), ("method", ctypes.c_int), ("lib_argc", ctypes.c_uint),
                   ("sim_argc", ctypes.c_uint), ("lib_argv", Argv), ("sim_argv", Argv), ("dlopen_fn", ctypes.c_void_p)]
def argv(items):
    return (ctypes.c_char_p * (len(items) + 1))(*[a.encode() for a in items], None)
lib_args, sim_args = argv(sys.argv[2:3]), argv(sys.argv[3:])
info = CoInfo(lib_argc=1, sim_argc=len(sys.argv) - 3, lib_argv=lib_args, sim_argv=sim_args,
              out_fn=IoFn(lambda info, bit, value: None))
ctypes.CDLL(sys.argv[1], mode=os.RTLD_LOCAL).Cosim_setup(ctypes.byref(info))
zero = Digital(0, 0)
for bit in range(info.in_count):
    info.in_fn(ctypes.byref(info), bit, ctypes.byref(zero))
info.step(ctypes.byref(info))
info.cleanup(ctypes.byref(info))
"""


def _check_ports(top: str, ports: list[DigitalPort]) -> None:
    seen: set[str] = set()
    for p in ports:
        if not _IDENT.match(p.name) or p.name.lower() in seen:
            raise WrsimError(f"digital unit '{top}': port name '{p.name}' is not a VHDL identifier or is repeated")
        if p.direction not in ("in", "out"):
            raise WrsimError(f"digital unit '{top}': port '{p.name}' has direction '{p.direction}'; the co-simulation "
                             f"carries only in and out ports")
        if isinstance(p.width, bool) or not isinstance(p.width, int) or p.width < 1:
            raise WrsimError(f"digital unit '{top}': port '{p.name}' has width {p.width!r}; it must be >= 1")
        seen.add(p.name.lower())


def _glue(workdir: Path, version: str) -> tuple[Path, Path]:
    """Compile ngghdl_glue.c and ngghdl_loader.c (once per workdir and glue version): (glue object, loader)."""
    glue_c, loader_c = COSIM_SOURCES / "ngghdl_glue.c", COSIM_SOURCES / "ngghdl_loader.c"
    try:
        texts = [glue_c.read_bytes(), loader_c.read_bytes()]
    except OSError as e:
        raise WrsimError(f"co-simulation glue source missing: {e.filename} ({e.strerror})") from None
    out = workdir / f"ngghdl-{_digest(version, ' '.join(_CFLAGS), *texts)[:16]}"
    glue_o, loader = out / "ngghdl_glue.o", out / "ngghdl_loader.so"
    if not loader.is_file():
        with _staging(out) as tmp:
            _compile([CC, *_CFLAGS, "-c", str(glue_c), "-o", str(tmp / glue_o.name)])
            _compile([CC, *_CFLAGS, "-shared", str(loader_c), "-o", str(tmp / loader.name), "-ldl"])
    return glue_o, loader


class _staging:
    """Build into a fresh folder next to `final` and rename it into place on success (atomic; a concurrent
    builder that finished first wins, ours is dropped)."""

    def __init__(self, final: Path):
        self.final = final

    def __enter__(self) -> Path:
        self.tmp = Path(tempfile.mkdtemp(prefix=f".{self.final.name}-", dir=self.final.parent))
        return self.tmp

    def __exit__(self, exc_type: object, exc: object, tb: object) -> None:
        if exc_type is None:
            try:
                os.rename(self.tmp, self.final)
                return
            except OSError:
                if not self.final.is_dir():
                    raise
        shutil.rmtree(self.tmp, ignore_errors=True)


def _digest(*parts: str | bytes) -> str:
    h = hashlib.sha256()
    for part in parts:
        data = part.encode() if isinstance(part, str) else part
        h.update(len(data).to_bytes(8, "little"))
        h.update(data)
    return h.hexdigest()


def _compile(cmd: list[str]) -> None:
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=_TIMEOUT)
    if proc.returncode != 0:
        raise WrsimError(f"cannot compile the co-simulation glue ({' '.join(cmd)}):\n{proc.stderr.strip()}")


_GHDL_LOC = re.compile(r"(?P<file>.+?):(?P<line>\d+):(?P<col>\d+):\s*(?P<msg>.*)")


def _ghdl(args: list[str], cwd: Path, what: str) -> None:
    """Run ghdl-llvm; a failure becomes a SourceError at GHDL's first `file:line:col:` (all its located lines
    quoted) or a WrsimError quoting GHDL's output."""
    proc = subprocess.run([GHDL, *args], capture_output=True, text=True, cwd=cwd, timeout=_TIMEOUT)
    if proc.returncode == 0:
        return
    lines = (proc.stderr + proc.stdout).splitlines()
    located = [m for m in map(_GHDL_LOC.match, lines) if m and not m["msg"].startswith("warning")]
    if located:
        first = located[0]
        rest = "".join(f"\n  {m.group(0)}" for m in located[1:])
        raise SourceError(Loc(first["file"], int(first["line"]), int(first["col"])),
                          f"{first['msg']} ({what}){rest}")
    said = [ln for ln in lines if ln.strip()]
    raise WrsimError(f"{what} failed:\n  " + "\n  ".join(said or [f"{GHDL} exit status {proc.returncode}"]))


def _write_args(path: Path, generics: dict[str, int | bool | str], vcd: Path | None) -> None:
    """GHDL run options, one per line (the glue's @file format): -gNAME=VALUE per generic, then --vcd=FILE."""
    lines = []
    for name, value in generics.items():
        if not _IDENT.match(name):
            raise WrsimError(f"generic name '{name}' is not a VHDL identifier")
        if isinstance(value, bool):
            text = "true" if value else "false"
        elif isinstance(value, (int, str)):
            text = str(value)
        else:
            raise WrsimError(f"generic '{name}' = {value!r}: only integer, boolean and string generics can be set "
                             f"on a GHDL top")
        if "\n" in text or "\r" in text:
            raise WrsimError(f"generic '{name}': value must not contain a line break")
        lines.append(f"-g{name}={text}")
    if vcd is not None:
        lines.append(f"--vcd={vcd.resolve()}")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("".join(f"{ln}\n" for ln in lines), encoding="utf-8")
    os.replace(tmp, path)


def _generics_text(generics: dict[str, int | bool | str]) -> str:
    return ", ".join(f"{k}={v!r}" for k, v in generics.items()) if generics else "default generics"


def _ports_text(ports: list[DigitalPort]) -> str:
    return "(" + ", ".join(f"{p.direction} {p.name}[{p.width}]" for p in ports) + ")"
