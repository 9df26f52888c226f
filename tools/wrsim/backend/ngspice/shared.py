"""The crossing driver: ngspice as a shared library (libngspice), for netlists with `q'above(e)` guards, so that
an 'above event (an A->D edge, a switch of equations) lands on its crossing within `RESOLUTION` whatever the
step size (IEEE 1076.1 puts an analog solution point at every 'above event). ngspice has no such mechanism for
behavioural sources; its shared-library interface offers the two callbacks this needs: the values of every
accepted point (SendData) and the step about to be taken, which the caller may shorten (GetSyncData).

The driver is a small C program, tools/cosim/wrsim_ngspice.c (the policy is described there and measured in
docs/performance.md), compiled on first use into the build tree and linked against libngspice; callbacks in
Python cost about 90 us per time point, more than the points the crossings save. It runs like `ngspice -b`,
one process per run in the run folder: it sources the netlist, whose .control section runs the analysis and
writes the raw file and the event record, and prints ngspice's messages. The same driver holds the values that
change only at events (a break's re-initialisation, signals of processes, samples), see `netlist.HOLDS_FILE`."""

from __future__ import annotations

from pathlib import Path

from wrsim import paths
from wrsim.backend.native import CC, compile_c, digest, staging
from wrsim.errors import WrsimError

__all__ = ["RESOLUTION", "HEADER", "driver", "argv"]

RESOLUTION = 1e-6  # [s] an 'above event lands at most this long after its crossing
HEADER = Path("/usr/include/ngspice/sharedspice.h")
_SOURCE = paths.COSIM / "wrsim_ngspice.c"
_CFLAGS = ["-O2", "-Wall", "-Wextra"]
_INSTALL = "on Debian 12: `make setup` installs libngspice0 and libngspice0-dev of ngspice's own version"


def driver(cache: Path) -> Path:
    """The compiled crossing driver in `cache` (built once per source and header)."""
    try:
        texts = [_SOURCE.read_bytes(), HEADER.read_bytes()]
    except OSError as e:
        what = "ngspice's shared-library header" if e.filename == str(HEADER) else "the crossing driver's source"
        raise WrsimError(
            f"{what} missing: {e.filename} ({e.strerror}); a model with 'above needs it ({_INSTALL})"
        ) from None
    out = cache / f"wrsim_ngspice-{digest(' '.join(_CFLAGS), *texts)[:16]}"
    exe = out / "wrsim_ngspice"
    if not exe.is_file():
        with staging(out) as tmp:
            compile_c(
                [CC, *_CFLAGS, str(_SOURCE), "-o", str(tmp / exe.name), "-lngspice", "-lm", "-lpthread"],
                f"the crossing driver ({_INSTALL})",
            )
    return exe


def argv(
    exe: Path, netlist: Path, max_step: float, stop: float, guards: list[str], holds: Path | None = None
) -> list[str]:
    """The command that simulates `netlist` with time points at the zeros of `guards` (raw node names; +NAME for a
    guard whose crossing switches no equation, after which the driver resumes the step it had planned) and the
    held values of the table `holds` (netlist.HOLDS_FILE)."""
    return [str(exe), repr(max_step), repr(stop), repr(RESOLUTION), str(netlist), str(holds or "-"), *guards]
