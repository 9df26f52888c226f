"""Results are never lost, mixed or half-written (issue 12): concurrent publishers, killed writers, benches that
crash, runs started together with different parameter sets."""

from __future__ import annotations

import json
import multiprocessing
import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from wrsim import cli, paths
from wrsim.benches import BENCHES
from wrsim.benches.core import Bench, Judgement, Run, metric
from wrsim.data.publish import clean_stale, publish_directory, unique_folder
from wrsim.results import Signal

TINY = """library IEEE;
use IEEE.ELECTRICAL_SYSTEMS.all;
entity tb_tiny is
  generic (level : real := 2.0);  -- [V] value of x
end entity tb_tiny;
architecture s of tb_tiny is
  quantity x : real;  -- [V] a constant
begin
  x == level;
end architecture s;
"""


def _publish(root: str, tag: str, files: int, pause: float) -> None:
    import time

    with publish_directory(Path(root), "bench") as folder:
        for k in range(files):
            (folder / f"f{k}.txt").write_text(tag)
            time.sleep(pause)


def test_concurrent_publishers_leave_one_complete_result(tmp_path: Path) -> None:
    ctx = multiprocessing.get_context("fork")
    procs = [ctx.Process(target=_publish, args=(str(tmp_path), tag, 20, 0.001)) for tag in "abcd"]
    for p in procs:
        p.start()
    for p in procs:
        p.join(60)
        assert p.exitcode == 0
    contents = {p.read_text() for p in (tmp_path / "bench").iterdir()}
    assert len(contents) == 1 and len(list((tmp_path / "bench").iterdir())) == 20
    clean_stale(tmp_path)
    assert len(list((tmp_path / ".versions").iterdir())) == 1


def test_a_writer_killed_at_any_moment_leaves_the_previous_result(tmp_path: Path) -> None:
    _publish(str(tmp_path), "good", 5, 0.0)
    ctx = multiprocessing.get_context("fork")
    for delay in (0.0, 0.005, 0.02, 0.05):
        p = ctx.Process(target=_publish, args=(str(tmp_path), "new", 50, 0.002))
        p.start()
        p.join(delay)
        if p.is_alive():
            os.kill(p.pid, signal.SIGKILL)
        p.join()
        texts = {q.read_text() for q in (tmp_path / "bench").iterdir()}
        assert texts in ({"good"}, {"new"}) and len(list((tmp_path / "bench").iterdir())) in (5, 50)
        if texts == {"new"}:
            _publish(str(tmp_path), "good", 5, 0.0)
    clean_stale(tmp_path)  # the killed writers' versions are gone once their processes are
    assert len(list((tmp_path / ".versions").iterdir())) == 1


def test_an_exception_inside_the_publish_keeps_the_previous_result(tmp_path: Path) -> None:
    _publish(str(tmp_path), "good", 3, 0.0)
    with pytest.raises(RuntimeError), publish_directory(tmp_path, "bench") as folder:
        (folder / "f0.txt").write_text("half")
        raise RuntimeError("disk full")
    assert {p.read_text() for p in (tmp_path / "bench").iterdir()} == {"good"}
    assert len(list((tmp_path / ".versions").iterdir())) == 1


def test_leftovers_of_dead_writers_are_removed(tmp_path: Path) -> None:
    dead = subprocess.run(
        [sys.executable, "-c", "import os; print(os.getpid())"], capture_output=True, text=True
    ).stdout.strip()
    legacy = tmp_path / f".bench.{dead}.0123abcd.tmp"  # an older wrsim's staging folder
    legacy.mkdir(parents=True)
    orphan = tmp_path / ".versions" / f"bench.20260101-000000.{dead}.0123abcd"
    orphan.mkdir(parents=True)
    mine = tmp_path / ".versions" / f"bench.20260101-000000.{os.getpid()}.0123abcd"
    mine.mkdir()
    clean_stale(tmp_path)
    assert not legacy.exists() and not orphan.exists() and mine.exists()


def test_work_folders_are_unique(tmp_path: Path) -> None:
    folders = {unique_folder(tmp_path / "work", keep=100) for _ in range(20)}
    assert len(folders) == 20


def _tiny(name: str, judge, params: Path) -> Bench:
    params.write_text("# no parameters\n", encoding="utf-8")
    return Bench(
        name=name,
        entity="tb_tiny",
        description="x == level",
        stop=1e-3,
        max_step=1e-4,
        runs=(Run("one", {}),),
        judge=judge,
        params=str(params),
    )


def test_a_crashing_bench_is_recorded_and_the_others_still_run(capsys, monkeypatch, tmp_path: Path) -> None:
    model = tmp_path / "tiny.vhd"
    model.write_text(TINY, encoding="utf-8")
    monkeypatch.setattr(paths, "LIBRARY", (paths.VHDL / "ieee", model))

    def crash(bench, sims, table, session):
        raise RuntimeError("a defect in the judge")

    def fine(bench, sims, table, session):
        w = sims[0].waves
        return Judgement(
            metrics=[metric("final x", w["x"][-1], 2.0, 0.1, "V")],
            waveforms=[Signal("time", "s", w.time), Signal("x", "V", w["x"])],
        )

    monkeypatch.setitem(BENCHES, "a-crash", _tiny("a-crash", crash, tmp_path / "empty.txt"))
    monkeypatch.setitem(BENCHES, "b-fine", _tiny("b-fine", fine, tmp_path / "empty.txt"))
    results = tmp_path / "results"
    code = cli.main(["testbench", "--bench", "a-crash", "--bench", "b-fine", "--results", str(results)])
    out, err = capsys.readouterr()
    assert code == 1 and err == ""
    failure = json.loads((results / "a-crash.failure.json").read_text())
    assert failure["error"].startswith("internal error: RuntimeError: a defect in the judge (traceback: ")
    assert json.loads((results / "b-fine" / "result.json").read_text())["passed"] is True
    page = (results / "index.html").read_text()
    assert "<b>a-crash</b>" in page and '<b><a href="b-fine/index.html">b-fine</a></b>' in page


def test_an_unknown_parameter_set_writes_nothing(capsys, tmp_path: Path) -> None:
    results = tmp_path / "results"
    code = cli.main(["testbench", "--bench", "motor-characteristic", "--params", "no_such", "--results", str(results)])
    assert code == 2 and capsys.readouterr().err.startswith("wrsim: error: unknown parameter set 'no_such'")
    assert not results.exists() and not (tmp_path / "work").exists()


SCRIPT = """
import sys
from pathlib import Path
from wrsim import cli, paths
from wrsim.benches import BENCHES
from wrsim.benches.core import Bench, Judgement, Run, metric
paths.LIBRARY = (paths.VHDL / "ieee", Path(sys.argv[1]))
from wrsim.results import Signal
def judge(bench, sims, table, session):
    w = sims[0].waves
    return Judgement(metrics=[metric("final x", w["x"][-1], 0.0, 1e9, "V")],
                     waveforms=[Signal("time", "s", w.time), Signal("x", "V", w["x"])])
BENCHES["tiny"] = Bench(name="tiny", entity="tb_tiny", description="x == level", stop=1e-3, max_step=1e-4,
                        runs=(Run("one", {}),), judge=judge, params=sys.argv[2])
sys.exit(cli.main(["testbench", "--bench", "tiny", "--params", sys.argv[3], "--results", sys.argv[4]]))
"""


def test_runs_started_together_each_get_their_own_result(tmp_path: Path) -> None:
    model = tmp_path / "tiny.vhd"
    model.write_text(TINY, encoding="utf-8")
    base = tmp_path / "base.txt"
    base.write_text("# nothing\n")
    procs = {}
    for k in range(6):
        level = 1.0 + k
        pset = tmp_path / f"level{k}.txt"
        pset.write_text(f"[tb_tiny]\nlevel = {level} V\n")
        procs[level] = (
            subprocess.Popen(
                [
                    sys.executable,
                    "-c",
                    textwrap.dedent(SCRIPT),
                    str(model),
                    str(base),
                    str(pset),
                    str(tmp_path / f"results{k}"),
                ],
                stdout=subprocess.PIPE,
                stderr=subprocess.PIPE,
                text=True,
            ),
            tmp_path / f"results{k}",
        )
    for level, (proc, results) in procs.items():
        out, err = proc.communicate(timeout=120)
        assert proc.returncode == 0, err
        data = json.loads((results / "tiny" / "result.json").read_text())
        assert data["metrics"]["final x"]["value"] == pytest.approx(level)
        assert len(list((results / "work" / "tiny").iterdir())) == 1  # its run folder, inside its results
