"""Helpers shared by our OMPL planners: writing a solution path into the problem definition."""

from __future__ import annotations

from typing import Any

from ompl import geometric as og

from ..se2 import Pose
from ..space import write_state


def states_to_path(planner: Any, states: list[tuple[Pose, int]], *,
                   approximate: bool = False) -> Any:
    """Add ``states`` as a ``PathGeometric`` solution of ``planner``'s problem definition."""
    si = planner.getSpaceInformation()
    path = og.PathGeometric(si)
    for pose, grasp in states:
        # the binding's append keeps the pointer (no copy): one fresh state each, owned by
        # the path from then on (never freed here)
        st = si.allocState()
        write_state(st, pose, grasp)
        path.append(st)
    pdef = planner.getProblemDefinition()
    pdef.addSolutionPath(path, approximate, 0.0, planner.getName())
    return path
