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

import logging
import os
import signal
import tempfile
import threading
from collections.abc import Iterable, Iterator
from concurrent.futures import ThreadPoolExecutor, as_completed
from typing import Any, Protocol

from pivot_ompl.bench.job import Job, JobResult, run_job
from pivot_ompl.bench.processes import JobProcesses
from pivot_ompl.errors import InputError, printable

log = logging.getLogger(__name__)

#: Seconds a stopped sweep waits for its Dask tasks to end once their processes are killed.
STOP_WAIT = 3.0


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
        cluster, scratch = None, None
        if self.scheduler:
            try:
                client = distributed.Client(self.scheduler, timeout="20s")
            except OSError as e:
                raise InputError("--scheduler", self.scheduler,
                                 f"cannot connect to a Dask scheduler ({e})") from None
        else:  # its scratch space ours, removed with it (Dask leaves its folder behind)
            import dask

            scratch = tempfile.TemporaryDirectory(prefix="pivot-bench-dask-",
                                                  ignore_cleanup_errors=True)
            with dask.config.set({"temporary-directory": scratch.name}):
                cluster = distributed.LocalCluster(
                    n_workers=self.workers, threads_per_worker=1, processes=True,
                    dashboard_address=None, local_directory=scratch.name)
            client = distributed.Client(cluster)
        futures: dict[Any, Job] = {}
        try:
            client.register_plugin(_job_plugin(distributed, own=cluster is not None),
                                   name="pivot-bench-jobs")
            for job in jobs:
                key = f"pivot-bench-{job.scene_name}-{job.label}-{job.seed}-{id(job):x}"
                futures[client.submit(_run_on_worker, job, key=key, pure=False)] = job
            for fut in distributed.as_completed(list(futures)):
                yield futures[fut], fut.result()
        finally:
            if any(not f.done() for f in futures):  # stopped: no job left running anywhere
                _stop_workers_jobs(client, list(futures))
            client.close()
            if cluster is not None:
                cluster.close()
            if scratch is not None:
                scratch.cleanup()


#: The running job processes of this process when it is a Dask worker (each job in a process
#: group of its own, as the local executor's): ended by :func:`_stop_jobs` when a sweep stops.
_worker_jobs = JobProcesses()


def _run_on_worker(job: Job) -> JobResult:
    """:func:`run_job` on a Dask worker, its process one of the worker's job processes."""
    return run_job(job, processes=_worker_jobs)


def _stop_jobs() -> int:
    """On a Dask worker: end its running job processes now; the number ended.

    Their ``run_job`` calls raise :class:`~pivot_ompl.errors.Interrupted` and remove their
    temporary folders; later sweeps get a fresh set.
    """
    global _worker_jobs
    stopped, _worker_jobs = _worker_jobs, JobProcesses()
    return stopped.close()


def _job_plugin(distributed: Any, *, own: bool) -> Any:
    """A worker plugin ending the worker's job processes when the worker closes.

    On workers of our own ``LocalCluster`` (``own``) it also leaves Ctrl-C to ``bench``: the
    terminal's SIGINT reaches the whole process group, and a worker that quit on it first
    would leave its jobs (each in a process group of its own) running.
    """

    class JobPlugin(distributed.WorkerPlugin):
        def setup(self, worker: Any) -> None:
            if own and threading.current_thread() is threading.main_thread():
                signal.signal(signal.SIGINT, signal.SIG_IGN)

        def teardown(self, worker: Any) -> None:
            _stop_jobs()

    return JobPlugin()


def _stop_workers_jobs(client: Any, futures: list[Any]) -> None:
    """Stop a sweep's Dask tasks: queued ones cancelled, every worker's job processes ended.

    Then the running tasks are waited for (a few seconds at most) so that their temporary
    folders are gone before the cluster closes.
    """
    import distributed

    client.cancel(futures)
    try:
        client.run(_stop_jobs)
        distributed.wait(futures, timeout=STOP_WAIT)
    except Exception as e:  # noqa: BLE001 - a lost worker or a timeout: close regardless
        log.warning("stopping the Dask jobs: %s", printable(str(e)))


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
