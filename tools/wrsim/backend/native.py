"""Native code the backends build on first use (the GHDL co-simulation glue, the ngspice crossing driver):
content-addressed folders in the build tree, each built in a staging folder and renamed into place."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from wrsim.errors import WrsimError

__all__ = ["CC", "TIMEOUT", "staging", "digest", "compile_c", "run_child"]

CC = "gcc"
TIMEOUT = 300.0


class staging:
    """Build into a fresh folder next to `final` and rename it into place on success (atomic; a concurrent
    builder that finished first wins, ours is dropped)."""

    def __init__(self, final: Path):
        self.final = final

    def __enter__(self) -> Path:
        self.final.parent.mkdir(parents=True, exist_ok=True)
        self.tmp = Path(tempfile.mkdtemp(prefix=f".{self.final.name}-", dir=self.final.parent))
        return self.tmp

    def __exit__(self, exc_type: object, exc: object, tb: object) -> None:
        if exc_type is None:
            try:
                os.rename(self.tmp, self.final)
                return
            except OSError:
                if not self.final.is_dir():
                    raise
        shutil.rmtree(self.tmp, ignore_errors=True)


def digest(*parts: str | bytes) -> str:
    """SHA-256 of the parts, each length-prefixed (no two part lists collide)."""
    h = hashlib.sha256()
    for part in parts:
        data = part.encode() if isinstance(part, str) else part
        h.update(len(data).to_bytes(8, "little"))
        h.update(data)
    return h.hexdigest()


def run_child(cmd: list[str], **kwargs: Any) -> subprocess.CompletedProcess:
    """subprocess.run for the simulator, GHDL and the compiler: the child dies with wrsim. subprocess.run kills it
    when the wait ends in an exception (a timeout, Ctrl-C); on Linux the child also asks the kernel for SIGKILL when
    its parent dies (PR_SET_PDEATHSIG, set by util-linux's setpriv, which then runs the command: a preexec function
    would make every start a fork of the whole Python process, 13 ms instead of 1), so that a wrsim killed by a CI
    job's timeout (SIGKILL, SIGTERM) leaves no simulator running on. Text output is decoded with replacement: a
    child that echoes a user's byte that is not UTF-8 (GHDL reporting a switch-sequence line) says so in its message
    instead of breaking wrsim."""
    if kwargs.get("text"):
        kwargs.setdefault("errors", "replace")
    return subprocess.run([*_WITH_PARENT, *cmd], **kwargs)


_SETPRIV = shutil.which("setpriv") if sys.platform == "linux" else None
_WITH_PARENT = [_SETPRIV, "--pdeathsig", "KILL", "--"] if _SETPRIV else []


def compile_c(cmd: list[str], what: str) -> None:
    """Run a compiler command; a failure is a WrsimError quoting the compiler."""
    if shutil.which(cmd[0]) is None:
        raise WrsimError(f"cannot compile {what}: {cmd[0]} not found (make setup installs gcc)")
    proc = run_child(cmd, capture_output=True, text=True, timeout=TIMEOUT)
    if proc.returncode != 0:
        raise WrsimError(f"cannot compile {what} ({' '.join(cmd)}):\n{proc.stderr.strip()}")
