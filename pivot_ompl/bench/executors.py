"""Executors of benchmark jobs: local processes (default) or a Dask cluster.

Every executor runs :func:`pivot_ompl.bench.job.run_job` (one fresh Python process per job)
and yields results as they complete, so results do not depend on the executor.

* :class:`LocalExecutor`: ``workers`` jobs at a time on this machine (default: the cores).
* :class:`DaskExecutor`: the jobs as tasks of a ``dask.distributed`` cluster: an existing
  scheduler (``scheduler="tcp://host:8786"``; every worker needs ``pivot_ompl`` installed) or,
  without an address, a ``LocalCluster`` of ``workers`` single-threaded worker processes.
  ``distributed`` is an optional dependency (``pip install pivot_ompl[dask]``).
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import Any, Protocol

from pivot_ompl.bench.job import Job, JobResult, run_job
from pivot_ompl.bench.processes import JobProcesses
from pivot_ompl.errors import InputError


class Executor(Protocol):
    """Runs jobs, yielding ``(job, result)`` pairs in completion order."""

    def run(self, jobs: Iterable[Job]) -> Iterator[tuple[Job, JobResult]]:
        """Run ``jobs``."""
        ...


def default_workers() -> int:
    """Return the number of cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


class LocalExecutor:
    """Run jobs as local processes, ``workers`` at a time.

    Args:
        workers: concurrent jobs (default: the number of usable cores).
    """

    def __init__(self, workers: int | None = None) -> None:
        """Create the executor."""
        self.workers = workers or default_workers()

    def run(self, jobs: Iterable[Job]) -> Iterator[tuple[Job, JobResult]]:
        """Run ``jobs``; stopped (Ctrl-C, SIGTERM, an error), every job process ends at once."""
        processes = JobProcesses()
        with ThreadPoolExecutor(max_workers=self.workers) as pool:
            futures = {pool.submit(run_job, job, processes=processes): job for job in jobs}
            try:
                for fut in as_completed(futures):
                    yield futures[fut], fut.result()
            finally:
                for fut in futures:
                    fut.cancel()
                processes.close()  # the running ones killed: the pool's threads end now


def _import_distributed() -> Any:
    try:
        import distributed
    except ImportError as e:
        raise InputError("--executor", "dask",
                         "needs the optional dependency 'distributed' "
                         "(pip install 'pivot_ompl[dask]')") from e
    return distributed


class DaskExecutor:
    """Run jobs on a Dask cluster (``dask.distributed``).

    Args:
        scheduler: address of an existing scheduler (``"tcp://host:8786"``); ``None`` starts a
            ``LocalCluster`` for the duration of :meth:`run`.
        workers: worker processes of the ``LocalCluster`` (default: the cores); ignored with
            a scheduler address.
    """

    def __init__(self, scheduler: str | None = None, workers: int | None = None) -> None:
        """Create the executor (checks that ``distributed`` is importable)."""
        _import_distributed()
        self.scheduler = scheduler
        self.workers = workers or default_workers()

    def run(self, jobs: Iterable[Job]) -> Iterator[tuple[Job, JobResult]]:  # noqa: D102
        distributed = _import_distributed()
        cluster = None
        if self.scheduler:
            try:
                client = distributed.Client(self.scheduler, timeout="20s")
            except OSError as e:
                raise InputError("--scheduler", self.scheduler,
                                 f"cannot connect to a Dask scheduler ({e})") from None
        else:
            cluster = distributed.LocalCluster(n_workers=self.workers, threads_per_worker=1,
                                               processes=True, dashboard_address=None)
            client = distributed.Client(cluster)
        try:
            futures = {}
            for job in jobs:
                key = f"pivot-bench-{job.scene_name}-{job.label}-{job.seed}-{id(job):x}"
                futures[client.submit(run_job, job, key=key, pure=False)] = job
            for fut in distributed.as_completed(list(futures)):
                yield futures[fut], fut.result()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()


def make_executor(kind: str = "local", *, scheduler: str | None = None,
                  workers: int | None = None) -> Executor:
    """Return an executor by name (``"local"`` or ``"dask"``).

    Raises:
        InputError: unknown kind, bad worker count, or ``distributed`` missing for ``"dask"``.
    """
    if workers is not None and workers < 1:
        raise InputError("--workers", workers, "must be >= 1")
    if kind == "local":
        if scheduler:
            raise InputError("--scheduler", scheduler, "needs --executor dask")
        return LocalExecutor(workers)
    if kind == "dask":
        return DaskExecutor(scheduler, workers)
    raise InputError("--executor", kind, "must be 'local' or 'dask'")
