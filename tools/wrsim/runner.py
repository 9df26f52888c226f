"""The one simulation path: lower an elaborated design, build the run folder (digital units first), run the
simulator, return the waveforms. Every bench, the identification bench and drive selection go through
`simulate`; `Runner` is the small interface a simulator backend offers (cocotb/VUnit style: an explicit build
step before the run)."""

from __future__ import annotations

from pathlib import Path
from typing import Protocol

from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import Analysis, Netlist, lower
from wrsim.backend.ngspice.raw import Waveforms
from wrsim.elab.design import Design

__all__ = ["Runner", "prepare", "simulate"]


class Runner(Protocol):
    """A simulator backend: `check` it is installed, `build` a run folder, `run` what was built."""

    name: str

    def check(self) -> str:
        """The simulator's version; raises WrsimError saying what to install when it is missing."""
        ...

    def build(self, netlist: Netlist, workdir: Path) -> Path:
        """Write everything the run needs into `workdir` (netlist, digital units); returns the netlist file."""
        ...

    def run(self, netlist: Netlist, workdir: Path, timeout: float = 600.0) -> Waveforms:
        """Simulate what `build` wrote into `workdir`: the waveforms, with the simulator's log, its wall time and
        the solver statistics read from the log (`Waveforms.statistics`)."""
        ...


def prepare(design: Design, analysis: Analysis, workdir: Path, runner: Runner, title: str = "") -> Netlist:
    """Lower `design` for `analysis` and build the run folder `workdir` (digital units, netlist)."""
    netlist = lower(design, analysis, title or design.top.entity.name)
    runner.build(netlist, workdir)
    return netlist


def simulate(
    design: Design, analysis: Analysis, workdir: Path, *, runner: Runner | None = None, title: str = ""
) -> Waveforms:
    """Lower `design` for `analysis`, build the run folder `workdir`, run it and return the waveforms."""
    runner = runner or NgspiceBatch()
    return runner.run(prepare(design, analysis, workdir, runner, title), workdir)
