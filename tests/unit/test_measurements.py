"""Measurement/result CSV tables: round trip, unit conversion, transcribed thesis data, error paths."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from wrsim import paths
from wrsim.data.measurements import read_table, write_table
from wrsim.data.units import convert
from wrsim.errors import WrsimError

ROOT = paths.ROOT
MEAS = ROOT / "params" / "measurements"


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "t.csv"
    path.write_text(text, encoding="utf-8")
    return path


GOOD = "# source: test\n# more\ntorque[N*m],speed[rpm]\n0.1,6000\n0.2,5000\n"


def test_round_trip_keeps_values_units_and_comments(tmp_path):
    path = tmp_path / "out" / "r.csv"
    torque = np.array([0.1, 0.2, 1 / 3])
    write_table(
        path,
        {"torque": torque, "current": [1.5, 2.5, 3.5]},
        {"torque": "N*m", "current": "A"},
        ["source: unit test", "two\nlines"],
    )
    assert path.read_text().splitlines()[:4] == ["# source: unit test", "# two", "# lines", "torque[N*m],current[A]"]
    table = read_table(path, increasing="torque", require_source=True)
    assert table.source == "unit test"
    assert table.units == {"torque": "N*m", "current": "A"}
    np.testing.assert_array_equal(table.column("torque"), torque)  # repr() is lossless
    assert list(tmp_path.joinpath("out").iterdir()) == [path]  # no temp file left behind
    path.chmod(0o640)
    write_table(path, {"torque": torque}, {"torque": "N*m"}, [])
    assert path.stat().st_mode & 0o777 == 0o640  # a rewrite keeps the mode


def test_column_converts_units(tmp_path):
    table = read_table(write(tmp_path, GOOD))
    np.testing.assert_allclose(table.column("speed", "rad/s"), [200 * math.pi, 500 / 3 * math.pi])
    np.testing.assert_allclose(table.column("torque", "N*cm"), [10.0, 20.0])
    assert convert(1.0, "Ohm", "V/A") == pytest.approx(1.0)


@pytest.mark.parametrize(
    "name, rows, first",
    [
        ("fig4_15_motor.csv", 7, [0.042956, 5276.9, 5238.3, 3.1141, 3.245]),
        ("table4_2_4_3_motor_verification.csv", 7, [0.031, 5452, 5456, 2.44, 2.42]),
        ("fig4_35_drive_verification.csv", 7, [1.0057, 75.041, 75.091, 2.3081, 2.2942]),
        ("fig4_44_drive.csv", 5, [1.0077, 72.357, 72.351, 3.0951, 2.9826]),
    ],
)
def test_transcribed_thesis_tables(name, rows, first):
    table = read_table(MEAS / name, increasing="torque", require_source=True)
    assert "thesis" in table.source
    assert list(table.columns)[0] == "torque" and table.units["torque"] == "N*m"
    assert [u for u in table.units.values()][1:] == ["rpm", "rpm", "A", "A"]
    assert all(len(col) == rows for col in table.columns.values())
    assert [float(col[0]) for col in table.columns.values()] == first


def test_fig4_15_last_row():
    table = read_table(MEAS / "fig4_15_motor.csv")
    assert [float(c[-1]) for c in table.columns.values()] == [0.31928, 1231.8, 1209.5, 18.642, 18.814]


@pytest.mark.parametrize(
    "text, message",
    [
        ("# source: x\ntorque[N*m],speed[rpm]\n0.1,6000\n0.2,abc\n", ":4: column 'speed': 'abc' is not a number"),
        ("# source: x\n# only comments\n", ":3: missing header row"),
        ("torque[N*m],torque[N*m]\n0.1,0.2\n", ":1: duplicate column 'torque' in header"),
        ("torque[N*m],speed[rpm]\n0.1,6000\n0.2,5000,7\n", ":3: row has 3 fields, the header has 2"),
        ("torque[N*m],speed\n0.1,6000\n", ":1: header column 2 'speed': missing [unit]"),
        (
            "torque[N*m],speed[furlong/fortnight/x]\n0.1,6000\n",
            ":1: header column 2 'speed[furlong/fortnight/x]': unknown unit 'furlong/fortnight/x'",
        ),
        ("torque[N*m],speed[]\n0.1,6000\n", ":1: header column 2 'speed[]': empty unit"),
        ("torque[N*m],[rpm]\n0.1,6000\n", ":1: header column 2 '[rpm]': missing column name"),
        ("torque[N*m],speed[rpm]\n", ":1: header without data rows"),
    ],
)
def test_read_errors(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(WrsimError) as err:
        read_table(path)
    assert str(err.value).startswith(f"{path}{message}")


def test_non_monotone_ramp_column(tmp_path):
    path = write(tmp_path, "torque[N*m],speed[rpm]\n0.1,6000\n\n0.3,5000\n0.3,4000\n")
    read_table(path)  # fine unless a ramp is asked for
    with pytest.raises(WrsimError) as err:
        read_table(path, increasing="torque")
    assert str(err.value) == (
        f"{path}:5: column 'torque': 0.3 does not increase (previous row 0.3); a ramp must rise strictly"
    )


def test_source_is_mandatory_for_measurements(tmp_path):
    path = write(tmp_path, "# no source here\ntorque[N*m]\n0.1\n")
    assert read_table(path).source == ""
    with pytest.raises(WrsimError, match=r":1: missing '# source: <thesis table/figure"):
        read_table(path, require_source=True)


def test_unknown_column_lists_available(tmp_path):
    table = read_table(write(tmp_path, GOOD))
    with pytest.raises(WrsimError) as err:
        table.column("current")
    assert str(err.value) == f"{table.path}: no column 'current'; available: torque, speed"
    with pytest.raises(WrsimError, match=r"column 'speed': cannot convert 'rpm' .* to 'A'"):
        table.column("speed", "A")
    with pytest.raises(WrsimError, match=r"column 'speed': unknown unit 'bogus'"):
        table.column("speed", "bogus")
    with pytest.raises(WrsimError, match=r"no column 'x'; available: torque, speed"):
        read_table(table.path, increasing="x")


def test_missing_file(tmp_path):
    with pytest.raises(WrsimError, match=r"nope\.csv: cannot read"):
        read_table(tmp_path / "nope.csv")


def test_write_errors(tmp_path):
    path = tmp_path / "w.csv"
    with pytest.raises(WrsimError, match=r"w\.csv: columns differ in length"):
        write_table(path, {"a": [1.0], "b": [1.0, 2.0]}, {"a": "s", "b": "s"}, [])
    with pytest.raises(WrsimError, match=r"w\.csv: units given for \['a'\] but columns are \['a', 'b'\]"):
        write_table(path, {"a": [1.0], "b": [1.0]}, {"a": "s"}, [])
    with pytest.raises(WrsimError, match=r"w\.csv: column 'a': unknown unit 'sec0nd'"):
        write_table(path, {"a": [1.0]}, {"a": "sec0nd"}, [])
    with pytest.raises(WrsimError, match=r"column name 'a\[s\]' cannot be written"):
        write_table(path, {"a[s]": [1.0]}, {"a[s]": "s"}, [])
    blocker = tmp_path / "file"
    blocker.write_text("")
    with pytest.raises(WrsimError, match=r"file/w\.csv: cannot write"):
        write_table(blocker / "w.csv", {"a": [1.0]}, {"a": "s"}, [])
    assert not path.exists()
