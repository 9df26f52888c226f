"""The HTML report in a real browser (headless Chromium, wrsim.report.browser): the stroke bench's report renders
without a JavaScript error, a failed load, a broken image or a broken link, and the checker finds each of those when
it is planted in a copy of the report."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from wrsim import paths
from wrsim.cli import main
from wrsim.errors import WrsimError
from wrsim.report.browser import check_pages, probe_plot
from wrsim.report.results import write_bench_result, write_index
from wrsim.results import BenchResult, Plot, Signal


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A folder with results/ of `wrsim testbench --bench stroke`, a `wrsim run` of a corpus model and a two-sample
    study of the stroke bench with one sample run again (its page with waveforms)."""
    root = tmp_path_factory.mktemp("site")
    results = str(root / "results")
    assert main(["testbench", "--bench", "stroke", "--results", results]) == 0
    rc = paths.ROOT / "tests" / "corpus" / "electrical" / "rc_charge_tb.vhd"
    assert main(["run", str(rc), "--top", "rc_charge_tb", "--stop", "5e-3", "--results", results]) == 0
    study = ["study", "stroke", "--params", "tolerances/production", "--samples", "2", "--results", results]
    assert main(study) == 0
    assert main([*study, "--rerun", "0"]) == 0
    return root


def pages_of(root: Path) -> list[Path]:
    """The index page and the stroke bench's page of a site."""
    return [root / "results" / "index.html", root / "results" / "stroke" / "index.html"]


def pngs_of(page: Path) -> list[str]:
    """The PNG files `page` links (each interactive plot's picture), relative to it."""
    return re.findall(r'<a href="([^"]+\.png)">', page.read_text(encoding="utf-8"))


def test_the_stroke_report_renders_without_problems(site: Path, tmp_path: Path):
    pages = pages_of(site)
    stroke = pages[1].read_text(encoding="utf-8")
    assert "Plotly.newPlot(" in stroke and pngs_of(pages[1]), "the stroke page shows no plot"
    assert check_pages(pages, tmp_path) == []
    shots = sorted(tmp_path.glob("*.png"))
    assert len(shots) == len(pages)
    for shot in shots:
        assert shot.stat().st_size > 10_000, shot
        pixels = imread(shot)[..., :3]  # floats in [0, 1]
        assert pixels.std() > 0.05, f"{shot.name} is (almost) one colour"
        rgb = np.round(pixels * 255).astype(np.uint32) @ np.array([1 << 16, 1 << 8, 1], dtype=np.uint32)
        assert len(np.unique(rgb)) > 50, f"{shot.name} has hardly any colours"


def _plant(page: Path, snippet: str) -> None:
    text = page.read_text(encoding="utf-8")
    assert "</body>" in text
    page.write_text(text.replace("</body>", f"{snippet}</body>", 1), encoding="utf-8")


def test_the_checker_finds_each_planted_problem(site: Path, tmp_path: Path, tmp_path_factory: pytest.TempPathFactory):
    cases = ("deleted-png", "broken-link", "exception", "console-error", "deleted-script")
    # each copy at the site's depth, so that its links to the repository's docs (a KNOWN metric's reason) still
    # resolve
    copies = {
        case: pages_of(shutil.copytree(site, tmp_path_factory.mktemp(case), symlinks=True, dirs_exist_ok=True))
        for case in cases
    }
    stroke = copies["deleted-png"][1]
    png = pngs_of(stroke)[0]
    (stroke.parent / png).unlink()
    _plant(copies["broken-link"][1], '<a href="nothere/missing.csv">missing</a>')
    _plant(copies["exception"][1], '<script>throw new Error("boom")</script>')
    _plant(copies["console-error"][1], '<script>console.error("bad")</script>')
    unscripted = copies["deleted-script"][1]
    (unscripted.parents[1] / "_static" / "plotly.min.js").unlink()
    expected = {  # a page's problems, each naming this
        stroke: [Path(png).name],
        copies["broken-link"][1]: ["missing.csv"],
        copies["exception"][1]: ["boom"],
        copies["console-error"][1]: ["bad"],
        unscripted: ["plotly.min.js"] + ["Plotly is not defined"] * stroke.read_text().count("Plotly.newPlot("),
    }
    pages = [p for case in cases for p in copies[case]]
    problems = check_pages(pages, tmp_path / "shots")
    for page in pages:
        found = [p for p in problems if p.startswith(f"{page}: ")]
        want = expected.get(page, [])
        assert len(found) == len(want), (page, found)
        assert all(any(w in f for f in found) for w in want), (page, found)
    assert len(problems) == sum(len(w) for w in expected.values()), problems
    assert len(list((tmp_path / "shots").glob("*.png"))) == len(pages)


def test_report_check_opens_every_page_of_every_kind(site: Path, capsys: pytest.CaptureFixture[str]):
    """`wrsim report-check` (make report-check): the dashboard, the bench page, the run pages, the study page and
    its rerun page, and the table pages, each in Chromium without a problem."""
    assert main(["report-check", "--results", str(site / "results")]) == 0
    out = capsys.readouterr().out
    pages = int(re.search(r"report-check: (\d+) pages, 0 problems", out).group(1))
    assert pages >= 7, out
    shots = {p.name for p in (site / "results" / "screenshots").glob("*.png")}
    assert {"index.png", "stroke-index.png", "rc_charge_tb-index.png", "study.png"} <= shots, shots


def test_a_page_that_is_missing_is_a_problem(tmp_path: Path):
    assert check_pages([tmp_path / "nothere.html"], tmp_path) == [f"{tmp_path / 'nothere.html'}: page does not exist"]


def test_without_chromium_the_error_says_what_to_install(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(WrsimError, match="make setup"):
        check_pages([tmp_path / "index.html"], tmp_path)


def test_an_interactive_plot_zooms_and_its_cursor_reads_the_value(tmp_path: Path):
    """Driven through the DevTools protocol with the browser's mouse events: a drag over the middle fifth of the
    plot area zooms x to about 4..6 s, and the cursor at t = 5 s reads y = 2 t = 10 V."""
    t = Signal("time", "s", np.linspace(0.0, 10.0, 20_001))
    y = Signal("y", "V", 2.0 * t.values)
    result = BenchResult("probe", "a ramp", None, [t, y], [], [Plot("ramp", t, [y], [], [], "ramp.png")], {}, True)
    page = write_bench_result(tmp_path, result) / "index.html"
    write_index(tmp_path)
    assert check_pages([page], tmp_path / "shots") == []
    seen = probe_plot(page, "plot0", (0.4, 0.6), 5.0)
    assert seen["before"] == pytest.approx([0.0, 10.0], abs=0.7)  # plotly pads the full range a little
    assert seen["after"] == pytest.approx([4.0, 6.0], abs=0.15)
    assert "y [V]" in seen["cursor"] and re.search(r"\b10(\.0+)? V\b", seen["cursor"]), seen["cursor"]
