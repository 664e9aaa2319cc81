"""Benchmarks of our planners beside OMPL's, in OMPL's own formats.

* :mod:`.job`: one (scene, planner, seed) run under ``ompl.tools.Benchmark`` in a fresh process.
* :mod:`.executors`: local processes (default) or a Dask cluster.
* :mod:`.ompl_log`: OMPL's benchmark log format (reader and byte-compatible writer).
* :mod:`.database`: the ``ompl_benchmark_statistics`` SQLite database.
* :mod:`.summary`, :mod:`.plots`, :mod:`.progress`: table, PNG plots, progress bar.
* :mod:`.sweep`: the whole sweep (``pivot-ompl bench``, :mod:`.cli`).
"""

from __future__ import annotations

from pivot_ompl.bench.database import build_database, run_columns
from pivot_ompl.bench.executors import DaskExecutor, LocalExecutor, make_executor
from pivot_ompl.bench.job import Job, JobResult, execute, run_extras, run_job
from pivot_ompl.bench.ompl_log import STATUS, STATUS_NAMES, ExperimentLog, PlannerResults, parse_log
from pivot_ompl.bench.summary import Row, format_table, summarize
from pivot_ompl.bench.sweep import SweepResult, make_jobs, run_sweep

__all__ = [
    "STATUS", "STATUS_NAMES", "DaskExecutor", "ExperimentLog", "Job", "JobResult",
    "LocalExecutor", "PlannerResults", "Row", "SweepResult", "build_database", "execute",
    "format_table", "make_executor", "make_jobs", "parse_log", "run_columns", "run_extras",
    "run_job", "run_sweep", "summarize",
]
