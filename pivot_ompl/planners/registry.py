"""Planner names: ours (``regrasp``, ``visprm``) and OMPL's baselines on the same space."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ompl import base as ob
from ompl import geometric as og

from pivot_ompl.base.problem import PivotProblem
from pivot_ompl.errors import InputError
from pivot_ompl.planners.regrasp import RegraspPlanner
from pivot_ompl.planners.visprm import VisibilityPRM

#: An allocator: ``(problem, seed) -> planner`` on ``problem.si``.
Allocator = Callable[[PivotProblem, int], ob.Planner]


def _ompl(cls: Any) -> Allocator:
    def make(problem: PivotProblem, seed: int) -> ob.Planner:
        return cls(problem.si)
    return make


#: Planner name -> allocator.
PLANNERS: dict[str, Allocator] = {
    "regrasp": lambda problem, seed: RegraspPlanner(problem.si, problem.checker, seed=seed),
    "visprm": lambda problem, seed: VisibilityPRM(problem.si, seed=seed),
    "rrtconnect": _ompl(og.RRTConnect),
    "rrt": _ompl(og.RRT),
    "rrtstar": _ompl(og.RRTstar),
    "kpiece1": _ompl(og.KPIECE1),
    "bkpiece1": _ompl(og.BKPIECE1),
}

#: OMPL planners refused, with the reason (``make_planner`` raises ``InputError``: exit 2).
REFUSED: dict[str, str] = {
    name: ("OMPL's PRM grows its roadmap on a C++ thread that calls our Python validators "
           "while the calling thread holds the GIL: in the ompl 2.0.1 wheel it deadlocks. "
           "Use 'visprm' (a visibility PRM) or 'regrasp'.")
    for name in ("prm", "prmstar")}

#: Planners whose randomness comes from OMPL's global seed (``ompl.util.RNG.setSeed``).
OMPL_PLANNERS = frozenset(PLANNERS) - {"regrasp", "visprm"}


def make_planner(name: str, problem: PivotProblem, *, seed: int = 0) -> ob.Planner:
    """Allocate planner ``name`` on ``problem``.

    Raises:
        InputError: unknown or refused planner name (the message gives the reason).
    """
    check_planner_name(name)
    return PLANNERS[name](problem, seed)


def check_planner_name(name: str) -> str:
    """Return ``name`` if it is a usable planner, else raise :class:`InputError` saying why."""
    if name in REFUSED:
        raise InputError("planner", name, f"refused: {REFUSED[name]}")
    if name not in PLANNERS:
        raise InputError("planner", name, f"unknown planner (known: {sorted(PLANNERS)})")
    return name
