import csv
import dataclasses
import html
import json
from pathlib import Path

import numpy as np
import pytest
from matplotlib.image import imread

from wrsim.errors import WrsimError
from wrsim.report import interactive, pages
from wrsim.report.results import format_table, result_dict, write_bench_result, write_failure, write_index
from wrsim.results import BenchResult, Grid, Metric, Overlay, Plot, Signal

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def make_result(bench: str = "motor_char", speed_scale: float = 1.0) -> BenchResult:
    t = Signal("time", "s", np.linspace(0.0, 1.0, 5))
    torque = Signal("torque", "N*m", np.array([0.0, 1.0, 2.0, 3.0, 4.0]))
    speed = Signal("speed", "rpm", speed_scale * np.array([3000.0, 2500.0, 2000.0, 1500.0, 1000.0]))
    current = Signal("current", "A", np.array([2.0, 6.0, 10.0, 14.0, 18.0]))
    meas_t = Signal("torque", "N*m", np.array([1.0, 3.0]))
    meas_n = Signal("speed", "rpm", np.array([2490.0, 1530.0]))
    meas_i = Signal("current", "A", np.array([6.5, 13.0]))
    metrics = [
        Metric("no_load_speed", 3000.0, 3010.0, 50.0, "rpm", True),
        Metric("stall_current", 18.0, 20.0, 5.0, "%", True, note="relative error"),
    ]
    plots = [
        Plot(
            "characteristic line",
            torque,
            [speed],
            [current],
            [Overlay("measured speed", meas_t, meas_n, "left"), Overlay("measured current", meas_t, meas_i, "right")],
            "characteristic.png",
        ),
        Plot("speed over time", t, [speed], [], [], "speed.png"),
    ]
    return BenchResult(
        bench=bench,
        description="motor characteristic line at 13.5 V",
        measurement="params/measurements/motor.csv",
        waveforms=[t, torque, speed, current],
        metrics=metrics,
        plots=plots,
        timings={"simulate": 0.25, "total": 0.5},
        passed=True,
    )


def test_waveforms_csv_header_and_columns(tmp_path: Path) -> None:
    result = make_result()
    out = write_bench_result(tmp_path, result)
    assert out == tmp_path / "motor_char"
    lines = (out / "waveforms.csv").read_text().splitlines()
    assert lines[0] == "time[s],torque[N*m],speed[rpm],current[A]"
    assert len(lines) == 6
    table = np.loadtxt(out / "waveforms.csv", delimiter=",", skiprows=1)
    expected = np.column_stack([s.values for s in result.waveforms])
    np.testing.assert_allclose(table, expected, rtol=1e-12)


def test_result_json_content(tmp_path: Path) -> None:
    out = write_bench_result(tmp_path, make_result())
    data = json.loads((out / "result.json").read_text())
    assert data == {
        "bench": "motor_char",
        "description": "motor characteristic line at 13.5 V",
        "measurement": "params/measurements/motor.csv",
        "passed": True,
        "known": False,
        "error": None,
        "metrics": {
            "no_load_speed": {
                "value": 3000.0,
                "reference": 3010.0,
                "tolerance": 50.0,
                "unit": "rpm",
                "pass": True,
                "note": "",
                "known": "",
                "kind": "",
            },
            "stall_current": {
                "value": 18.0,
                "reference": 20.0,
                "tolerance": 5.0,
                "unit": "%",
                "pass": True,
                "note": "relative error",
                "known": "",
                "kind": "",
            },
        },
        "plots": [
            {"title": "characteristic line", "file": "characteristic.png"},
            {"title": "speed over time", "file": "speed.png"},
        ],
        "timings": {"simulate": 0.25, "total": 0.5},
    }


def test_non_finite_metric_values_become_null(tmp_path: Path) -> None:
    result = make_result()
    result.metrics = [Metric("settling_time", float("nan"), 0.2, 0.05, "s", False)]
    result.passed = False
    data = json.loads((write_bench_result(tmp_path, result) / "result.json").read_text())
    assert data["metrics"]["settling_time"]["value"] is None
    assert data["passed"] is False


def test_plots_are_valid_pngs(tmp_path: Path) -> None:
    out = write_bench_result(tmp_path, make_result())
    for name in ("characteristic.png", "speed.png"):
        raw = (out / name).read_bytes()
        assert raw.startswith(PNG_MAGIC)
        image = imread(out / name)
        assert image.ndim == 3 and image.shape[0] > 100 and image.shape[1] > 100
    assert sorted(p.name for p in out.iterdir()) == [
        "characteristic.png",
        "index.html",
        "result.json",
        "speed.png",
        "waveforms.csv",
        "waveforms.mf4",
    ]


def test_failure_midway_keeps_previous_result(tmp_path: Path) -> None:
    out = write_bench_result(tmp_path, make_result())
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    broken = make_result(speed_scale=2.0)  # its second plot cannot be drawn: the first is written by then
    t = broken.plots[1].x
    broken.plots[1].left = [Signal("speed", "rpm", np.arange(t.values.size + 2, dtype=float))]
    with pytest.raises(WrsimError, match="plot 'speed.png': speed\\[rpm\\] has 7 values, time\\[s\\] 5"):
        write_bench_result(tmp_path, broken)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    assert visible(tmp_path) == ["motor_char"] and len(list((tmp_path / ".versions").iterdir())) == 1


def test_rewrite_replaces_whole_directory(tmp_path: Path) -> None:
    write_bench_result(tmp_path, make_result())
    result = make_result(speed_scale=2.0)
    result.plots = result.plots[:1]
    out = write_bench_result(tmp_path, result)
    assert not (out / "speed.png").exists()
    table = np.loadtxt(out / "waveforms.csv", delimiter=",", skiprows=1)
    assert table[0, 2] == 6000.0
    assert visible(tmp_path) == ["motor_char"] and len(list((tmp_path / ".versions").iterdir())) == 1


def visible(root: Path) -> list[str]:
    """The results and pages a user sees (not the hidden versions, nor the shared page resources of _static)."""
    return sorted(p.name for p in root.iterdir() if not p.name.startswith((".", "_")))


def test_a_failure_is_recorded_beside_the_last_good_result(tmp_path: Path) -> None:
    out = write_bench_result(tmp_path, make_result())
    good = (out / "result.json").read_bytes()
    record = write_failure(tmp_path, "motor_char", "ngspice: timestep too small")
    assert record == tmp_path / "motor_char.failure.json"
    assert (out / "result.json").read_bytes() == good
    data = json.loads(record.read_text())
    assert (data["bench"], data["passed"], data["error"]) == ("motor_char", False, "ngspice: timestep too small")
    page = write_index(tmp_path).read_text()
    assert "failed, the numbers are the last good result" in page and "timestep too small" in page
    assert "1 benches: " in page and '<span class="fail">1 FAIL</span>' in page
    write_bench_result(tmp_path, make_result())
    assert not record.exists()
    assert '<span class="pass">1 PASS</span>' in write_index(tmp_path).read_text()


def test_index_lists_all_benches(tmp_path: Path) -> None:
    write_bench_result(tmp_path, make_result("motor_char"))
    failing = make_result("door_close")
    failing.metrics[0].passed = False
    failing.passed = False
    write_bench_result(tmp_path, failing)
    write_failure(tmp_path, "pinch_test", "simulation <diverged>")
    stray = tmp_path / ".motor_char.123.abcd.tmp"  # an interrupted write
    stray.mkdir()
    (stray / "result.json").write_text("{}")

    index = write_index(tmp_path)
    assert index == tmp_path / "index.html"
    page = index.read_text()
    for bench in ("motor_char", "door_close"):
        assert f'<b><a href="{bench}/index.html">{bench}</a></b>' in page
    assert "<b>pinch_test</b>" in page  # no result: no page of its own
    assert ".motor_char.123" not in page
    assert "3 benches: " in page and '<span class="pass">1 PASS</span>' in page and "2 FAIL" in page
    assert "simulation &lt;diverged&gt;" in page
    assert "no_load_speed: 3000 rpm" in page  # a headline number; the details are on the bench's page
    row = page[page.index('href="door_close/index.html"') :].split("</tr>")[0]
    assert '<span class="pass">1</span> / <span class="known">0</span> / <span class="fail">1</span>' in row
    bench_page = (tmp_path / "motor_char" / "index.html").read_text()
    row = '<td>no_load_speed</td><td class="num">3000 rpm</td><td class="req">3010 +- 50 rpm (-0.3 %)</td>'
    assert row in bench_page
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".index")]


def test_index_of_missing_root_is_empty(tmp_path: Path) -> None:
    page = write_index(tmp_path / "results").read_text()
    assert "0 benches: " in page


def test_format_table() -> None:
    failing = make_result("door_close")
    failing.metrics[1] = Metric("stall_current", 30.0, 20.0, 5.0, "%", False)
    failing.passed = False
    text = format_table([make_result(), failing])
    assert text.splitlines() == [  # the references are measurements: the deviations in %
        "bench / metric   value     required                 result",
        "motor_char                                          PASS",
        "  no_load_speed  3000 rpm  3010 +- 50 rpm (-0.3 %)  PASS",
        "  stall_current  18 %      20 +- 5 % (-10.0 %)      PASS",
        "door_close                                          FAIL",
        "  no_load_speed  3000 rpm  3010 +- 50 rpm (-0.3 %)  PASS",
        "  stall_current  30 %      20 +- 5 % (+50.0 %)      FAIL",
    ]


def test_format_table_reads_result_json(tmp_path: Path) -> None:
    result = make_result()
    data = json.loads((write_bench_result(tmp_path, result) / "result.json").read_text())
    failure = json.loads(write_failure(tmp_path, "pinch_test", "no\nconvergence").read_text())
    assert format_table([data]) == format_table([result])
    assert format_table([failure]).splitlines()[1:] == [
        "pinch_test" + " " * 23 + "FAIL",
        "  error: no",
        "  convergence",
    ]


def test_grid_is_written_as_csv_and_html_with_failing_cells_marked(tmp_path: Path) -> None:
    result = make_result()
    result.plots.append(
        Grid("matrix", ["gauge [N/mm]", "9 V"], [["10", "PASS 48.1 N"], ["65", "FAIL 112.0 N"]], "matrix.csv")
    )
    folder = write_bench_result(tmp_path, result)
    assert (folder / "matrix.csv").read_text().splitlines() == ["gauge [N/mm],9 V", "10,PASS 48.1 N", "65,FAIL 112.0 N"]
    page = (folder / "matrix.html").read_text()
    assert '<td class="fail">FAIL 112.0 N</td>' in page and '<td class="">PASS 48.1 N</td>' in page
    assert '<td class="fail">FAIL 112.0 N</td>' in (folder / "index.html").read_text()  # on the bench page too
    files = [p["file"] for p in json.loads((folder / "result.json").read_text())["plots"]]
    assert "matrix.html" in files and "matrix.csv" in files


@pytest.mark.parametrize(
    ("change", "message"),
    [
        (lambda r: setattr(r, "bench", "../evil"), "invalid bench name"),
        (lambda r: r.plots.append(Grid("g", ["a", "b"], [["1"]], "g.csv")), "a row has 1 cells for 2 columns"),
        (lambda r: r.plots.append(Grid("g", ["a"], [["1"]], "../g.csv")), "plain name ending in .csv"),
        (lambda r: r.plots.append(Grid("g", ["a"], [["1"]], "g.csv", margins=[[1.0, 2.0]])), "margins do not have"),
        (lambda r: r.plots.append(Grid("g", ["a"], [["1"]], "g.csv", links=[])), "links do not have the shape"),
        (lambda r: r.waveforms.reverse(), "first waveform must be time"),
        (lambda r: setattr(r, "passed", False), "disagrees with its metrics"),
        (lambda r: setattr(r.waveforms[1], "values", np.zeros(3)), "different lengths"),
        (lambda r: setattr(r.plots[0].overlays[0], "axis", "top"), "must be 'left' or 'right'"),
        (lambda r: setattr(r.plots[0].overlays[0].y, "unit", "rad/s"), "not on the left axis"),
        (lambda r: setattr(r.plots[0], "filename", "sub/x.png"), "plain name ending in .png"),
    ],
)
def test_invalid_results_are_rejected(tmp_path: Path, change, message: str) -> None:
    result = make_result()
    change(result)
    with pytest.raises(WrsimError, match=message):
        write_bench_result(tmp_path, result)
    assert not tmp_path.exists() or not any(tmp_path.iterdir())


def test_unwritable_root_is_a_wrsim_error(tmp_path: Path) -> None:
    root = tmp_path / "results"
    root.write_text("not a directory")
    with pytest.raises(WrsimError, match="cannot write results of bench motor_char"):
        write_bench_result(root, make_result())


def test_the_mdf4_file_holds_the_samples_of_the_csv(tmp_path: Path) -> None:
    from asammdf import MDF

    out = write_bench_result(tmp_path, make_result())
    with (out / "waveforms.csv").open() as f:
        rows = list(csv.reader(f))
    table = np.array(rows[1:], dtype=float)
    mdf = MDF(out / "waveforms.mf4")
    try:
        assert mdf.version.startswith("4.")
        channels = [(c.name, c.unit) for c in mdf.groups[0].channels]
        assert [f"{n}[{u}]" for n, u in channels] == rows[0]  # the CSV's columns, with their units
        for k, (name, _) in enumerate(channels[1:], start=1):
            sig = mdf.get(name, 0, k)
            np.testing.assert_allclose(sig.timestamps, table[:, 0], rtol=1e-12)
            np.testing.assert_allclose(sig.samples, table[:, k], rtol=1e-12)
        assert "motor_char" in mdf.header.comment
    finally:
        mdf.close()


def test_plots_are_interactive_with_plotly_written_once(tmp_path: Path) -> None:
    """Each plot of a bench page is a plotly.js figure inlined in the page; the script is the plotly package's copy,
    written once into the results folder's _static/ and loaded by a relative path (file:// without network)."""
    folder = write_bench_result(tmp_path, make_result())
    script = tmp_path / interactive.STATIC / interactive.PLOTLY_JS
    assert script.stat().st_size > 1_000_000 and script.read_bytes().startswith(b"/**\n* plotly.js v")
    stamp = script.stat().st_mtime_ns
    write_bench_result(tmp_path, make_result("door_close"))
    assert script.stat().st_mtime_ns == stamp  # the same copy is kept
    page = (folder / "index.html").read_text()
    assert '<script src="../_static/plotly.min.js"></script>' in page
    assert page.count("Plotly.newPlot(") == 2 and '<a href="speed.png">PNG</a>' in page
    spec = interactive.figure(make_result().plots[0])
    names = [t["name"] for t in spec["data"]]
    assert "speed [rpm]" in names and spec["layout"]["hovermode"] == "x unified"


def test_long_waveforms_are_decimated_to_the_extremes_of_each_pixel_column() -> None:
    t = np.linspace(0.0, 1.0, 100_001)
    y = np.sin(2 * np.pi * 50 * t)
    y[54_321] = 7.0  # a spike inside one column
    x, v = interactive.decimate(t, y, columns=500)
    assert len(x) <= 1002 and x[0] == 0.0 and x[-1] == 1.0 and np.all(np.diff(x) > 0)
    assert v.max() == 7.0 and v.min() == pytest.approx(-1.0, abs=1e-3)
    short = np.arange(10.0)
    assert interactive.decimate(short, short)[0].tolist() == short.tolist()


@pytest.mark.parametrize(
    ("metric", "value", "required"),
    [
        (Metric("peak", 47.6, 50.0, 50.0, "N", True, kind="limit"), "47.6 N", "<= 100 N"),
        (Metric("reversed", 1.0, 1.0, 0.0, "1", True, kind="flag"), "yes", "yes"),
        (Metric("false reversal", 0.0, 0.0, 0.0, "1", True, kind="flag"), "no", "no"),
        (Metric("speed", 3000.0, 3010.0, 50.0, "rpm", True), "3000 rpm", "3010 +- 50 rpm"),
    ],
)
def test_metrics_state_limits_flags_and_units_once(metric: Metric, value: str, required: str) -> None:
    data = result_dict(dataclasses.replace(make_result(), measurement=None, metrics=[metric], passed=True))
    m = data["metrics"][metric.name]
    assert (pages.value_text(m), pages.requirement_text(m)) == (value, required)


def test_a_grid_with_margins_is_a_heat_map() -> None:
    grid = Grid(
        "matrix",
        ["gap", "9 V", "13 V"],
        [["4", "PASS 40 N", "FAIL 112 N"], ["10", "INFO 60 N", "PASS 99 N"]],
        "m.csv",
        margins=[[None, 60.0, -12.0], [None, None, 1.0]],
        scale=50.0,
    )
    html_table = pages.grid_table(grid)
    assert '<td class="" style="background:rgb(120,200,120)">PASS 40 N</td>' in html_table  # beyond the scale
    assert '<td class="fail" style="background:#f4a6a6">FAIL 112 N</td>' in html_table
    assert '<td class="info">INFO 60 N</td>' in html_table and "colour: the margin to the limit" in html_table


MARKUP = "<script>alert('x')</script><b>bold</b>"


def test_text_that_reaches_html_is_escaped(tmp_path: Path) -> None:
    """Markup planted in every text a page shows (a description from a parameter file or VHDL comment, metric
    names and notes, signal names as an extended identifier gives them, plot and table titles, table cells, an
    error) reaches the pages as text, never as markup; in a plot's JSON no '</' can close its script."""
    t = Signal("time", "s", np.linspace(0.0, 1.0, 11))
    y = Signal(f"\\\\{MARKUP}\\\\", "V", np.arange(11.0))
    result = BenchResult(
        "planted",
        f"from {MARKUP}.vhd",
        MARKUP,
        [t, y],
        [Metric(MARKUP, 1.0, 1.0, 0.5, "V", True, note=MARKUP)],
        [
            Plot(MARKUP, t, [y], [], [Overlay(MARKUP, t, y, "left")], "p.png"),
            Grid(MARKUP, [MARKUP], [[MARKUP]], "g.csv"),
        ],
        {},
        True,
    )
    folder = write_bench_result(tmp_path, result)
    write_failure(tmp_path, "other", MARKUP)
    for page in [folder / "index.html", folder / "g.html", write_index(tmp_path)]:
        text = page.read_text()
        assert "<script>alert" not in text and "<b>bold</b>" not in text, page
        # escaped once: as HTML text, or the same inside a JSON string (& as \u0026); never twice (&amp;lt;)
        assert "&amp;lt;" not in text and "\\u0026amp;lt;" not in text, page
        assert "&lt;script&gt;alert" in text or "\\u0026lt;script" in text, page
    spec = interactive.figure(result.plots[0])
    assert [t["name"] for t in spec["data"]] == [html.escape(y.axis_label), html.escape(MARKUP)]


def test_plots_of_a_page_of_their_own_and_cells_that_open_it(tmp_path: Path) -> None:
    """A run's plots on its own page beside the bench page (interactive only: no PNG), opened from a table cell."""
    result = make_result()
    speed = result.plots[1]
    result.plots[1] = dataclasses.replace(speed, page="run-a.html")
    result.plots.append(Grid("m", ["run"], [["PASS a"]], "m.csv", links=[["run-a.html"]]))
    folder = write_bench_result(tmp_path, result)
    assert not (folder / speed.filename).exists()
    assert (folder / "run-a.html").read_text().count("Plotly.newPlot(") == 1
    bench = (folder / "index.html").read_text()
    assert bench.count("Plotly.newPlot(") == 1 and '<td class=""><a href="run-a.html">PASS a</a></td>' in bench
