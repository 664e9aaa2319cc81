"""OMPL planner statuses by name."""

from __future__ import annotations

from typing import Any


def status_name(status: Any) -> str:
    """The name of an OMPL ``PlannerStatus`` as its enum spells it (``EXACT_SOLUTION``)."""
    s = str(status)
    names = {"Exact solution": "EXACT_SOLUTION", "Approximate solution": "APPROXIMATE_SOLUTION",
             "Timeout": "TIMEOUT", "Invalid start": "INVALID_START",
             "Invalid goal": "INVALID_GOAL", "Crash": "CRASH", "Abort": "ABORT",
             "Infeasible": "INFEASIBLE", "Unknown status": "UNKNOWN",
             "Unrecognized goal type": "UNRECOGNIZED_GOAL_TYPE"}
    return names.get(s, s.upper().replace(" ", "_"))
