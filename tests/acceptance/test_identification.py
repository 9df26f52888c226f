"""Issue 6 acceptance: `wrsim identify motor|drive|damper` on raw files, the round trip from the thesis's
Fig. 4.15 mean line to the issue-2 parameter set, and the `identification` bench (synthetic group ->
identified set -> simulation -> report) within its tolerances."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from wrsim import paths
from wrsim.cli import main
from wrsim.data.measurements import read_table, write_table
from wrsim.data.params import load_params
from wrsim.identify.synthetic import Truth, write_group

ROOT = paths.ROOT
FPG2 = ROOT / "params" / "fpg2_12nm.txt"
UNITS = {"time": "s", "torque": "N*m", "speed": "rpm", "current": "A", "voltage": "V", "direction": "1"}


def _raw_from_thesis(tmp_path: Path, csv: str, speed: str, current: str, rate: float) -> Path:
    """A thesis line as a raw characteristic file: time from the stated load ramp, 13 V, cw."""
    t = read_table(ROOT / "params" / "measurements" / csv, require_source=True)
    m = t.column("torque", "N*m")
    out = tmp_path / f"{Path(csv).stem}_cw.csv"
    write_table(
        out,
        {
            "time": m / rate,
            "torque": m,
            "speed": t.column(speed, "rpm"),
            "current": t.column(current, "A"),
            "voltage": np.full(m.size, 13.0),
            "direction": np.ones(m.size),
        },
        UNITS,
        [f"source: {t.source}"],
    )
    return out


def test_cli_round_trip_fig4_15_reproduces_the_issue_2_set(tmp_path, capsys):
    raw = _raw_from_thesis(tmp_path, "fig4_15_motor.csv", "mean_speed", "mean_current", 0.5 / 3)
    out, report = tmp_path / "motor.txt", tmp_path / "report"
    assert main(["identify", "motor", str(raw), "--out", str(out), "--report", str(report)]) == 0
    printed = capsys.readouterr().out
    assert "motor (calculator): ke=0.020437 V*s/rad kt=0.017028 N*m/A ra=0.553848 Ohm" in printed

    def motor_lines(path: Path) -> list[str]:
        text = path.read_text().split("[dcpm_motor]")[1].split("\n\n")[0]
        return [line.split("#")[0].strip() for line in text.strip().splitlines()]

    assert motor_lines(out) == motor_lines(FPG2)  # ke, kt, ra, laa, j, visc, mc: all 10 significant digits
    assert len(motor_lines(out)) == 7
    page = (report / "index.html").read_text()
    assert "inside the channel" in page and (report / "channel.png").is_file() and (report / "curves.png").is_file()


def test_cli_drive_from_fig4_44_with_the_motor_set(tmp_path, capsys):
    raw = _raw_from_thesis(tmp_path, "fig4_44_drive.csv", "fit_speed", "fit_current", 13.0 / 2)
    out = tmp_path / "drive.txt"
    # Fig. 4.44 tabulates 1.0077 .. 5.0168 N*m, inside the 1-6 N*m working range
    assert main(["identify", "drive", str(raw), "--base", str(FPG2), "--out", str(out)]) == 0
    assert "drive: ratio=73 eta=0.455845 m_gc=0.345983 N*m" in capsys.readouterr().out
    pset = load_params(out)
    assert pset.value_in("dcpm_motor", "ke", "V*s/rad") == 0.0204369637  # carried over from the base
    assert pset.value_in("worm_gear", "eta", "1") == pytest.approx(0.455845, abs=1e-6)


def test_cli_chain_on_a_synthetic_group(tmp_path, capsys):
    files = write_group(tmp_path / "raw", Truth.from_params(load_params(FPG2)), count=5, seed=0)
    motor, drive, full = tmp_path / "motor.txt", tmp_path / "drive.txt", tmp_path / "full.txt"
    assert main(["identify", "motor", *map(str, files["motor"]), "--out", str(motor)]) == 0
    assert (
        main(
            ["identify", "drive", *map(str, files["drive"]), "--base", str(motor), "--ratio", "73", "--out", str(drive)]
        )
        == 0
    )
    assert main(["identify", "damper", *map(str, files["damper"]), "--base", str(drive), "--out", str(full)]) == 0
    assert main(["check", "--params", str(full)]) == 0  # every bench elaborates with the identified set
    pset, truth = load_params(full), load_params(FPG2)
    for entity, key, unit in (
        ("dcpm_motor", "ke", "V*s/rad"),
        ("dcpm_motor", "kt", "N*m/A"),
        ("dcpm_motor", "ra", "Ohm"),
        ("worm_gear", "eta", "1"),
    ):
        assert pset.value_in(entity, key, unit) == pytest.approx(truth.value_in(entity, key, unit), rel=0.02), key
    capsys.readouterr()


@pytest.mark.parametrize(
    "args, message",
    [
        (["identify", "motor", "--out", "x.txt"], "identify motor: give one or more measurement files"),
        (["identify", "drive", "FILE", "--out", "x.txt"], "identify drive: needs the motor set: give --base PARAMS"),
        (["identify", "temperature", "--out", "x.txt"], "identify temperature: give --base PARAMS --celsius T"),
        (["identify", "default", "FILE"], "identify default takes no files"),
    ],
)
def test_cli_usage_errors(args, message, capsys):
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err.startswith("wrsim: error: ") and message in err and err.count("\n") == 1


def test_cli_reports_a_bad_file_in_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.csv"
    bad.write_text("# source: test\ntime[s],torque[N*m],speed[rpm],current[A]\n0,0,6000,1\n0.1,0.1,5000,5\n")
    assert main(["identify", "motor", str(bad), "--out", str(tmp_path / "x.txt")]) == 2
    err = capsys.readouterr().err
    assert err == (
        f"wrsim: error: {bad}: a raw characteristic measurement (docs/measurement-format.md) needs the "
        f"columns time, torque, speed, current, voltage, direction; missing: voltage, direction "
        f"(found: time, torque, speed, current)\n"
    )
    assert not (tmp_path / "x.txt").exists()


def test_identification_bench(tmp_path, capsys):
    assert main(["testbench", "--bench", "identification", "--results", str(tmp_path / "results")]) == 0
    result = json.loads((tmp_path / "results" / "identification" / "result.json").read_text())
    capsys.readouterr()
    m = {name: v["value"] for name, v in result["metrics"].items()}
    assert result["passed"] and all(v["pass"] for v in result["metrics"].values())
    for name in ("ke", "kt", "ra", "eta", "least squares ke", "least squares ra"):
        assert abs(m[f"{name} recovered"]) < 2.0, name
    assert m["ra recovered"] == pytest.approx(-1.528, abs=0.01)  # seed 0, measured
    assert m["eta recovered"] == pytest.approx(-1.504, abs=0.01)
    for kind in ("motor cw", "motor ccw", "drive cw", "drive ccw"):
        assert m[f"{kind}: speed outside the measured channel"] == 0.0
        assert m[f"{kind}: current outside the measured channel"] == 0.0
    assert m["motor cw: speed vs middle line"] < 0.3 and m["drive cw: speed vs mean line"] < 0.01
    assert m["drive cw: identified vs truth simulation, speed"] < 0.1
    out = max((tmp_path / "results" / "work" / "identification").iterdir())  # the run's own work folder
    assert load_params(out / "identified.txt").value_in("worm_gear", "ratio", "1") == 73.0
    for report in ("motor_report", "drive_report", "damper_report"):
        assert (out / report / "index.html").is_file()
    assert sorted(p["file"] for p in result["plots"]) == ["drive_channel.png", "motor_channel.png"]
