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
import re
import shutil
import subprocess
from dataclasses import dataclass
from pathlib import Path
from typing import Literal

from wrsim import paths
from wrsim.backend.native import CC, TIMEOUT, compile_c, digest, run_child, staging
from wrsim.errors import Loc, SourceError, WrsimError

__all__ = ["DigitalPort", "DigitalBuild", "check", "build", "executable", "c_sources"]

GHDL = "ghdl-llvm"
GHDL_INCLUDE = Path("/usr/lib/ghdl/include/ghdl")
NGSPICE_INCLUDE = Path("/usr/share/ngspice/scripts/src")
COSIM_SOURCES = paths.COSIM
"""Environment ngspice runs with: a failing VHDL simulation ends ngspice with its non-zero status, and each
digital unit writes its coupling counts to the log at the end (`wrsim bench` reports them)."""

_INSTALL = "install: make setup (apt-get install ghdl-llvm gcc)"
_CFLAGS = ["-O2", "-fPIC", "-Wall", "-Wextra", f"-I{GHDL_INCLUDE}", f"-I{NGSPICE_INCLUDE}"]
_LINK = ["-Wl,-Wl,-Bsymbolic", "-Wl,-lm"]
IDENT = re.compile(r"[A-Za-z][A-Za-z0-9_]*\Z")


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
    headers = {
        GHDL_INCLUDE / "vpi_user.h": "GHDL's VPI header (package ghdl-common, pulled in by ghdl-llvm)",
        NGSPICE_INCLUDE / "ngspice" / "cosim.h": "ngspice's d_cosim header (package ngspice 46)",
        NGSPICE_INCLUDE / "ngspice" / "cmtypes.h": "ngspice's code-model types (package ngspice 46)",
    }
    for path, what in headers.items():
        if not path.is_file():
            raise WrsimError(f"{path} missing: {what}; {_INSTALL}")
    out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
    if "llvm" not in out.lower():
        raise WrsimError(f"{exe} is not GHDL's LLVM back-end (needed for `-e -shared`); {_INSTALL}")
    return out.splitlines()[0].strip()


def build(
    top: str, files: list[Path], ports: list[DigitalPort], workdir: Path, replace: dict[str, Path] | None = None
) -> DigitalBuild:
    """Analyse `files` (VHDL-2008, library work, in the caller's dependency order), compile the glue and the loader
    once per `workdir`, compile the C files the sources name (`c_sources`; `replace` swaps one by its file name),
    and elaborate `top` into a shared library. The result is cached in `workdir` by a hash of
    the sources, the glue and `top`: an unchanged second call runs no compiler. `ports` is the top's port list in
    declaration order (checked against the design by `preflight`)."""
    if not IDENT.match(top):
        raise WrsimError(f"digital top '{top}' is not a VHDL identifier")
    _check_ports(top, ports)
    version = check()
    sources = _read(top, files)
    foreign = c_sources(sources, replace)
    workdir.mkdir(parents=True, exist_ok=True)
    glue_o, loader = _glue(workdir.resolve(), version)
    library = _elaborate(top, sources, foreign, workdir, ["-shared", f"-Wl,{glue_o}"], glue_o.parent.name, ".so")
    return DigitalBuild(top, library, loader, list(ports))


def executable(top: str, files: list[Path], workdir: Path, replace: dict[str, Path] | None = None) -> Path:
    """Analyse `files` (VHDL-2008, in dependency order), compile the C files they name (`c_sources`, `replace` as in
    `build`) and elaborate `top`, a bench that GHDL runs alone (no co-simulation), into an executable; cached in
    `workdir` by a hash of the sources as `build` is. Returns the executable."""
    if not IDENT.match(top):
        raise WrsimError(f"digital top '{top}' is not a VHDL identifier")
    version = check()
    sources = _read(top, files)
    workdir.mkdir(parents=True, exist_ok=True)
    return _elaborate(top, sources, c_sources(sources, replace), workdir, [], version, "")


def _read(top: str, files: list[Path]) -> list[tuple[Path, bytes]]:
    """The VHDL sources of `top`'s build with their texts."""
    sources = []
    for f in files:
        try:
            sources.append((Path(f).resolve(), Path(f).read_bytes()))
        except OSError as e:
            raise WrsimError(f"{f}: cannot read VHDL source of digital unit '{top}': {e.strerror}") from None
    return sources


def _elaborate(
    top: str,
    sources: list[tuple[Path, bytes]],
    foreign: list[tuple[Path, bytes]],
    workdir: Path,
    options: list[str],
    salt: str,
    suffix: str,
) -> Path:
    """Analyse `sources`, compile `foreign` (C) and elaborate `top` with the extra `options` into
    `workdir`/<top>-<hash>/<top><suffix>, unless it is there already (the hash covers the texts and `salt`)."""
    key = digest(
        salt, top.lower(), suffix, " ".join(_CFLAGS), *(text for _, text in sources), *(text for _, text in foreign)
    )
    out = workdir.resolve() / f"{top.lower()}-{key[:16]}"
    target = out / f"{top.lower()}{suffix}"
    if not target.is_file():
        with staging(out) as tmp:
            work = tmp / "work"
            work.mkdir()
            _ghdl(
                ["-a", "--std=08", f"--workdir={work}", *(str(p) for p, _ in sources)],
                tmp,
                f"analysis of digital unit '{top}'",
            )
            objects = []
            for k, (c, _) in enumerate(foreign):
                objects.append(tmp / f"foreign{k}_{c.stem}.o")
                compile_c(
                    [CC, *_CFLAGS, "-c", str(c), "-o", str(objects[-1])],
                    f"{c}, the C code of digital unit '{top}' (VHPIDIRECT)",
                )
            _ghdl(
                [
                    "-e",
                    "--std=08",
                    f"--workdir={work}",
                    *options,
                    *(f"-Wl,{o}" for o in objects),
                    *_LINK,
                    "-o",
                    target.name,
                    top,
                ],
                tmp,
                f"elaboration of digital unit '{top}'",
            )
    return target


_C_SOURCE = re.compile(r"^\s*--\s*c source:\s*(\S+)\s*$", re.M | re.I)


def c_sources(sources: list[tuple[Path, bytes]], replace: dict[str, Path] | None = None) -> list[tuple[Path, bytes]]:
    """The C files that VHDL sources name in a `-- c source: FILE` line (relative to the VHDL file), with their
    texts: the VHPIDIRECT implementations GHDL links into the unit. `replace` maps a named file's name to another
    file that is linked instead (a user's implementation of the same functions)."""
    out: list[tuple[Path, bytes]] = []
    for path, text in sources:
        for name in _C_SOURCE.findall(text.decode("utf-8", "replace")):
            given = (replace or {}).get(Path(name).name)
            c = Path(given).resolve() if given is not None else (path.parent / name).resolve()
            try:
                out.append((c, c.read_bytes()))
            except OSError as e:
                what = (
                    f"{given}, given for its '-- c source: {name}',"
                    if given is not None
                    else f"its '-- c source: {name}'"
                )
                raise WrsimError(f"{path}: {what} cannot be read: {e.strerror}") from None
    return out


# --- helpers ---------------------------------------------------------------------------------------------------


def _check_ports(top: str, ports: list[DigitalPort]) -> None:
    seen: set[str] = set()
    for p in ports:
        if not IDENT.match(p.name) or p.name.lower() in seen:
            raise WrsimError(f"digital unit '{top}': port name '{p.name}' is not a VHDL identifier or is repeated")
        if p.direction not in ("in", "out"):
            raise WrsimError(
                f"digital unit '{top}': port '{p.name}' has direction '{p.direction}'; the co-simulation "
                f"carries only in and out ports"
            )
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
    out = workdir / f"ngghdl-{digest(version, ' '.join(_CFLAGS), *texts)[:16]}"
    glue_o, loader = out / "ngghdl_glue.o", out / "ngghdl_loader.so"
    if not loader.is_file():
        with staging(out) as tmp:
            compile_c([CC, *_CFLAGS, "-c", str(glue_c), "-o", str(tmp / glue_o.name)], "the co-simulation glue")
            compile_c(
                [CC, *_CFLAGS, "-shared", str(loader_c), "-o", str(tmp / loader.name), "-ldl"], "the co-simulation glue"
            )
    return glue_o, loader


_GHDL_LOC = re.compile(r"(?P<file>.+?):(?P<line>\d+):(?P<col>\d+):\s*(?P<msg>.*)")


def _ghdl(args: list[str], cwd: Path, what: str) -> None:
    """Run ghdl-llvm; a failure becomes a SourceError at GHDL's first `file:line:col:` (all its located lines
    quoted) or a WrsimError quoting GHDL's output."""
    proc = run_child([GHDL, *args], capture_output=True, text=True, cwd=cwd, timeout=TIMEOUT)
    if proc.returncode == 0:
        return
    lines = (proc.stderr + proc.stdout).splitlines()
    located = [m for m in map(_GHDL_LOC.match, lines) if m and not m["msg"].startswith("warning")]
    if located:
        first = located[0]
        rest = "".join(f"\n  {m.group(0)}" for m in located[1:])
        raise SourceError(Loc(first["file"], int(first["line"]), int(first["col"])), f"{first['msg']} ({what}){rest}")
    said = [ln for ln in lines if ln.strip()]
    raise WrsimError(f"{what} failed:\n  " + "\n  ".join(said or [f"{GHDL} exit status {proc.returncode}"]))


def ports_text(ports: list[DigitalPort]) -> str:
    return "(" + ", ".join(f"{p.direction} {p.name}[{p.width}]" for p in ports) + ")"
