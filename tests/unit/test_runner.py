"""The ngspice runner: a missing or old ngspice says what to install; a failed simulation is a WrsimError in
VHDL-AMS terms (instance path, quantity, the equation's file:line:col); waveforms that do not cover the
analysis are never returned as a result; unreadable raw files are a clear error."""

from __future__ import annotations

import os
import random
import re
import signal
import stat
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from wrsim import paths
from wrsim.backend.native import run_child
from wrsim.backend.ngspice.batch import DCOSIM_NGSPICE, MIN_NGSPICE, NgspiceBatch, solver_statistics
from wrsim.backend.ngspice.netlist import Analysis, lower
from wrsim.backend.ngspice.raw import SolverStatistics, read_events, read_raw, sample_events
from wrsim.elab.design import Design
from wrsim.elab.elaborate import elaborate
from wrsim.elab.library import load_library
from wrsim.errors import WrsimError
from wrsim.runner import simulate

ROOT = paths.ROOT
USES = "library IEEE;\nuse IEEE.MATH_REAL.all;\n"
INSTALL = f"install ngspice >= {MIN_NGSPICE}"


class Model:
    """A VHDL-AMS file written to tmp_path and its bench `tb`, elaborated."""

    def __init__(self, tmp_path: Path, *units: str):
        self.text = "".join(USES + u for u in units)
        self.path = tmp_path / "model.vhd"
        self.path.write_text(self.text, encoding="utf-8")
        self.design: Design = elaborate(load_library([ROOT / "vhdl" / "ieee", self.path]), "tb")

    def at(self, marker: str) -> str:
        """`file:line:col` of the first occurrence of `marker`."""
        k = self.text.index(marker)
        return f"{self.path}:{self.text.count(chr(10), 0, k) + 1}:{k - self.text.rfind(chr(10), 0, k)}"

    def run(
        self, workdir: Path, stop: float = 1e-3, max_step: float | None = None, runner=None, compiled: bool = False
    ):
        analysis = Analysis(stop, max_step, compiled=compiled)
        return simulate(self.design, analysis, workdir, runner=runner, title="test")

    def failure(self, workdir: Path, stop: float = 1e-3, max_step: float | None = None, compiled: bool = False) -> str:
        with pytest.raises(WrsimError) as err:
            self.run(workdir, stop, max_step, compiled=compiled)
        return str(err.value)


def tb(decls: str, stmts: str) -> str:
    return f"entity tb is end entity tb;\narchitecture s of tb is\n{decls}\nbegin\n{stmts}\nend architecture s;\n"


def write_raw(path: Path, names: list[str], rows: np.ndarray, points: int | None = None) -> Path:
    """An ngspice binary raw file (real data) with the vectors `names` and one row per time point."""
    header = [
        "Title: test",
        "Date: today",
        "Plotname: Transient Analysis",
        "Flags: real",
        f"No. Variables: {len(names)}",
        f"No. Points: {len(rows) if points is None else points}",
        "Variables:",
    ]
    header += [f"\t{k}\t{n}\t{'time' if k == 0 else 'voltage'}" for k, n in enumerate(names)]
    path.write_bytes(("\n".join(header) + "\nBinary:\n").encode() + np.asarray(rows, dtype="<f8").tobytes())
    return path


def fake_ngspice(tmp_path: Path, version: str, raw: Path | None = None) -> Path:
    """A stand-in executable: prints `version` for --version, else copies `raw` to the -r target, exit 0."""
    exe = tmp_path / "fake-ngspice"
    copy = f'cp "{raw}" "$3"' if raw else "true"
    exe.write_text(
        f'#!/bin/sh\nif [ "$1" = "--version" ]; then echo "** {version} : Circuit level simulation '
        f'program"; exit 0; fi\n{copy}\n',
        encoding="utf-8",
    )
    exe.chmod(exe.stat().st_mode | stat.S_IXUSR)
    return exe


# ------------------------------------------------------------------------------------------------ the simulator
def test_missing_ngspice_says_what_to_install(tmp_path):
    runner = NgspiceBatch(executable=str(tmp_path / "no-ngspice"))
    with pytest.raises(WrsimError, match=rf"^ngspice not found: {INSTALL} \(on Debian 12: `make setup`"):
        runner.check()
    model = Model(tmp_path, tb("  quantity x : real;  -- [1] x", "  x == 2.0;"))
    with pytest.raises(WrsimError, match=rf"^ngspice not found: {INSTALL}"):
        model.run(tmp_path / "work", runner=runner)
    assert not (tmp_path / "work").exists()


def test_old_ngspice_says_what_to_install(tmp_path):
    runner = NgspiceBatch(executable=str(fake_ngspice(tmp_path, "ngspice-40")))
    with pytest.raises(WrsimError) as err:
        runner.check()
    assert str(err.value) == (
        f"ngspice >= {MIN_NGSPICE} required, found ngspice-40 (on Debian 12: `make setup` "
        f"installs ngspice from bookworm-backports)"
    )


def test_one_ngspice_floor_and_digital_units_only_on_the_d_cosim_the_glue_reads(tmp_path):
    """The set-up script installs the floor the runner checks, and a design with digital units is refused on an
    ngspice whose private d_cosim layout the glue was not written for (it would read the wrong memory)."""
    setup = (paths.ROOT / "ci" / "setup.sh").read_text(encoding="utf-8")
    assert re.search(r"^NGSPICE_MIN=(\d+)", setup, re.M).group(1) == str(MIN_NGSPICE)
    assert f"ngspice {MIN_NGSPICE} and its shared library" in (paths.ROOT / "README.md").read_text(encoding="utf-8")
    assert NgspiceBatch(executable=str(fake_ngspice(tmp_path, f"ngspice-{DCOSIM_NGSPICE}"))).check_digital() is None
    newer = NgspiceBatch(executable=str(fake_ngspice(tmp_path, f"ngspice-{DCOSIM_NGSPICE + 1}")))
    assert newer.check() == f"ngspice-{DCOSIM_NGSPICE + 1}"  # analog designs run on it
    with pytest.raises(WrsimError, match=rf"^ngspice-{DCOSIM_NGSPICE + 1}: the co-simulation glue .* ngspice 46 lays"):
        newer.check_digital()


def test_waveforms_by_vhdl_ams_name(tmp_path):
    model = Model(tmp_path, tb("  quantity x : real;  -- [V] x", "  x == 2.0;"))
    waves = model.run(tmp_path / "work")
    assert waves.time[0] == 0.0 and waves.time[-1] == pytest.approx(1e-3)
    np.testing.assert_allclose(waves["x"], 2.0, rtol=1e-9)
    assert waves.unit("x") == "V"
    with pytest.raises(WrsimError, match=r"^no quantity 'y' in the simulation \(quantities: x\)$"):
        waves["y"]


def test_the_run_skips_ngspices_memory_check_at_every_point(tmp_path):
    """ngspice 46 reads /proc/meminfo at every accepted point to check that the output still fits in memory,
    unless the variable no_mem_check is set: the netlist's .control section sets it before the run (strace on the
    normalization bench: 16,274 reads before, 2 after; docs/performance.md)."""
    model = Model(tmp_path, tb("  quantity x : real;  -- [V] x", "  x == 2.0;"))
    for compiled in (False, True):
        lines = lower(model.design, Analysis(1e-3, compiled=compiled), "test").text.splitlines()
        control = lines[lines.index(".control") :]
        assert control[control.index("run") - 1] == "set no_mem_check"


def test_a_save_list_writes_only_its_quantities(tmp_path):
    model = Model(
        tmp_path, tb("  quantity x : real;  -- [V] x\n  quantity y : real;  -- [V] y", "  x == 2.0;\n  y == 3.0;")
    )
    netlist = lower(model.design, Analysis(1e-3, save=("y",)), "test")
    assert ".save v(y)" in netlist.text.splitlines()
    runner = NgspiceBatch()
    runner.build(netlist, tmp_path / "work")
    waves = runner.run(netlist, tmp_path / "work")
    np.testing.assert_allclose(waves["y"], 3.0, rtol=1e-9)
    with pytest.raises(
        WrsimError, match=r"^quantity 'x' was not saved \(no vector v\(x\)\): add it to the bench's save list$"
    ):
        waves["x"]
    with pytest.raises(WrsimError, match=r"cannot save z: no such quantity or signal in test"):
        lower(model.design, Analysis(1e-3, save=("z",)), "test")


# ------------------------------------------------------------------------------------------------ failures
def test_nonconvergent_model_names_the_quantity_and_its_equation(tmp_path):
    model = Model(tmp_path, tb("  quantity x : real;  -- [1] x", "  x * x == -1.0;"))  # no real solution
    work = tmp_path / "work"
    msg = model.failure(work)
    assert msg.startswith("simulation failed: ")
    assert (
        f"quantity x (free, declared at {model.at('quantity x')}), solved by the equation at "
        f"{model.at('x * x')}: x * x == -1.0;"
    ) in msg
    assert f"netlist: {work / 'netlist.cir'}, log: {work / 'ngspice.log'}" in msg


def test_failure_inside_an_instance_names_the_instance_path(tmp_path):
    bad = (
        "entity bad is\n  port (quantity q : out real);  -- [1] q\nend entity bad;\n"
        "architecture a of bad is\n  quantity y : real;  -- [1] y\nbegin\n"
        "  y * y == -1.0 - q * q;\n  q == 1.0;\nend architecture a;\n"
    )
    model = Model(tmp_path, bad, tb("  quantity x : real;  -- [1] x", "  u1: entity work.bad port map (q => x);"))
    msg = model.failure(tmp_path / "work")
    assert (
        f"quantity u1.y (free, declared at {model.at('quantity y')}), solved by the equation at "
        f"{model.at('y * y')}: y * y == -1.0 - q * q;"
    ) in msg


BLOW_UP = tb(
    "  quantity x : real;  -- [1] x = 1/(1 - t), infinite at t = 1 s",
    "  if domain = quiescent_domain use\n    x == 1.0;\n  else\n    x'dot == x * x;\n  end use;",
)


def test_failure_during_the_transient_is_an_error_with_its_time(tmp_path):
    # the raw file holds the waveforms up to the failure; they must not come back as a result
    model = Model(tmp_path, BLOW_UP)
    msg = model.failure(tmp_path / "work", stop=2.0, max_step=1e-2)
    assert msg.startswith("simulation failed: ")
    t = float(re.search(r"\n  at t = (\S+) s\n", msg).group(1))
    assert 0.9 < t < 1.0
    assert f"quantity x (free, declared at {model.at('quantity x')})" in msg


def test_failure_names_the_equation_that_was_active(tmp_path):
    # in the time domain x is solved by x'dot == x * x, not by the quiescent-domain x == 1.0
    model = Model(tmp_path, BLOW_UP)
    msg = model.failure(tmp_path / "work", stop=2.0, max_step=1e-2)
    assert model.at("x'dot") in msg, msg


def test_a_compiled_failure_that_names_no_node_says_how_to_find_the_equation(tmp_path):
    # the compiled device's truncation error names no node: the message points to the behavioural run that does
    model = Model(tmp_path, BLOW_UP)
    msg = model.failure(tmp_path / "work", stop=2.0, max_step=1e-2, compiled=True)
    t = float(re.search(r"\n  at t = (\S+) s\n", msg).group(1))
    assert 0.9 < t < 1.0
    assert "ngspice names no node of the model" in msg and "--no-compile" in msg, msg


# an event storm: a process that triggers itself 1 fs later never lets the simulated time advance
STORM = tb(
    "  quantity x : real;  -- [1] x\n  signal s : bit := '0';",
    "  x'dot == -x + 1.0;\n  storm: process (s) begin\n    s <= not s after 1 fs;\n  end process storm;",
)
ZENO = tb(  # a ball dropped from 1 m at rest, restitution 0.5: its bounces accumulate
    "  quantity x : real;  -- [m] x\n  quantity v : real;  -- [m/s] v",
    "  x'dot == v;\n  v'dot == -9.81;\n  break x => 1.0, v => 0.0;\n  break v => -0.5 * v when not x'above(0.0);",
)
LONG = tb("  quantity x : real;  -- [1] x", "  x'dot == -x + 1.0;")  # runs as long as its stop asks


def _children(pid: int) -> set[int]:
    """The processes whose parent is `pid`."""
    out = set()
    for stat_file in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat_file.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            out.add(int(stat_file.parent.name))
    return out


def _wrsim_run(tmp_path: Path, model: str, *extra: str) -> subprocess.Popen:
    Model(tmp_path, model)
    return subprocess.Popen(
        [str(Path(sys.executable).with_name("wrsim")), "run", str(tmp_path / "model.vhd"), "--top", "tb"]
        + ["--results", str(tmp_path / "results"), *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def _gone(pids: set[int], within: float = 10.0) -> bool:
    deadline = time.monotonic() + within
    while time.monotonic() < deadline:
        if not any(Path(f"/proc/{p}").exists() for p in pids):
            return True
        time.sleep(0.1)
    return False


@pytest.mark.skipif(sys.platform != "linux", reason="the parent-death signal is Linux's")
def test_a_killed_wrsim_leaves_no_simulator_running(tmp_path):
    """A CI job's timeout kills `wrsim run` with SIGKILL: its simulator child dies with it (PR_SET_PDEATHSIG)."""
    proc = _wrsim_run(tmp_path, LONG, "--stop", "1e4", "--max-step", "1e-5")
    deadline = time.monotonic() + 120.0
    children: set[int] = set()
    while not children and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.2)
        children = {c for c in _children(proc.pid) if "ngspice" in Path(f"/proc/{c}/cmdline").read_bytes().decode()}
    assert children, f"no simulator started: {proc.communicate()}"
    os.kill(proc.pid, signal.SIGKILL)
    proc.communicate()
    assert _gone(children), f"the simulator {children} outlived wrsim"


@pytest.mark.skipif(sys.platform != "linux", reason="the parent-death signal is Linux's")
def test_a_quiet_child_dies_with_its_killed_parent():
    """The mechanism alone, with a child that writes nothing (no broken pipe to end it): wrsim's child processes
    (backend.native.run_child) get SIGKILL when wrsim dies."""
    parent = subprocess.Popen(
        [sys.executable, "-c", "from wrsim.backend.native import run_child; run_child(['sleep', '300'])"]
    )
    deadline = time.monotonic() + 30.0
    children: set[int] = set()
    while not children and time.monotonic() < deadline:
        time.sleep(0.1)
        children = _children(parent.pid)
    assert children
    os.kill(parent.pid, signal.SIGKILL)
    parent.wait()
    assert _gone(children), f"{children} outlived their parent"


def test_a_childs_output_that_is_not_utf8_is_read_with_replacement():
    out = run_child(["printf", "line \\377 here"], capture_output=True, text=True).stdout
    assert out == "line \ufffd here"


def test_a_run_over_its_wall_time_is_stopped_with_an_error(tmp_path):
    proc = _wrsim_run(tmp_path, LONG, "--stop", "1e4", "--max-step", "1e-5", "--timeout", "2")
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, (out, err)
    assert "ngspice did not finish within 2 s and was stopped" in err and "Traceback" not in err, err
    assert not _children(proc.pid)


def test_an_event_cascade_is_stopped_naming_its_process(tmp_path):
    """More than 100,000 events within 1 us of simulated time end the run with one error naming the process."""
    proc = _wrsim_run(tmp_path, STORM, "--stop", "1")
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, (out, err)
    found = re.search(
        r"an event cascade at t = (\S+) s: (\d+) events within (\S+) s, (\d+) of them the one of (.*)", err
    )
    assert found, err
    assert float(found.group(1)) < 1e-6 and int(found.group(2)) > 100_000 and int(found.group(4)) > 100_000 - 2
    assert found.group(5).startswith(f"{tmp_path / 'model.vhd'}:") and "storm: process (s) begin" in found.group(5)
    assert "ngspice names no node" not in err


def test_a_sampling_period_below_the_resolution_of_time_is_one_error(tmp_path):
    """'ztf, 'zoh at 1e-300 s (found by make fuzz): the driver's next sample instant never advanced past the point
    (t + 1e-300 == t) and the run spun until its wall-time bound; now one error naming the equation."""
    model = tb("  quantity x, y : real;  -- [1] x", "  x'dot == -x + 1.0;\n  y == x'zoh(1.0e-300);")
    proc = _wrsim_run(tmp_path, model, "--stop", "1e-3")
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, (out, err)
    assert "the period 1e-300 s of " in err and "y == x'zoh(1.0e-300);" in err
    assert "is below the resolution of time at t = 0 s" in err


SINGULAR_AT_REST = tb(  # found by make fuzz: a mass whose speed is a sampled copy of its position
    "  terminal p : translational;\n  quantity x across fm through p to translational_ref;\n"
    "  quantity xk across fk through p to translational_ref;\n  quantity vel : real;  -- [m/s] vel",
    "  vel == x'ztf((0 => 1.0), (1.0, 0.5), 1.0e-3);\n  fm == 0.5 * vel'dot;\n  fk == 200.0 * xk;\n"
    "  break x => 0.01, vel => 0.0;",
)


def test_a_quiescent_point_ngspice_never_finds_is_one_error(tmp_path, monkeypatch):
    """ngspice's transient operating point of this singular system never returned (the run ended only at its wall
    time); the crossing driver bounds the quiescent point (60 s, WRSIM_OP_WALL) and names it and the equation."""
    monkeypatch.setenv("WRSIM_OP_WALL", "3")
    model = "library ieee;\nuse ieee.mechanical_systems.all;\n" + SINGULAR_AT_REST
    proc = _wrsim_run(tmp_path, model, "--stop", "1e-3", "--timeout", "120")
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, (out, err)
    assert "the quiescent point was not found within 3 s of wall time" in err, err
    assert "did not finish within 120 s" not in err


def test_a_zeno_model_is_stopped_at_its_accumulation_point(tmp_path):
    """The bounces accumulate at t1 + 2 e v1 / (g (1 - e)) (t1 = sqrt(2 h / g), v1 = g t1): 1.354568 s. Past it a
    crossing located 1 us late leaves the ball below the floor by more than its rebound lifts it, and it fell
    through the floor without an error; now the run stops with one error naming the break and the end of the
    series of bounce times."""
    proc = _wrsim_run(tmp_path, ZENO, "--stop", "3")
    out, err = proc.communicate(timeout=300)
    assert proc.returncode == 2, (out, err)
    found = re.search(r"the events of (.*) accumulate \(a Zeno model\).*the series ends at t = (\S+) s", err)
    assert found, err
    assert found.group(1).startswith(f"{tmp_path / 'model.vhd'}:") and "break v => -0.5 * v when" in found.group(1)
    t1 = np.sqrt(2.0 / 9.81)
    assert float(found.group(2)) == pytest.approx(t1 + 2.0 * 0.5 * 9.81 * t1 / (9.81 * 0.5), rel=1e-3)
    assert "Traceback" not in err and "ngspice names no node" not in err


def test_a_break_list_the_quiescent_point_cannot_hold_is_one_error(tmp_path):
    """1076.1 replaces x'dot = 0 by x = 1 at the quiescent point and keeps v'dot = 0, which says x = 0: the model
    contradicts itself, and ngspice's .ic (1 TOhm) gave x(0) = 0 silently. Breaking v too makes it consistent."""
    oscillator = "  x'dot == v;\n  v'dot == -x;\n  break x => 1.0{};"
    decls = "  quantity x : real;  -- [1] x\n  quantity v : real;  -- [1] v"
    model = Model(tmp_path, tb(decls, oscillator.format("")))
    msg = model.failure(tmp_path / "work", stop=0.1, max_step=1e-3)
    assert "the quiescent point does not hold the break list's value 1 (it is " in msg, msg
    assert f"the break at {model.at('break x')}: break x => 1.0; contradicts the quiescent equations" in msg
    consistent = Model(tmp_path, tb(decls, oscillator.format(", v => 0.0")))
    waves = consistent.run(tmp_path / "work2", stop=np.pi, max_step=1e-3)
    np.testing.assert_allclose(waves["x"], np.cos(waves.time), atol=2e-3)


def test_waveforms_that_stop_before_the_end_are_no_result(tmp_path):
    # a simulator that exits 0 but wrote only the first half of the analysis
    half = write_raw(tmp_path / "half.raw", ["time", "v(x)"], [[0.0, 2.0], [2.5e-4, 2.0], [5e-4, 2.0]])
    runner = NgspiceBatch(executable=str(fake_ngspice(tmp_path, "ngspice-46", half)))
    model = Model(tmp_path, tb("  quantity x : real;  -- [1] x", "  x == 2.0;"))
    with pytest.raises(WrsimError):
        model.run(tmp_path / "work", stop=1e-3, runner=runner)


# ------------------------------------------------------------------------------------------------ raw files
def test_read_raw(tmp_path):
    path = write_raw(tmp_path / "ok.raw", ["time", "V(X)", "i(v_a)"], [[0.0, 1.0, -1.0], [1.0, 3.0, -2.0]])
    data = read_raw(path)
    assert list(data) == ["time", "v(x)", "i(v_a)"]
    np.testing.assert_array_equal(data["v(x)"], [1.0, 3.0])


def _rows(n: int) -> np.ndarray:
    return np.arange(2.0 * n).reshape(n, 2)


RAW_ERRORS = [
    ("truncated data", lambda p: write_raw(p, ["time", "v(x)"], _rows(3), points=4), "truncated raw file"),
    ("garbage", lambda p: p.write_bytes(b"\x00\x01 not a raw file \xff"), "not an ngspice binary raw file"),
    ("empty file", lambda p: p.write_bytes(b""), "not an ngspice binary raw file"),
    (
        "ascii raw file",
        lambda p: p.write_bytes(
            b"Title: t\nFlags: real\nNo. Variables: 1\nNo. Points: 1\nVariables:\n\t0\ttime\ttime\nValues:\n 0\t0.0\n"
        ),
        "not an ngspice binary raw file",
    ),
    (
        "fewer variable names than declared",
        lambda p: write_raw(p, ["time", "v(x)"], _rows(1)).write_bytes(
            p.read_bytes().replace(b"No. Variables: 2", b"No. Variables: 3")
        ),
        "",
    ),
    (
        "count that is not a number",
        lambda p: write_raw(p, ["time", "v(x)"], _rows(1)).write_bytes(
            p.read_bytes().replace(b"No. Points: 1", b"No. Points: one")
        ),
        "",
    ),
]


@pytest.mark.parametrize("what, content, message", RAW_ERRORS, ids=[r[0] for r in RAW_ERRORS])
def test_unreadable_raw_files_are_a_clear_error(tmp_path, what, content, message):
    path = tmp_path / "bad.raw"
    content(path)
    with pytest.raises(WrsimError, match=rf"^{re.escape(str(path))}: {re.escape(message)}"):
        read_raw(path)


# ------------------------------------------------------------------------------------------------ blame
TWO = ("  quantity y : real;  -- [1] y, unrelated to the failure\n  quantity x : real;  -- [1] x",)


def test_a_failure_names_only_what_ngspice_blames(tmp_path):
    model = Model(tmp_path, tb(*TWO, "  y == 2.0;\n  x * x == -1.0;"))  # x has no real solution
    msg = model.failure(tmp_path / "work")
    assert f"quantity x (free, declared at {model.at('quantity x')})" in msg
    assert "quantity y" not in msg, msg  # in ngspice's node table, not blamed


def test_a_singular_system_is_called_singular(tmp_path):
    sub = (
        "entity sub is\n  generic (g : real := 1.0);  -- [1] g\n  port (quantity q : out real);  -- [1] q\n"
        "end entity sub;\narchitecture a of sub is\nbegin\n  q * g == 1.0;\nend architecture a;\n"
    )
    model = Model(
        tmp_path, sub, tb(*TWO, "  y == 2.0;\n  u: entity work.sub generic map (g => 0.0) port map (q => x);")
    )
    msg = model.failure(tmp_path / "work")
    assert "the equation system is singular" in msg
    assert (
        f"quantity u.q (out, declared at {model.at('quantity q')}), solved by the equation at {model.at('q * g')}"
    ) in msg
    assert "quantity y" not in msg


def test_a_derivative_helper_maps_back_to_its_quantity(tmp_path):
    model = Model(tmp_path, BLOW_UP)
    msg = model.failure(tmp_path / "work", stop=2.0, max_step=1e-2)
    assert 'trouble with node "v_x__d#branch"' in msg
    assert f"x'dot, the derivative of quantity x: quantity x (free, declared at {model.at('quantity x')})" in msg


def test_every_truncation_and_header_flip_of_a_raw_file_is_one_error(tmp_path):
    raw = write_raw(tmp_path / "ok.raw", ["time", "v(x)", "v(y)"], _rows(12).reshape(8, 3))
    data = raw.read_bytes()
    cases = [data[:k] for k in range(len(data))]
    rng = random.Random(7)
    header = data.index(b"Binary:")
    for _ in range(2000):
        flipped = bytearray(data)
        for _ in range(rng.randint(1, 3)):
            flipped[rng.randrange(header + 8)] = rng.randrange(256)
        cases.append(bytes(flipped))
    bad = tmp_path / "bad.raw"
    for case in cases:
        bad.write_bytes(case)
        try:
            read_raw(bad)
        except WrsimError as e:
            assert str(e).startswith(f"{bad}: ") and "\n" not in str(e)


def test_digital_event_record_is_read_with_its_timescale(tmp_path):
    vcd = tmp_path / "events.vcd"
    vcd.write_text(
        '$timescale 10 ns $end\n$var wire 1 ! Relay_Up $end\n$var wire 1 " pinch $end\n'
        '$enddefinitions $end\n$dumpvars\n0!\n0"\n$end\n#150\n1!\n#300\nx!\n#400\n0!\n'
    )
    events = read_events(vcd)
    assert set(events) == {"relay_up", "pinch"}
    t, level = events["relay_up"]
    assert np.allclose(t, [0.0, 1.5e-6, 3e-6, 4e-6]) and list(level) == [0.0, 1.0, 0.5, 0.0]
    grid = np.array([0.0, 1.4e-6, 1.5e-6, 2e-6, 3.5e-6, 5e-6])
    assert list(sample_events(events["relay_up"], grid)) == [0.0, 0.0, 1.0, 1.0, 0.5, 0.0]
    vcd.write_text("$var wire 1 ! a $end\n$enddefinitions $end\n#5\n1?\n")
    with pytest.raises(WrsimError, match="events.vcd: malformed value change dump"):
        read_events(vcd)


def test_bench_timing_reads_the_solver_counts_from_the_logs():
    log = (
        "Transient iterations = 120\nTransient timepoints = 60\nAccepted timepoints = 50\nRejected timepoints = 3\n"
        "Transient analysis time = 1.25\nngghdl stats: step=9 wake=9 in_events=1 out_events=2 ghdl_time=1 s "
        "wall_in_step=0.5 s\nwrsim crossings: 50 accepted points; steps shortened per guard: x.above__1 4, "
        "x.above__2 7\nwrsim late crossings per guard: x.above__1 0, x.above__2 1\n"
    )
    assert solver_statistics(log) + solver_statistics(log) == SolverStatistics(100, 6, 240, 2.5, 1.0, 22, 2)
    assert solver_statistics("ngspice -b without rusage") == SolverStatistics(0, 0, 0, 0.0, 0.0, 0, 0)
