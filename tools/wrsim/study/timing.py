"""How fast studies run (`wrsim bench --study`, `make bench-study`): the 1000-sample open-loop stroke study, the
100-sample closed-loop pinch study, and samples per second of one stroke study on the local pool and on a Dask
LocalCluster with 1 and 2 workers."""

from __future__ import annotations

import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

from wrsim import paths
from wrsim.study.engine import local_cluster
from wrsim.study.report import write_study_page
from wrsim.study.study import StudySpec, run_study

__all__ = ["StudyTiming", "STUDIES", "SCALING", "time_studies"]

_TOLERANCES = ("tolerances/production", "tolerances/ambient")
STUDIES = (
    StudySpec("stroke", _TOLERANCES, samples=1000, seed=1, stop=8.0, name="stroke-1000"),
    StudySpec("pinch", ("antipinch/observer", "tolerances/production"), samples=100, seed=1, name="pinch-100"),
)
SCALING = StudySpec("stroke", _TOLERANCES, samples=40, seed=2, stop=8.0, name="stroke-scaling")


@dataclass(frozen=True)
class StudyTiming:
    """One timed study: where it ran, how many samples, the wall time."""

    study: str
    executor: str  # "local" or "dask"
    workers: int
    samples: int
    failed: int
    wall: float  # [s]

    @property
    def per_second(self) -> float:
        return self.samples / self.wall


def _timed(spec: StudySpec, executor: str, workers: int, results: Path) -> StudyTiming:
    t0 = time.perf_counter()
    if executor == "dask":
        from distributed import Client

        with local_cluster(workers) as cluster, Client(cluster) as client:
            study = run_study(spec, results, client=client, fresh=True)
    else:
        study = run_study(spec, results, workers=workers, fresh=True)
    wall = time.perf_counter() - t0
    write_study_page(study)
    return StudyTiming(spec.folder_name, executor, workers, len(study.rows), len(study.failed()), wall)


def time_studies(results: Path = paths.RESULTS, scaling_only: bool = False) -> Iterator[StudyTiming]:
    """Time the scaling study on the local pool and on Dask with 1 and 2 workers, then (unless `scaling_only`) the
    1000-sample stroke and the 100-sample pinch study on the local pool (2 processes), each as it finishes; each
    starts afresh and leaves its results and page in `results`/study/. Dask's times include starting the
    cluster."""
    for executor in ("local", "dask"):
        for workers in (1, 2):
            yield _timed(SCALING, executor, workers, results)
    for spec in () if scaling_only else STUDIES:
        yield _timed(spec, "local", 2, results)
