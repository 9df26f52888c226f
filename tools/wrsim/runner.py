"""Running a lowered netlist and reading the waveforms back.

A runner is a small interface: it builds the command line (`argv`) and knows how to read its result.
The default is ngspice as a batch subprocess writing a binary raw file. ngspice failures are reported in
VHDL-AMS terms: the quantity, its declaration and the equation that solves it, and the time point."""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import time
from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import ghdl
from .errors import WrsimError
from .ngspice import Netlist, Probe

__all__ = ["Waveforms", "Runner", "NgspiceBatch", "read_raw", "MIN_NGSPICE"]

MIN_NGSPICE = 42


@dataclass
class Waveforms:
    """Simulated quantities by hierarchical VHDL-AMS name (instance labels joined by dots)."""

    time: np.ndarray
    vectors: dict[str, np.ndarray]
    probes: dict[str, Probe]
    log: str = ""
    seconds: float = 0.0

    def __contains__(self, name: str) -> bool:
        return name in self.probes

    def __getitem__(self, name: str) -> np.ndarray:
        p = self.probes.get(name)
        if p is None:
            raise WrsimError(f"no quantity '{name}' in the simulation (quantities: {', '.join(sorted(self.probes))})")
        try:
            if p.branch is not None:
                return self.vectors[f"i({p.branch})"]
            if p.bits is not None:
                bits = [self._v(b) > 0.5 for b in p.bits]
                value = sum(b.astype(float) * 2.0 ** k for k, b in enumerate(bits))
                if p.signed and len(bits) > 1:
                    value -= bits[-1] * 2.0 ** len(bits)
                return value
            return self._v(p.plus) - self._v(p.minus)
        except KeyError as e:
            raise WrsimError(f"quantity '{name}' was not saved (no vector {e.args[0]}): add it to the bench's "
                             f"save list") from None

    def unit(self, name: str) -> str:
        self[name]
        return self.probes[name].unit

    def _v(self, node: str | None) -> np.ndarray:
        if node in (None, "0"):
            return np.zeros_like(self.time)
        return self.vectors[f"v({node})"]


class Runner(ABC):
    """A simulator behind a command line."""

    name: str = "simulator"

    @abstractmethod
    def argv(self, netlist: Path, raw: Path) -> list[str]:
        """The command that simulates `netlist` and writes its waveforms to `raw`."""

    @abstractmethod
    def check(self) -> str:
        """The simulator's version; raises WrsimError saying what to install when it is missing."""

    @abstractmethod
    def run(self, netlist: Netlist, workdir: Path, timeout: float = 600.0) -> Waveforms:
        """Simulate and return the waveforms."""


@dataclass
class NgspiceBatch(Runner):
    """ngspice in batch mode (`ngspice -b -r out.raw netlist.cir`)."""

    executable: str = "ngspice"
    name: str = "ngspice"
    ghdl_cache: Path = Path(__file__).resolve().parents[2] / "build" / "ghdl"   # built digital units
    _version: str | None = field(default=None, repr=False)

    def argv(self, netlist: Path, raw: Path) -> list[str]:
        return [self.executable, "-b", "-r", str(raw), str(netlist)]

    def check(self) -> str:
        if self._version:
            return self._version
        exe = shutil.which(self.executable)
        if exe is None:
            raise WrsimError(f"ngspice not found: install ngspice >= {MIN_NGSPICE} (on Debian 12: `make setup`, "
                             f"which installs it from bookworm-backports)")
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
        m = re.search(r"ngspice-(\d+)", out)
        if not m or int(m.group(1)) < MIN_NGSPICE:
            raise WrsimError(f"ngspice >= {MIN_NGSPICE} required, found {m.group(0) if m else 'unknown version'} "
                             f"(on Debian 12: `make setup` installs ngspice from bookworm-backports)")
        self._version = m.group(0)
        return self._version

    def run(self, netlist: Netlist, workdir: Path, timeout: float = 600.0) -> Waveforms:
        self.check()
        workdir.mkdir(parents=True, exist_ok=True)
        cir, raw = workdir / "netlist.cir", workdir / "waveforms.raw"
        self.prepare_digital(netlist, workdir)
        netlist.write(cir)
        raw.unlink(missing_ok=True)
        t0 = time.perf_counter()
        try:
            proc = subprocess.run(self.argv(cir, raw), capture_output=True, text=True, timeout=timeout,
                                  cwd=workdir, env={**os.environ, **ghdl.RUN_ENV})
        except subprocess.TimeoutExpired:
            raise WrsimError(f"ngspice did not finish within {timeout:.0f} s ({cir})") from None
        seconds = time.perf_counter() - t0
        log = proc.stdout + proc.stderr
        (workdir / "ngspice.log").write_text(log, encoding="utf-8")
        problem = _failure(log, proc.returncode)
        if problem is None and not raw.exists():
            problem = "ngspice wrote no waveforms"
        if problem is None:
            data = read_raw(raw)
            t = data.get("time", np.zeros(0))
            if t.size < 2 or t[-1] < netlist.stop * (1 - 1e-9):
                problem = (f"ngspice stopped at t = {t[-1] if t.size else 0:.6g} s before the end of the analysis "
                           f"({netlist.stop:g} s)")
        if problem:
            raise WrsimError(_explain(problem, log, netlist, cir))
        return Waveforms(data["time"], data, netlist.probes, log, seconds)


    def prepare_digital(self, netlist: Netlist, workdir: Path) -> None:
        """Build every digital unit with GHDL (cached), check its generics, and write its d_cosim model card."""
        if not netlist.digital:
            return
        ghdl.check()
        for uid, use in enumerate(netlist.digital, start=1):
            ports = [ghdl.DigitalPort(p.name, p.mode, p.width or 1) for p in use.ports]
            build = ghdl.build(use.entity, netlist.digital_files, ports, self.ghdl_cache)
            ghdl.preflight(build, use.generics, workdir)
            card = ghdl.model_card(build, use.model, use.generics, workdir / f"{use.label}.args", uid)
            (workdir / use.include).write_text(card + "\n", encoding="utf-8")


_FATAL = [r"timestep too small", r"transient op failed", r"could not be simulated",
          r"simulation\(s\) aborted", r"error on line", r"unknown subckt", r"no such vector",
          r"error: .*", r"fatal"]


def _failure(log: str, returncode: int) -> str | None:
    cosim = ghdl.log_failure(log)
    if cosim:
        return cosim
    for line in log.splitlines():
        low = line.lower()
        if any(re.search(p, low) for p in _FATAL) and "warning" not in low:
            return line.strip()
    if returncode != 0:
        return f"ngspice exited with status {returncode}"
    return None


def _explain(problem: str, log: str, netlist: Netlist, cir: Path) -> str:
    """Turn an ngspice failure into a message naming VHDL-AMS quantities and equations."""
    lines = [f"simulation failed: {problem}"]
    m = re.search(r"time\s*=\s*([-+0-9.eE]+)", log)
    if m:
        lines.append(f"  at t = {float(m.group(1)):.6g} s")
    named = []
    low = log.lower()
    # the node ngspice blames first, then any other netlist name the log mentions
    blamed = re.findall(r"(?:trouble with|check) node \"?([^\"\s]+)", low)
    for token in blamed + re.findall(r"[a-z0-9_.#]+", low):
        for cand in (token, token.split("#")[0], token.split("#")[0].removeprefix("v.").removeprefix("e.")):
            if cand in netlist.source_map and netlist.source_map[cand] not in named:
                named.append(netlist.source_map[cand])
    for what in named[:4]:
        lines.append(f"  {what}")
    lines.append(f"  netlist: {cir}, log: {cir.parent / 'ngspice.log'}")
    return "\n".join(lines)


def read_raw(path: Path) -> dict[str, np.ndarray]:
    """Read an ngspice binary raw file (real data) into {vector name (lower case): values}."""
    try:
        data = path.read_bytes()
    except OSError as e:
        raise WrsimError(f"{path}: cannot read raw file: {e}") from None
    marker = data.find(b"Binary:\n")
    if marker < 0:
        raise WrsimError(f"{path}: not an ngspice binary raw file")
    header = data[:marker].decode("latin-1").splitlines()
    nvars = npts = 0
    names: list[str] = []
    try:
        for k, line in enumerate(header):
            if line.startswith("No. Variables:"):
                nvars = int(line.split(":")[1])
            elif line.startswith("No. Points:"):
                npts = int(line.split(":")[1])
            elif line.startswith("Flags:") and "complex" in line:
                raise WrsimError(f"{path}: complex data is not supported")
            elif line.startswith("Variables:"):
                names = [header[k + 1 + j].split()[1].lower() for j in range(nvars)]
    except (ValueError, IndexError):
        raise WrsimError(f"{path}: malformed raw file header (line {k + 1}: {line!r})") from None
    if not names or len(names) != nvars:
        raise WrsimError(f"{path}: malformed raw file header ({nvars} variables declared, {len(names)} listed)")
    body = np.frombuffer(data[marker + 8:marker + 8 + 8 * nvars * npts], dtype="<f8")
    if body.size != nvars * npts:
        raise WrsimError(f"{path}: truncated raw file")
    arr = body.reshape(npts, nvars)
    return {n: arr[:, j].copy() for j, n in enumerate(names)}
