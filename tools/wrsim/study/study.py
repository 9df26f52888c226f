"""A tolerance study from its specification to its results file: the parameter set with its tolerances, the plan
(Monte Carlo samples, a one-at-a-time sensitivity, worst-case corners), the samples run by an executor
(engine), every result kept in `samples.parquet` as it arrives, the page (study.report) at the end.

A study's folder is `results/study/<name>/`. Running the same study again resumes it: the samples already in the
file are kept and only the missing (or failed) ones run, so a study interrupted, killed or extended to more
samples loses nothing. A study whose specification or parameter files changed is refused unless `fresh`."""

from __future__ import annotations

import contextlib
import hashlib
import json
import math
import os
import time
from collections.abc import Callable, Generator
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from wrsim import paths
from wrsim.benches.core import bench_params
from wrsim.data.params import ParamSet, Value, find_param_set
from wrsim.errors import WrsimError
from wrsim.study.engine import (
    SampleResult,
    Task,
    check_runs,
    execute_dask,
    execute_local,
    library_digest,
    study_bench,
)
from wrsim.study.sampling import Factor, draw, factors, sample_set, sensitivity_plan, units, worst_case_plan

__all__ = ["METHODS", "StudySpec", "Study", "study_params", "run_study", "rerun_sample", "read_study", "effects_of"]

METHODS = ("montecarlo", "sensitivity", "worst-case")
SAMPLES_FILE = "samples.parquet"
_SAVE_EVERY = 2.0  # [s] the results file is rewritten at most this often while samples arrive


@dataclass(frozen=True)
class StudySpec:
    """What a study runs: a bench (only the runs `runs` names, when any; `generics` laid over its runs' top-level
    generics; `stop` instead of its end), the parameter sets laid over the bench's own set in order (the last one
    usually the tolerances), the method and, for Monte Carlo, the number of samples and the seed. `limits`
    replace an output's specification limits: (output, lower, upper), None for no limit."""

    bench: str
    params: tuple[str, ...] = ()
    method: str = "montecarlo"
    samples: int = 100
    seed: int = 1
    generics: tuple[tuple[str, float], ...] = ()
    runs: tuple[str, ...] = ()
    stop: float | None = None
    limits: tuple[tuple[str, float | None, float | None], ...] = ()
    name: str = ""

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise WrsimError(f"unknown study method '{self.method}' (methods: {', '.join(METHODS)})")
        if self.samples < 1:
            raise WrsimError(f"--samples {self.samples}: a study needs at least one sample")

    @property
    def folder_name(self) -> str:
        return self.name or f"{self.bench}-{self.method}"

    def identity(self, files: list[Path]) -> dict[str, Any]:
        """What makes two runs of a study the same study (all but the sample count and the limits), with a digest
        of the parameter files' text."""
        out = {k: v for k, v in asdict(self).items() if k not in ("samples", "limits", "name")}
        out["files"] = hashlib.sha256(b"".join(f.read_bytes() for f in files)).hexdigest()[:16]
        out["library"] = library_digest()
        return json.loads(json.dumps(out))


@dataclass
class Study:
    """A study's results: the factors it varied, one row per sample (see `rows`), the outputs' units and limits."""

    spec: StudySpec
    folder: Path
    factors: list[Factor]
    rows: dict[int, dict[str, Any]] = field(default_factory=dict)
    outputs: dict[str, dict[str, Any]] = field(default_factory=dict)  # name -> unit, lower, upper, note

    @property
    def file(self) -> Path:
        return self.folder / SAMPLES_FILE

    def values(self, output: str) -> np.ndarray:
        """The output's value of every sample that ran (NaN where the sample failed), in sample order."""
        return np.array([r["outputs"].get(output, math.nan) for _, r in sorted(self.rows.items())], dtype=float)

    def failed(self) -> list[dict[str, Any]]:
        return [r for _, r in sorted(self.rows.items()) if r["error"]]


def study_params(spec: StudySpec) -> tuple[ParamSet, list[Path]]:
    """The bench's parameter set with the spec's sets laid over it in order (the user's sets, kept on top of a
    run's own set), and the files read."""
    bench = study_bench(spec.bench)
    return bench_params(bench, spec.params), [find_param_set(p) for p in (bench.params, *spec.params)]


def _plan(
    spec: StudySpec, fs: list[Factor], offset: int = 0, effects: dict[str, dict[str, float]] | None = None
) -> list[tuple[int, str, dict[str, Value]]]:
    if spec.method == "montecarlo":
        return [(i, f"mc{i}", draw(fs, spec.seed, i)) for i in range(spec.samples)]
    plan = sensitivity_plan(fs) if effects is None else worst_case_plan(fs, effects)
    return [(offset + i, label, values) for i, (label, values) in enumerate(plan)]


def effects_of(study: Study) -> dict[str, dict[str, float]]:
    """One-at-a-time effects from a study's sensitivity rows: output -> unit (a factor, or a group of them; see
    sampling.units) -> the output at the unit's high limit minus at its low limit (NaN where either is missing)."""
    by_label = {r["label"]: r for r in study.rows.values()}
    out: dict[str, dict[str, float]] = {}
    for name in study.outputs:
        out[name] = {}
        for unit, _ in units(study.factors):
            lo, hi = by_label.get(f"{unit} low"), by_label.get(f"{unit} high")
            out[name][unit] = (
                hi["outputs"].get(name, math.nan) - lo["outputs"].get(name, math.nan) if lo and hi else math.nan
            )
    return out


def _row(result: SampleResult) -> dict[str, Any]:
    return {
        "sample": result.sample,
        "label": result.label,
        "error": result.error,
        "seconds": result.seconds,
        "worker": result.worker,
        "values": result.values,
        "outputs": {o.name: o.value for o in result.outputs},
    }


def _save(study: Study, identity: dict[str, Any]) -> None:
    """Write the results file atomically (a temporary file renamed over it): one row per sample, the factors and
    outputs as columns, the study's identity and the outputs' units and limits in the file's metadata."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    rows = [r for _, r in sorted(study.rows.items())]
    columns: dict[str, Any] = {k: [r[k] for r in rows] for k in ("sample", "label", "error", "seconds", "worker")}
    for f in study.factors:
        columns[f"in:{f.name}"] = [r["values"].get(f.name) for r in rows]
    for name in study.outputs:
        columns[f"out:{name}"] = pa.array([r["outputs"].get(name) for r in rows], type=pa.float64())
    meta = {
        "identity": identity,
        "outputs": study.outputs,
        "factors": {f.name: {"unit": f.unit, "nominal": f.nominal, "law": f.tolerance.law} for f in study.factors},
    }
    table = pa.table(columns).replace_schema_metadata({"wrsim.study": json.dumps(meta)})
    study.folder.mkdir(parents=True, exist_ok=True)
    tmp = study.file.with_name(f".{SAMPLES_FILE}.{os.getpid()}.tmp")
    pq.write_table(table, tmp)
    os.replace(tmp, study.file)


def read_study(spec: StudySpec, results: Path = paths.RESULTS) -> tuple[Study, dict[str, Any]]:
    """The study's results as its file holds them (no rows when there is no file) and the identity stored there."""
    base, _ = study_params(spec)
    study = Study(spec, results / "study" / spec.folder_name, factors(base))
    return study, _read(study)


def _read(study: Study) -> dict[str, Any]:
    """Fill `study` with the rows and outputs of its file; the identity stored there ({} without a file)."""
    if not study.file.is_file():
        return {}
    import pyarrow.parquet as pq

    try:
        table = pq.read_table(study.file)
        meta = json.loads(table.schema.metadata[b"wrsim.study"])
    except Exception as e:  # noqa: BLE001 - pyarrow's errors for a damaged file are of many types
        raise WrsimError(
            f"{study.file}: not a study results file ({type(e).__name__}: {e}); remove it or give --fresh"
        ) from None
    data = table.to_pydict()
    study.outputs = meta["outputs"]
    for k in range(table.num_rows):
        study.rows[data["sample"][k]] = {
            **{c: data[c][k] for c in ("sample", "label", "error", "seconds", "worker")},
            "values": {f.name: data[f"in:{f.name}"][k] for f in study.factors if f"in:{f.name}" in data},
            "outputs": {n: data[f"out:{n}"][k] for n in study.outputs if data[f"out:{n}"][k] is not None},
        }
    return meta["identity"]


def run_study(
    spec: StudySpec,
    results: Path = paths.RESULTS,
    *,
    workers: int | None = None,
    client: Any = None,
    fresh: bool = False,
    progress: bool | None = None,
    on_result: Callable[[SampleResult], None] | None = None,
) -> Study:
    """Run (or resume) the study `spec`: its samples on `workers` local processes (default: one per core), or on
    the Dask cluster of `client`; returns the study with every sample's row. `progress`: a progress bar with ETA
    (None: only on a terminal). `on_result` is called with every sample as it arrives."""
    base, files = study_params(spec)
    fs = factors(base)
    if not fs:
        raise WrsimError(
            f"no value of the parameter sets ({', '.join(str(f) for f in files)}) has a tolerance; lay "
            f"a set with tolerances over them (e.g. params/tolerances/production.txt)"
        )
    bench = study_bench(spec.bench, spec.generics, spec.runs, spec.stop)
    check_runs(bench, base)
    identity = spec.identity(files)
    study = Study(spec, results / "study" / spec.folder_name, fs)
    stored = {} if fresh else _read(study)
    if stored and stored != identity:
        changed = sorted(k for k in identity if stored.get(k) != identity[k])
        raise WrsimError(
            f"{study.file}: made by another study (differs in: {', '.join(changed)}); give --name for a "
            f"new study or --fresh to replace it"
        )
    study.rows = {k: r for k, r in study.rows.items() if not r["error"]}  # failed samples run again
    workdir = paths.WORK / "study" / spec.folder_name

    def tasks(plan: list[tuple[int, str, dict[str, Value]]]) -> list[Task]:
        return [
            Task(
                spec.bench,
                i,
                label,
                values,
                sample_set(base, values, label),
                spec.generics,
                spec.runs,
                spec.stop,
                str(workdir),
                digest=library_digest(),
            )
            for i, label, values in plan
            if i not in study.rows
        ]

    _execute(study, identity, tasks(_plan(spec, fs)), workers, client, progress, on_result)
    if spec.method == "worst-case":
        offset = len(sensitivity_plan(fs))
        _execute(
            study, identity, tasks(_plan(spec, fs, offset, effects_of(study))), workers, client, progress, on_result
        )
    return study


def _execute(
    study: Study,
    identity: dict[str, Any],
    tasks: list[Task],
    workers: int | None,
    client: Any,
    progress: bool | None,
    on_result: Callable[[SampleResult], None] | None,
) -> None:
    """Run `tasks`, keeping each result in the study and its file (rewritten every few seconds and at the end,
    also when interrupted)."""
    from tqdm import tqdm

    results: Generator[SampleResult, None, None] = (
        execute_dask(tasks, client) if client is not None else execute_local(tasks, workers)
    )
    saved = time.monotonic()
    bar = tqdm(
        total=len(tasks), unit="sample", desc=study.spec.folder_name, disable=None if progress is None else not progress
    )
    try:
        with contextlib.closing(results):
            for result in results:
                study.rows[result.sample] = _row(result)
                for o in result.outputs:
                    study.outputs.setdefault(
                        o.name, {"unit": o.unit, "lower": o.lower, "upper": o.upper, "note": o.note}
                    )
                bar.update(1)
                bar.set_postfix(failed=len(study.failed()), refresh=False)
                if on_result is not None:
                    on_result(result)
                if time.monotonic() - saved > _SAVE_EVERY:
                    _save(study, identity)
                    saved = time.monotonic()
    finally:
        bar.close()
        if study.rows:
            _save(study, identity)


def rerun_sample(spec: StudySpec, sample: int, results: Path = paths.RESULTS) -> Path:
    """Run sample `sample` of the study again with the bench's judge, plots and waveforms, published as
    `<study folder>/reruns/sample-<id>/` (listed in reruns/index.html); returns that folder. When the judge cannot
    judge the sample (a glass that does not close), the page has every saved waveform and the judge's message."""
    from wrsim.backend.ngspice.batch import NgspiceBatch
    from wrsim.benches.core import Session, every_waveform, measurement_of, simulate_runs
    from wrsim.data.measurements import read_table
    from wrsim.data.publish import unique_folder
    from wrsim.elab.library import load_library
    from wrsim.report.results import write_bench_result, write_index
    from wrsim.results import BenchResult

    study, _ = read_study(spec, results)
    row = study.rows.get(sample)
    if row is None:
        ids = sorted(study.rows)
        raise WrsimError(
            f"study {spec.folder_name} has no sample {sample} ({study.file} holds "
            f"{f'{ids[0]} .. {ids[-1]}' if ids else 'none'})"
        )
    base, _ = study_params(spec)
    bench = study_bench(spec.bench, spec.generics, spec.runs, spec.stop)
    lib, runner, params = load_library(paths.LIBRARY), NgspiceBatch(), sample_set(base, row["values"], row["label"])
    workdir = unique_folder(paths.WORK / "study" / spec.folder_name / f"rerun-{sample}")
    sims, timings = simulate_runs(bench, lib, params, runner, workdir)
    csv = measurement_of(lib, bench.entity)
    description = f"{spec.folder_name}, sample {sample} ({row['label']}): {bench.description}"
    try:
        j = bench.judge(
            bench, sims, read_table(csv, require_source=True) if csv else None, Session(lib, params, runner, workdir)
        )
        waveforms, metrics, plots = j.waveforms, j.metrics, list(j.plots)
    except WrsimError as e:
        waveforms = every_waveform(sims, bench.stop)
        metrics, plots, description = [], [], f"{description}; the judge stopped: {e}"
    result = BenchResult(
        f"sample-{sample}", description, None, waveforms, metrics, plots, timings, all(m.passed for m in metrics)
    )
    folder = write_bench_result(study.folder / "reruns", result)
    write_index(study.folder / "reruns")
    return folder
