"""Non-finite numbers are refused at every boundary, naming where they are (issue 12): parameter sets, tables,
the identification's inputs and outputs, command-line options, top-level generics; a UTF-8 BOM is accepted."""

from __future__ import annotations

import shutil
from pathlib import Path

import numpy as np
import pytest

import wrsim
from wrsim import cli, paths
from wrsim.data.can import load_dbc
from wrsim.data.measurements import read_table, write_table
from wrsim.data.params import load_params, save_params
from wrsim.errors import SourceError, WrsimError
from wrsim.identify import identify_default_set


def one_error(capsys, *argv: str) -> str:
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    assert code == 2 and err.startswith("wrsim: error: ") and err.count("\n") == 1, (code, err)
    return err.removeprefix("wrsim: error: ").rstrip("\n")


@pytest.mark.parametrize(
    "text, message",
    [
        ("ra = inf Ohm", "[dcpm_motor] ra: 'inf' is not a finite number"),
        ("ra = nan Ohm", "[dcpm_motor] ra: 'nan' is not a finite number"),
        ("angles = [0.0, nan] rad", "[dcpm_motor] angles: 'nan' is not a finite number"),
    ],
)
def test_parameter_set_refuses_non_finite_values(tmp_path: Path, text: str, message: str) -> None:
    path = tmp_path / "p.txt"
    path.write_text(f"[dcpm_motor]\n{text}\n", encoding="utf-8")
    with pytest.raises(WrsimError) as err:
        load_params(path)
    assert str(err.value) == f"{path}:2: {message}"


def test_a_value_that_overflows_its_unit_names_the_key(tmp_path: Path, capsys) -> None:
    path = tmp_path / "p.txt"
    path.write_text("[dcpm_motor]\nra = 1e308 kOhm\n", encoding="utf-8")
    assert one_error(capsys, "lower", "tb_motor_characteristic", "--params", str(path)) == (
        f"{path}:2: [dcpm_motor] ra: 1e+308 kOhm is not a finite number in Ohm"
    )


def test_byte_order_marks_are_accepted(tmp_path: Path) -> None:
    pset = tmp_path / "p.txt"
    pset.write_bytes(b"\xef\xbb\xbf[dcpm_motor]\nra = 0.5 Ohm\n")
    assert load_params(pset).value_in("dcpm_motor", "ra", "Ohm") == 0.5
    table = tmp_path / "t.csv"
    table.write_bytes(b"\xef\xbb\xbf# source: test\nx[m],y[N]\n1,2\n")
    assert read_table(table, require_source=True).column("y", "N").tolist() == [2.0]


@pytest.mark.parametrize("cell", ["nan", "inf", "-inf"])
def test_tables_refuse_non_finite_cells_by_row_and_column(tmp_path: Path, cell: str) -> None:
    path = tmp_path / "t.csv"
    path.write_text(f"# source: test\nx[m],y[N]\n1,2\n2,{cell}\n", encoding="utf-8")
    with pytest.raises(WrsimError) as err:
        read_table(path)
    assert str(err.value) == f"{path}:4: column 'y': '{cell}' is not a finite number"


def test_writers_refuse_non_finite_values_and_keep_the_old_file(tmp_path: Path) -> None:
    pset = tmp_path / "p.txt"
    save_params(pset, ["good"], {"dcpm_motor": [("ra", 0.5, "Ohm", "")]})
    before = pset.read_bytes()
    with pytest.raises(WrsimError, match=r"\[dcpm_motor\] ra = nan: not a finite number; nothing written"):
        save_params(pset, ["bad"], {"dcpm_motor": [("ra", float("nan"), "Ohm", "")]})
    assert pset.read_bytes() == before
    table = tmp_path / "t.csv"
    with pytest.raises(WrsimError, match=r"column 'y', row 2: inf is not a finite number; nothing written"):
        write_table(table, {"x": np.array([1.0, 2.0]), "y": np.array([1.0, np.inf])}, {"x": "m", "y": "N"}, [])
    assert not table.exists()


def test_identification_of_the_default_set_refuses_a_nan_measurement(tmp_path: Path) -> None:
    shutil.copytree(paths.PARAMS, tmp_path / "params")
    csv = tmp_path / "params" / "measurements" / "fig4_15_motor.csv"
    lines = csv.read_text(encoding="utf-8").splitlines()
    row = next(k for k, line in enumerate(lines) if line[:1].isdigit())
    lines[row] = "nan," + lines[row].split(",", 1)[1]
    csv.write_text("\n".join(lines) + "\n", encoding="utf-8")
    with pytest.raises(WrsimError) as err:
        identify_default_set(tmp_path)
    assert str(err.value) == f"{csv}:{row + 1}: column 'torque': 'nan' is not a finite number"


@pytest.mark.parametrize(
    "argv, message",
    [
        (
            ("lower", "tb_motor_characteristic", "--stop", "nan"),
            "wrsim lower: argument --stop: 'nan' is not a finite number",
        ),
        (
            ("lower", "tb_motor_characteristic", "--max-step", "-1"),
            "wrsim lower: argument --max-step: '-1' must be > 0",
        ),
        (
            ("lower", "tb_motor_characteristic", "--set", "direction=inf"),
            "--set direction=inf: 'inf' is not a finite number",
        ),
        (("averaging", "--t-end", "1e9"), "wrsim averaging: argument --t-end: '1e9' is more than 1000 s"),
        (
            ("identify", "temperature", "--celsius", "nan"),
            "wrsim identify: argument --celsius: 'nan' is not a finite number",
        ),
    ],
)
def test_command_line_numbers_are_finite_and_in_range(capsys, argv: tuple[str, ...], message: str) -> None:
    assert one_error(capsys, *argv) == message


def test_top_level_generics_are_finite() -> None:
    with pytest.raises(WrsimError, match=r"generic 'direction' = nan: not a finite number"):
        wrsim.elaborate(wrsim.load_library(), "tb_motor_characteristic", None, {"direction": float("nan")})


def test_a_broken_dbc_is_one_located_line(tmp_path: Path) -> None:
    path = tmp_path / "bad.dbc"
    path.write_text('VERSION ""\nBO_ 1 X: 8 Vector\n SG_ a : 0|8@1+ (1,0) [0|255] "" Vector\n garbage\n')
    with pytest.raises(SourceError) as err:
        load_dbc(path)
    assert str(err.value).startswith(f"{path}:4:") and "\n" not in str(err.value)
