"""Tolerance studies: parameter spreads (data.params) sampled reproducibly (`sampling`), the samples run on local
processes or a Dask cluster (`engine`), results kept in a columnar file and resumable (`study`), a study's statistics
and page (`report`); the anti-pinch fleet score over drawn doors on replayed records (`fleet`) and the calibration
of an algorithm on it (`calibrate`)."""

from __future__ import annotations

from wrsim.study.engine import SampleResult, Task, execute_dask, execute_local, run_sample, study_bench
from wrsim.study.sampling import Factor, draw, factors, sample_set, sensitivity_plan, units, worst_case_plan
from wrsim.study.study import METHODS, Study, StudySpec, read_study, rerun_sample, run_study, study_params

__all__ = [
    "METHODS",
    "Factor",
    "SampleResult",
    "Study",
    "StudySpec",
    "Task",
    "draw",
    "execute_dask",
    "execute_local",
    "factors",
    "units",
    "read_study",
    "rerun_sample",
    "run_sample",
    "run_study",
    "sample_set",
    "sensitivity_plan",
    "study_bench",
    "study_params",
    "worst_case_plan",
]
