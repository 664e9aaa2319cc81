"""The job processes of a sweep, ended together and at once when the sweep is stopped.

Each job process starts in a process group of its own (a new session): Ctrl-C at the terminal
reaches only ``bench``, which then ends every running job's group with SIGKILL
(:meth:`JobProcesses.close`) instead of waiting for the jobs to notice; a process that would
start after that is not started. ``bench`` also takes SIGTERM as an interruption
(:func:`terminate_as_interrupt`), so the same cleanup runs: no job is left running, no
temporary folder or partial output is left behind.
"""

from __future__ import annotations

import os
import signal
import subprocess
import threading
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from types import FrameType
from typing import Any

from pivot_ompl.errors import Interrupted


class JobProcesses:
    """The running job processes of one sweep (thread-safe)."""

    def __init__(self) -> None:
        """No process yet."""
        self._lock = threading.Lock()
        self._running: set[subprocess.Popen] = set()
        self.closed = False

    def run(self, cmd: Sequence[str], *, timeout: float,
            env: dict[str, str] | None = None) -> tuple[int | None, bytes]:
        """Run ``cmd`` in a new process group: its exit code and its stderr.

        The exit code is ``None`` when the process was killed at ``timeout`` s.

        Raises:
            Interrupted: the sweep was stopped (before or while the process ran).
        """
        with self._lock:
            if self.closed:
                raise Interrupted("the sweep")
            proc = subprocess.Popen(list(cmd), stdin=subprocess.DEVNULL,
                                    stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, env=env,
                                    start_new_session=True)
            self._running.add(proc)
        try:
            try:
                _, err = proc.communicate(timeout=timeout)
            except subprocess.TimeoutExpired:
                _kill(proc)
                _, err = proc.communicate()
                return None, err
            except BaseException:
                _kill(proc)
                proc.wait()
                raise
        finally:
            with self._lock:
                self._running.discard(proc)
        if self.closed:
            raise Interrupted("the sweep")
        return proc.returncode, err

    def close(self) -> int:
        """End every running job process group now; start no more. The number ended."""
        with self._lock:
            self.closed = True
            running = list(self._running)
        for proc in running:
            _kill(proc)
        return len(running)


def _kill(proc: subprocess.Popen) -> None:
    """SIGKILL ``proc``'s process group (it leads one), quietly when it is gone."""
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass


def _interrupt(signum: int, frame: FrameType | None) -> Any:
    raise KeyboardInterrupt


@contextmanager
def terminate_as_interrupt() -> Iterator[None]:
    """Inside the block (main thread only), SIGTERM raises ``KeyboardInterrupt`` as Ctrl-C."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)
