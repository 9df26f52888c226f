"""Tolerance studies end to end on the open-loop stroke (issue 15 acceptance): a study on a Dask LocalCluster gives
the metrics of a direct run of the same samples and loses no completed sample when a worker is killed; a local
study resumes, records failed samples and goes on; sensitivity and worst case; the command line and its page."""

from __future__ import annotations

import multiprocessing
import os
import signal

import pandas as pd
import pytest

from wrsim.cli import main
from wrsim.errors import WrsimError
from wrsim.study import (
    Study,
    StudySpec,
    Task,
    draw,
    factors,
    read_study,
    run_sample,
    run_study,
    sample_set,
    study_params,
)
from wrsim.study.engine import local_cluster
from wrsim.study.report import statistics, write_study_page

TOLERANCES = ("tolerances/production", "tolerances/ambient")


def test_dask_study_equals_direct_runs_and_survives_a_killed_worker(tmp_path):
    distributed = pytest.importorskip("distributed")
    spec = StudySpec("stroke", TOLERANCES, samples=20, seed=5, stop=6.0, name="dask")
    killed: list[int] = []
    before_kill: dict[int, dict] = {}
    with local_cluster(2) as cluster, distributed.Client(cluster) as client:

        def kill_one_worker(result) -> None:
            if len(killed) == 0 and result.sample >= 0 and len(before_kill) < 4:
                before_kill[result.sample] = result.outputs
                if len(before_kill) == 4:
                    pid = sorted(client.run(os.getpid).values())[0]
                    os.kill(pid, signal.SIGKILL)
                    killed.append(pid)

        study = run_study(spec, tmp_path, client=client, progress=False, on_result=kill_one_worker)
    assert killed and sorted(study.rows) == list(range(20))
    assert not study.failed(), study.failed()
    for sample, outputs in before_kill.items():  # kept as they arrived before the kill
        assert study.rows[sample]["outputs"] == {o.name: o.value for o in outputs}
    stored, _ = read_study(spec, tmp_path)  # the results file holds the same rows
    assert {k: r["outputs"] for k, r in stored.rows.items()} == {k: r["outputs"] for k, r in study.rows.items()}

    base, _ = study_params(spec)
    fs = factors(base)
    direct = Study(spec, tmp_path / "direct", fs)
    for i in range(20):
        values = draw(fs, spec.seed, i)
        r = run_sample(
            Task(
                "stroke",
                i,
                f"mc{i}",
                values,
                sample_set(base, values, f"mc{i}"),
                stop=6.0,
                workdir=str(tmp_path / "direct"),
            )
        )
        assert not r.error, r.error
        assert {o.name: o.value for o in r.outputs} == study.rows[i]["outputs"]  # identical, not close
        direct.rows[i] = {"sample": i, "label": r.label, "error": "", "outputs": {o.name: o.value for o in r.outputs}}
    direct.outputs = study.outputs
    assert statistics(direct) == statistics(study)
    closing = [r["outputs"]["stroke time"] for r in study.rows.values() if r["outputs"]["closes"] == 1.0]
    assert 2.0 < min(closing) and max(closing) < 6.0  # a 13 V stroke: 2.45 s at 85 degC, 3.62 s at -40 degC nominal


def test_local_study_resumes_and_records_failed_samples(tmp_path):
    spec = StudySpec("stroke", ("tolerances/production",), samples=3, seed=2, name="resume")
    first = run_study(spec, tmp_path, workers=2, progress=False)
    assert sorted(first.rows) == [0, 1, 2] and not first.failed()
    ran: list[int] = []
    more = run_study(
        StudySpec("stroke", ("tolerances/production",), samples=5, seed=2, name="resume"),
        tmp_path,
        workers=2,
        progress=False,
        on_result=lambda r: ran.append(r.sample),
    )
    assert sorted(ran) == [3, 4] and sorted(more.rows) == [0, 1, 2, 3, 4]
    assert all(more.rows[k] == first.rows[k] for k in range(3))  # resumed, not re-run
    with pytest.raises(WrsimError, match=r"samples.parquet: made by another study \(differs in: seed\)"):
        run_study(
            StudySpec("stroke", ("tolerances/production",), samples=5, seed=3, name="resume"),
            tmp_path,
            workers=2,
            progress=False,
        )

    spread = tmp_path / "negative_glass.txt"
    spread.write_text("[glass]\nm +- 200 % uniform   # a third of the samples have a negative mass\n")
    bad = StudySpec("stroke", (str(spread),), samples=9, seed=1, name="failing")
    study = run_study(bad, tmp_path, workers=2, progress=False)
    failed = study.failed()
    masses = {k: r["values"]["glass.m"] for k, r in study.rows.items()}
    assert sorted(r["sample"] for r in failed) == sorted(k for k, m in masses.items() if m <= 0.0)
    assert failed and len(failed) < 9 and all("glass: m must be > 0" in r["error"] for r in failed)
    assert "Failed samples" in write_study_page(study).read_text()

    (tmp_path / "study" / "resume" / "samples.parquet").write_bytes(b"not parquet")
    with pytest.raises(WrsimError, match="not a study results file"):
        run_study(spec, tmp_path, workers=2, progress=False)


def test_local_pool_survives_a_killed_process(tmp_path):
    killed: list[int] = []
    first: dict[int, dict] = {}

    def kill_a_worker(result) -> None:
        first.setdefault(result.sample, {o.name: o.value for o in result.outputs})
        if not killed:
            victim = multiprocessing.active_children()[0]
            os.kill(victim.pid, signal.SIGKILL)
            killed.append(victim.pid)

    spec = StudySpec("stroke", ("tolerances/production",), samples=6, seed=4, name="killed")
    study = run_study(spec, tmp_path, workers=2, progress=False, on_result=kill_a_worker)
    assert killed and sorted(study.rows) == list(range(6)) and not study.failed()
    assert all(study.rows[k]["outputs"] == outputs for k, outputs in first.items())


def test_sensitivity_signs_and_worst_case_corners(tmp_path):
    spec = StudySpec("stroke", ("tolerances/production",), method="worst-case", stop=6.0, name="wc")
    study = run_study(spec, tmp_path, workers=2, progress=False)
    by_label = {r["label"]: r["outputs"] for r in study.rows.values()}

    def effect(unit: str, output: str = "stroke time") -> float:
        return by_label[f"{unit} high"][output] - by_label[f"{unit} low"][output]

    assert effect("dcpm_motor.ra") > 0.05  # more resistance: slower
    assert effect("worm_gear.eta") < -0.05  # a better gear: faster
    assert effect("seal_friction.forces") > 0.05  # more seal friction: slower
    assert effect("seal_friction.forces", "drum torque top") > 0.1
    sensitivity = [
        o["stroke time"] for label, o in by_label.items() if "lowest" not in label and "highest" not in label
    ]
    highest, lowest = by_label["stroke time highest"], by_label["stroke time lowest"]
    assert highest["closes"] == 0.0 or highest["stroke time"] >= max(sensitivity)
    assert lowest["stroke time"] <= min(sensitivity)


def test_command_line_study_page_limits_rerun_and_errors(tmp_path, capsys):
    args = [
        "study",
        "stroke",
        "--params",
        "tolerances/production",
        "--samples",
        "3",
        "--workers",
        "2",
        "--results",
        str(tmp_path),
        "--limit",
        "stroke time=..3.0",
    ]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "stroke time" in out and "..3" in out and "3 samples, 0 failed" in out
    folder = tmp_path / "study" / "stroke-montecarlo"
    page = (folder / "study.html").read_text()
    assert "hist_stroke_time.png" in page and (folder / "hist_stroke_time.png").stat().st_size > 1000
    samples = pd.read_parquet(folder / "samples.parquet")  # the output's section names the sample nearest its limit
    nearest = int(samples.loc[samples["out:stroke time"].idxmax(), "sample"])
    first = page[page.index("<h3 id='stroke_time'>") :].split("<li>")[1]
    assert first.startswith(f"sample {nearest} ") and f"--rerun {nearest}" in first
    assert (folder / "statistics.csv").read_text().startswith("output,unit,n,mean,std,p1,p5,p50,p95,p99")
    assert main([*args, "--rerun", "1"]) == 0
    assert "stroke time deviation" in (folder / "reruns" / "sample-1" / "result.json").read_text()
    for bad, message in (
        (["--run", "down"], "bench stroke has no run 'down' (runs: up)"),
        (["--limit", "stroke time"], "write OUTPUT=LOW..HIGH"),
        (["--set", "drum_diameter=-1"], "drum"),
        (["--rerun", "99"], "has no sample 99"),
        (["--scheduler", "notanaddress"], "cannot reach the Dask scheduler"),
    ):
        assert main([*args, *bad]) == 2
        assert message in capsys.readouterr().err
    assert main(["study", "stroke", "--samples", "2", "--results", str(tmp_path)]) == 2
    assert "has a tolerance" in capsys.readouterr().err
