"""`wrsim run`: a user's VHDL-AMS files from outside the repository (.ams, IEEE_PROPOSED, a library of their own),
simulated against a closed form; a file that does not parse stops only a run that needs it."""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest

from conftest import table
from wrsim import paths
from wrsim.cli import main

ROOT = paths.ROOT

RC = """\
-- An RC charge: v_c(t) = u*(1 - exp(-t/(r*c))).
library ieee_proposed, mylib;
use ieee_proposed.electrical_systems.all;
use mylib.rc_values.all;

entity rc_tb is
  generic (u : voltage := 5.0; r : resistance := r_default; c : capacitance := 1.0e-6);
end entity rc_tb;

architecture behav of rc_tb is
  terminal a, b : electrical;
  quantity v_src across i_src through a to electrical_ref;
  quantity v_r across i_r through a to b;
  quantity v_c across i_c through b to electrical_ref;
begin
  if domain = quiescent_domain use
    v_src == 0.0;
  else
    v_src == u;
  end use;
  v_r == r * i_r;
  i_c == c * v_c'dot;
end architecture behav;
"""
VALUES = """\
package rc_values is
  constant r_default : real := 1.0e3;
end package rc_values;
"""
BROKEN = "entity broken is\n  generic (x : real := );\nend entity;\n"
USES_BROKEN = (
    "entity uses_broken is\nend entity;\narchitecture a of uses_broken is\nbegin\n"
    "  b: entity work.broken;\nend architecture;\n"
)


def _user_files(tmp_path: Path) -> tuple[Path, Path]:
    models, lib = tmp_path / "models", tmp_path / "mylib"
    models.mkdir()
    lib.mkdir()
    (models / "rc_tb.ams").write_text(RC)
    (models / "broken.vhd").write_text(BROKEN)
    (models / "uses_broken.vhdl").write_text(USES_BROKEN)
    (lib / "rc_values.vhd").write_text(VALUES)
    return models, lib


def _run(tmp_path: Path, sources: list[Path], top: str, stop: str, *args: str) -> int:
    """`wrsim run` into tmp_path/out; the exit status."""
    return main(["run", *map(str, sources), "--top", top, "--stop", stop, "--results", str(tmp_path / "out"), *args])


def _waves(tmp_path: Path, top: str) -> Path:
    return tmp_path / "out" / "run" / top / "waveforms.csv"


def _column(path: Path, name: str) -> tuple[np.ndarray, np.ndarray]:
    with path.open() as f:
        rows = list(csv.reader(f))
    data = np.array(rows[1:], dtype=float)
    assert name in rows[0], f"{name} not in {rows[0]}"
    return data[:, 0], data[:, rows[0].index(name)]


def test_run_a_users_files_against_the_closed_form(tmp_path, capsys):
    models, lib = _user_files(tmp_path)
    for r, args in ((1e3, []), (2e3, ["--set", "r=2e3"])):
        assert _run(tmp_path, [models], "rc_tb", "5e-3", "--lib", f"mylib={lib}", *args) == 0
        assert "rc_tb: 6 waveforms over 0.005 s" in capsys.readouterr().out
        folder = tmp_path / "out" / "run" / "rc_tb"
        t, v = _column(folder / "waveforms.csv", "v_c[V]")
        np.testing.assert_allclose(v, 5.0 * (1.0 - np.exp(-t / (r * 1e-6))), atol=5e-3)  # 1e-3 of the step
        assert (folder / "waveforms.png").stat().st_size > 1000


def test_a_file_that_does_not_parse_stops_only_a_run_that_needs_it(tmp_path, capsys):
    models, lib = _user_files(tmp_path)
    assert _run(tmp_path, [models], "uses_broken", "1e-3", "--lib", f"mylib={lib}") == 2
    err = capsys.readouterr().err
    assert "uses_broken.vhdl:5:6: unknown entity 'broken'" in err
    assert "not loaded: " in err and "broken.vhd:2:24: expected an expression" in err
    assert _run(tmp_path, [models], "rc_tb", "1e-3") == 2
    assert "unknown package mylib.rc_values" in capsys.readouterr().err  # its library was not mapped
    assert _run(tmp_path, [models], "rc_tb", "1e-3", "--lib", "mylib") == 2
    assert "write NAME=DIR" in capsys.readouterr().err


PARALLEL = """\
library ieee;
use ieee.electrical_systems.all;
entity source_and_load is
  generic (mode : string := "full"; u : voltage := 2.0; r : resistance := 1.0e3);
end entity source_and_load;
architecture behav of source_and_load is
  terminal a : electrical;
  quantity v across i through a to electrical_ref;    -- an ideal source ...
  quantity w across j through a to electrical_ref;    -- ... and a resistor on the same two terminals
begin
  if mode = "full" use
    v == u;
  elsif mode /= "half" use
    v == 0.0;
  else
    v == 0.5 * u;
  end use;
  w == r * j;
end architecture behav;

library ieee;
use ieee.electrical_systems.all;
entity half_tb is
end entity half_tb;
architecture structural of half_tb is
begin
  dut: entity work.source_and_load(behav) generic map (mode => "half");
end architecture structural;
"""


def test_a_source_across_a_load_and_string_generics(tmp_path, capsys):
    (tmp_path / "parallel.vhd").write_text(PARALLEL)
    for top, volts, prefix in (("source_and_load", 2.0, ""), ("half_tb", 1.0, "dut.")):
        assert _run(tmp_path, [tmp_path / "parallel.vhd"], top, "1e-3") == 0, capsys.readouterr().err
        csv_file = _waves(tmp_path, top)
        _, w = _column(csv_file, f"{prefix}w[V]")
        _, i = _column(csv_file, f"{prefix}i[A]")
        np.testing.assert_allclose(w[-1], volts, rtol=1e-9)
        np.testing.assert_allclose(i[-1], -volts / 1e3, rtol=1e-6)  # the source feeds the resistor


CLOCK = """\
library ieee;
use ieee.std_logic_1164.all;
entity clock_gen is
  generic (half_period_us : natural := 5000);
  port (clk : out std_logic; code : out std_logic_vector(1 downto 0));
end entity clock_gen;
architecture rtl of clock_gen is
begin
  code <= "00";
  ticking : process
  begin
    clk <= '0';
    wait for half_period_us * 1 us;
    clk <= '1';
    wait for half_period_us * 1 us;
  end process ticking;
end architecture rtl;
"""
CLOCKED = """\
library ieee;
use ieee.electrical_systems.all;
use ieee.std_logic_1164.all;
entity tb_clocked is
end entity tb_clocked;
architecture bench of tb_clocked is
  terminal b : electrical;
  signal clk : std_logic;
  signal code : std_logic_vector(1 downto 0);
begin
  gen: entity work.clock_gen port map (clk => clk, code => code);
  src: entity work.t_switched_source port map (p => b, on_cmd => clk, code => code);
end architecture bench;
"""


def test_a_digital_unit_with_outputs_only_drives_the_analog_part(tmp_path, capsys):
    (tmp_path / "clock_gen.vhd").write_text(CLOCK)
    (tmp_path / "tb_clocked.vhd").write_text(CLOCKED)
    signals = ROOT / "tests" / "fixtures" / "signals" / "t_signals.vhd"
    assert _run(tmp_path, [tmp_path, signals], "tb_clocked", "0.03", "--max-step", "1e-4") == 0, capsys.readouterr().err
    t, v = _column(_waves(tmp_path, "tb_clocked"), "src.v[V]")
    at = np.arange(0.0025, 0.03, 0.005)  # the middle of each 5 ms half period: 1 V, then 5 V
    np.testing.assert_allclose(np.interp(at, t, v), np.tile([1.0, 5.0], 3), atol=1e-6)


SECOND_ORDER = """\
library ieee;
use ieee.mechanical_systems.all;
entity dd_tb is
end entity dd_tb;
architecture a of dd_tb is
  quantity x : real;
begin
  if domain = quiescent_domain use
    x == 0.0;
  else
    x'dot'dot == 1.0 - 4.0 * x;
  end use;
end architecture a;
"""


def test_second_derivative_against_the_closed_form(tmp_path, capsys):
    (tmp_path / "dd.vhd").write_text(SECOND_ORDER)
    assert _run(tmp_path, [tmp_path / "dd.vhd"], "dd_tb", "3", "--max-step", "1e-3") == 0, capsys.readouterr().err
    t, x = _column(_waves(tmp_path, "dd_tb"), "x[1]")
    np.testing.assert_allclose(x, 0.25 * (1.0 - np.cos(2.0 * t)), atol=5e-4)  # 1e-3 of the 0.5 swing
    (tmp_path / "dd.vhd").write_text(SECOND_ORDER.replace("x'dot'dot", "x'dot'integ"))
    assert _run(tmp_path, [tmp_path / "dd.vhd"], "dd_tb", "3") == 2
    assert "dd.vhd:11:6: unsupported construct: attribute 'dot'integ" in capsys.readouterr().err


BREAK_LIST = """\
library ieee;
use ieee.electrical_systems.all;
entity brk_tb is
  generic (v0 : voltage := 3.0);
end entity brk_tb;
architecture a of brk_tb is
  terminal n : electrical;
  quantity v across i through n to electrical_ref;     -- a 1 uF capacitor ...
  quantity vr across ir through n to electrical_ref;   -- ... discharging into 1 kOhm
  quantity x : real;
begin
  i == 1.0e-6 * v'dot;
  vr == 1.0e3 * ir;
  x'dot == -1000.0 * x;
  break v => v0, x => 2.0;                             -- the quiescent point takes these instead of 'dot = 0
end architecture a;
"""


def test_a_break_list_sets_the_initial_values(tmp_path, capsys):
    (tmp_path / "brk.vhd").write_text(BREAK_LIST)
    assert _run(tmp_path, [tmp_path / "brk.vhd"], "brk_tb", "5e-3", "--max-step", "1e-5", "--set", "v0=4") == 0, (
        capsys.readouterr().err
    )
    csv_file = _waves(tmp_path, "brk_tb")
    t, v = _column(csv_file, "v[V]")
    _, x = _column(csv_file, "x[1]")
    np.testing.assert_allclose(v, 4.0 * np.exp(-t / 1e-3), atol=4e-3)  # 1e-3 of the initial value
    np.testing.assert_allclose(x, 2.0 * np.exp(-1000.0 * t), atol=2e-3)
    # x restarts from 2.0 where v falls through 1.0 (t = ln 4 ms): the break on an event
    (tmp_path / "brk.vhd").write_text(BREAK_LIST.replace("begin\n", "begin\n  break x => 2.0 on v'above(1.0);\n"))
    assert _run(tmp_path, [tmp_path / "brk.vhd"], "brk_tb", "5e-3", "--max-step", "1e-5", "--set", "v0=4") == 0, (
        capsys.readouterr().err
    )
    t, x = _column(_waves(tmp_path, "brk_tb"), "x[1]")
    tc = 1e-3 * np.log(4.0)
    away = np.abs(t - tc) > 2e-6  # the jump itself takes the driver's resolution (1 us), then one step
    np.testing.assert_allclose(x[away], 2.0 * np.exp(-1000.0 * np.where(t < tc, t, t - tc))[away], atol=2e-3)


ASPECTS = """\
library ieee;
use ieee.electrical_systems.all;
use ieee.math_real.all;
entity aspects_tb is
  generic (gains : real_vector := (0 => 2.0));          -- a one-element aggregate is written with its index
end entity aspects_tb;
architecture a of aspects_tb is
  constant taus : real_vector := (1 => 2.0e-3, 0 => 1.0e-3);
  terminal n : electrical;
  quantity v tolerance "default_voltage" := 0.0 across i tolerance "default_current" through n to electrical_ref;
  quantity x : real tolerance "default" := 0.0;
begin
  if domain = quiescent_domain use
    v == 0.0 tolerance "default_voltage";
  else
    v == gains(0) * (1.0 - exp(-now / taus(0)));
  end use;
  x == v / taus(1) * 1.0e-3;
end architecture a;
"""


def test_tolerance_aspects_initial_values_and_named_aggregates(tmp_path, capsys):
    (tmp_path / "aspects.vhd").write_text(ASPECTS)
    assert _run(tmp_path, [tmp_path / "aspects.vhd"], "aspects_tb", "5e-3") == 0, capsys.readouterr().err
    csv_file = _waves(tmp_path, "aspects_tb")
    t, v = _column(csv_file, "v[V]")
    _, x = _column(csv_file, "x[1]")
    np.testing.assert_allclose(v, 2.0 * (1.0 - np.exp(-t / 1e-3)), atol=2e-3)
    np.testing.assert_allclose(x, v / 2.0, atol=1e-9)


ALIASES = """\
library ieee;
use ieee.electrical_systems.all;
package my_names is
  alias elec is electrical;
  alias gnd is electrical_ref;
  alias volts is voltage;
end package my_names;

library ieee;
use ieee.electrical_systems.all;
use work.my_names.all;
entity alias_tb is
  generic (u : volts := 2.0);
end entity alias_tb;
architecture a of alias_tb is
  terminal n : elec;
  quantity v across i through n to gnd;
  quantity vr across ir through n to gnd;
  alias vsrc is v;
begin
  vsrc == u;
  vr == 1.0e3 * ir;
end architecture a;
"""


def test_aliases_of_a_nature_a_terminal_a_subtype_and_a_quantity(tmp_path, capsys):
    (tmp_path / "alias.vhd").write_text(ALIASES)
    assert _run(tmp_path, [tmp_path / "alias.vhd"], "alias_tb", "1e-3", "--set", "u=3") == 0, capsys.readouterr().err
    _, v = _column(_waves(tmp_path, "alias_tb"), "v[V]")
    _, ir = _column(_waves(tmp_path, "alias_tb"), "ir[A]")
    np.testing.assert_allclose([v[-1], ir[-1]], [3.0, 3e-3], rtol=1e-9)
    (tmp_path / "alias.vhd").write_text(ALIASES.replace("alias vsrc is v;", "alias vsrc is w;"))
    assert _run(tmp_path, [tmp_path / "alias.vhd"], "alias_tb", "1e-3") == 2
    assert "alias.vhd:19:3: alias vsrc: unknown name 'w'" in capsys.readouterr().err


def test_an_assertion_in_a_generated_instance_names_the_copy(tmp_path, capsys):
    leaf = (
        "library ieee;\nuse ieee.electrical_systems.all;\nentity leaf is\n  generic (r : resistance := 1.0);\n"
        "  port (terminal a : electrical);\nend entity leaf;\narchitecture x of leaf is\n"
        "  quantity v across i through a;\nbegin\n"
        '  assert r > 0.0 report "leaf: r must be > 0" severity failure;\n  v == r * i;\nend architecture x;\n'
    )
    bench = (
        "library ieee;\nuse ieee.electrical_systems.all;\nentity gen_tb is\nend entity gen_tb;\n"
        "architecture a of gen_tb is\n  terminal n : electrical;\n  quantity vs across i_s through n;\nbegin\n"
        "  vs == 1.0;\n  g: for k in 0 to 2 generate\n    constant rk : real := 1.0 - real(k);\n  begin\n"
        "    u: entity work.leaf generic map (r => rk) port map (a => n);\n  end generate g;\n"
        "end architecture a;\n"
    )
    (tmp_path / "leaf.vhd").write_text(leaf)
    (tmp_path / "gen_tb.vhd").write_text(bench)
    assert _run(tmp_path, [tmp_path / "leaf.vhd", tmp_path / "gen_tb.vhd"], "gen_tb", "1e-3") == 2
    assert capsys.readouterr().err.strip() == (
        f"wrsim: error: {tmp_path / 'leaf.vhd'}:10:3: leaf: r must be > 0 (instance gen_tb.g__1__u: r = 0)"
    )


ACROSS_SUBTYPE = """\
library ieee;
use ieee.electrical_systems.all;
entity across_tb is
end entity across_tb;
architecture a of across_tb is
  nature pins is array (natural range <>) of electrical;
  subtype pin_voltages is pins'across;                 -- as the 1076.1.1 packages declare voltage_vector
  quantity q : pin_voltages(1 to 2);
  quantity s : real;
begin
  if domain = quiescent_domain use
    s == 0.0;
  else
    s == 1.0;
  end use;
  q(1)'dot == 1000.0 * (s - q(1));
  q(2)'dot == 2000.0 * (2.0 * s - q(2));
end architecture a;
"""


def test_a_subtype_that_is_an_array_natures_across_type_is_a_real_vector(tmp_path, capsys):
    (tmp_path / "across.vhd").write_text(ACROSS_SUBTYPE)
    assert _run(tmp_path, [tmp_path / "across.vhd"], "across_tb", "3e-3", "--max-step", "1e-5") == 0, (
        capsys.readouterr().err
    )
    t, q1 = _column(_waves(tmp_path, "across_tb"), "q(1)[1]")
    _, q2 = _column(_waves(tmp_path, "across_tb"), "q(2)[1]")
    np.testing.assert_allclose(q1, 1.0 - np.exp(-1000.0 * t), atol=1e-3)
    np.testing.assert_allclose(q2, 2.0 * (1.0 - np.exp(-2000.0 * t)), atol=2e-3)


ANALYSIS = paths.ROOT / "tests" / "corpus" / "analysis"


def test_the_quiescent_point_and_a_dc_sweep_write_their_tables(tmp_path, capsys):
    """`--op` prints every quantity at the quiescent point and writes op.csv; `--dc u 0 1 0.125` one point per value
    (dc.csv, dc.png). corpus/analysis/diode_dc_tb checks the values against Lambert's W; here: the quiescent point
    is the sweep's point at the default u = 0.7, and a transient without --stop is one error."""
    run = ["run", str(ANALYSIS / "diode_dc_tb.vhd"), "--top", "diode_dc_tb", "--results", str(tmp_path / "out")]
    assert main([*run, "--op"]) == 0
    v = float(re.search(r"^v\s+(\S+) V$", capsys.readouterr().out, re.M).group(1))
    head, values = table(tmp_path / "out" / "run" / "diode_dc_tb" / "op.csv")
    assert head == ["i[A]", "s[V]", "v[V]"] and values[0, 1] == pytest.approx(0.7) and values[0, 2] == v
    assert main([*run, "--dc", "u", "0.7", "1", "0.3"]) == 0
    head, values = table(tmp_path / "out" / "run" / "diode_dc_tb" / "dc.csv")
    assert head == ["u[V]", "i[A]", "s[V]", "v[V]"] and values[:, 0].tolist() == [0.7, 1.0]
    assert values[0, 3] == pytest.approx(v, rel=1e-9)
    assert (tmp_path / "out" / "run" / "diode_dc_tb" / "dc.png").is_file()
    assert main([*run]) == 2  # a transient needs its stop
    assert "give --stop" in capsys.readouterr().err


def test_the_small_signal_response_follows_the_domain(tmp_path, capsys):
    """`--ac`: corpus/analysis/filters_ac_tb checks the Bode of a lag, an 'ltf, an 'integ and an RLC; here: the RC
    of corpus/noise_rc_tb is driven by its spectrum source only in the time domain's branch of an if-use, which
    holds in AC, and AC needs the compiled equations."""
    out = tmp_path / "out"
    rc = paths.ROOT / "tests" / "corpus" / "electrical" / "noise_rc_tb.vhd"
    assert main(["run", str(rc), "--top", "noise_rc_tb", "--ac", "10", "1e4", "5", "--results", str(out)]) == 0
    head, values = table(out / "run" / "noise_rc_tb" / "ac.csv")
    h = 1.0 / (1.0 + 2j * np.pi * values[:, 0] * 1e-3)
    np.testing.assert_allclose(values[:, head.index("|vc|[dB]")], 20 * np.log10(np.abs(h)), atol=1e-6)
    assert (out / "run" / "noise_rc_tb" / "ac.png").is_file()
    assert main(["run", str(rc), "--top", "noise_rc_tb", "--ac", "10", "1e4", "5", "--no-compile"]) == 2
    assert "drop --no-compile" in capsys.readouterr().err


def test_the_noise_density_against_the_closed_form(tmp_path, capsys):
    """`--noise vc 10 1e5 5` on corpus/noise_rc_tb: the thermal noise of r (4kTR, its noise source quantity) at the
    capacitor, sqrt(4kTR) / |1 + j*w*R*C|, within 1e-6."""
    rc = paths.ROOT / "tests" / "corpus" / "electrical" / "noise_rc_tb.vhd"
    out = tmp_path / "out"
    run = ["run", str(rc), "--top", "noise_rc_tb", "--results", str(out)]
    assert main([*run, "--noise", "vc", "10", "1e5", "5"]) == 0
    head, values = table(out / "run" / "noise_rc_tb" / "noise.csv")
    assert head == ["frequency[Hz]", "vc noise[V/sqrt(Hz)]"]
    np.testing.assert_allclose(values[:, 0], np.logspace(1, 5, 21), rtol=1e-8)
    expected = np.sqrt(4 * 1.380649e-23 * 300 * 1e3) / np.abs(1 + 2j * np.pi * values[:, 0] * 1e-3)
    np.testing.assert_allclose(values[:, 1], expected, rtol=1e-6)
    assert main([*run, "--noise", "nope", "10", "1e5", "5"]) == 2
    assert "--noise nope: no quantity 'nope' in noise_rc_tb" in capsys.readouterr().err


def test_the_input_referred_noise_against_the_closed_form(tmp_path, capsys):
    """Referred to the spectrum source v_ac (in series with the resistor's noise source), the RC's noise is the
    resistor's own sqrt(4kTR) at every frequency: the output density divided by the gain 1 / |1 + j*w*R*C|."""
    rc = paths.ROOT / "tests" / "corpus" / "electrical" / "noise_rc_tb.vhd"
    out = tmp_path / "out"
    run = ["run", str(rc), "--top", "noise_rc_tb", "--results", str(out), "--noise", "vc", "10", "1e5", "5"]
    assert main([*run, "--noise-input", "v_ac"]) == 0
    head, values = table(out / "run" / "noise_rc_tb" / "noise.csv")
    assert head == ["frequency[Hz]", "vc noise[V/sqrt(Hz)]", "vc noise referred to v_ac[1/sqrt(Hz)]"]
    thermal = np.sqrt(4 * 1.380649e-23 * 300 * 1e3)
    np.testing.assert_allclose(values[:, 1], thermal / np.abs(1 + 2j * np.pi * values[:, 0] * 1e-3), rtol=1e-6)
    np.testing.assert_allclose(values[:, 2], thermal, rtol=1e-6)
    capsys.readouterr()
    assert main([*run, "--noise-input", "vs"]) == 2
    assert "--noise-input vs: no spectrum source quantity 'vs' in noise_rc_tb (v_ac)" in capsys.readouterr().err
