import xml.etree.ElementTree as ET
from pathlib import Path

import asammdf
import numpy as np
import pytest

from wrsim.data import atomic
from wrsim.errors import WrsimError
from wrsim.report.mdf import read_mdf, write_mdf
from wrsim.results import Signal

METADATA = {
    "bench": "motor_char",
    "description": "Motor characteristic line: torque & speed <no load>",
    "parameter_set": "params/motor_a.toml",
    "wrsim_version": "0.1.0",
    "git_revision": "0123456789abcdef",
}


def make_waveforms() -> list[Signal]:
    t = np.linspace(0.0, 1.0, 1001)
    with_nan = np.cos(t)
    with_nan[[0, 500, 1000]] = np.nan
    return [
        Signal("time", "s", t),
        Signal("sine", "V", np.sin(2 * np.pi * 5 * t)),
        Signal("step", "N*m", np.where(t >= 0.5, 2.5, 0.0)),
        Signal("dut.motor.omega(1)", "rad/s", 100.0 * t**2 + 1e-300),
        Signal("with nan / gaps", "A", with_nan),
    ]


def common_properties(comment: str) -> dict[str, ET.Element]:
    root = ET.fromstring(comment)
    return {e.attrib["name"]: e for e in root.iterfind("common_properties/*")}


def test_asammdf_reads_channels_units_and_exact_samples(tmp_path: Path) -> None:
    path = tmp_path / "waveforms.mf4"
    waveforms = make_waveforms()
    write_mdf(path, waveforms, METADATA)

    with asammdf.MDF(path) as mdf:
        assert mdf.version.startswith("4.")
        assert len(mdf.groups) == 1
        channels = mdf.groups[0].channels
        assert [(c.name, c.unit) for c in channels] == [(s.name, s.unit) for s in waveforms]
        time = mdf.get_master(0)
        assert time.dtype == np.float64
        assert np.array_equal(time, waveforms[0].values)
        for index, expected in enumerate(waveforms[1:], start=1):
            got = mdf.get(group=0, index=index)
            assert (got.name, got.unit) == (expected.name, expected.unit)
            assert got.samples.dtype == np.float64
            assert np.array_equal(got.samples, expected.values, equal_nan=True)
            assert np.array_equal(got.timestamps, waveforms[0].values)
        assert np.isnan(mdf.get("with nan / gaps").samples[[0, 500, 1000]]).all()

        properties = common_properties(mdf.header.comment)
        assert {name: e.text for name, e in properties.items()} == METADATA
        assert mdf.header.description == METADATA["description"]
        assert [ET.fromstring(fh.comment).findtext("tool_id") for fh in mdf.file_history] == ["wrsim"]
    assert b"##DZ" in path.read_bytes()  # data blocks are compressed


def test_read_mdf_round_trips_signals_and_metadata(tmp_path: Path) -> None:
    path = tmp_path / "waveforms.mf4"
    waveforms = make_waveforms()
    write_mdf(path, waveforms, METADATA)
    got, metadata = read_mdf(path)
    assert metadata == METADATA
    assert [(s.name, s.unit) for s in got] == [(s.name, s.unit) for s in waveforms]
    for g, w in zip(got, waveforms, strict=True):
        assert np.array_equal(g.values, w.values, equal_nan=True)


def test_metadata_values_survive_exactly(tmp_path: Path) -> None:
    path = tmp_path / "w.mf4"
    metadata = {
        "description": "  first line, indented\n\tsecond line with trailing blanks  \n\nlast\n",
        "author": "Zoë Müller",
        "quote": 'a "b" <c/> & d]]>',
        "empty": "",
        "key with spaces.and(dots)": "  padded  ",
    }
    write_mdf(path, make_waveforms()[:2], metadata)
    assert read_mdf(path)[1] == metadata
    with asammdf.MDF(path) as mdf:
        assert mdf.header.author == "Zoë Müller"  # a standard header field when the key is one


@pytest.mark.parametrize("samples", [1001, 0])
def test_time_axis_alone(tmp_path: Path, samples: int) -> None:
    path = tmp_path / "w.mf4"
    time = np.linspace(0.0, 1.0, samples)
    write_mdf(path, [Signal("time", "s", time)], {"bench": "b"})
    got, metadata = read_mdf(path)
    assert metadata == {"bench": "b"}
    assert [(s.name, s.unit) for s in got] == [("time", "s")]
    assert np.array_equal(got[0].values, time)


def test_signals_without_samples(tmp_path: Path) -> None:
    path = tmp_path / "w.mf4"
    write_mdf(path, [Signal("time", "s", np.zeros(0)), Signal("u", "V", np.zeros(0))], {})
    got, _ = read_mdf(path)
    assert [(s.name, s.unit, len(s.values)) for s in got] == [("time", "s", 0), ("u", "V", 0)]


def test_unwritable_directory_names_the_path(tmp_path: Path) -> None:
    blocker = tmp_path / "not_a_dir"
    blocker.write_text("a file where the directory should be")
    path = blocker / "waveforms.mf4"
    with pytest.raises(WrsimError, match="cannot write") as err:
        write_mdf(path, make_waveforms(), METADATA)
    assert str(path) in str(err.value)


def test_overwrite_replaces_the_file(tmp_path: Path) -> None:
    path = tmp_path / "w.mf4"
    write_mdf(path, make_waveforms(), METADATA)
    new = [Signal("time", "s", np.array([0.0, 0.5])), Signal("x", "m", np.array([1.0, 2.0]))]
    write_mdf(path, new, {"bench": "other"})
    got, metadata = read_mdf(path)
    assert metadata == {"bench": "other"}
    assert [(s.name, list(s.values)) for s in got] == [("time", [0.0, 0.5]), ("x", [1.0, 2.0])]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.mf4"]


def test_failure_while_saving_keeps_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "w.mf4"
    write_mdf(path, make_waveforms(), METADATA)
    before = path.read_bytes()

    def broken_save(self: asammdf.MDF, dst: object, *args: object, **kwargs: object) -> None:
        dst.write(b"MDF     4.10    half a file")  # type: ignore[attr-defined]
        raise RuntimeError("disk on fire")

    monkeypatch.setattr(asammdf.MDF, "save", broken_save)
    with pytest.raises(RuntimeError, match="disk on fire"):
        write_mdf(path, make_waveforms()[:2], {"bench": "new"})
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.mf4"]


def test_failure_while_replacing_keeps_the_old_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = tmp_path / "w.mf4"
    write_mdf(path, make_waveforms(), METADATA)
    before = path.read_bytes()

    def broken_replace(src: str, dst: object) -> None:
        assert Path(src).parent == tmp_path and Path(src).stat().st_size > 0  # the new file was complete
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(atomic.os, "replace", broken_replace)
    with pytest.raises(WrsimError, match="No space left on device") as err:
        write_mdf(path, make_waveforms()[:2], {"bench": "new"})
    assert str(path) in str(err.value)
    assert path.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["w.mf4"]


def test_read_rejects_files_wrsim_did_not_write(tmp_path: Path) -> None:
    text = tmp_path / "notes.mf4"
    text.write_text("time,u\n0,1\n")
    with pytest.raises(WrsimError, match="cannot read MDF file") as err:
        read_mdf(text)
    assert str(text) in str(err.value)

    with pytest.raises(WrsimError, match="cannot read MDF file"):
        read_mdf(tmp_path / "missing.mf4")

    foreign = tmp_path / "foreign.mf4"
    mdf = asammdf.MDF(version="4.10")
    t = np.linspace(0.0, 1.0, 11)
    mdf.append([asammdf.Signal(t, t, name="u", unit="V")])
    mdf.save(foreign)
    mdf.close()
    with pytest.raises(WrsimError, match="not an MDF file written by wrsim") as err:
        read_mdf(foreign)
    assert str(foreign) in str(err.value)


def test_write_rejects_what_it_cannot_store(tmp_path: Path) -> None:
    path = tmp_path / "w.mf4"
    t = np.linspace(0.0, 1.0, 3)
    with pytest.raises(WrsimError, match="time axis"):
        write_mdf(path, [Signal("u", "V", t)], {})
    with pytest.raises(WrsimError, match="'u' has 2 values"):
        write_mdf(path, [Signal("time", "s", t), Signal("u", "V", t[:2])], {})
    with pytest.raises(WrsimError, match=r"'description' contains the character U\+000D"):
        write_mdf(path, [Signal("time", "s", t)], {"description": "dos\r\nline"})
    with pytest.raises(WrsimError, match="metadata key"):
        write_mdf(path, [Signal("time", "s", t)], {"two\nlines": "x"})
    assert not path.exists()
