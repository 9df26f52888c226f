"""The co-simulation step between a GHDL build and an ngspice run: each digital instance's d_cosim model card and
element line, its generics checked by loading the design in a separate process (preflight), and the failures a
co-simulation leaves in the ngspice log. The contract is in `wrsim.backend.ghdl.build`'s docstring."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

from wrsim.backend.ghdl.build import (
    IDENT,
    DigitalBuild,
    DigitalPort,
    ports_text,
)
from wrsim.backend.native import TIMEOUT, run_child
from wrsim.errors import WrsimError

__all__ = ["RUN_ENV", "preflight", "model_card", "instance_line", "log_failure"]


RUN_ENV: dict[str, str] = {"NGGHDL_FATAL": "1", "NGGHDL_STATS": "1"}


_NODE = re.compile(r"[A-Za-z0-9_.#$]+\Z")


_SPICE_STRING_UNSAFE = re.compile(r'[A-Z\s"=\[\]{}]')


def model_card(
    build: DigitalBuild,
    model_name: str,
    generics: dict[str, int | bool | str],
    args_file: Path,
    uid: int,
    *,
    vcd: Path | None = None,
    delay: float = 1e-6,
    lazy: Sequence[str] = (),
) -> str:
    """Write GHDL's run options (generics as -gNAME=VALUE, optionally --vcd=FILE) to `args_file` and return the
    `.model` line of one d_cosim instance. `uid` is the instance's `irreversible=` number, unique in the netlist
    and >= 1; `delay` [s] is the delay d_cosim adds to every output change. `lazy` names output ports that no
    analog element reads: their changes are reported at the end of the analog step instead of cutting it back to
    the change (the glue's "+lazy=NAME").

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
    names = {
        "loader": build.loader.name,
        "design library": f"{model_name}_{build.library.name}",
        "args file": args_file.name,
    }
    for what, name in names.items():
        if _SPICE_STRING_UNSAFE.search(name):
            raise WrsimError(
                f"d_cosim model '{model_name}': {what} name {name} cannot go on a .model line (ngspice "
                f"lower-cases it and mangles '=', quotes and blanks): use only lower-case letters, "
                f"digits and ._-"
            )
    for name in lazy:
        if not IDENT.match(name) or name.lower() not in {p.name.lower() for p in build.outputs}:
            raise WrsimError(f"d_cosim model '{model_name}': {name} is not an output port of {build.top}")
    _write_args(args_file, generics, vcd, lazy, delay)
    for target, name in ((build.loader, names["loader"]), (build.library, names["design library"])):
        link = run_dir / name
        if link.is_symlink() or link.exists():
            link.unlink()
        link.symlink_to(target.resolve())
    return (
        f'.model {model_name} d_cosim(simulation="./{names["loader"]}" lib_args=["./{names["design library"]}"] '
        f'sim_args=["{build.top.lower()}" "@./{names["args file"]}"] delay={delay:.6g} irreversible={uid})'
    )


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


_VHDL_FAILURE = re.compile(r":\((assertion|report) failure\):|^\S+:error: ")


_COSIM_FAILURE = re.compile(
    r"ngghdl(_loader)?: error: |d_cosim failed to load|no entry function in|"
    r"mismatched XSPICE/co-simulator|Duplicate value \d+ in cm_irreversible|"
    r"VHDL simulation ended at .* with status [1-9]"
)


def _write_args(
    path: Path,
    generics: dict[str, int | bool | str],
    vcd: Path | None,
    lazy: Sequence[str] = (),
    delay: float | None = None,
) -> None:
    """GHDL run options, one per line (the glue's @file format): -gNAME=VALUE per generic, then --vcd=FILE, then the
    glue's own +lazy=PORT lines and +delay=SECONDS (d_cosim's output delay, which tells the glue when d_cosim cuts
    its step back for a report)."""
    lines = []
    for name, value in generics.items():
        if not IDENT.match(name):
            raise WrsimError(f"generic name '{name}' is not a VHDL identifier")
        if isinstance(value, bool):
            text = "true" if value else "false"
        elif isinstance(value, (int, str)):
            text = str(value)
        else:
            raise WrsimError(
                f"generic '{name}' = {value!r}: only integer, boolean and string generics can be set on a GHDL top"
            )
        if "\n" in text or "\r" in text:
            raise WrsimError(f"generic '{name}': value must not contain a line break")
        lines.append(f"-g{name}={text}")
    if vcd is not None:
        lines.append(f"--vcd={vcd.resolve()}")
    lines += [f"+lazy={name}" for name in lazy]
    if delay is not None:
        lines.append(f"+delay={delay:.6g}")
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text("".join(f"{ln}\n" for ln in lines), encoding="utf-8")
    os.replace(tmp, path)


def _generics_text(generics: dict[str, int | bool | str]) -> str:
    return ", ".join(f"{k}={v!r}" for k, v in generics.items()) if generics else "default generics"


def preflight(build: DigitalBuild, generics: dict[str, int | bool | str], workdir: Path) -> None:
    """Load `build` with `generics` the way ngspice will (loader, args file, glue) in a separate process and run
    VHDL time 0 with all inputs '0'. Unknown or out-of-range generics, elaboration errors and failing generic
    assertions raise WrsimError with GHDL's own message; so does a port map that differs from `build.ports`."""
    workdir.mkdir(parents=True, exist_ok=True)
    args = workdir / f"{build.top.lower()}.preflight.args"
    _write_args(args, generics, None)
    env = {**os.environ, **RUN_ENV, "NGGHDL_PORTS": "1"}
    try:
        proc = run_child(
            [
                sys.executable,
                "-I",
                "-S",
                "-c",
                _PROBE,
                str(build.loader),
                str(build.library),
                build.top,
                f"@{args.resolve()}",
            ],
            capture_output=True,
            text=True,
            env=env,
            cwd=workdir,
            timeout=TIMEOUT,
        )
    except subprocess.TimeoutExpired:
        raise WrsimError(f"preflight of digital unit '{build.top}' did not finish within {TIMEOUT:.0f} s") from None
    lines = [ln.rstrip() for ln in (proc.stderr + proc.stdout).splitlines() if ln.strip()]
    said = [ln for ln in lines if not _NOISE.match(ln)]
    if proc.returncode != 0:
        raise WrsimError(
            f"digital unit '{build.top}' with {_generics_text(generics)} fails before the simulation "
            f"starts:\n  " + "\n  ".join(said or [f"exit status {proc.returncode}"])
        )
    port_lines = [re.match(r"ngghdl: (in|out) +(\S+) (\d+) ", ln + " ") for ln in lines]
    seen = [DigitalPort(m[2], "in" if m[1] == "in" else "out", int(m[3])) for m in port_lines if m]
    want = [DigitalPort(p.name.lower(), p.direction, p.width) for p in build.inputs + build.outputs]
    if seen != want:
        raise WrsimError(
            f"digital unit '{build.top}': GHDL sees the ports {ports_text(seen)}, the netlist expects "
            f"{ports_text(want)} (in ports, then out ports, in declaration order)"
        )


_NOISE = re.compile(
    r"loading VPI module |VPI module loaded!|ngghdl: (in|out) |ngghdl: VHDL simulation ended |"
    r"ngghdl: error: VHDL simulation failed \(NGGHDL_FATAL"
)


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
