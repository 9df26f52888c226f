"""Electronics of the window regulator (vhdl/electronics, vhdl/digital): digital units run by GHDL (ECU software unit
test bench, switch sequences) and the AMS models with signal ports (Hall sensor, ECU hardware) in ngspice."""

from __future__ import annotations

import math
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import netlist
from wrsim import paths
from wrsim.backend.ghdl.build import c_sources
from wrsim.elab import load_library
from wrsim.errors import SourceError, WrsimError

GHDL = shutil.which("ghdl-llvm")  # the back-end wrsim builds with: it links VHPIDIRECT C code
needs_ghdl = pytest.mark.skipif(GHDL is None, reason="GHDL not installed (make setup installs it)")
DIGITAL_FILES = load_library(paths.LIBRARY).digital_files  # a unit's files, each after the packages it uses
AMS_FILES = ("vhdl/electronics", "vhdl/digital", "vhdl/equipment", "vhdl/drive")


def ghdl_build(workdir: Path, files: list[Path], top: str) -> Path:
    """Analyse `files` into `workdir` and link `top` with the C code they name (`-- c source:`, as wrsim's GHDL build
    does); the executable."""
    work = ["--std=08", f"--workdir={workdir}"]
    subprocess.run([GHDL, "-a", *work, *map(str, files)], check=True, capture_output=True, text=True)
    objects = []
    for k, (c, _) in enumerate(c_sources([(Path(f), Path(f).read_bytes()) for f in files])):
        objects.append(workdir / f"foreign{k}.o")
        subprocess.run(
            ["gcc", "-O2", "-fPIC", "-Wall", "-Wextra", "-Werror", "-c", str(c), "-o", str(objects[-1])],
            check=True,
            capture_output=True,
            text=True,
        )
    subprocess.run(
        [GHDL, "-e", *work, *(f"-Wl,{o}" for o in objects), top],
        check=True,
        capture_output=True,
        text=True,
        cwd=workdir,
    )
    return workdir / top.lower()


def ghdl_exec(executable: Path, cwd: Path, *generics: str) -> subprocess.CompletedProcess:
    """Run a linked GHDL design in `cwd` with -g`generics` and --assert-level=error."""
    return subprocess.run(
        [str(executable), *(f"-g{g}" for g in generics), "--assert-level=error"],
        capture_output=True,
        text=True,
        cwd=cwd,
        stdin=subprocess.DEVNULL,
    )


def ghdl_run(workdir: Path, files: list[Path], top: str, *generics: str) -> subprocess.CompletedProcess:
    """`ghdl_build` and `ghdl_exec` in `workdir`; stdout and stderr together."""
    return ghdl_exec(ghdl_build(workdir, files, top), workdir, *generics)


@needs_ghdl
def test_ecu_software_unit_bench(tmp_path):
    files = DIGITAL_FILES(["tb_ecu_software_unit"])
    out = ghdl_run(tmp_path, files, "tb_ecu_software_unit")
    text = out.stdout + out.stderr
    assert out.returncode == 0, text
    assert "normalization: stroke 850 edges" in text
    assert "bottom: position 850" in text
    assert "free run at 16 V: top at position" in text
    for volts in ("9.0", "1.3e1", "1.6e1"):
        assert f"pinch at {volts} V: detected at position" in text
    assert text.count("stopped 211 edges lower") == 3
    assert "tb_ecu_software_unit: all checks passed" in text
    # the C twin of the anti-pinch algorithm (antipinch.c, through VHPIDIRECT) decides on the same edges
    twin = ghdl_run(tmp_path, files, "tb_ecu_software_unit", "algorithm=1")
    assert twin.returncode == 0, twin.stdout + twin.stderr
    assert [ln for ln in twin.stdout.splitlines() if "(report note)" in ln] == [
        ln for ln in out.stdout.splitlines() if "(report note)" in ln
    ]
    # the other algorithms pass the same checks (normalization, no false pinch, pinch under 100 N, reversal)
    for algorithm in (2, 3, 4):
        other = ghdl_run(tmp_path, files, "tb_ecu_software_unit", f"algorithm={algorithm}")
        assert other.returncode == 0 and "all checks passed" in other.stdout, other.stdout + other.stderr


@pytest.fixture(scope="module")
def ecu_unit(tmp_path_factory) -> Path:
    """The ECU unit bench, linked once for the tests of the warm start."""
    return ghdl_build(
        tmp_path_factory.mktemp("ecu_unit"), DIGITAL_FILES(["tb_ecu_software_unit"]), "tb_ecu_software_unit"
    )


def notes(out: subprocess.CompletedProcess) -> list[str]:
    """The report notes of a GHDL run, without their file:line:time prefix."""
    return [ln.split("(report note): ", 1)[1] for ln in out.stdout.splitlines() if "(report note)" in ln]


def learned_bins(text: str) -> dict[int, int]:
    """The reference bins of a learned-state file: bin -> [rpm]."""
    return {int(f[1]): int(f[2]) for f in (ln.split() for ln in text.splitlines()) if f and f[0] == "bin"}


@needs_ghdl
def test_a_warm_start_reads_back_the_learned_state(ecu_unit, tmp_path):
    cold = ghdl_exec(ecu_unit, tmp_path, "learned_out=cold.txt")
    assert cold.returncode == 0, cold.stdout + cold.stderr
    text = (tmp_path / "cold.txt").read_text()
    # the state after the last run that reached the top (the 16 V free run refined the normalization's reference)
    assert text.splitlines()[:4] == [
        "wrsim-antipinch-learned 1",
        "algorithm 0",
        "edges_per_bin 8",
        "share 1024 1024 1024 1024",
    ]
    bins = learned_bins(text)
    # from the top down, 8 edges per bin, over the 850 edges of the stroke less the first second of the run (startup_ms)
    assert sorted(bins) == list(range(len(bins))) and 50 <= len(bins) < 850 // 8
    assert all(1000 < v < 2000 for v in bins.values())  # the stand-in plant's load: 900 + 800 rpm/m * x, + start
    # a warm start from that file at the bottom (850 edges, as the cold run counted) holds the same state: it
    # writes it back unchanged at power-up, and the pinch runs detect on the same edges
    warm = ghdl_exec(ecu_unit, tmp_path, "learned_file=cold.txt", "start_position=850", "learned_out=warm.txt")
    assert warm.returncode == 0, warm.stdout + warm.stderr
    assert learned_bins((tmp_path / "warm.txt").read_text()) == bins
    assert (tmp_path / "warm.txt").read_text() == text
    assert notes(warm)[0] == "warm start: position 850"

    def detections(out: subprocess.CompletedProcess) -> list[str]:
        return [n.split(" (glass", 1)[0] for n in notes(out) if n.startswith("pinch at")]

    assert len(detections(cold)) == 3 and detections(warm) == detections(cold)
    assert notes(warm)[-1] == "tb_ecu_software_unit: all checks passed"


GOOD_HEAD = "wrsim-antipinch-learned 1\nalgorithm 0\nedges_per_bin 8\n"


@needs_ghdl
@pytest.mark.parametrize(
    "text, line, message",
    [
        ("", 1, "empty file, expected the header 'wrsim-antipinch-learned 1'"),
        ("wrsim-antipinch 1\n", 1, "expected the header 'wrsim-antipinch-learned 1'"),
        ("wrsim-antipinch-learned 2\n", 1, "format version 2, this ECU reads version 1"),
        (GOOD_HEAD + "bin 0 x\n", 4, "malformed line, expected: bin <k> <ref>"),
        (GOOD_HEAD + "bin 0 12e3\n", 4, "malformed line, expected: bin <k> <ref>"),
        (GOOD_HEAD + "bin 0 5 # ok\nbin 1 2 3\n", 5, "unexpected text '3' after the values"),
        (GOOD_HEAD + "bin 128 5\n", 4, "bin 128 outside 0 .. 127 (the ECU's reference_bins)"),
        (GOOD_HEAD + "bin 3 5\n\n# again\nbin 3 6\n", 7, "bin 3 given twice"),
        (GOOD_HEAD + "share 1024 1024 0 1024\n", 4, "a pole share must be in 1 .. 4095 (1/4096 rev)"),
        (GOOD_HEAD + "speed 3\n", 4, "unknown key 'speed', expected algorithm, edges_per_bin, share or bin"),
        ("wrsim-antipinch-learned 1\nalgorithm 4\n", 2, "learned by algorithm 4, the ECU runs algorithm 0"),
        ("wrsim-antipinch-learned 1\nedges_per_bin 16\n", 2, "learned with edges_per_bin 16, the ECU has 8"),
        ("wrsim-antipinch-learned 1\nalgorithm 0\nbin 0 5\n", 3, "no 'edges_per_bin' line"),
        (GOOD_HEAD + "share 1024 1024 1024 1024\n", 4, "no learned bin"),
    ],
)
def test_a_malformed_learned_state_stops_the_ecu_at_its_line(ecu_unit, tmp_path, text, line, message):
    (tmp_path / "learned.txt").write_text(text)
    out = ghdl_exec(ecu_unit, tmp_path, "learned_file=learned.txt", "start_position=850")
    assert out.returncode != 0
    assert f"ecu_software: learned.txt:{line}: {message}" in out.stdout + out.stderr
    assert "@0ms" in out.stdout + out.stderr  # at power-up, before anything moves


@needs_ghdl
@pytest.mark.parametrize(
    "generics, message",
    [
        (("learned_file=nowhere.txt",), "ecu_software: cannot open nowhere.txt (learned_file)"),
        (("learned_out=no/such/folder.txt",), "ecu_software: cannot write no/such/folder.txt (learned_out)"),
        (("algorithm=1", "learned_out=c.txt"), "ecu_software: learned_file and learned_out need a VHDL algorithm"),
        (("algorithm=8",), "ecu_software: algorithm must be 0 .. 7 (the antipinch package's algorithms"),
        (
            ("start_position=850",),
            "ecu_software: start_position is the position of a warm start: it needs learned_file",
        ),
    ],
)
def test_a_warm_start_the_ecu_cannot_make_is_one_failure(ecu_unit, tmp_path, generics, message):
    out = ghdl_exec(ecu_unit, tmp_path, *generics)
    assert out.returncode != 0
    assert message in out.stdout + out.stderr


def test_the_closed_loop_bench_passes_the_warm_start_through():
    from wrsim import BENCHES, bench_params
    from wrsim.benches.core import instance
    from wrsim.elab import elaborate

    lib = load_library(paths.LIBRARY)
    params = bench_params(BENCHES["pinch"])
    cold = elaborate(lib, "tb_closed_loop", params, {"gauge_travel": 0.2})
    ecu = {c.label: c.generics for c in cold.top.digital}["ecu"]
    # the empty file names are the ECU's own defaults, not set on GHDL's command line (it takes no "-gNAME=")
    assert "learned_file" not in ecu and "learned_out" not in ecu and ecu["start_position"] == 0
    assert instance(cold.tree, "plant.mechanism").generics["glass_position0"] == 0.0
    assert instance(cold.tree, "gauge").generics["position0"] == pytest.approx(-0.2)
    warm = elaborate(
        lib,
        "tb_closed_loop",
        params,
        {
            "glass_start": 0.1,
            "gauge_travel": 0.02,
            "learned_file": "a.txt",
            "start_position": 700,
            "learned_out": "b.txt",
        },
    )
    ecu = {c.label: c.generics for c in warm.top.digital}["ecu"]
    assert (ecu["learned_file"], ecu["start_position"], ecu["learned_out"]) == ("a.txt", 700, "b.txt")
    for path in ("plant.mechanism", "plant.door", "plant.door.pane"):
        assert instance(warm.tree, path).generics[
            "glass_position0" if path == "plant.mechanism" else "position0"
        ] == pytest.approx(0.1)
    assert instance(warm.tree, "gauge").generics["position0"] == pytest.approx(0.08)
    # an empty string where the digital unit's default is not empty cannot reach GHDL: one error
    with pytest.raises(
        SourceError, match="generic 'sequence_file' of digital unit switch: GHDL cannot set a string generic to \"\""
    ):
        elaborate(lib, "tb_closed_loop", params, {"sequence_file": ""})


SEQUENCE = """\
# normalization, then a position/voltage unit and a stop
T 0 1          # up (an integer time is accepted)
T 0.5 0
t 1.25e0 2
P 0.1 -4 0 0.2
T 3.0 0
"""


@needs_ghdl
def test_switch_runs_a_sequence(tmp_path):
    (tmp_path / "seq.txt").write_text(SEQUENCE)
    out = ghdl_run(tmp_path, DIGITAL_FILES(["switch"]), "switch", "sequence_file=seq.txt")
    lines = [ln.split("(report note): ", 1)[1] for ln in out.stdout.splitlines() if "(report note)" in ln]
    assert out.returncode == 0, out.stdout + out.stderr
    times = [ln.split(":@", 1)[1].split(":", 1)[0] for ln in out.stdout.splitlines() if "(report note)" in ln]
    assert lines == [
        "switch: line 2: T unit, command 1",
        "switch: line 3: T unit, command 0",
        "switch: line 4: T unit, command 2",
        "switch: line 5: P unit, target 211 edges, offset -40 x 0.1 V",
        # the position input is open on a top-level run: unknown, so the unit stops and times out
        "switch: line 5: P unit ends, position unknown",
        "switch: line 6: T unit, command 0",
        "switch: sequence finished",
    ]
    assert times == ["0ms", "500ms", "1250ms", "1250ms", "1450ms", "3000ms", "3000ms"]


@needs_ghdl
def test_a_t_unit_may_offset_the_supply(tmp_path):
    # a 10 ms supply dip while the motor runs up: the command stays up, only the offset changes
    (tmp_path / "seq.txt").write_text("T 0 1\nT 0.5 1 -4   # dip to 9 V\nT 0.51 1\n")
    out = ghdl_run(tmp_path, DIGITAL_FILES(["switch"]), "switch", "sequence_file=seq.txt")
    assert out.returncode == 0, out.stdout + out.stderr
    lines = [ln.split("(report note): ", 1)[1] for ln in out.stdout.splitlines() if "(report note)" in ln]
    assert lines[:3] == [
        "switch: line 1: T unit, command 1",
        "switch: line 2: T unit, command 1, offset -40 x 0.1 V",
        "switch: line 3: T unit, command 1",
    ]


SWITCH_HARNESS = """\
library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

-- tb_switch_p: a stand-in ECU moves the position one edge per ms in the commanded direction; the position
-- is undefined for the first ms.
entity tb_switch_p is
end entity tb_switch_p;

architecture bench of tb_switch_p is
  signal position : std_logic_vector(31 downto 0);
  signal command  : std_logic_vector(1 downto 0);
  signal offset   : std_logic_vector(7 downto 0);
begin
  sw: entity work.switch
    generic map (sequence_file => "seq.txt")
    port map (position => position, command => command, voltage_offset => offset);
  ecu: process
    variable p : integer := 100;
  begin
    wait for 1 ms;
    while now < 1 sec loop
      position <= std_logic_vector(to_signed(p, 32));
      wait for 1 ms;
      if command = "01" then
        p := p - 1;
      elsif command = "10" then
        p := p + 1;
      end if;
    end loop;
    report "final position " & integer'image(p) & ", offset " & integer'image(to_integer(signed(offset)));
    std.env.finish;
  end process ecu;
end architecture bench;
"""


@needs_ghdl
def test_switch_drives_to_position_targets(tmp_path):
    (tmp_path / "seq.txt").write_text("P 0.0 0 0 0.05   # up to the top\nP 0.02 3 0 0.05  # down to 42 edges at +3 V\n")
    (tmp_path / "tb_switch_p.vhd").write_text(SWITCH_HARNESS)
    out = ghdl_run(tmp_path, [*DIGITAL_FILES(["switch"]), tmp_path / "tb_switch_p.vhd"], "tb_switch_p")
    assert out.returncode == 0, out.stdout + out.stderr
    notes = [ln.split("(report note): ", 1)[1] for ln in out.stdout.splitlines() if "(report note)" in ln]
    assert notes == [
        "switch: line 1: P unit, target 0 edges, offset 0 x 0.1 V",
        "switch: line 1: P unit ends at position 0",
        "switch: line 2: P unit, target 42 edges, offset 30 x 0.1 V",
        "switch: line 2: P unit ends at position 42",
        "switch: sequence finished",
        "final position 42, offset 30",
    ]


@needs_ghdl
@pytest.mark.parametrize(
    "line, message",
    [
        ("X 1 2", "unknown unit 'X', expected T or P"),
        ("T 1 4", "unknown command 4 (0 stop, 1 up, 2 down, 3 one-touch up)"),
        ("T 1.0", "malformed T unit"),
        ("T 1 1 1 1", "unexpected text '1' after the unit"),
        ("T 1 1 x", "malformed T unit"),
        ("T 1 1 13", "voltage offset must be in -12.8 .. 12.7 V"),
        ("T abc 1", "malformed T unit"),
        ("P 0.1 0 0", "malformed P unit"),
        ("P 0.1 0 0 0", "timeout must be > 0 s"),
        ("P 0.1 20 0 1", "voltage offset must be in -12.8 .. 12.7 V"),
    ],
)
def test_switch_rejects_a_malformed_line(tmp_path, line, message):
    (tmp_path / "seq.txt").write_text(f"T 0.0 0\n\n# comment\n{line}\n")
    out = ghdl_run(tmp_path, DIGITAL_FILES(["switch"]), "switch", "sequence_file=seq.txt")
    assert out.returncode != 0
    assert f"switch: seq.txt:4: {message}" in out.stdout + out.stderr


@needs_ghdl
def test_switch_rejects_times_that_do_not_rise(tmp_path):
    (tmp_path / "seq.txt").write_text("T 0.0 1\nT 2.0 0\nP 0 0 0 1\nT 2.0 2\n")
    out = ghdl_run(tmp_path, DIGITAL_FILES(["switch"]), "switch", "sequence_file=seq.txt")
    assert out.returncode != 0
    assert "switch: seq.txt:4: time 2.0 s does not follow 2.0 s" in out.stdout + out.stderr


HALL_BENCH = """\
library IEEE;
use IEEE.MATH_REAL.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_hall_turns: the armature angle swings +-8 rad (two reversals in 2 s) past the Hall sensor.
entity tb_hall_turns is
end entity tb_hall_turns;

architecture bench of tb_hall_turns is
  terminal shaft : rotational_v;
  quantity speed across torque through shaft;
  signal a, b, dir : std_logic;
begin
  speed == 8.0 * math_pi * cos(math_pi * now);  -- armature angle 8*sin(pi*t) [rad]
  sensor: entity work.hall_sensor(behavioral)
    generic map (pole_shares => ({shares}))
    port map (shaft => shaft, hall_a => a, hall_b => b, direction => dir);
end architecture bench;
"""


def hall_bench(tmp_path: Path, shares: str) -> Path:
    """Folder holding tb_hall_turns with the given pole_shares aggregate."""
    folder = tmp_path / "bench"
    folder.mkdir(exist_ok=True)
    (folder / "tb_hall_turns.vhd").write_text(HALL_BENCH.format(shares=shares))
    return folder


def expected_level(angle: np.ndarray, shares: list[float], offset: float) -> np.ndarray:
    """Parity of the pole index at `angle` (pole 1 begins at `offset`)."""
    frac = np.mod((angle - offset) / (2 * math.pi), 1.0)
    return np.searchsorted(np.cumsum(shares)[:3], frac, side="right") % 2


def test_hall_sensor_edges_thresholds_and_direction(simulate, tmp_path):
    bench = hall_bench(tmp_path, "0.24, 0.26, 0.23, 0.27")
    w = simulate("tb_hall_turns", 2.0, max_step=1e-4, files=(*AMS_FILES, bench))
    shares, offset, shift = [0.24, 0.26, 0.23, 0.27], -3 * math.pi / 8, math.pi / 4
    angle = w["sensor.angle"]
    for name, off in (("a", offset), ("b", offset + shift)):
        level = expected_level(angle, shares, off)
        crossings = w.time[np.flatnonzero(np.diff(level)) + 1]
        edges = w.time[np.flatnonzero(np.diff(w[name])) + 1]
        assert crossings.size == edges.size == 20
        # an A->D edge lands on the first time point after the crossing, within max_step
        assert np.all((edges >= crossings) & (edges - crossings <= 1e-4))
        away = np.min(np.abs(w.time[:, None] - crossings[None, :]), axis=1) > 1e-4
        assert np.array_equal(w[name][away], level[away])
    bottom, top = w["sensor.threshold_bottom"], w["sensor.threshold_top"]
    assert np.all(bottom <= angle + 1e-9) and np.all(angle < top + 1e-9)
    bounds = offset + 2 * math.pi * np.concatenate([[0.0], np.cumsum(shares)])
    turns = np.floor((bottom - offset) / (2 * math.pi) + 1e-9)
    on_bound = np.min(np.abs((bottom - 2 * math.pi * turns)[:, None] - bounds[None, :]), axis=1)
    assert on_bound.max() < 1e-9  # thresholds are pole boundaries (Fig. 4.74)
    speed = 8.0 * math.pi * np.cos(math.pi * w.time)
    moving = (np.abs(speed) > 0.1) & (w.time > 1e-4)  # the DC point has speed 0 ('0')
    assert np.array_equal(w["dir"][moving], (speed[moving] > 0).astype(float))


@pytest.mark.parametrize(
    "shares, message",
    [
        ("0.25, 0.25, 0.25, 0.26", "pole_shares must sum to 1"),
        ("0.5, -0.1, 0.3, 0.3", "pole_shares must be > 0"),
        ("0.3, 0.3, 0.4", "pole_shares needs 4 values"),
    ],
)
def test_hall_sensor_checks_the_pole_shares(tmp_path, shares, message):
    with pytest.raises(SourceError, match=f"hall_sensor: {message}"):
        netlist("tb_hall_turns", 1.0, files=(*AMS_FILES, hall_bench(tmp_path, shares)))


RELAY_BENCH = """\
library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.MECHANICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_relays: the ECU hardware switches a motor up (0.1-0.4 s), stop, down (0.7-1.0 s), stop, while the
-- supply ramps from 12 V to 27 V.
entity tb_relays is
end entity tb_relays;

architecture bench of tb_relays is
  terminal bat, mp, mn : electrical;
  terminal shaft : rotational_v;
  quantity up_cmd : real;    -- [1]
  quantity down_cmd : real;  -- [1]
  signal up, down : std_logic;
  signal code : std_logic_vector(7 downto 0);
begin
  supply: entity work.pwl_supply(behavioral)
    generic map (times => (0.0, 1.0, 1.6), values => (12.0, 14.0, 27.0))
    port map (p => bat, n => electrical_ref);
  if now > 0.1 and now < 0.4 use
    up_cmd == 1.0;
  else
    up_cmd == 0.0;
  end use;
  if now > 0.7 and now < 1.0 use
    down_cmd == 1.0;
  else
    down_cmd == 0.0;
  end use;
  up <= '1' when up_cmd'above(0.5) else '0';
  down <= '1' when down_cmd'above(0.5) else '0';
  hw: entity work.ecu_hardware(behavioral)
    generic map (r_contact => 0.01)
    port map (bat_p => bat, bat_n => electrical_ref, mot_p => mp, mot_n => mn,
              relay_up => up, relay_down => down, supply_code => code);
  motor: entity work.dcpm_motor(simple)
    port map (p => mp, n => mn, shaft => shaft);
end architecture bench;
"""


def test_ecu_hardware_relays_and_supply_code(simulate, tmp_path):
    (tmp_path / "bench").mkdir()
    (tmp_path / "bench" / "tb_relays.vhd").write_text(RELAY_BENCH)
    w = simulate("tb_relays", 1.6, max_step=1e-4, files=(*AMS_FILES, tmp_path / "bench"))
    t, u = w.time, w["supply.ua"]
    ua, ia, omega = w["motor.ua"], w["motor.ia"], w["motor.omega"]
    up = (t > 0.15) & (t < 0.4)
    down = (t > 0.75) & (t < 1.0)
    # up: motor on the supply through two closed contacts; down: reversed
    assert np.allclose(ua[up], u[up] - 2 * 0.01 * ia[up], atol=1e-6)
    assert np.allclose(ua[down], -u[down] - 2 * 0.01 * ia[down], atol=1e-6)
    assert omega[np.searchsorted(t, 0.39)] > 100.0 and omega[np.searchsorted(t, 0.99)] < -100.0
    # stop: both motor terminals on bat_n through the normally-closed contacts (dynamic brake)
    stop = (t > 0.41) & (t < 0.69)
    assert np.allclose(ua[stop], -2 * 0.01 * ia[stop], atol=1e-6)
    assert abs(omega[np.searchsorted(t, 0.6)]) < 1.0
    # supply register: 0.1 V steps, rounded, clamped at 255 (25.5 V)
    expected = np.clip(np.floor(u / 0.1 + 0.5), 0, 255)
    changes = t[np.flatnonzero(np.diff(expected)) + 1]
    steady = np.min(np.abs(t[:, None] - changes[None, :]), axis=1) > 1e-4  # A->D edges: within max_step
    assert np.array_equal(w["code"][steady], expected[steady])
    assert w["code"][-1] == 255


LAB_SUPPLY_BENCH = """\
library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
use IEEE.STD_LOGIC_1164.all;

-- tb_lab_supply: the switch offsets the lab supply (-4 V, then +3 V, then 0 V) into a 1 Ohm load.
entity tb_lab_supply is
  generic (sequence_file : string := "seq.txt");  -- [-] switch sequence
end entity tb_lab_supply;

architecture bench of tb_lab_supply is
  terminal p : electrical;
  quantity ul across il through p;
  signal position : std_logic_vector(31 downto 0);
  signal command : std_logic_vector(1 downto 0);
  signal offset : std_logic_vector(7 downto 0);
begin
  ul == 1.0 * il;
  supply: entity work.lab_supply(behavioral)
    generic map (u_nominal => 13.0, r_internal => 0.5)
    port map (p => p, n => electrical_ref, voltage_offset => offset);
  sw: entity work.switch
    generic map (sequence_file => sequence_file)
    port map (position => position, command => command, voltage_offset => offset);
end architecture bench;
"""


@needs_ghdl
def test_lab_supply_follows_the_switch_voltage_offset(simulate, tmp_path):
    (tmp_path / "bench").mkdir()
    (tmp_path / "bench" / "tb_lab_supply.vhd").write_text(LAB_SUPPLY_BENCH)
    seq = tmp_path / "seq.txt"
    # P units with an open position input end after their timeout (0.1 s) plus the 100 ms release
    seq.write_text("T 0.0 0\nP 0 -4 0 0.1\nP 0 3 0 0.1\nT 0.5 0\n")
    w = simulate(
        "tb_lab_supply",
        0.6,
        max_step=1e-3,
        files=(*AMS_FILES, tmp_path / "bench"),
        overrides={"sequence_file": str(seq)},
    )
    t = w.time
    for at, offset, source in ((0.1, -40, 9.0), (0.3, 30, 16.0), (0.55, 0, 13.0)):
        k = int(np.searchsorted(t, at))
        code = w["offset"][k]
        assert (code - 256 if code >= 128 else code) == offset
        # u = u_nominal + 0.1 V * offset, divided between 0.5 Ohm inside and the 1 Ohm load
        assert w["supply.ua"][k] == pytest.approx(source / 1.5, rel=1e-9)
        assert w["ul"][k] == pytest.approx(source / 1.5, rel=1e-9)


def test_a_missing_c_source_is_named_with_its_vhdl_file(tmp_path):
    vhd = tmp_path / "unit.vhd"
    vhd.write_text("-- c source: nowhere.c\nentity unit is end entity unit;\n")
    with pytest.raises(WrsimError, match=r"unit\.vhd: its '-- c source: nowhere\.c' cannot be read"):
        c_sources([(vhd, vhd.read_bytes())])
    (tmp_path / "nowhere.c").write_text("int x;\n")
    assert c_sources([(vhd, vhd.read_bytes())]) == [((tmp_path / "nowhere.c").resolve(), b"int x;\n")]
