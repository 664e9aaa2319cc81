"""Planners: ours (``RegraspPlanner``, ``VisibilityPRM``) and OMPL's baselines, by name."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ompl import base as ob
from ompl import geometric as og

from ..errors import InputError
from .multiplex import RegraspParams
from .regrasp import RegraspPlanner
from .visibility import VisibilityPRM


def _ompl(cls: Any) -> Callable[[ob.SpaceInformation, int], Any]:
    def make(si: ob.SpaceInformation, seed: int) -> Any:
        return cls(si)
    return make


#: Planner name -> allocator ``(si, seed) -> planner``. OMPL's PRM is not listed: in the
#: ompl 2.0.1 wheel ``PRM::solve`` grows its roadmap on a C++ thread that calls our Python
#: validators while the calling thread holds the GIL, so it deadlocks (seen in bench runs).
PLANNERS: dict[str, Callable[[ob.SpaceInformation, int], Any]] = {
    "regrasp": lambda si, seed: RegraspPlanner(si, seed=seed),
    "visprm": lambda si, seed: VisibilityPRM(si, seed=seed),
    "rrtconnect": _ompl(og.RRTConnect),
    "rrt": _ompl(og.RRT),
    "rrtstar": _ompl(og.RRTstar),
    "kpiece1": _ompl(og.KPIECE1),
    "bkpiece1": _ompl(og.BKPIECE1),
}

#: Planners whose randomness comes from OMPL's global seed (``ompl.util.RNG.setSeed``).
OMPL_PLANNERS = frozenset(PLANNERS) - {"regrasp", "visprm"}


def make_planner(name: str, si: ob.SpaceInformation, *, seed: int = 0) -> Any:
    """Allocate planner ``name`` on ``si``.

    Raises:
        InputError: unknown planner name.
    """
    try:
        alloc = PLANNERS[name]
    except KeyError:
        raise InputError("planner", name, f"unknown planner (known: {sorted(PLANNERS)})") from None
    return alloc(si, seed)


__all__ = ["OMPL_PLANNERS", "PLANNERS", "RegraspParams", "RegraspPlanner", "VisibilityPRM",
           "make_planner"]
