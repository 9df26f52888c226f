"""Waveform regression (issue 17): the fast benches against their references inside the tolerance tubes; the
comparison bites (the motor's ke 2 % off fails, 0.05 % off passes); a reference changes only with a reason; the
stored references reproduce what was simulated within a tenth of the tube."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from wrsim import paths
from wrsim.cli import main
from wrsim.report.regression import bless, compare, decimate
from wrsim.results import Signal

KE = 0.01971201435  # [V*s/rad] params/drive_8p5nm.txt [dcpm_motor], included by params/rail_wr_8p5nm.txt
FAST = (
    "stroke",
    "motor-characteristic",
    "drive-characteristic",
    "startup",
    "stiffness",
    "worm-gear-self-locking",
    "worm-gear-architectures",
)


def _regression(tmp_path: Path, *args: str) -> int:
    return main(["regression", *args, "--results", str(tmp_path / "results")])


def _ke(tmp_path: Path, factor: float) -> str:
    path = tmp_path / f"ke_{factor}.txt"
    path.write_text(f"[dcpm_motor]\nke = {KE * factor!r} V*s/rad\n")
    return str(path)


def test_the_fast_benches_stay_inside_their_tubes(tmp_path, capsys):
    assert _regression(tmp_path, *(a for b in FAST for a in ("--bench", b))) == 0, capsys.readouterr().out
    captured = capsys.readouterr()
    assert f"regression: {len(FAST)} of {len(FAST)} benches within their tubes" in captured.out
    assert "runs |" not in captured.err and "ETA" not in captured.err  # no progress bar off a terminal


def test_the_motor_constant_2_percent_off_fails_with_a_page_naming_signal_and_time(tmp_path, capsys):
    assert _regression(tmp_path, "--bench", "stroke", "--params", _ke(tmp_path, 1.02)) == 1
    out = capsys.readouterr().out
    assert "stroke: REGRESSION in 7 of 7 signals" in out
    assert "glass_position_up: outside its tube from " in out  # the signal and its time range
    page = tmp_path / "results" / "regression" / "stroke" / "004_glass_position_up.html"
    text = page.read_text()
    assert "glass_position_up: outside its tube from" in text and (page.with_suffix(".png")).stat().st_size > 10_000
    assert 'href="004_glass_position_up.html"' in (page.parent / "index.html").read_text()


def test_a_change_below_the_tube_passes(tmp_path, capsys):
    assert _regression(tmp_path, "--bench", "stroke", "--params", _ke(tmp_path, 1.0005)) == 0
    assert "stroke: 7 signals within their tubes" in capsys.readouterr().out


def test_blessing_needs_a_reason(tmp_path, capsys):
    assert _regression(tmp_path, "--bench", "stroke", "--bless") == 2
    assert "--bless needs a --reason" in capsys.readouterr().err
    assert (paths.GOLDEN / "stroke.npz").exists()


def test_stored_references_reproduce_the_samples_within_a_tenth_of_the_tube():
    t = np.linspace(0.0, 2.0, 2001)
    y = np.where(t < 1.0, np.sin(7 * t), 0.3) + 0.01 * t**2
    tol = 1e-4
    keep = decimate(t, y, tol)
    assert len(keep) < len(t) / 4  # smooth parts are thinned out
    assert np.max(np.abs(np.interp(t, t[keep], y[keep]) - y)) <= tol
    assert keep[0] == 0 and keep[-1] == len(t) - 1


@pytest.mark.parametrize("bench", FAST)
def test_every_fast_bench_has_a_reference_with_its_reason(bench):
    log = (paths.GOLDEN / "BLESSINGS.tsv").read_text().splitlines()
    assert log[0] == "date\tbench\trevision\tparams\treason"
    assert any(line.split("\t")[1] == bench and line.split("\t")[4].strip() for line in log[1:])


def test_a_signal_zero_up_to_rounding_compares_at_the_solvers_resolution(tmp_path):
    """A reference that is 0 up to rounding (+-3e-12 N) gets a value tube of RESOLUTION (1e-9 N): another machine's
    rounding passes, a force of a micronewton does not."""
    t = np.linspace(0.0, 1.0, 1001)
    noise = 3e-12 * np.sin(1e3 * t)
    bless("tube", [Signal("time", "s", t), Signal("force", "N", noise)], 1.0, "test", golden=tmp_path / "golden")
    for result, passes in ((-noise, True), (noise + 1e-6, False)):
        reg = compare(
            "tube", [Signal("time", "s", t), Signal("force", "N", result)], tmp_path / "out", tmp_path / "golden"
        )
        assert reg is not None and (not reg.violations) is passes
