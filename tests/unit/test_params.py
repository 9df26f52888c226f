"""Parameter-set files: parsing, unit conversion, lookup by name, saving, error paths."""

from __future__ import annotations

import math
import os
from pathlib import Path

import pytest

from wrsim import paths
from wrsim.data.atomic import INPUT_LIMIT
from wrsim.data.params import Param, find_param_set, load_params, save_params
from wrsim.errors import WrsimError

ROOT = paths.ROOT

GOOD = """\
# a test set
[DCPM_Motor]   # entity names are case-insensitive
ke = 0.0204 V*s/rad   # back EMF
Ra = 550 mOhm
laa	=	90e-6	H
[rubber_damper]
angles = [0, 2, 10] deg
stiffness = [57.3, 51.6, 68.8] N*m/rad
[worm_gear]
eta = 0.45 1
"""


def write(tmp_path: Path, text: str, name: str = "set.txt") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def test_load_and_convert(tmp_path):
    path = write(tmp_path, GOOD)
    pset = load_params(path)
    assert pset.name == "set" and pset.path == path
    assert list(pset.sections) == ["dcpm_motor", "rubber_damper", "worm_gear"]
    assert pset.sections["dcpm_motor"]["ke"] == Param(0.0204, "V*s/rad", str(path), 3)
    assert pset.sections["dcpm_motor"]["laa"] == Param(90e-6, "H", str(path), 5)
    assert pset.value_in("dcpm_motor", "RA", "Ohm") == pytest.approx(0.55)
    assert pset.value_in("dcpm_motor", "ke", "V/rpm") == pytest.approx(0.0204 * math.pi / 30)
    assert pset.value_in("rubber_damper", "angles", "rad") == pytest.approx([0, math.pi / 90, math.pi / 18])
    assert pset.value_in("rubber_damper", "stiffness", "N*m/deg") == pytest.approx(
        [57.3 * math.pi / 180, 51.6 * math.pi / 180, 68.8 * math.pi / 180]
    )
    assert pset.value_in("worm_gear", "eta", "1") == 0.45


def test_value_in_errors(tmp_path):
    path = write(tmp_path, GOOD)
    pset = load_params(path)
    with pytest.raises(WrsimError) as err:
        pset.value_in("dcpm_motor", "ke", "N*m")
    assert str(err.value).startswith(f"{path}:3: [dcpm_motor] ke: cannot convert 'V*s/rad'")
    with pytest.raises(WrsimError, match=r"no section \[drive\]; sections: dcpm_motor, rubber_damper, worm_gear"):
        pset.value_in("drive", "m_gc", "N*m")
    with pytest.raises(WrsimError, match=r"\[dcpm_motor\] has no key 'kt'; keys: ke, ra, laa"):
        pset.value_in("dcpm_motor", "kt", "N*m/A")


@pytest.mark.parametrize(
    "text, message",
    [
        ("[m]\nke 0.02 V*s/rad\n", ":2: 'ke 0.02 V*s/rad': missing '='"),
        ("[m]\nke = 0.0.2 V*s/rad\n", ":2: [m] ke: '0.0.2' is not a number"),
        ("[m]\nv = [1.0, x2] V\n", ":2: [m] v: 'x2' is not a number"),
        ("[m]\nv = [1.0, 2.0 V\n", ":2: [m] v: list value without closing ']'"),
        ("[m]\nv = [] V\n", ":2: [m] v: empty list"),
        ("[m]\nke =   # nothing\n", ":2: [m] ke: missing value after '='"),
        ("[m]\nke = 0.02 Vs/radd\n", ":2: [m] ke: unknown unit 'Vs/radd'"),
        ("[m]\nke = 0.02\n", ":2: [m] ke: missing unit after the value (write 1 for dimensionless)"),
        ("[m]\nke = 0.02 V*s/rad\n\nKE = 0.03 V*s/rad\n", ":4: [m] KE: duplicate key (first set on line 2)"),
        ("# header\nke = 0.02 V*s/rad\n", ":2: key 'ke' comes before any [entity] section"),
        ("[m]\n[M]\n", ":2: duplicate section [M] (first on line 1)"),
        ("[2nd motor]\n", ":1: section [2nd motor] is not a VHDL entity name"),
        ("[m]\nk-e = 1 V\n", ":2: 'k-e' is not a VHDL generic name"),
    ],
)
def test_load_errors(tmp_path, text, message):
    path = write(tmp_path, text)
    with pytest.raises(WrsimError) as err:
        load_params(path)
    assert str(err.value).startswith(f"{path}{message}")


def test_missing_file(tmp_path):
    with pytest.raises(WrsimError, match=r"nope\.txt: cannot read"):
        load_params(tmp_path / "nope.txt")


def test_find_param_set(tmp_path):
    (tmp_path / "params").mkdir()
    a = write(tmp_path / "params", "[m]\n", "alpha.txt")
    write(tmp_path / "params", "[m]\n", "beta.txt")
    assert find_param_set("alpha", tmp_path) == a
    assert find_param_set(a, tmp_path) == a
    with pytest.raises(WrsimError) as err:
        find_param_set("gamma", tmp_path)
    assert str(err.value) == (f"unknown parameter set 'gamma'; available in {tmp_path / 'params'}: alpha, beta")
    with pytest.raises(WrsimError, match=r"gamma\.txt: parameter-set file not found"):
        find_param_set(tmp_path / "gamma.txt", tmp_path)
    assert find_param_set("fpg2_12nm", ROOT) == ROOT / "params" / "fpg2_12nm.txt"


def test_save_round_trip(tmp_path):
    path = tmp_path / "sub" / "saved.txt"
    save_params(
        path,
        ["header line", "second"],
        {
            "dcpm_motor": [("ke", 0.1 + 0.2, "V*s/rad", "sum"), ("mc", 0.0, "N*m", "")],
            "rubber_damper": [("angles", [0.0, 1 / 3], "rad", "list")],
        },
    )
    text = path.read_text()
    assert text.startswith("# header line\n# second\n\n[dcpm_motor]\n")
    assert "ke = 0.30000000000000004 V*s/rad  # sum\n" in text
    assert "mc = 0.0 N*m\n" in text
    pset = load_params(path)
    assert pset.value_in("dcpm_motor", "ke", "V*s/rad") == 0.1 + 0.2
    assert pset.value_in("rubber_damper", "angles", "rad") == [0.0, 1 / 3]
    assert list(path.parent.iterdir()) == [path]


def test_save_errors(tmp_path):
    path = tmp_path / "s.txt"
    with pytest.raises(WrsimError, match=r"s\.txt: \[m\] ke: unknown unit 'Vxs'"):
        save_params(path, [], {"m": [("ke", 1.0, "Vxs", "")]})
    with pytest.raises(WrsimError, match=r"s\.txt: section \[a b\] is not a VHDL entity name"):
        save_params(path, [], {"a b": []})
    with pytest.raises(WrsimError, match=r"s\.txt: \[m\] '1x' is not a VHDL generic name"):
        save_params(path, [], {"m": [("1x", 1.0, "1", "")]})
    assert not path.exists()


def test_committed_default_set_layout():
    pset = load_params(ROOT / "params" / "fpg2_12nm.txt")
    assert {s: list(keys) for s, keys in pset.sections.items()} == {
        "dcpm_motor": ["ke", "kt", "ra", "laa", "j", "visc", "mc"],
        "worm_gear": ["ratio", "eta"],
        "drive": ["m_gc"],
        "rubber_damper": ["angles", "stiffness"],
    }
    lines = (ROOT / "params" / "fpg2_12nm.txt").read_text().splitlines()
    for section in pset.sections.values():
        for param in section.values():
            assert param.unit and "  # " in lines[param.line - 1]  # every line has a unit and a comment
    assert pset.value_in("rubber_damper", "angles", "deg") == pytest.approx([0, 2, 4, 6, 8, 10], abs=1e-12)
    assert pset.value_in("rubber_damper", "stiffness", "N*m/rad") == [57.3, 51.6, 48.7, 47.7, 51.6, 68.8]
    assert pset.value_in("worm_gear", "ratio", "1") == 73.0
    assert pset.value_in("worm_gear", "eta", "1") == 0.45162397


def test_overlay_replaces_and_adds_keys(tmp_path):
    from wrsim.data.params import load_params

    base = tmp_path / "base.txt"
    base.write_text("[dcpm_motor]\nke = 0.02 V*s/rad\nra = 0.5 Ohm\n[drive]\nm_gc = 0.3 N*m\n", encoding="utf-8")
    top = tmp_path / "hot.txt"
    top.write_text("[dcpm_motor]\nra = 0.6 Ohm\n[worm_gear]\neta = 0.4 1\n", encoding="utf-8")
    merged = load_params(base).overlay(load_params(top))
    assert merged.value_in("dcpm_motor", "ra", "Ohm") == 0.6  # replaced
    assert merged.value_in("dcpm_motor", "ke", "V*s/rad") == 0.02  # kept
    assert merged.value_in("drive", "m_gc", "N*m") == 0.3
    assert merged.value_in("worm_gear", "eta", "1") == 0.4  # added
    assert load_params(base).value_in("dcpm_motor", "ra", "Ohm") == 0.5  # the base set is not modified


def test_a_runs_own_set_goes_beneath_the_users(tmp_path):
    """A bench run's own set (e.g. the anti-pinch algorithm under test) replaces the bench's values, and the
    user's `--params` still replaces both."""
    from wrsim.benches.core import Run
    from wrsim.data.params import load_params

    base = tmp_path / "system.txt"
    base.write_text("[ecu_software]\nalgorithm = 0 1\nthreshold_rpm = 400 rpm\n", encoding="utf-8")
    own = tmp_path / "observer.txt"
    own.write_text("[ecu_software]\nalgorithm = 4 1\nthreshold_rpm = 300 rpm\n", encoding="utf-8")
    user = tmp_path / "mine.txt"
    user.write_text("[ecu_software]\nthreshold_rpm = 350 rpm\n", encoding="utf-8")
    bench_set = load_params(base).overlay(load_params(user), user=True)
    merged = Run("r", {}, own).parameters(bench_set)
    assert merged is not None
    assert merged.value_in("ecu_software", "algorithm", "1") == 4.0  # the run's own set
    assert merged.value_in("ecu_software", "threshold_rpm", "rpm") == 350.0  # the user's, on top
    assert Run("r", {}).parameters(bench_set) is bench_set  # a run without its own set
    plain = Run("r", {}, own).parameters(load_params(base))  # no user set: the run's wins
    assert plain is not None and plain.value_in("ecu_software", "threshold_rpm", "rpm") == 300.0


# ------------------------------------------------------------------------------------------------
# include lines: a set built on others
def test_an_included_set_lies_beneath_the_files_own_keys(tmp_path):
    base = write(tmp_path, "[dcpm_motor]\nke = 0.02 V*s/rad\nra = 0.5 Ohm\n", "base.txt")
    (tmp_path / "sub").mkdir()
    mine = write(tmp_path / "sub", "# one key changed\ninclude ../base\n[dcpm_motor]\nra = 0.6 Ohm\n", "mine.txt")
    pset = load_params(mine)
    assert pset.name == "mine"
    assert pset.number_in("dcpm_motor", "ke", "V*s/rad") == 0.02
    assert pset.number_in("dcpm_motor", "ra", "Ohm") == 0.6
    assert pset.sections["dcpm_motor"]["ra"].file == str(mine)  # errors and exports name the line that set it
    assert pset.sections["dcpm_motor"]["ke"].file == str(base)


def test_includes_are_laid_in_order_and_the_system_set_can_be_included(tmp_path):
    system = ROOT / "params" / "rail_wr_8p5nm.txt"
    first = write(tmp_path, "[dcpm_motor]\nra = 0.7 Ohm\n", "first.txt")
    second = write(tmp_path, "[dcpm_motor]\nra = 0.8 Ohm\n", "second.txt")
    mine = write(tmp_path, f"include {system}\ninclude {first.name}\ninclude second.txt\n", "mine.txt")
    pset = load_params(mine)
    assert pset.number_in("dcpm_motor", "ra", "Ohm") == 0.8
    assert pset.number_in("top_frame_seal", "position", "m") == load_params(system).number_in(
        "top_frame_seal", "position", "m"
    )
    assert second.is_file()


@pytest.mark.parametrize(
    "text, message",
    [
        ("include nothing_here\n", "{f}:1: include nothing_here: no such parameter set"),
        ("[dcpm_motor]\nra = 1 Ohm\ninclude other.txt\n", "{f}:3: include comes after section [dcpm_motor]"),
        ("include a b\n", "{f}:1: write 'include FILE'"),
        ("include set.txt\n", "{f}:1: include set.txt: a cycle"),
    ],
)
def test_include_errors_name_the_line(tmp_path, text, message):
    path = write(tmp_path, text)
    write(tmp_path, "[dcpm_motor]\nra = 1 Ohm\n", "other.txt")
    with pytest.raises(WrsimError) as e:
        load_params(path)
    assert str(e.value).startswith(message.format(f=path))


def test_a_cycle_through_two_files_is_named_with_its_chain(tmp_path):
    a = write(tmp_path, "include b.txt\n", "a.txt")
    write(tmp_path, "include a.txt\n", "b.txt")
    with pytest.raises(WrsimError, match=r"b.txt:1: include a.txt: a cycle \(.*a.txt -> .*b.txt -> .*a.txt\)"):
        load_params(a)


def test_a_key_twice_in_one_file_stays_an_error_beside_includes(tmp_path):
    write(tmp_path, "[dcpm_motor]\nra = 1 Ohm\n", "base.txt")
    path = write(tmp_path, "include base.txt\n[dcpm_motor]\nra = 2 Ohm\nra = 3 Ohm\n")
    with pytest.raises(WrsimError, match=r"set.txt:4: \[dcpm_motor\] ra: duplicate key \(first set on line 3\)"):
        load_params(path)


def test_a_key_named_include_is_still_a_key(tmp_path):
    path = write(tmp_path, "[my_model]\ninclude = 3 V\n")
    assert load_params(path).number_in("my_model", "include", "V") == 3.0


def test_a_calibration_range_is_no_spread(tmp_path):
    """`in LOW .. HIGH unit calibrate` declares what `wrsim calibrate` may search: kept as a tolerance of law
    'calibrate' (with its line), the value unchanged, and left out of a study's factors."""
    from wrsim.study.sampling import factors

    f = tmp_path / "alg.txt"
    f.write_text("[ecu_software]\nthreshold_rpm = 400 rpm in 150 .. 700 rpm calibrate\nstartup_ms = 900 ms +- 10 %\n")
    pset = load_params(f)
    t = pset.tolerances["ecu_software"]["threshold_rpm"]
    assert (t.law, t.limits, t.unit, t.line) == ("calibrate", (150.0, 700.0), "rpm", 2)
    assert pset.sections["ecu_software"]["threshold_rpm"].value == 400.0
    assert [x.name for x in factors(pset)] == ["ecu_software.startup_ms"]
    f.write_text("[ecu_software]\nthreshold_rpm = 400 rpm +- 10 % calibrate\n")
    with pytest.raises(WrsimError, match=r"alg.txt:2: \[ecu_software\] threshold_rpm: 'calibrate' is not part of"):
        load_params(f)
    f.write_text("[ecu_software]\nthreshold_rpm = 800 rpm in 150 .. 700 rpm calibrate\n")
    with pytest.raises(WrsimError, match="the nominal 800 rpm is outside the range 150 .. 700 rpm"):
        load_params(f)


@pytest.mark.skipif(not Path("/dev/zero").exists() or not hasattr(os, "mkfifo"), reason="POSIX special files")
def test_a_special_file_is_one_error_not_a_read_without_end(tmp_path):
    """A FIFO would block the read for ever and /dev/zero never end: input files are regular files of at most
    INPUT_LIMIT bytes (a table named by `from` as much as the set itself)."""
    fifo = tmp_path / "table.csv"
    os.mkfifo(fifo)
    (tmp_path / "set.txt").write_text("[motor]\nra from table.csv:ra\n")
    with pytest.raises(WrsimError, match=r"table\.csv: not a regular file"):
        load_params(tmp_path / "set.txt")
    with pytest.raises(WrsimError, match=r"^/dev/zero: not a regular file$"):
        load_params("/dev/zero")
    big = tmp_path / "big.txt"
    with big.open("wb") as f:
        f.truncate(INPUT_LIMIT + 1)
    with pytest.raises(WrsimError, match=r"big\.txt: larger than 64 MB, the limit for an input file"):
        load_params(big)
