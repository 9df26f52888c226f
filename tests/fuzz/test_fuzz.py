"""Every user input ends in success or one located WrsimError: the reproducers of the hostile-user findings
(issue 12) as regression tests, and property-based fuzzing over the lexer, parser, elaborator, lowering and the
data-file readers. The budget is short in `make test` (WRSIM_FUZZ_EXAMPLES, default 60 per property); `make fuzz`
runs the long one (tests/fuzz/fuzzer.py: 100,000 VHDL-AMS and 20,000 data-file cases with time and memory limits)."""

from __future__ import annotations

import math
import os
import re
from pathlib import Path

import fuzzer
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import wrsim
from wrsim import paths
from wrsim.errors import SourceError, WrsimError
from wrsim.frontend import parse_text, tokenize

EXAMPLES = int(os.environ.get("WRSIM_FUZZ_EXAMPLES", "60"))
BUDGET = settings(max_examples=EXAMPLES, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.too_slow])

MODEL = """library IEEE; use IEEE.MATH_REAL.all; use IEEE.STD_LOGIC_1164.all;
entity vec_user is generic (v : real_vector := (0.0, 1.0)); end entity vec_user;  -- [s] v
architecture a of vec_user is begin end architecture a;
library IEEE; use IEEE.MATH_REAL.all; use IEEE.STD_LOGIC_1164.all;
entity tb is end entity tb;
architecture a of tb is
  quantity x : real; -- [V] x
  {decls}
  function f(a : real; b : real) return real is
    variable acc : real := 0.0;
  begin
    {body}
    return acc + a + b;
  end function f;
begin
  {stmts}
end architecture a;
"""

# (decls, function body, statements) -> the message at the offending construct
REPRODUCERS = {
    "based literal, base 37": ("constant c : integer := 37#1#;", "", "x == real(c);", "the base must be 2 to 16"),
    "based literal, digit 2 in base 2": (
        "constant c : integer := 2#102#;",
        "",
        "x == real(c);",
        "digit '2' is not a base-2 digit",
    ),
    "based literal, no digits": (
        "constant c : integer := 16#_#;",
        "",
        "x == real(c);",
        "digits with single underscores between them expected",
    ),
    "based literal, 5000 digits": (
        f"constant c : integer := 2#{'1' * 5000}#;",
        "",
        "x == real(c);",
        "more than 64 digits",
    ),
    "real literal out of range": ("", "", "x == 1.0e999;", "is out of range"),
    "real power overflow": ("", "", "x == 10.0 ** 400;", "'**' overflows"),
    "integer power overflow": ("constant c : integer := 2 ** 100000000;", "", "x == real(c);", "'**' overflows"),
    "product overflow": ("constant c : real := 1.0e300 * 1.0e300;", "", "x == c;", "not a finite number"),
    "integer out of range": (
        "constant c : integer := 2000000000 * 2000000000 * 2000000000;",
        "",
        "x == real(c);",
        "out of the integer range",
    ),
    "real vector bound": (
        "signal s : std_logic_vector(7.0 downto 0);",
        "",
        "x == 1.0;",
        "std_logic_vector range other than (N-1 downto 0)",
    ),
    "vector of a million bits": (
        "signal s : std_logic_vector(1000000 downto 0);",
        "",
        "x == 1.0;",
        "at most 256 are supported",
    ),
    "loop of 1e8 iterations": (
        "",
        "for n in 1 to 100000000 loop acc := acc + 1.0; end loop;",
        "x == f(1.0, 2.0);",
        "at most 10000 are unrolled",
    ),
    "nested loops of 1e8 steps": (
        "",
        "for n in 1 to 10000 loop for m in 1 to 10000 loop acc := acc + 1.0; end loop; end loop;",
        "x == f(1.0, 2.0);",
        "more than 1000000 steps",
    ),
    "real loop bound": (
        "",
        "for n in 1 to 10.5 loop acc := acc + 1.0; end loop;",
        "x == f(1.0, 2.0);",
        "loop bounds must be integers",
    ),
    "loop that builds a deep expression": (
        "",
        "for n in 1 to 3000 loop acc := acc + a; end loop;",
        "x == f(x, 2.0);",
        "more than 256 operations deep",
    ),
    "open as an argument": ("", "", "x == f(open, 1.0);", "'open' as an argument of 'f'"),
    "real index": ("constant v : real_vector := (1.0, 2.0);", "", "x == v(1.5);", "must be an integer"),
    "164 nested parentheses": ("", "", "x == " + "(" * 165 + "1.0" + ")" * 165 + ";", "nested more than 64 levels"),
    "a vector generic that is not static": (
        "",
        "",
        "u: entity work.vec_user generic map (v => (0.0, -now));",
        "generic 'v' must be static",
    ),
    "flat sum of 500 terms": ("", "", "x == " + " + ".join(["1.0"] * 500) + ";", "more than 256 operations deep"),
    "a time divided by no time": (
        "constant c : integer := 1 ms / 0 ms;",
        "",
        "x == real(c);",
        "the ratio is not an integer in range",
    ),
    "a time divided by 0": ("constant c : time := 1 ms / 0;", "", "x == 1.0;", "division by zero"),
    "a for-generate of 1e8 iterations": (
        "",
        "",
        "g: for k in 1 to 100000000 generate\n  end generate;",
        "at most 10000",
    ),
    "an array quantity of 1e8 elements": (
        "quantity q : real_vector(1 to 100000000);",
        "",
        "x == 1.0;",
        "at most 10000",
    ),
    "an element of an array quantity of no elements": (
        "quantity q : real_vector(1 to 0);",
        "",
        "x == q(1);",
        "'q' has no elements (a null range)",
    ),
    "'ztf with an infinite DC gain": (
        "",
        "",
        "x == x'ztf((1.0, 0.0), (1.0, -1.0), 1.0e-3);",
        "the sum of the denominator of 'ztf",
    ),
    "a derivative broken at an event": (
        "",
        "",
        "x'dot == 1.0; break x'dot => 0.5 when x'above(1.0);",
        "unsupported construct: a break on x'dot at an event",
    ),
    "'zoh with a period that moves with now": (
        "quantity y : real; -- [V] y",
        "",
        "x == sin(now); y == x'zoh(now);",
        "the sampling period must be static, found an expression of now",
    ),
}


@pytest.mark.parametrize("name", list(REPRODUCERS))
def test_reproducer_ends_in_one_located_error(tmp_path: Path, name: str) -> None:
    decls, body, stmts, message = REPRODUCERS[name]
    path = tmp_path / "model.vhd"
    path.write_text(MODEL.format(decls=decls, body=body, stmts=stmts), encoding="utf-8")
    with pytest.raises(SourceError) as err:
        design = wrsim.elaborate(wrsim.load_library([paths.VHDL / "ieee", path]), "tb")
        wrsim.lower(design, wrsim.Analysis(1e-3), "tb")
    assert re.match(rf"^{re.escape(str(path))}:\d+:\d+: ", str(err.value)), err.value
    assert message in str(err.value)


def test_statements_after_a_final_wait_never_run(tmp_path: Path) -> None:
    """A `wait for` after `wait;` (an internal KeyError once): the process is suspended for good at `wait;`."""
    path = tmp_path / "model.vhd"
    stmts = "p: process begin s <= 1.0; wait; wait for 1 ms; s <= 2.0; end process p; x == s;"
    path.write_text(MODEL.format(decls="signal s : real := 0.0;", body="", stmts=stmts), encoding="utf-8")
    design = wrsim.elaborate(wrsim.load_library([paths.VHDL / "ieee", path]), "tb")
    (model,) = [m for m in [design.top, *design.models] if m.entity.name == "tb"]
    assert model.holds["s__s"].initial == wrsim.elab.symbolic.const(1.0)  # set at initialisation
    assert not any(e.at for e in model.hold_events)  # and no wake-up after the `wait;`
    assert "p__wake" not in wrsim.lower(design, wrsim.Analysis(1e-3), "tb").text


def test_a_file_that_ends_inside_a_port_list_is_located() -> None:
    with pytest.raises(SourceError) as err:
        parse_text("entity e is port (signal s : out std_logic_vector(7 downto", "cut.vhd")
    assert str(err.value) == "cut.vhd:1:59: expected ')', found end of file"


def test_limits_leave_room_for_the_library() -> None:
    """The limits are far above what the model library needs: a 256-term sum and a 64-bit vector still work."""
    text = MODEL.format(
        decls="signal s : std_logic_vector(63 downto 0);", body="", stmts="x == " + " + ".join(["1.0"] * 257) + ";"
    )
    assert parse_text(text, "model.vhd").units


# ------------------------------------------------------------------------------------------------ properties
@BUDGET
@given(st.text(max_size=400))
def test_any_text_lexes_and_parses_or_fails_located(text: str) -> None:
    try:
        tokenize(text, "any.vhd")
        parse_text(text, "any.vhd")
    except SourceError as e:
        assert str(e).startswith("any.vhd:")


VHDL_FILES = sorted(str(p) for p in fuzzer.project()[0])
DATA_FILES = sorted(str(p) for p in fuzzer.data_files())


@BUDGET
@given(st.sampled_from(VHDL_FILES), st.integers(0, 2**31))
def test_mutated_library_files_elaborate_or_fail_cleanly(path: str, seed: int) -> None:
    try:
        fuzzer.vhdl_case(Path(path), seed)
    except WrsimError:
        pass


@BUDGET
@given(st.sampled_from(DATA_FILES), st.integers(0, 2**31))
def test_mutated_data_files_read_or_fail_cleanly(path: str, seed: int) -> None:
    try:
        fuzzer.data_case(Path(path), seed)
    except WrsimError:
        pass


def test_a_spectrum_phase_of_any_size_is_lowered_within_one_turn(tmp_path: Path) -> None:
    """`spectrum 1.0, 1.0e308` (found by make fuzz): its degrees overflowed to infinity in the lowering (an internal
    FoldError); the phase is taken within one turn first, as AC sees it."""
    path = tmp_path / "model.vhd"
    decls = "quantity u : real spectrum 1.0, 1.0e308;"
    path.write_text(MODEL.format(decls=decls, body="", stmts="x == u;"), encoding="utf-8")
    design = wrsim.elaborate(wrsim.load_library([paths.VHDL / "ieee", path]), "tb")
    line = next(ln for ln in wrsim.lower(design, wrsim.Analysis(1e-3), "tb").text.splitlines() if "__ac " in ln)
    degrees = float(line.split()[-1])
    assert -180.0 <= degrees <= 180.0
    assert math.isclose(math.radians(degrees), math.remainder(1.0e308, 2 * math.pi), rel_tol=1e-9)


# Reproducers of issue 51 (hostile inputs, round 3): each ends in one error naming the place, never an internal one.


def test_a_scenario_nested_past_the_bound_is_one_located_error(tmp_path: Path) -> None:
    from wrsim.benches.scenario import load_scenario

    f = tmp_path / "deep.toml"
    f.write_text('purpose = "x"\nstop = 1.0\n[generics]\nx = ' + "[" * 3000 + "1" + "]" * 3000 + "\n")
    with pytest.raises(WrsimError, match=r"deep\.toml:4:37: arrays and inline tables nested more than 32 deep"):
        load_scenario(f)
    ok = tmp_path / "brackets_in_strings.toml"  # brackets in strings and comments are no nesting
    ok.write_text(
        'purpose = "'
        + "[" * 40
        + '"  # '
        + "{" * 40
        + '\nstop = 1.0\n[switch]\nunits = [{ at = 0.0, command = "up" }]\n'
    )
    assert load_scenario(ok).purpose == "[" * 40


@pytest.mark.parametrize("name", [".", ".."])
def test_a_folder_named_as_a_scenarios_parameter_set_is_one_error(tmp_path: Path, monkeypatch, name: str) -> None:
    from wrsim.benches.scenario import load_scenario

    (tmp_path / "dot.toml").write_text(f'purpose = "x"\nstop = 1.0\nparams = ["{name}"]\n')
    monkeypatch.chdir(tmp_path)  # the scenario by a relative name: its folder is "."
    with pytest.raises(WrsimError, match=rf"dot\.toml:3: params: unknown parameter set '{re.escape(name)}'"):
        load_scenario("dot.toml")


@pytest.mark.skipif(__import__("shutil").which("ghdl-llvm") is None, reason="GHDL not installed")
def test_a_record_with_a_revolution_within_one_microsecond_replays(tmp_path: Path) -> None:
    """A record may hold equal times: twelve Hall-A edges at one microsecond (four make a revolution of 0 us, which
    divided by zero in tb_replay and killed it with SIGFPE, an empty message) replay like any record."""
    import numpy as np

    from wrsim.benches.replay import Record, Replayer, ecu_generics
    from wrsim.benches.scenario import scenario_params
    from wrsim.data.params import load_params
    from wrsim.elab.library import load_library

    fixture = paths.ROOT / "tests" / "fixtures" / "records" / "fleet-seed1-door2"
    rows = (fixture / "rod_10npmm_25mm_9v.txt").read_text().splitlines()
    k = next(i for i, r in enumerate(rows) if i > 300 and not r.startswith("#"))
    t, a, *rest = rows[k].split()
    burst = []
    for _ in range(12):
        a = "1" if a == "0" else "0"
        burst.append(" ".join([t, a, *rest]))
    folder = tmp_path / "rec"
    folder.mkdir()
    (folder / "inputs.txt").write_text("\n".join(rows[: k + 1] + burst + rows[k + 1 :]) + "\n")
    (folder / "learning.txt").write_bytes((fixture / "learning.txt").read_bytes())
    lib = load_library(paths.LIBRARY)
    generics = ecu_generics(lib, scenario_params().beneath(load_params(paths.ALGORITHMS / "observer_rise.txt")))
    rec = Record("rec", folder, 887, np.zeros(1), np.zeros(1), np.zeros(1))
    decision = Replayer(tmp_path / "build", lib).replay(rec, generics, "burst")
    assert decision.detected is None or decision.detected > 0.0


def test_a_chain_of_includes_past_the_bound_is_one_error_at_the_include(tmp_path: Path) -> None:
    from wrsim.data.params import load_params

    for i in range(1200):  # no cycle: each file includes the next (Python's recursion ended it before)
        text = f"include p{i + 1}.txt\n" if i < 1199 else "[dcpm_motor]\nra = 0.9 Ohm\n"
        (tmp_path / f"p{i}.txt").write_text(text)
    with pytest.raises(WrsimError, match=r"p31\.txt:1: include p32\.txt: includes nested more than 32 deep"):
        load_params(tmp_path / "p0.txt")


def test_a_scenario_longer_than_the_ecus_timer_is_refused_before_it_runs(tmp_path: Path) -> None:
    from wrsim.benches.scenario import load_scenario

    f = tmp_path / "long.toml"
    f.write_text('purpose = "x"\nstop = 3000.0\n[switch]\nunits = [{ at = 0.0, command = "up" }]\n')
    with pytest.raises(WrsimError, match=r"long\.toml:2: stop = 3000 s: at most 2147 s"):
        load_scenario(f)


def test_a_replay_csv_with_a_byte_order_mark_reads(tmp_path: Path) -> None:
    from wrsim.benches.replay import read_inputs

    f = tmp_path / "door.csv"
    f.write_bytes("\ufefft_us,hall_a,hall_b,supply_dv,command\n0,0,0,130,01\n100,1,0,130,01\n".encode())
    assert read_inputs(f, tmp_path / "checked.txt") == 2


_UP = '[switch]\nunits = [{ at = 0.1, command = "up" }]\n'


@pytest.mark.parametrize(
    "body, error",
    [
        (  # a supply the switch cannot offset: found when the sequence was written, in the run
            'purpose = "x"\nstop = 1.0\n[switch]\nunits = [{ at = 0.1, command = "up", supply = "40 V" }]\n',
            r"s\.toml:4: \[switch\] unit 1: supply 40 V is \+27\.0 V from the nominal 13 V",
        ),
        (  # an ambient outside the temperature rules: found when the run's set was made
            'purpose = "x"\nstop = 1.0\n[ambient]\ntemperature = "500 degC"\n' + _UP,
            r"s\.toml:4: \[ambient\] temperature: 500 degC is outside -40 \.\. 85 degC",
        ),
        (  # an include cycle in the scenario's own set
            'purpose = "x"\nstop = 1.0\nparams = ["a.txt"]\n' + _UP,
            r"b\.txt:1: include a\.txt: a cycle",
        ),
        (  # a scenario's params naming a file that is no parameter set
            'purpose = "x"\nstop = 1.0\nparams = ["s.toml"]\n' + _UP,
            r"s\.toml:1: key 'purpose' comes before any \[entity\] section",
        ),
        (  # ngspice's "timestep too small" at the first step
            'purpose = "x"\nstop = 1.0\n[solver]\nmax_step = 1e300\n' + _UP,
            r"s\.toml:4: \[solver\] max_step = 1e\+300 s: at most the run's stop, 1 s",
        ),
        (  # replaced by the scenario's own sequence without a word
            'purpose = "x"\nstop = 1.0\n[generics]\nsequence_file = "/etc/hostname"\n' + _UP,
            r"s\.toml:4: \[generics\] sequence_file: written from \[switch\]",
        ),
        (  # found by the fuzzer's structural operator: OSError from pathlib
            'purpose = "x"\nstop = 1.0\nparams = ["' + "x" * 300 + '"]\n' + _UP,
            r"s\.toml:3: params: x{40}\.\.\.: File name too long",
        ),
        (  # found by make fuzz: tomllib's ValueError from Python's bound on a whole number's digits
            'purpose = "x"\nstop = ' + "9" * 5000 + "\n" + _UP,
            r"s\.toml:2:8: a whole number of more than 4300 digits",
        ),
    ],
    ids=["supply", "ambient", "include-cycle", "not-a-set", "max-step", "sequence-file", "long-name", "digits"],
)
def test_a_scenario_error_is_found_before_anything_runs(tmp_path: Path, capsys, body: str, error: str) -> None:
    """Each of these surfaced only in the run (an ERROR row, pages written, exit 1) or not at all: now one error
    naming the file and line, exit 2, and no results folder."""
    from wrsim.cli import main

    (tmp_path / "a.txt").write_text("include b.txt\n")
    (tmp_path / "b.txt").write_text("include a.txt\n")
    (tmp_path / "s.toml").write_text(body)
    results = tmp_path / "results"
    assert main(["scenario", "--results", str(results), str(tmp_path / "s.toml")]) == 2
    assert re.search(error, capsys.readouterr().err)
    assert not results.exists()


@pytest.mark.parametrize(
    "line, error",
    [
        ("ra = 1e-400 Ohm", r"p\.txt:2: \[dcpm_motor\] ra: '1e-400' is below the smallest number kept in full"),
        ("ra = 4e-320 Ohm", r"'4e-320' is below the smallest number kept in full"),  # subnormal: digits lost
        ("ra = 0.55 Ohm +- 5 % normal 1e-300sigma", r"'1e-300sigma': the tolerance is 0\.5 \.\. 10 standard"),
        ("ra +- 5 % normal uniform", r"p\.txt:2: \[dcpm_motor\] ra: 'uniform' after 'normal': a tolerance has one"),
    ],
    ids=["underflow", "subnormal", "sigmas", "two-laws"],
)
def test_a_number_or_law_that_would_be_read_as_another_is_refused(tmp_path: Path, line: str, error: str) -> None:
    """Each was read silently: 1e-400 as 0, a tolerance of 1e-300 standard deviations drew ra = 3e298 Ohm, the last
    of two laws won. `--set` reads numbers the same way."""
    from wrsim.data.params import load_params
    from wrsim.elab.generics import number

    (tmp_path / "p.txt").write_text(f"[dcpm_motor]\n{line}\n")
    with pytest.raises(WrsimError, match=error):
        load_params(tmp_path / "p.txt")
    with pytest.raises(WrsimError, match=r"--set u_nominal: '1e-400' is below the smallest number"):
        number("1e-400 V", "V", "--set u_nominal")
    assert number("0.0e-400 V", "V", "--set u_nominal") == 0.0  # a written zero is zero


def test_a_small_signal_analysis_of_a_design_with_a_process_names_the_process(capsys) -> None:
    """--ac and --noise on a design whose values change at events ended in ngspice's "external unknown parameter
    (external)": one error at the process that sets the first held value, exit 2."""
    from wrsim.cli import main

    tb = paths.ROOT / "tests" / "corpus" / "signal" / "process_all_tb.vhd"
    for analysis in (["--ac", "1", "1000", "10"], ["--noise", "yl", "1", "1000", "10"]):
        assert main(["run", str(tb), "--top", "process_all_tb", *analysis]) == 2
        err = capsys.readouterr().err
        assert re.search(
            r"process_all_tb\.vhd:17:14: a small-signal \(AC, noise\) analysis needs a design without "
            r"events; here 'a' changes at one \(stimulus : process is\)",
            err,
        ), err


@pytest.mark.parametrize("period", ["0.0", "-1.0e-3"])
def test_a_ztf_sampling_period_that_is_no_period_is_one_located_error(tmp_path: Path, capsys, period: str) -> None:
    from wrsim.cli import main

    text = (paths.ROOT / "tests" / "corpus" / "signal" / "ztf_tb.vhd").read_text()
    (tmp_path / "z.vhd").write_text(text.replace("period, 0.5 * period)", f"{period}, 0.0)"))
    assert main(["run", str(tmp_path / "z.vhd"), "--top", "ztf_tb", "--stop", "0.01"]) == 2
    assert re.search(
        r"z\.vhd:22:9: a sampling period of -?[0-9.e-]+ s .*: the period must be > 0", capsys.readouterr().err
    )


def test_a_signal_assignment_in_a_simultaneous_if_is_one_located_error(tmp_path: Path, capsys) -> None:
    """Found by make fuzz (seed 89531 of process_threshold_tb): `vs1 <= unaffected;` in an if-use branch was taken
    for a simultaneous case (AttributeError: 'Process' object has no attribute 'selector')."""
    from wrsim.cli import main

    text = (paths.ROOT / "tests" / "corpus" / "signal" / "process_threshold_tb.vhd").read_text()
    assert "    vs1 == 0.0;\n" in text
    (tmp_path / "p.vhd").write_text(text.replace("    vs1 == 0.0;\n", "    vs1 <= unaffected;\n", 1))
    assert main(["run", str(tmp_path / "p.vhd"), "--top", "process_threshold_tb", "--stop", "0.01"]) == 2
    assert re.search(
        r"p\.vhd:\d+:5: a branch of a simultaneous if or case holds only simultaneous statements",
        capsys.readouterr().err,
    )
