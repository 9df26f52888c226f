"""Elaboration: the design library (`library`), scopes and symbolic evaluation (`scope`, `evaluate` and its parts,
`context`), the instance tree (`instances`) and one equation system per architecture (`elaborate` and the modules
of its statement kinds), producing the elaborated design (`design`), and the pairing pass that gives every equation
its unknown (`pairing`)."""

from __future__ import annotations

from wrsim.elab.design import ArchModel, Design, Equation, InstanceInfo, Unknown
from wrsim.elab.elaborate import check_param_set, elaborate
from wrsim.elab.library import Library, load_library, missing_units
from wrsim.elab.pairing import pair_equations, pair_model

__all__ = [
    "ArchModel",
    "Design",
    "Equation",
    "InstanceInfo",
    "Unknown",
    "check_param_set",
    "elaborate",
    "Library",
    "load_library",
    "missing_units",
    "pair_equations",
    "pair_model",
]
