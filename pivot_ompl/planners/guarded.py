"""What our OMPL planners share: the crash guard and writing a solution path."""

from __future__ import annotations

import gc
import logging
from typing import Any

from ompl import base as ob
from ompl import geometric as og

from pivot_ompl.base.state import write_state
from pivot_ompl.errors import InputError
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)


class GuardedPlanner(ob.Planner):
    """An ``ob.Planner`` whose ``solve`` never lets an exception escape.

    An exception escaping a Python ``solve`` aborts a whole ``ompl.tools.Benchmark`` run: it
    is logged and reported as ``CRASH`` instead. Subclasses implement ``_solve(ptc)``.

    Python's cyclic garbage collector is paused during ``solve`` (and restored after): a
    full collection over a large roadmap took up to 80 ms, enough to overrun a 0.5 s time
    limit by 16 % when it fell at the end; the planners' data hold no reference cycles
    (measured: nothing to collect after a 15 s solve, and the same peak memory).
    """

    def __init__(self, si: ob.SpaceInformation, name: str) -> None:
        """The planner on ``si`` (:class:`InputError` naming ``si`` when it is not one)."""
        if not isinstance(si, ob.SpaceInformation):
            raise InputError("si", type(si).__name__, "must be an ompl.base.SpaceInformation")
        super().__init__(si, name)

    def clear(self) -> None:  # noqa: D102
        super().clear()

    def solve(self, ptc: Any) -> ob.PlannerStatus:  # noqa: D102
        collecting = gc.isenabled()
        gc.disable()
        try:
            return self._solve(ptc)
        except _NoQuery as e:
            return ob.PlannerStatus(e.status)
        except Exception:
            log.exception("%s crashed", self.getName())
            return ob.PlannerStatus(ob.PlannerStatus.CRASH)
        finally:
            if collecting:
                gc.enable()

    def _solve(self, ptc: Any) -> ob.PlannerStatus:
        raise NotImplementedError

    def _endpoints(self, ptc: Any) -> tuple[Any, Any]:
        """The query's start and goal states, read the safe way.

        Through ``PlannerInputStates``; never ``pdef.getStartState``, which hands the
        state's ownership to Python.
        """
        pis = self.getPlannerInputStates()
        start = pis.nextStart()
        if start is None:
            raise _NoQuery(ob.PlannerStatus.INVALID_START)
        goal = pis.nextGoal(ptc)
        if goal is None:
            raise _NoQuery(ob.PlannerStatus.INVALID_GOAL)
        return start, goal


class _NoQuery(Exception):  # noqa: N818 - internal control flow, never escapes solve()
    def __init__(self, status: Any) -> None:
        self.status = status


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
