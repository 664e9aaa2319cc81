"""A planner's solve within the time left, stopped once to ask whether any plan exists.

Our regrasp planner polls the late proof (:class:`~pivot_ompl.analysis.late_proof.LateProof`)
itself while it has no path. OMPL's planners (RRTConnect, KPIECE1, ...) run in C++ and poll
nothing of ours, so on a scene without any plan they would run to the limit. Their solve is
therefore cut in two at the proof's ``begin``: OMPL's planners keep their trees between two
``solve`` calls, so the second stage goes on where the first stopped, and a path found in the
first stage ends the solve as before. Between the stages, still without an exact path, the
proof is asked once; when it proves that no plan exists the solve ends there (the caller
reads the proof).
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from typing import Any

from pivot_ompl.base.status import status_name

log = logging.getLogger(__name__)

#: Least time (s) left after the setup for which the search still starts.
MIN_SOLVE_TIME = 1e-3
#: Statuses after which a first stage goes on (no exact path yet, nothing wrong).
GOES_ON = frozenset({"TIMEOUT", "APPROXIMATE_SOLUTION"})


def solve_staged(ss: Any, time_limit: float, started: float, *,
                 proof: Callable[[], bool] | None = None, ask_at: float = float("inf"),
                 clock: Callable[[], float] = time.monotonic) -> str:
    """Solve ``ss`` (an OMPL ``SimpleSetup``) within what is left of ``time_limit``; the status.

    Args:
        ss: the problem, its planner set.
        time_limit: seconds from ``started`` (on ``clock``) within which the solve ends.
        started: when the time limit started counting.
        proof: asked once, at ``ask_at``, when the solve has no exact path then: ``True``
            ends the solve (no plan exists); ``None``: one stage only.
        ask_at: the clock time at which the first stage stops to ask ``proof``.
        clock: the clock of ``started`` and ``ask_at``.

    Returns:
        OMPL's status name; ``TIMEOUT`` when the setup left no time to solve.
    """
    left = time_limit - (clock() - started)
    if left <= MIN_SOLVE_TIME:
        log.warning("setup took the whole %.4g s limit: no time left to solve", time_limit)
        return "TIMEOUT"
    first = ask_at - clock()
    if proof is None or first >= left:
        return status_name(ss.solve(left))
    name = status_name(ss.solve(first)) if first > MIN_SOLVE_TIME else "TIMEOUT"
    if name not in GOES_ON or proof():
        return name
    left = time_limit - (clock() - started)
    return status_name(ss.solve(left)) if left > MIN_SOLVE_TIME else name
