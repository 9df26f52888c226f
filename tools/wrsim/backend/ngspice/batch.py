"""ngspice as a batch subprocess: the build step (netlist file, digital units built by GHDL, their d_cosim model
cards) and the run (binary raw file -> Waveforms). ngspice failures are reported in VHDL-AMS terms: the
quantity, its declaration and the equation that solves it, and the time point."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from wrsim import paths
from wrsim.backend import ghdl
from wrsim.backend.native import CC, compile_c, digest, run_child, staging
from wrsim.backend.ngspice import osdi, shared
from wrsim.backend.ngspice.netlist import EVENT_FILE, HOLDS_FILE, RAW_FILE, Netlist
from wrsim.backend.ngspice.raw import (
    SolverStatistics,
    Waveforms,
    check_finite,
    read_events,
    read_raw,
    sample_events,
)
from wrsim.errors import WrsimError

__all__ = ["NgspiceBatch", "MIN_NGSPICE", "DCOSIM_NGSPICE", "solver_statistics"]

MIN_NGSPICE = 46  # the one floor (ci/setup.sh and the README read it): OSDI devices, XSPICE d_cosim, libngspice
# The co-simulation glue reads d_cosim's private instance (its input queue, tools/cosim/ngghdl_glue.c input_due) as
# ngspice 46 lays it out (src/xspice/icm/digital/d_cosim/cfunc.mod): a design with digital units runs on that major
# version only, since on another the glue would read the wrong memory without a sign.
DCOSIM_NGSPICE = 46


@dataclass
class NgspiceBatch:
    """ngspice in batch mode (`ngspice -b netlist.cir`), one process per run folder; the netlist's .control
    section writes the raw file and the digital event record.

    `build` writes everything a run needs into its folder (the netlist, the digital units built by GHDL into
    the shared `cache`, their model cards, the crossing driver); `run` simulates what `build` wrote."""

    executable: str = "ngspice"
    name: str = "ngspice"
    cache: Path = paths.NATIVE
    c_files: dict[str, Path] = field(default_factory=dict)  # C files that replace, by file name, those the digital
    # sources name in `-- c source:` (a user's algorithm)
    _version: str | None = field(default=None, repr=False)

    def argv(self, netlist: Path, lowered: Netlist) -> list[str]:
        """The command that simulates `netlist` in its folder: `ngspice -b`, or the crossing driver that puts a
        time point at every 'above crossing when the netlist has guards (`wrsim.backend.ngspice.shared`)."""
        if lowered.ac or (not lowered.crossings and not lowered.holds):
            return [self.executable, "-b", str(netlist)]
        return shared.argv(
            shared.driver(self.cache),
            netlist,
            lowered.max_step,
            lowered.stop,
            [f"+{g}" if g in lowered.edge_only else g for g in lowered.crossings],
            netlist.parent / HOLDS_FILE if lowered.holds else None,
        )

    def check(self) -> str:
        """ngspice's version; raises WrsimError saying what to install when it is missing or too old."""
        if self._version:
            return self._version
        exe = shutil.which(self.executable)
        if exe is None:
            raise WrsimError(
                f"ngspice not found: install ngspice >= {MIN_NGSPICE} (on Debian 12: `make setup`, "
                f"which installs it from bookworm-backports)"
            )
        out = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=30).stdout
        m = re.search(r"ngspice-(\d+)", out)
        if not m or int(m.group(1)) < MIN_NGSPICE:
            raise WrsimError(
                f"ngspice >= {MIN_NGSPICE} required, found {m.group(0) if m else 'unknown version'} "
                f"(on Debian 12: `make setup` installs ngspice from bookworm-backports)"
            )
        self._version = m.group(0)
        return self._version

    def check_digital(self) -> None:
        """Refuse, with one error, an ngspice whose d_cosim the glue was not written for (DCOSIM_NGSPICE)."""
        major = int(self.check().split("-")[1])
        if major != DCOSIM_NGSPICE:
            raise WrsimError(
                f"ngspice-{major}: the co-simulation glue (tools/cosim/ngghdl_glue.c) reads d_cosim's input queue as "
                f"ngspice {DCOSIM_NGSPICE} lays it out, and a design with digital units cannot run on another "
                f"version (install ngspice {DCOSIM_NGSPICE}: on Debian 12 `make setup`)"
            )

    def build(self, netlist: Netlist, workdir: Path) -> Path:
        """Write the run folder: build the crossing driver if the netlist has 'above guards, every digital unit
        with GHDL and the compiled models (all cached), check the units' generics, write their d_cosim model cards,
        then the netlist.
        Returns the netlist file."""
        self.check()
        workdir.mkdir(parents=True, exist_ok=True)
        if netlist.crossings or netlist.holds:
            shared.driver(self.cache)
        if netlist.digital:
            self.check_digital()
            ghdl.check()
        for uid, use in enumerate(netlist.digital, start=1):
            ports = [ghdl.DigitalPort(p.name, p.mode, p.width or 1) for p in use.ports]
            unit = ghdl.build(use.entity, netlist.digital_files, ports, self.cache, self.c_files)
            ghdl.preflight(unit, use.generics, workdir)
            card = ghdl.model_card(unit, use.model, use.generics, workdir / f"{use.label}.args", uid, lazy=use.lazy)
            (workdir / use.include).write_text(card + "\n", encoding="utf-8")
        link = workdir / osdi.LIBRARY_FILE
        link.unlink(missing_ok=True)
        if netlist.devices:
            link.symlink_to(osdi.build(netlist.devices, self.cache))
        cir = workdir / "netlist.cir"
        netlist.write(cir)
        return cir

    def run(self, netlist: Netlist, workdir: Path, timeout: float = 600.0) -> Waveforms:
        """Simulate the netlist `build` wrote into `workdir` and return the waveforms (with the solver statistics
        of the log, `solver_statistics`)."""
        cir, raw, record = workdir / "netlist.cir", workdir / RAW_FILE, workdir / EVENT_FILE
        if not cir.is_file():
            raise WrsimError(f"{cir}: no netlist; build the run folder first (NgspiceBatch.build)")
        raw.unlink(missing_ok=True)
        record.unlink(missing_ok=True)
        t0 = time.perf_counter()
        try:
            proc = run_child(
                self.argv(cir, netlist),
                capture_output=True,
                text=True,
                timeout=timeout,
                cwd=workdir,
                env={**os.environ, **ghdl.RUN_ENV, **(_one_thread(self.cache) if netlist.devices else {})},
            )
        except subprocess.TimeoutExpired:
            raise WrsimError(f"ngspice did not finish within {timeout:g} s and was stopped ({cir})") from None
        seconds = time.perf_counter() - t0
        log = proc.stdout + proc.stderr
        (workdir / "ngspice.log").write_text(log, encoding="utf-8")
        problem = _failure(log, proc.returncode)
        if problem is None and not raw.exists():
            problem = "ngspice wrote no waveforms"
        if problem is None and netlist.events and not record.exists():
            problem = "ngspice wrote no record of the digital nodes"
        if problem is None and netlist.ac:
            data = read_raw(raw)
            frequency = data.get("frequency", np.zeros(0)).real
            if frequency.size < 1:
                problem = "ngspice wrote no small-signal analysis"
            else:
                return Waveforms(frequency, data, netlist.probes, log, seconds, solver_statistics(log))
        if problem is None:
            data = read_raw(raw)
            t = data.get("time", np.zeros(0))
            if t.size < 2 or t[-1] < netlist.stop * (1 - 1e-9):
                problem = (
                    f"ngspice stopped at t = {t[-1] if t.size else 0:.6g} s before the end of the analysis "
                    f"({netlist.stop:g} s)"
                )
            else:
                problem = _break_not_held(data, netlist) or _dot_not_at_rest(log, netlist)
        if problem:
            raise WrsimError(_explain(problem, log, netlist, cir))
        if not netlist.ac:
            _not_finite(data, netlist)
        if netlist.events:
            changes = read_events(record)
            for level, node in netlist.events.items():
                if node not in changes:
                    raise WrsimError(f"{record}: no record of digital node {node}")
                data[f"v({level})"] = sample_events(changes[node], data["time"])
        return Waveforms(data["time"], data, netlist.probes, log, seconds, solver_statistics(log))


_COUNTS = {  # what ngspice's `rusage all` (the netlist's .control), the GHDL glue and the crossing driver log
    "points": r"Accepted timepoints = (\d+)",
    "rejected": r"Rejected timepoints = (\d+)",
    "iterations": r"Transient iterations = (\d+)",
    "analysis": r"Transient analysis time = ([\d.]+)",
    "ghdl": r"ngghdl stats: .* wall_in_step=([\d.]+) s",
    "landed": r"wrsim crossings: .*",
    "late": r"wrsim late crossings per guard: .*",
}


def solver_statistics(log: str) -> SolverStatistics:
    """The solver statistics of a run's log (ngspice's output with the GHDL glue's and the crossing driver's
    lines); what the log does not say is 0."""
    total = dict.fromkeys(_COUNTS, 0.0)
    for key, pattern in _COUNTS.items():
        for m in re.finditer(pattern, log):
            if key in ("landed", "late"):
                total[key] += sum(int(n) for n in re.findall(r" (\d+)(?:,|$)", m.group(0)))
            else:
                total[key] += float(m.group(1))
    return SolverStatistics(
        int(total["points"]),
        int(total["rejected"]),
        int(total["iterations"]),
        total["analysis"],
        total["ghdl"],
        int(total["landed"]),
        int(total["late"]),
    )


_FATAL = [
    r"an event cascade",  # the crossing driver's: too many events in too little time ...
    r"accumulate \(a zeno model\)",  # ... or events that accumulate
    r"timestep too small",
    r"transient op failed",
    r"could not be simulated",
    r"simulation\(s\) aborted",
    r"error on line",
    r"unknown subckt",
    r"no such vector",
    r"error: .*",
    r"fatal",
]


def _not_finite(data: dict[str, np.ndarray], netlist: Netlist) -> None:
    """A saved waveform that is not a finite number somewhere (NaN, infinity: a square root of a negative value, a
    division by zero at run time) is one error naming the quantity: the run has no faithful result."""
    t = data["time"]
    vectors: dict[str, str] = {}
    for p in netlist.probes.values():
        for node in (p.plus, p.minus):
            if node and node != "0":
                vectors.setdefault(f"v({node})", p.name)
        if p.branch:
            vectors.setdefault(f"i({p.branch})", p.name)
    for vector, values in data.items():
        check_finite(vectors.get(vector, vector), values, t)


def _break_not_held(data: dict[str, np.ndarray], netlist: Netlist) -> str | None:
    """A break list at t = 0 that the quiescent point does not hold: 1076.1 replaces the quantity's 'dot = 0 by its
    value and keeps every other 'dot = 0, so equations that force another value contradict it (ngspice's .ic only
    pulls the node there through 1 TOhm and the equations win)."""
    for node, value, where in netlist.initial:
        got = data.get(f"v({node})")
        if got is not None and got.size and _off(float(got[0]), value):
            return (
                f"the quiescent point does not hold the break list's value {value:g} (it is {float(got[0]):.6g}): "
                f"the break at {where} contradicts the quiescent equations (1076.1 replaces that quantity's 'dot = 0 "
                f"by the value and keeps every other 'dot = 0; break those quantities too)"
            )
    return None


def _dot_not_at_rest(log: str, netlist: Netlist) -> str | None:
    """A q'dot the quiescent point does not hold at 0 (or at a break list's value), read from the operating point
    ngspice prints (its "Initial Transient Solution"): 1076.1's quiescent point has no solution then, since an
    equation asks another value of that derivative, and what ngspice found instead is no start a user can trust (an
    integrator of a constant, `x'dot == 1.0` without a break list, started from x = -1e-5 silently)."""
    if not netlist.at_rest or "Initial Transient Solution" not in log:
        return None
    table = log.split("Initial Transient Solution", 1)[1].split("\n\n\n", 1)[0]
    op = {}
    for line in table.splitlines():
        parts = line.split()
        if len(parts) == 2:
            try:
                op[parts[0].lower()] = float(parts[1])
            except ValueError:
                continue
    for node, value, quantity, where in netlist.at_rest:
        got = op.get(node)
        if got is not None and _off(got, value):
            return (
                f"the quiescent point has no solution: {quantity}'dot{where} is {got:.6g} there, but 1076.1 holds "
                f"every 'dot at {value:g} at the quiescent point{'' if value == 0.0 else ' (its break list)'} and an "
                f"equation asks another value; give the quantity its value at t = 0 (`break {quantity} => ...;`) or "
                f"an equation for the quiescent domain (`if domain = quiescent_domain use ...`)"
            )
    return None


def _off(got: float, value: float) -> bool:
    """The quiescent point's `got` is not the value 1076.1 asks (within a millionth of it, or of 1)."""
    return abs(got - value) > 1e-6 * max(1.0, abs(value))


def _failure(log: str, returncode: int) -> str | None:
    cosim_failure = ghdl.log_failure(log)
    if cosim_failure:
        return cosim_failure
    lines = log.splitlines()
    for k, line in enumerate(lines):
        low = line.lower()
        if any(re.search(p, low) for p in _FATAL) and "warning" not in low:
            if line.rstrip().endswith(":"):  # "Error on line 32 or its substitute:", the line and the reason follow
                return " ".join([line.strip(), *(ln.strip() for ln in lines[k + 1 : k + 3] if ln.strip())])
            return line.strip()
    if returncode != 0:
        return f"ngspice exited with status {returncode}"
    return None


# the crossing driver names the event in these errors
_DRIVER_NAMES_EVENT = (
    r"an event cascade|accumulate \(a Zeno model\)|below the resolution of time|the value assigned has none"
)

_BLAME = [r'trouble with node "?([^"\s]+)', r"check node\(?s?\)?:?\s+([^\s,]+)", r"^\s*in line (\S+)"]


def blamed_names(log: str) -> list[str]:
    """The netlist names ngspice blames for a failure, first blamed first: the node of "timestep too small ...
    trouble with node", of "singular matrix: check node", the element of "... in line" (not the node table)."""
    out: list[str] = []
    for line in log.lower().splitlines():
        for pattern in _BLAME:
            for name in re.findall(pattern, line):
                name = name.strip('"')
                if name not in out:
                    out.append(name)
    return out


def _explain(problem: str, log: str, netlist: Netlist, cir: Path) -> str:
    """Turn an ngspice failure into a message naming the VHDL-AMS quantities and equations ngspice blames."""
    lines = [f"simulation failed: {problem}"]
    # "...; time = 0.99, timestep = ..." (not the "... loading time = ..." lines of `rusage all`)
    m = re.search(r"(?:^|[;:,]\s*)time\s*=\s*([-+0-9.eE]+)", f"{problem}\n{log}", re.M)
    if m:
        lines.append(f"  at t = {float(m.group(1)):.6g} s")
    blamed = blamed_names(log)
    named: list[str] = []
    for name in blamed:
        what = netlist.source_map.get(name) or netlist.source_map.get(name.removesuffix("#branch"))
        if what and what not in named:
            named.append(what)
    if re.search(r"singular matrix", log, re.I):
        lines.append(
            "  the equation system is singular there (an unknown no equation determines, e.g. a coefficient that is 0)"
        )
    lines += [f"  {what}" for what in named[:4]]
    if not named and not re.search(_DRIVER_NAMES_EVENT, problem):
        lines.append("  ngspice names no node of the model")
        if netlist.devices:  # a device's truncation error names no node; a behavioural source's capacitor does
            lines.append("  (the equations are compiled: --no-compile runs them as behavioural sources, whose failure")
            lines.append("  names the quantity and the equation)")
    lines.append(f"  netlist: {cir}, log: {cir.parent / 'ngspice.log'}")
    return "\n".join(lines)


def _one_thread(cache: Path) -> dict[str, str]:
    """The environment that loads tools/cosim/one_thread_omp.c (built once per source into `cache`) before libgomp:
    ngspice's parallel region around each load of the compiled device runs on the calling thread, without libgomp's
    two futex calls per Newton iteration (a third of ngspice's time on the smallest benches)."""
    source = paths.COSIM / "one_thread_omp.c"
    text = source.read_bytes()
    folder = cache / f"one_thread_omp-{digest(text)[:16]}"
    library = folder / "one_thread_omp.so"
    if not library.is_file():
        with staging(folder) as tmp:
            compile_c([CC, "-O2", "-shared", "-fPIC", str(source), "-o", str(tmp / library.name)], "the OpenMP shim")
    preload = os.environ.get("LD_PRELOAD")
    return {"LD_PRELOAD": f"{library} {preload}" if preload else str(library)}
