"""GHDL backend: a digital top entity built into a shared library with wrsim's VPI glue (`build`), and the
co-simulation step that couples it to ngspice through XSPICE d_cosim (`cosim`)."""

from __future__ import annotations

from wrsim.backend.ghdl.build import DigitalBuild, DigitalPort, build, check
from wrsim.backend.ghdl.cosim import (
    RUN_ENV,
    instance_line,
    log_failure,
    model_card,
    preflight,
)

__all__ = [
    "DigitalBuild",
    "DigitalPort",
    "build",
    "check",
    "RUN_ENV",
    "instance_line",
    "log_failure",
    "model_card",
    "preflight",
]
