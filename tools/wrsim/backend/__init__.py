"""Backends: `ngspice` (netlist generation, batch runs, raw files) for the analog part and `ghdl` (builds of the
digital units and their d_cosim co-simulation inside ngspice)."""
