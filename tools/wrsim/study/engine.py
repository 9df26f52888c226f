"""Running a study's samples: one task per sample (`run_sample`, the same function in every executor), executed in
a local process pool on all cores or on a Dask cluster, results kept in the study's columnar file as they arrive.

A sample's run is self-contained: the task carries the sampled parameter set, the worker loads the model library
once per process and checks it is the one the study was planned with. A sample that fails (the glass never
reaches the top, the simulator gives up) is recorded with its error and the study goes on; a worker lost mid-study
costs only its samples, which run again (Dask's scheduler does that on a cluster; here the pool is rebuilt)."""

from __future__ import annotations

import concurrent.futures
import dataclasses
import functools
import hashlib
import multiprocessing
import os
import shutil
import socket
import tempfile
import time
import traceback
from collections.abc import Generator, Iterable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from wrsim import paths
from wrsim.backend.ngspice.batch import NgspiceBatch
from wrsim.backend.ngspice.netlist import compiled_default, compiled_setting
from wrsim.benches import BENCHES
from wrsim.benches.core import Bench, Output, Run, Session, Simulated, measurement_of, simulate_runs
from wrsim.data.measurements import read_table
from wrsim.data.params import ParamSet, Value
from wrsim.elab.elaborate import elaborate
from wrsim.elab.library import Library, load_library
from wrsim.errors import WrsimError

__all__ = [
    "Task",
    "SampleResult",
    "study_bench",
    "run_sample",
    "execute_local",
    "execute_dask",
    "local_cluster",
    "library_digest",
    "check_runs",
]

RETRIES = 2  # a sample whose worker is lost runs again this many times before it is recorded as failed


@dataclass(frozen=True)
class Task:
    """One sample to run: the bench (its runs with `generics` laid over theirs, only the runs `runs` names when
    any, `stop` instead of the bench's end), the sampled parameter set, and where to work."""

    bench: str
    sample: int
    label: str
    values: dict[str, Value]
    params: ParamSet
    generics: tuple[tuple[str, float], ...] = ()
    runs: tuple[str, ...] = ()
    stop: float | None = None
    workdir: str = ""  # its run folders go below it and are removed once the outputs are read
    digest: str = ""  # library_digest() of the planning process ("": not checked)
    # compiled models: the setting of the process that makes the task (WRSIM_COMPILE), which a remote worker lacks
    compiled: bool = field(default_factory=compiled_default)


@dataclass
class SampleResult:
    """What one sample produced: its outputs, or the error that stopped it."""

    sample: int
    label: str
    values: dict[str, Value]
    outputs: list[Output]
    error: str = ""
    seconds: float = 0.0
    worker: str = ""

    @property
    def ok(self) -> bool:
        return not self.error


def study_bench(
    name: str, generics: Iterable[tuple[str, float]] = (), runs: tuple[str, ...] = (), stop: float | None = None
) -> Bench:
    """The bench `name` as a study runs it: only the runs labelled `runs` (all when empty), the top-level
    `generics` laid over each run's, `stop` instead of the bench's end."""
    if name not in BENCHES:
        raise WrsimError(f"unknown bench '{name}' (benches: {', '.join(BENCHES)})")
    bench = BENCHES[name]
    unknown = [r for r in runs if r not in {run.label for run in bench.runs}]
    if unknown:
        raise WrsimError(f"bench {name} has no run '{unknown[0]}' (runs: {', '.join(r.label for r in bench.runs)})")
    extra = dict(generics)
    selected = tuple(Run(r.label, {**r.generics, **extra}, r.params) for r in bench.runs if not runs or r.label in runs)
    return dataclasses.replace(bench, runs=selected, stop=stop or bench.stop)


@functools.lru_cache(maxsize=1)
def _library() -> Library:
    return load_library(paths.LIBRARY)


@functools.lru_cache(maxsize=1)
def library_digest() -> str:
    """A digest of the model library's files (VHDL and C), to tell a worker with another checkout."""
    h = hashlib.sha256()
    for root in paths.LIBRARY:
        for f in sorted(Path(root).rglob("*")):
            if f.is_file() and f.suffix in (".vhd", ".c", ".h"):
                h.update(str(f.relative_to(root)).encode() + b"\0" + f.read_bytes())
    return h.hexdigest()[:16]


def check_runs(bench: Bench, params: ParamSet) -> None:
    """Elaborate every run of `bench` with `params` (the nominal set): a user error shows here, before any
    sample runs."""
    lib = _library()
    with tempfile.TemporaryDirectory() as tmp:
        for run in bench.runs:
            elaborate(lib, bench.entity, run.parameters(params), run.resolved(Path(tmp) / run.label))


def _outputs(bench: Bench, sims: list[Simulated], params: ParamSet, folder: Path) -> list[Output]:
    """The bench's outputs, or its judge's metrics with reference -+ tolerance as limits."""
    if bench.outputs is not None:
        return bench.outputs(bench, sims)
    csv = measurement_of(_library(), bench.entity)
    table = read_table(csv, require_source=True) if csv else None
    metrics = bench.judge(bench, sims, table, Session(_library(), params, NgspiceBatch(), folder)).metrics
    return [
        Output(m.name, m.value, m.unit, m.reference - m.tolerance, m.reference + m.tolerance, m.note) for m in metrics
    ]


def run_sample(task: Task) -> SampleResult:
    """Simulate one sample and return its outputs; every failure is recorded in the result, never raised."""
    t0 = time.perf_counter()
    worker = f"{socket.gethostname()}:{os.getpid()}"
    folder = Path(task.workdir) / f"sample_{task.sample:06d}"
    shutil.rmtree(folder, ignore_errors=True)  # what a lost worker left of this sample
    outputs: list[Output] = []
    try:
        if task.digest and task.digest != library_digest():
            raise WrsimError(
                f"worker {worker}: its model library ({paths.ROOT}) differs from the study's (another "
                f"checkout?): digest {library_digest()} vs {task.digest}"
            )
        bench = study_bench(task.bench, task.generics, task.runs, task.stop)
        with compiled_setting(task.compiled):
            sims, _ = simulate_runs(bench, _library(), task.params, NgspiceBatch(), folder, parallel=1)
        outputs = _outputs(bench, sims, task.params, folder)
        error = ""
    except WrsimError as e:
        error = str(e)
    except Exception as e:  # noqa: BLE001 - a defect in one sample must not stop the study
        error = f"internal error: {type(e).__name__}: {e} | " + " ".join(traceback.format_exception(e)[-3:])
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    return SampleResult(task.sample, task.label, task.values, outputs, error, time.perf_counter() - t0, worker)


def _lost(task: Task, why: str) -> SampleResult:
    return SampleResult(task.sample, task.label, task.values, [], f"worker lost: {why}")


def execute_local(tasks: list[Task], workers: int | None = None) -> Generator[SampleResult, None, None]:
    """Run `tasks` in a pool of `workers` processes (default: one per core), yielding results as they finish. A
    worker that dies breaks the pool: the samples not finished run again in a new one (at most RETRIES times)."""
    pending = {t.sample: t for t in tasks}
    attempts = dict.fromkeys(pending, 0)
    workers = workers or os.cpu_count() or 1
    while pending:
        pool = concurrent.futures.ProcessPoolExecutor(
            min(workers, len(pending)), mp_context=multiprocessing.get_context("forkserver")
        )
        try:
            futures = [pool.submit(run_sample, t) for t in pending.values()]
            for f in concurrent.futures.as_completed(futures):
                try:
                    result = f.result()
                except concurrent.futures.process.BrokenProcessPool:
                    continue
                del pending[result.sample]
                yield result
        finally:  # also when the study stops early (an interrupt): the samples not started are dropped
            pool.shutdown(wait=True, cancel_futures=True)
        for sample in list(pending):
            attempts[sample] += 1
            if attempts[sample] > RETRIES:
                yield _lost(pending.pop(sample), f"its process died {RETRIES + 1} times")


def local_cluster(workers: int) -> Any:
    """A Dask LocalCluster of `workers` single-threaded processes, quiet (no dashboard, errors only), to run a
    study's samples on."""
    import logging

    from distributed import LocalCluster

    return LocalCluster(
        n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None, silence_logs=logging.ERROR
    )


def execute_dask(tasks: list[Task], client: Any) -> Generator[SampleResult, None, None]:
    """Run `tasks` on the Dask cluster of `client`, yielding results as they finish. The scheduler runs again the
    samples of a worker it loses; a sample that kills its worker each time ends as KilledWorker, recorded."""
    from distributed import as_completed
    from distributed.scheduler import KilledWorker

    futures = {client.submit(run_sample, t, pure=False): t for t in tasks}
    for f in as_completed(list(futures)):
        try:
            yield f.result()
        except KilledWorker as e:
            yield _lost(futures[f], str(e))
