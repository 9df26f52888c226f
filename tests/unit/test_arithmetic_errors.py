"""Arithmetic the LRM makes an error, or that has no finite value, is one error at its place, never an internal error
nor a silently wrong number (issue 50): a negative real to a fractional power, an integer to a negative power, an
integer outside integer'low .. integer'high, a division by zero or an overflow at initialisation or in a process's
waits, a negative timeout, and a quantity that is not a finite number at run time."""

from __future__ import annotations

from pathlib import Path

import pytest

from wrsim import cli

HEADER = "library IEEE;\nuse IEEE.MATH_REAL.all;\n"


def one_error(capsys, *argv: str) -> str:
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    assert code == 2 and err.startswith("wrsim: error: ") and "internal error" not in err, (code, err)
    return err.removeprefix("wrsim: error: ").splitlines()[0]


def model(tmp_path: Path, decls: str, body: str) -> Path:
    f = tmp_path / "t.vhd"
    f.write_text(
        f"{HEADER}entity t is\nend entity t;\narchitecture a of t is\n{decls}\n  quantity x : real;\nbegin\n{body}\n"
        "end architecture a;\n"
    )
    return f


@pytest.mark.parametrize(
    "decls, body, where, message",
    [
        ("  constant c : real := (-2.0) ** 0.5;", "  x == c * now;", "6:31", "a negative base to a power that is not"),
        ("  constant c : real := 0.0 ** (-1);", "  x == c * now;", "6:28", "0.0 ** -1: division by zero"),
        ("  constant k : integer := 2 ** (-1);", "  x == real(k) + now;", "6:29", "a negative power of an integer"),
        ("  constant k : integer := 2 ** 31;", "  x == real(k) + now;", "6:3", "outside the integer range"),
        ("  constant k : integer := integer'high * 2;", "  x == real(k) + now;", "6:3", "outside the integer range"),
        (
            "  signal s, d : real := 0.0;",
            "  p: process\n  begin\n    s <= 10.0 / d;\n    wait for 1 ms;\n  end process;\n  x == s;",
            "9:6",
            "at initialisation: division by zero",
        ),
        (
            "  signal s : real := 0.0;",
            "  p: process\n  begin\n    s <= s + 1.0;\n    wait for 1.0e308 sec;\n    wait for 1.0e308 sec;\n"
            "  end process;\n  x == s;",
            "13:5",
            "the waits' times add up past the largest time",
        ),
        (
            "  signal s : real := 0.0;",
            "  p: process\n  begin\n    s <= s + 1.0;\n    wait for -1 us;\n    wait for 2 us;\n  end process;\n"
            "  x == s;",
            "12:14",
            "a timeout must not be negative",
        ),
    ],
)
def test_static_arithmetic_without_a_value_is_one_located_error(tmp_path, capsys, decls, body, where, message):
    f = model(tmp_path, decls, body)
    err = one_error(capsys, "run", str(f), "--top", "t", "--stop", "0.01", "--results", str(tmp_path / "r"))
    assert err.startswith(f"{f}:{where}: ") and message in err, err


def test_an_integer_generic_past_integer_high_is_refused(tmp_path, capsys):
    f = tmp_path / "g.vhd"
    f.write_text(
        "entity g is\n  generic (n : integer := 1);\nend entity g;\narchitecture a of g is\n"
        "  quantity x : real;\nbegin\n  x == real(n) * now;\nend architecture a;\n"
    )
    err = one_error(
        capsys, "run", str(f), "--top", "g", "--stop", "0.01", "--set", "n=2147483648", "--results", str(tmp_path / "r")
    )
    assert "'n' = 2147483648 is outside the integer range -2147483648 .. 2147483647" in err, err


def test_a_quantity_without_a_finite_value_at_run_time_is_an_error_and_writes_nothing(tmp_path, capsys):
    f = model(tmp_path, "", "  x == sqrt(1.0 - now);")
    results = tmp_path / "r"
    err = one_error(capsys, "run", str(f), "--top", "t", "--stop", "2", "--results", str(results))
    assert err.startswith("x is not a finite number (nan) from t = 1.0") and "the run has no result" in err, err
    assert not (results / "run" / "t" / "waveforms.csv").exists()


_RUN_TIME = (
    "  p: process\n  begin\n    wait for 1 ms;\n    d <= {d};\n    wait for 1 ms;\n    s <= {expr};\n    wait;\n"
    "  end process;\n  x == s;"
)


@pytest.mark.parametrize("compiled", ["--compile", "--no-compile"])
@pytest.mark.parametrize(
    "expr", ["10.0 / d", "sqrt(d - 1.0)", "log(d)", "(d - 0.5) ** 0.5", "d ** (-1.0)", "arcsin(d + 1.5)"]
)
def test_a_process_value_without_one_at_run_time_stops_the_run_at_the_process(tmp_path, capsys, expr, compiled):
    """A division by zero (the compiled device's guarded division gave 1e33, silently), the square root of a negative
    number, the logarithm of 0, a negative base to a fractional power (the device took |x| ** y), zero to a negative
    power or an arcsine beyond 1 in a value a process assigns at 2 ms: one error at the process's line with the
    time, and no result."""
    f = model(tmp_path, "  signal s, d : real := 1.0;", _RUN_TIME.format(d="0.0", expr=expr))
    results = tmp_path / "r"
    err = one_error(capsys, "run", str(f), "--top", "t", "--stop", "0.005", compiled, "--results", str(results))
    assert err.startswith("simulation failed: error: at t = 0.002 s the value assigned has none"), err
    assert err.endswith(f"{f}:9:6 (the bench): p: process"), err
    assert not (results / "run" / "t" / "waveforms.csv").exists()


@pytest.mark.parametrize(
    "d, expr, value",
    [("4.0", "10.0 / d", 2.5), ("4.0", "d ** 0.5", 2.0), ("-4.0", "d ** 3.0", -64.0), ("0.5", "arcsin(d)", 0.5235988)],
)
def test_a_process_value_that_has_one_at_its_event_runs(tmp_path, capsys, d, expr, value):
    """The check looks at the value the event takes, not between events: 10 / d with d = 0 until 1 ms, assigned at
    2 ms when d = 4, gives s = 2.5; a negative base to a whole power has its value."""
    f = model(tmp_path, "  signal s : real := 0.0;\n  signal d : real := 0.0;", _RUN_TIME.format(d=d, expr=expr))
    assert cli.main(["run", str(f), "--top", "t", "--stop", "0.005", "--results", str(tmp_path / "r")]) == 0
    rows = (tmp_path / "r" / "run" / "t" / "waveforms.csv").read_text().splitlines()
    assert rows[0].startswith("time[s]") and float(rows[-1].split(",")[3]) == pytest.approx(value)


@pytest.mark.parametrize("compiled", ["--compile", "--no-compile"])
def test_an_integer_a_process_takes_past_integer_high_stops_the_run(tmp_path, capsys, compiled):
    """An integer signal doubled every 10 ms from 1 passes integer'high at its 31st doubling (0.31 s): IEEE 1076
    makes that an error (GHDL stops); it went on to 2**100 as a real. 2**30 at 0.30 s is kept."""
    body = "  p: process\n  begin\n    wait for 10 ms;\n    n <= n * 2;\n  end process;\n  x == real(n);"
    f = model(tmp_path, "  signal n : integer := 1;", body)
    err = one_error(capsys, "run", str(f), "--top", "t", "--stop", "1", compiled, "--results", str(tmp_path / "r"))
    assert err.startswith("simulation failed: error: at t = 0.31 s the value assigned has none"), err
    assert "an integer past integer'high" in err and err.endswith(f"{f}:9:6 (the bench): p: process"), err


def test_a_quiescent_point_without_a_solution_is_an_error_not_a_start(tmp_path, capsys):
    """`x'dot == -1.0` with no break list: 1076.1 holds x'dot = 0 at the quiescent point, so it has no solution. The
    compiled device's operating point gave x'dot = -1 and x = -1e-5, a start that ran on without a word; now one error
    naming the derivative. With `break x => 0.0;` the integrator runs: x(1 s) = -1."""
    f = model(tmp_path, "", "  x'dot == -1.0;")
    err = one_error(capsys, "run", str(f), "--top", "t", "--stop", "1", "--compile", "--results", str(tmp_path / "r"))
    assert err.startswith(f"simulation failed: the quiescent point has no solution: x'dot (x declared at {f}:7:3)")
    assert "is -1 there" in err, err
    f = model(tmp_path, "", "  break x => 0.0;\n  x'dot == -1.0;")
    assert cli.main(["run", str(f), "--top", "t", "--stop", "1", "--compile", "--results", str(tmp_path / "r")]) == 0
    rows = (tmp_path / "r" / "run" / "t" / "waveforms.csv").read_text().splitlines()
    assert float(rows[1].split(",")[1]) == 0.0 and float(rows[-1].split(",")[1]) == pytest.approx(-1.0, rel=1e-6)


@pytest.mark.parametrize("compiled", ["--compile", "--no-compile"])
def test_integer_division_mod_and_rem_follow_ieee_1076_at_elaboration_and_at_run_time(tmp_path, compiled):
    """IEEE 1076 9.2.7: an integer quotient truncates toward zero, `a rem b` takes a's sign and `a mod b` b's; the same
    from constants folded at elaboration and from an integer signal a process changes at run time (it ran as a real
    division, silently: -7 / 2 gave -3.5). k steps -7, -6, ... every 1 ms."""
    decls = (
        "  constant c1 : integer := (-7) / 2;\n  constant c2 : integer := (-7) mod 3;\n"
        "  constant c3 : integer := (-7) rem 3;\n  constant c4 : integer := 7 mod (-3);\n"
        "  signal k : integer := -7;\n  signal d, m, r : integer := 0;\n  quantity y1, y2, y3 : real;"
    )
    body = (
        "  p: process\n  begin\n    wait for 1 ms;\n    d <= k / 2;\n    m <= k mod 3;\n    r <= k rem 3;\n"
        "    k <= k + 1;\n  end process;\n  x == real(c1 * 1000 + c2 * 100 + c3 * 10 + c4);\n"
        "  y1 == real(d);\n  y2 == real(m);\n  y3 == real(r);"
    )
    f = model(tmp_path, decls, body)
    assert cli.main(["run", str(f), "--top", "t", "--stop", "0.0155", compiled, "--results", str(tmp_path / "r")]) == 0
    rows = [r.split(",") for r in (tmp_path / "r" / "run" / "t" / "waveforms.csv").read_text().splitlines()]
    head = rows[0]
    col = {name.split("[")[0]: head.index(name) for name in head}
    last = rows[-1]
    assert float(last[col["x"]]) == -3000 + 200 - 10 - 2  # -7/2 = -3, -7 mod 3 = 2, -7 rem 3 = -1, 7 mod -3 = -2
    seen = {}
    for row in rows[1:]:  # the values assigned at 1 ms + j ms from k = -7 + j - 1 (the run before the change of k)
        t = float(row[0])
        seen[round(t * 1000 - 0.5)] = (float(row[col["y1"]]), float(row[col["y2"]]), float(row[col["y3"]]))
    for j in range(1, 15):
        k = -7 + j - 1
        expected = (float(int(k / 2)), float(k % 3), float(k - 3 * int(k / 3)))
        assert seen[j] == expected, (j, k, seen[j], expected)
