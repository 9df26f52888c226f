"""ngspice backend: the readable netlist (`netlist`: one .subckt per architecture, source lines as comments), the
batch runner (`batch`), the binary raw file (`raw`)."""

from __future__ import annotations

from wrsim.backend.ngspice.batch import MIN_NGSPICE, NgspiceBatch
from wrsim.backend.ngspice.netlist import Analysis, Netlist, Probe, lower
from wrsim.backend.ngspice.raw import Waveforms, read_raw

__all__ = ["MIN_NGSPICE", "NgspiceBatch", "Analysis", "Netlist", "Probe", "lower", "Waveforms", "read_raw"]
