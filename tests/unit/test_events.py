"""Events on the analog side (IEEE 1076.1's mixed-signal cycle), each against a closed form: a break list that
re-initialises a quantity at an 'above event (a bouncing ball, a hard stop)."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from wrsim.cli import main

BALL = """\
-- A ball dropped from h0 bounces on the floor with restitution e: the apex after bounce k is e**(2k) * h0.
library ieee;
use ieee.mechanical_systems.all;
entity ball_tb is
  generic (g : real := 9.81; e : real := 0.8; h0 : displacement := 1.0);
end entity ball_tb;
architecture bounce of ball_tb is
  quantity x : displacement;
  quantity v : velocity;
begin
  break x => h0, v => 0.0;
  break v => -e * v when not x'above(0.0);
  x'dot == v;
  v'dot == -g;
end architecture bounce;
"""


def _waves(tmp_path: Path, name: str, text: str, top: str, stop: str, *args: str) -> dict[str, np.ndarray]:
    """`wrsim run` of one file; its waveforms by column name (the time as "t")."""
    (tmp_path / f"{name}.vhd").write_text(text)
    assert (
        main(
            [
                "run",
                str(tmp_path / f"{name}.vhd"),
                "--top",
                top,
                "--stop",
                stop,
                "--results",
                str(tmp_path / "out"),
                *args,
            ]
        )
        == 0
    )
    with (tmp_path / "out" / "run" / top / "waveforms.csv").open() as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    return {"t": data[:, 0], **{name.split("[")[0]: data[:, k] for k, name in enumerate(rows[0]) if k}}


def test_a_bouncing_ball_restarts_its_speed_at_each_impact(tmp_path):
    w = _waves(tmp_path, "ball", BALL, "ball_tb", "3", "--max-step", "1e-4")
    t, x, v = w["t"], w["x"], w["v"]
    g, e = 9.81, 0.8
    t1 = np.sqrt(2.0 / g)
    impacts = t1 + np.concatenate([[0.0], np.cumsum(2.0 * e ** np.arange(1, 5) * g * t1 / g)])
    jumps = t[1:][np.diff(v) > 0.5]  # v jumps from -v to +e*v within the driver's 1 us
    seen = np.array([jumps[np.argmin(np.abs(jumps - ti))] for ti in impacts])
    np.testing.assert_allclose(seen, impacts, rtol=1e-3, atol=2e-3)  # 2 ms: the CSV's sample spacing (1.5 ms)
    for k in range(1, 4):
        apex = x[(t > impacts[k - 1]) & (t < impacts[k])].max()
        assert abs(apex / (e ** (2 * k)) - 1.0) < 1e-2, (k, apex)
    assert x.min() > -1e-4  # the floor: a 1 us landing at 4.4 m/s


PROCESSES = """\
-- Processes in an AMS architecture: a clock (wait for, last), a counter (wait for, first), a comparator process
-- on x'above(0.5) that sets a real signal a source reads.
library ieee;
use ieee.electrical_systems.all;
use ieee.math_real.all;
entity proc_tb is
  generic (period : time := 1 ms);
end entity proc_tb;
architecture a of proc_tb is
  signal clk : bit := '0';
  signal level : real := 0.0;
  signal count : integer := 0;
  terminal n : electrical;
  quantity vs across i_s through n to electrical_ref;
  quantity vr across ir through n to electrical_ref;
  quantity x : real;
begin
  clock: process
  begin
    clk <= not clk;
    wait for period / 2;
  end process clock;
  counter: process
    variable k : integer := 0;
  begin
    wait for period;
    k := k + 2;
    count <= k / 2;
  end process;
  watch: process (x'above(0.5))
  begin
    if x'above(0.5) then
      level <= 2.0;
    else
      level <= -1.0;
    end if;
  end process;
  x == sin(math_2_pi * 100.0 * now);
  vs == level;
  vr == 1.0e3 * ir;
end architecture a;
"""


def test_processes_set_signals_at_their_events(tmp_path):
    w = _waves(tmp_path, "proc", PROCESSES, "proc_tb", "0.02", "--max-step", "1e-5")
    t = w["t"]
    half = np.abs(t / 5e-4 - np.round(t / 5e-4)) > 0.01  # away from the edges (the CSV interpolates)
    np.testing.assert_array_equal(w["clk"][half], (np.floor(t / 5e-4) % 2 == 0)[half])  # '1' first: the run at 0
    whole = np.abs(t / 1e-3 - np.round(t / 1e-3)) > 0.01
    np.testing.assert_array_equal(w["count"][whole], np.floor(t / 1e-3)[whole])  # the variable persists
    above = np.sin(2 * np.pi * 100 * t) > 0.5
    edges = np.abs(np.sin(2 * np.pi * 100 * t) - 0.5) < 0.02
    assert w["level"][0] == 0.0 and w["level"][1] == -1.0  # a run at initialisation that reads a quantity acts
    edges[0] = True  # at the first time point, after the quiescent point
    np.testing.assert_array_equal(w["level"][~edges], np.where(above, 2.0, -1.0)[~edges])
    np.testing.assert_allclose(w["ir"][~edges], np.where(above, 2e-3, -1e-3)[~edges], rtol=1e-6)


DOMAIN = """\
library ieee;
use ieee.math_real.all;
entity domain_tb is
end entity domain_tb;
architecture a of domain_tb is
  signal level : real := 0.5;
  quantity y : real;
begin
  drive: process begin
    for k in 1 to 2 loop
      if domain = quiescent_domain then level <= 1.0; else level <= 2.0; end if;
      wait for 0.1 sec;
    end loop;
    wait;
  end process drive;
  y'dot == (level - y) / 0.1;
end architecture a;
"""


def test_a_process_reads_the_domain_of_its_run(tmp_path):
    """1076.1: the run at initialisation sees domain = quiescent_domain, so the quiescent point has level = 1 (not
    the declared 0.5, nor the time domain's 2); the run at 0.1 s sees time_domain. y = 1, then
    2 - exp(-(t - 0.1)/0.1)."""
    w = _waves(tmp_path, "domain", DOMAIN, "domain_tb", "0.4", "--max-step", "1e-3")
    t, before = w["t"], w["t"] < 0.1 - 1e-9
    np.testing.assert_allclose(w["level"][before], 1.0)
    np.testing.assert_allclose(w["y"][before], 1.0, atol=1e-9)
    after = t > 0.1 + 1e-9
    np.testing.assert_allclose(w["level"][after], 2.0)
    np.testing.assert_allclose(w["y"][after], 2.0 - np.exp(-(t[after] - 0.1) / 0.1), atol=1e-3)


EVENT_MISUSE = """\
library ieee;
use ieee.std_logic_1164.all;
entity ev_tb is
end entity ev_tb;
architecture a of ev_tb is
  signal clk : std_ulogic := '0';
  quantity q : real;
begin
  clock: process begin wait for 1 ms; clk <= not clk; end process;
  watch: process (clk) begin if PREFIX'event then clk <= '0'; end if; end process;
  q == 1.0;
end architecture a;
"""


def _fails(tmp_path: Path, capsys, text: str, message: str) -> None:
    """`wrsim run` of `text` ends in one error (exit 2, no traceback) that contains `message`."""
    (tmp_path / "ev.vhd").write_text(text)
    assert (
        main(["run", str(tmp_path / "ev.vhd"), "--top", "ev_tb", "--stop", "1e-3", "--results", str(tmp_path / "out")])
        == 2
    )
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err, err


def test_event_needs_a_signal_in_a_process(tmp_path, capsys):
    """'event reads the event of a signal in the process's run; anything else is one error at its place."""
    _fails(
        tmp_path,
        capsys,
        EVENT_MISUSE.replace("PREFIX", "q"),
        "ev.vhd:10:34: 'event needs a signal prefix, 'q' is not a signal",
    )
    _fails(
        tmp_path,
        capsys,
        EVENT_MISUSE.replace("PREFIX", "clk'above"),
        "ev.vhd:10:36: unsupported construct: attribute 'above'event",
    )
    concurrent = "  if clk'event use q == 1.0; else q == 0.0; end use;"
    _fails(
        tmp_path,
        capsys,
        EVENT_MISUSE.replace("  q == 1.0;", concurrent).replace("PREFIX", "clk"),
        "ev.vhd:11:9: unsupported construct: 'event outside a process",
    )


@pytest.mark.parametrize(
    "old, new, message",
    [
        ("PREFIX'event", "clk'stable(1 ms)", "ev.vhd:10:36: unsupported construct: 'stable(T) with T other than 0 ns"),
        ("PREFIX'event", "clk'stable(1.0)", "ev.vhd:10:36: unsupported construct: 'stable(T) with T other than 0 ns"),
        (
            "  q == 1.0;",
            "  if clk'stable use q == 1.0; else q == 0.0; end use;",
            "ev.vhd:11:9: unsupported construct: 'stable outside a process",
        ),
        (
            "process (clk) begin",
            "process (all) begin wait for 1 ms;",
            "ev.vhd:10:30: a process with a sensitivity list must not contain a wait statement",
        ),
    ],
)
def test_stable_needs_no_time_and_a_process(tmp_path, capsys, old, new, message):
    """s'stable is `not s'event` in a process's run; 'stable(T) for a T > 0 (a time since the last event) is not
    read; nor is a wait in `process (all)`."""
    _fails(tmp_path, capsys, EVENT_MISUSE.replace(old, new).replace("PREFIX", "clk"), message)


def test_a_wait_in_an_if_needs_a_static_condition(tmp_path, capsys):
    watch = "  watch: process begin if clk = '1' then wait for 1 ms; end if; wait on clk; end process;"
    text = EVENT_MISUSE.replace("PREFIX", "clk")
    text = text.replace(next(line for line in text.splitlines() if line.startswith("  watch:")), watch)
    _fails(
        tmp_path,
        capsys,
        text,
        "ev.vhd:10:42: unsupported construct: wait statement inside an if whose condition is not static",
    )


@pytest.mark.parametrize(
    "assignment, message",
    [
        (
            "clk <= reject 3 ms inertial '0' after 2 ms;",
            "ev.vhd:10:62: the 'reject' limit is longer than the delay (1076 10.5.2.1)",
        ),
        ("clk <= reject -1 ms inertial '0' after 2 ms;", "ev.vhd:10:62: a negative 'reject' limit"),
        (
            "clk <= transport '0' after 1 ms; clk <= '1' after 2 ms;",
            "ev.vhd:10:81: unsupported construct: a second assignment to 'clk' after a delay in one run of a process",
        ),
        ("clk <= '1' after 2 ms, '0' after 1 ms;", "ev.vhd:10:81: the delays of a waveform's elements must ascend"),
        ("clk <= '1', '0';", "ev.vhd:10:60: the delays of a waveform's elements must ascend"),
        (
            "clk <= '1', '0' after q * 1 ms;",
            "ev.vhd:10:72: unsupported construct: a waveform of several elements whose delays are not static",
        ),
        ("clk <= '0' after 1.0;", "ev.vhd:10:65: the delay after `after` must be a time, found real"),
        ("clk <= '0' after -1 ms;", "ev.vhd:10:65: a negative delay"),
    ],
)
def test_delays_outside_the_subset_are_one_error_each(tmp_path, capsys, assignment, message):
    """`after` takes a time, `reject` a time up to the delay, a waveform's elements ascending static delays; a run
    does not assign a signal twice with different delays."""
    _fails(tmp_path, capsys, EVENT_MISUSE.replace("PREFIX", "clk").replace("clk <= '0';", assignment), message)


SEQUENCE = """\
library ieee;
use ieee.std_logic_1164.all;
entity seq_tb is
end entity seq_tb;
architecture a of seq_tb is
  signal clk : std_ulogic := '0';
  signal n, m : integer := 0;
  quantity qn, qm : real;
begin
  clock: process begin wait for 0.5 ms; clk <= not clk; end process;
  stimulus: process
  begin
BODY
  end process;
  qn == real(n);
  qm == real(m);
end architecture a;
"""
EDGES = np.array([0.5e-3, 1.5e-3, 2.5e-3])  # clk's rising edges


@pytest.mark.parametrize(
    "body, n, m, stop",
    [
        # a clock edge and a time in turn: after 0.7 ms the next rising edge is a whole period later
        (
            "    wait until rising_edge(clk);\n    n <= n + 1;\n    wait for 0.7 ms;\n    m <= m + 1;",
            (EDGES, 1.0),
            (EDGES + 0.7e-3, 1.0),
            "3.4e-3",
        ),
        # a for loop of waits, unrolled: its variable bound after each wait; then `wait;` for good
        (
            "    for i in 1 to 3 loop\n      wait until clk = '1';\n      n <= i;\n      wait for 0.2 ms;\n"
            "      m <= 10 * i;\n    end loop;\n    wait;",
            (EDGES, 1.0),
            (EDGES + 0.2e-3, 10.0),
            "4e-3",
        ),
        # ... with a wait in an if on the loop variable (static in each copy): 0.1 ms more in the second round
        (
            "    for i in 1 to 3 loop\n      wait until clk = '1';\n      n <= i;\n      if i = 2 then\n"
            "        wait for 0.1 ms;\n      end if;\n      wait for 0.2 ms;\n      m <= 10 * i;\n"
            "    end loop;\n    wait;",
            (EDGES, 1.0),
            (EDGES + np.array([0.2e-3, 0.3e-3, 0.2e-3]), 10.0),
            "4e-3",
        ),
        # one wait on a signal with a timeout: the earlier of clk's next change (every 0.5 ms) and 0.3 ms
        (
            "    wait on clk for 0.3 ms;\n    n <= n + 1;",
            (np.array([0.3, 0.5, 0.8, 1.0, 1.3, 1.5]) * 1e-3, 1.0),
            (np.array([]), 1.0),
            "1.7e-3",
        ),
    ],
    ids=["edge-then-time", "for-loop", "static-if", "timeout"],
)
def test_waits_of_several_kinds_run_in_sequence(tmp_path, body, n, m, stop):
    """n and m step at the given times by the given amounts (the process is a state machine over its waits)."""
    w = _waves(tmp_path, "seq", SEQUENCE.replace("BODY", body), "seq_tb", stop, "--max-step", "1e-5")
    t = w["t"]
    away = np.all(np.abs(t[:, None] - np.concatenate([n[0], m[0]])[None, :]) > 2e-5, axis=1)
    for column, (times, step) in (("qn", n), ("qm", m)):
        np.testing.assert_array_equal(w[column][away], step * np.sum(t[:, None] >= times[None, :], axis=1)[away])


LAST_VALUE = """\
library ieee;
use ieee.std_logic_1164.all;
entity last_tb is
end entity last_tb;
architecture a of last_tb is
  signal s : real := 0.0;
  signal clk : std_ulogic := '0';
  signal n : integer := 0;
  quantity ql, qn : real;
begin
  steps: process begin wait for 1 ms; s <= 1.0; wait for 1 ms; s <= 2.0; wait for 1 ms; s <= 5.0; wait; end process;
  clock: process begin wait for 0.25 ms; clk <= not clk; end process;
  edges: process (clk) begin
    if clk'event and clk = '1' and clk'last_value = '0' then
      n <= n + 1;
    end if;
  end process;
  ql == s'last_value;
  qn == real(n);
end architecture a;
"""


def test_last_value_is_the_value_before_the_last_change(tmp_path):
    """s steps 0 -> 1 -> 2 -> 5 at 1, 2, 3 ms: s'last_value is 0 until 2 ms, then 1, then 2 from 3 ms; the old
    rising-edge idiom with clk'last_value counts clk's rising edges (0.25 ms + k * 0.5 ms)."""
    w = _waves(tmp_path, "last", LAST_VALUE, "last_tb", "3.5e-3", "--max-step", "1e-5")
    t = w["t"]
    away = np.all(np.abs(t[:, None] - np.array([1e-3, 2e-3, 3e-3])[None, :]) > 2e-5, axis=1)
    np.testing.assert_array_equal(w["ql"][away], np.select([t < 2e-3, t < 3e-3], [0.0, 1.0], 2.0)[away])
    edges = 0.25e-3 + 0.5e-3 * np.arange(7)
    away = np.all(np.abs(t[:, None] - edges[None, :]) > 2e-5, axis=1)
    np.testing.assert_array_equal(w["qn"][away], np.sum(t[:, None] >= edges[None, :], axis=1)[away])


SIMULTANEOUS = """\
library ieee;
use ieee.std_logic_1164.all;
entity sim_tb is
end entity sim_tb;
architecture a of sim_tb is
  signal a, b : std_ulogic := '0';
  signal q, m, j : integer := 0;
  quantity qm : real;
begin
  qm == real(m);
  stimulus: process begin
    wait for 1 ms; a <= '1';
    wait for 1 ms; a <= '0'; b <= '1';
    wait for 1 ms; a <= '1';
    wait for 1 ms; a <= '0'; b <= '0';
    wait for 1 ms; a <= '1'; b <= '1';
    wait for 1 ms; b <= '0';
    wait for 1 ms; a <= '0';
    wait for 1 ms; a <= '1';
    wait;
  end process;
  flip_flop: process (a, b) begin
    if b = '1' then q <= 0; elsif rising_edge(a) then q <= q + 1; end if;
  end process;
  changes: process (a, b) is
    variable k : integer := 0;
  begin
    if a'event then k := k + 1; end if;
    if not b'stable then k := k + 1; end if;
    m <= k;
  end process;
  both: process begin
    wait on a, b until a'event and b'event;
    j <= j + 1;
  end process;
end architecture a;
"""


def test_signals_changing_together_run_a_process_once(tmp_path):
    """a changes at 1..8 ms, b at 2, 4, 5 and 6 ms, together at 2, 4 and 5 ms (IEEE 1076: one run of a process
    sensitive to both, with the 'event of each): the flip-flop with b as its asynchronous reset counts a's rising
    edges at 1 and 8 ms and is reset from 2 ms (a rises with b at 5 ms: the reset wins); m counts the signals that
    changed in each run (2 where both did); j the instants at which both changed."""
    w = _waves(tmp_path, "sim", SIMULTANEOUS, "sim_tb", "8.5e-3", "--max-step", "1e-5")
    t = w["t"]
    instants = 1e-3 * np.arange(1, 9)
    away = np.all(np.abs(t[:, None] - instants[None, :]) > 2e-5, axis=1)

    def steps(times: list[float], sizes: list[float]) -> np.ndarray:
        return np.sum(np.where(t[:, None] >= 1e-3 * np.array(times)[None, :], np.array(sizes)[None, :], 0.0), axis=1)

    np.testing.assert_array_equal(w["q"][away], steps([1, 2, 8], [1, -1, 1])[away])
    np.testing.assert_array_equal(w["m"][away], steps(list(range(1, 9)), [1, 2, 1, 2, 2, 1, 1, 1])[away])
    np.testing.assert_array_equal(w["j"][away], steps([2, 4, 5], [1, 1, 1])[away])


WAIT_EVENT = """library ieee;
entity wait_event_tb is end entity wait_event_tb;
architecture a of wait_event_tb is
  signal clk : bit := '0';
  signal n : real := 0.0;
  quantity y : real;
begin
  clk <= not clk after 1 ms;
  count : process begin
    wait until clk'event;
    n <= n + 1.0;
  end process count;
  y == n;
end architecture a;
"""


def test_wait_until_an_event_waits_on_its_signal(tmp_path):
    """`wait until clk'event` (no `on`): 1076 waits on the signals the condition names, clk too when only its
    'event is read (the condition was once rejected as reading no signal): n counts both edges, every 1 ms."""
    w = _waves(tmp_path, "wait_event", WAIT_EVENT, "wait_event_tb", "4.5e-3", "--max-step", "1e-5")
    away = np.all(np.abs(w["t"][:, None] - 1e-3 * np.arange(1, 5)[None, :]) > 2e-5, axis=1)
    np.testing.assert_array_equal(w["y"][away], np.floor(w["t"][away] / 1e-3))
