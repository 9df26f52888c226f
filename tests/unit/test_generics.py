"""Top-level generic values as users write them (`--set`, scenario files): numbers with units converted to the unit
of the generic's subtype, strings (files relative to the working directory made absolute), booleans; one error that
names the option and the generic."""

from __future__ import annotations

import os

import pytest

from wrsim import load_library, paths
from wrsim.elab.generics import number, top_generics
from wrsim.errors import WrsimError

TB = "tb_closed_loop"


@pytest.fixture(scope="module")
def lib():
    return load_library(paths.LIBRARY)


@pytest.mark.parametrize(
    "given, expected",
    [
        ({"u_nominal": "9V"}, {"u_nominal": 9.0}),
        ({"u_nominal": "9 V"}, {"u_nominal": 9.0}),
        ({"u_nominal": "9"}, {"u_nominal": 9.0}),  # a bare number is in the generic's unit
        ({"U_Nominal": 9500e-3}, {"u_nominal": 9.5}),
        ({"pinch_position": "320mm"}, {"pinch_position": 0.32}),
        ({"gauge_stiffness": "65 N/mm"}, {"gauge_stiffness": 65e3}),
        ({"road_frequency": "8 Hz"}, {"road_frequency": 8.0}),  # a real with a `-- [Hz]` comment
    ],
)
def test_numbers_with_units_are_converted_to_the_generics_unit(lib, given, expected):
    out = top_generics(lib, TB, given)
    assert {k: out[k] for k in expected} == pytest.approx(expected)


def test_a_string_naming_a_file_here_becomes_its_absolute_path(lib, tmp_path):
    (tmp_path / "seq.txt").write_text("T 0 1\n", encoding="utf-8")
    out = top_generics(lib, TB, {"sequence_file": "seq.txt"}, cwd=tmp_path)
    assert out["sequence_file"] == str(tmp_path / "seq.txt")
    assert top_generics(lib, TB, {"sequence_file": "not_here.txt"}, cwd=tmp_path)["sequence_file"] == "not_here.txt"


def test_a_string_default_naming_a_file_here_is_found_too(lib, tmp_path):
    """tb_closed_loop's sequence_file defaults to switch_sequence.txt: the one in the directory of the command."""
    assert "sequence_file" not in top_generics(lib, TB, {}, cwd=tmp_path)
    (tmp_path / "switch_sequence.txt").write_text("T 0 1\n", encoding="utf-8")
    assert top_generics(lib, TB, {}, cwd=tmp_path)["sequence_file"] == str(tmp_path / "switch_sequence.txt")


def test_a_file_a_generic_names_is_an_input_file_with_bounded_lines(lib, tmp_path):
    """A switch sequence with a 10 MB line kept GHDL's textio busy for minutes, a FIFO blocked the reader: the file
    a string generic names is checked before the design reads it (the same without --set, for a default)."""
    (tmp_path / "long.txt").write_text("T 0 1\nT " + "1" * 10_000_000 + " 0\n", encoding="utf-8")
    with pytest.raises(WrsimError) as err:
        top_generics(lib, TB, {"sequence_file": "long.txt"}, cwd=tmp_path)
    assert str(err.value) == (
        f"--set sequence_file=long.txt: {tmp_path / 'long.txt'}:2: a line of 10000004 characters, more than the "
        "4096 allowed"
    )
    os.mkfifo(tmp_path / "switch_sequence.txt")
    with pytest.raises(WrsimError, match="switch_sequence.txt: not a regular file"):
        top_generics(lib, TB, {}, cwd=tmp_path)


@pytest.mark.parametrize(
    "given, message",
    [
        ({"u_nominal": "nine"}, "--set u_nominal=nine: the generic is a number (real in V): write a number"),
        ({"u_nominal": "9 N"}, "--set u_nominal=9 N: "),
        ({"u_nominal": True}, "--set u_nominal=True: the generic is a number (real in V), not a boolean"),
        ({"sequence_file": 3.0}, "--set sequence_file=3.0: the generic is a string"),
        ({"volts": "9"}, "--set volts: tb_closed_loop has no generic 'volts' (it has: sequence_file, u_nominal"),
        ({"u_nominal": "inf"}, "--set u_nominal=inf: 'inf' is not a finite number"),
        ({"u_nominal": "-NaN"}, "--set u_nominal=-NaN: '-NaN' is not a finite number"),
    ],
)
def test_a_wrong_value_is_one_error_naming_the_option_and_generic(lib, given, message):
    with pytest.raises(WrsimError) as e:
        top_generics(lib, TB, given)
    assert str(e.value).startswith(message)


def test_booleans_and_integers(lib, tmp_path):
    model = tmp_path / "flags.vhd"
    model.write_text(
        "entity flags_tb is\n  generic (enabled : boolean := false; n : natural := 1);\n"
        "end entity flags_tb;\narchitecture a of flags_tb is\nbegin\nend architecture a;\n",
        encoding="utf-8",
    )
    small = load_library([paths.VHDL / "ieee", model])
    assert top_generics(small, "flags_tb", {"enabled": "true", "n": "3"}) == {"enabled": True, "n": 3.0}
    assert top_generics(small, "flags_tb", {"enabled": "FALSE"}) == {"enabled": False}
    with pytest.raises(WrsimError, match="--set enabled=yes: the generic is a boolean: write true or false"):
        top_generics(small, "flags_tb", {"enabled": "yes"})
    with pytest.raises(WrsimError, match="--set n=2.5: the generic is an integer"):
        top_generics(small, "flags_tb", {"n": "2.5"})


def test_number_takes_a_unit_or_the_given_one():
    assert number("4 mm", "m", "x") == pytest.approx(0.004)
    assert number(0.5, "s", "x") == 0.5
    assert number("-40 degC", "degC", "x") == -40.0
