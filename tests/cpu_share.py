"""Runs whose premise is a share of a core: the time limit scaled to the CPU the process got.

A plan's time limit and its schedule (when the late proof begins and ends) run on the wall
clock. On a machine loaded by other processes, a run gets a share of a core and its proof
may not fit the limit: the run then ends ``TIMEOUT``, which tells nothing about the code.
:func:`with_cpu_limit` runs again with the limit divided by the share the failed run got
(what the whole core would have done in the limit), while that share was below
:data:`WHOLE`; on a machine that gave the run its core, the first run is the one asserted.
The assertions stay the test's own, on the last run and the limit it had.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import TypeVar

R = TypeVar("R")

#: A run that got at least this share of a core had its limit's worth of CPU: not run again.
WHOLE = 0.8
#: Most runs, and the largest factor the limit is scaled by.
RUNS, MOST = 3, 10.0


def with_cpu_limit(run: Callable[[float], R], limit: float,
                   done: Callable[[R, float, float], bool], *,
                   wall: Callable[[], float] = time.monotonic,
                   cpu: Callable[[], float] = time.process_time) -> tuple[R, float, float]:
    """``run(limit)`` until ``done(result, took, limit)``, the limit scaled by the CPU share.

    ``took``: the run's wall seconds. Returns the last run's ``(result, took, limit)``; a run
    that got :data:`WHOLE` of a core or more, or the :data:`RUNS`-th, is the last whatever
    ``done`` says (the caller's assertions then fail on it).
    """
    now = limit
    for k in range(RUNS):
        w0, c0 = wall(), cpu()
        out = run(now)
        took, used = wall() - w0, cpu() - c0
        share = used / took if took > 0 else 1.0
        if done(out, took, now) or share >= WHOLE or k == RUNS - 1:
            break
        now = min(MOST * limit, max(now, limit / max(share, 1.0 / MOST)))
    return out, took, now
