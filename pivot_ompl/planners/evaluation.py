"""The planners' one evaluation of motions: each check answers valid, invalid or stopped.

The checker (:class:`~pivot_ompl.checking.pivot_checker.PivotChecker`) tells whether a pivot
transfer or a walk is collision-free, and the cost model (:class:`~pivot_ompl.cost.CostModel`)
what it costs. The planners (search, optimiser, lattice refinement, repair, the object
roadmap's visibility) ask both through :class:`Evaluator`, whose every answer is an
:class:`Evaluation` with a :class:`Status`:

* ``VALID``: the motion passes, with its cost (s);
* ``INVALID``: it does not, with the reason;
* ``STOPPED``: the termination condition stopped the check before it knew (nothing is
  cached: a later check computes it). As OMPL's ``PlannerStatus`` keeps ``TIMEOUT`` apart
  from ``INVALID``, a stopped check is never taken for a failed one, and no caller polls the
  stop condition again to tell the two apart.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Generic, TypeVar

from pivot_ompl.checking.pivot_checker import EdgeResult, PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose
from pivot_ompl.transit.planner import WalkResult

__all__ = ["Evaluation", "Evaluator", "Found", "Status", "lazy_search"]

Stop = Callable[[], bool]
State = tuple[Pose, int]
P = TypeVar("P")


class Status(enum.Enum):
    """What a check found: the motion passes, fails, or the check was stopped first."""

    VALID = "valid"
    INVALID = "invalid"
    STOPPED = "stopped"


@dataclass(frozen=True)
class Evaluation:
    """The answer of one check (a transfer, a walk, or a path of them).

    Attributes:
        status: valid, invalid or stopped.
        cost: seconds of the motion (:class:`~pivot_ompl.cost.CostModel`) when valid, else
            ``inf``.
        reason: why it is invalid, or what stopped (empty when valid).
        edge: the transfer's checked pivot sequence (a valid or invalid transfer).
        walk: the checked walk (a valid or invalid walk).
    """

    status: Status
    cost: float = math.inf
    reason: str = ""
    edge: EdgeResult | None = None
    walk: WalkResult | None = None

    @property
    def valid(self) -> bool:
        """The motion passes (``status is Status.VALID``)."""
        return self.status is Status.VALID


#: The answer of a check that was stopped.
STOPPED = Evaluation(Status.STOPPED, reason="stopped by the termination condition")


class Evaluator:
    """Checks transfers and walks with ``checker`` and prices them with ``costs``.

    Args:
        checker: the validity of motions (its caches make a repeated check free).
        costs: the cost model.
    """

    checker: PivotChecker
    costs: CostModel

    def __init__(self, checker: PivotChecker, costs: CostModel) -> None:
        """An evaluator over ``checker`` and ``costs``."""
        self.checker, self.costs = checker, costs

    def transfer(self, a: Pose, b: Pose, grasp: int, *, should_stop: Stop | None = None,
                 with_robot: bool = True) -> Evaluation:
        """The pivot transfer from object pose ``a`` to ``b`` at ``grasp``, priced."""
        try:
            e = self.checker.transfer(a, b, grasp, with_robot=with_robot,
                                      should_stop=should_stop)
        except Interrupted:
            return STOPPED
        if not e.valid:
            return Evaluation(Status.INVALID, reason=e.reason or "invalid transfer", edge=e)
        return Evaluation(Status.VALID, self.costs.sequence(e.sequence), edge=e)

    def walk(self, obj: Pose, from_grasp: int, to_grasp: int, *,
             should_stop: Stop | None = None) -> Evaluation:
        """The regrasp at object pose ``obj``: its walk, priced as a regrasp."""
        try:
            w = self.checker.transit(obj, from_grasp, to_grasp, should_stop=should_stop)
        except Interrupted:
            return STOPPED
        if not w.valid:
            return Evaluation(Status.INVALID, reason="no walk between the grasps", walk=w)
        return Evaluation(Status.VALID, self.costs.regrasp_seconds(w.length), walk=w)

    def step(self, a: State, b: State, *, should_stop: Stop | None = None) -> Evaluation:
        """The path edge from state ``a`` to ``b``: a transfer, or a regrasp at one pose."""
        (pa, ga), (pb, gb) = a, b
        if ga == gb:
            return self.transfer(pa, pb, ga, should_stop=should_stop)
        if pa != pb:
            return Evaluation(Status.INVALID, reason="a grasp change between two poses")
        return self.walk(pa, ga, gb, should_stop=should_stop)

    def path(self, states: Sequence[State], *, should_stop: Stop | None = None) -> Evaluation:
        """Every edge of ``states`` in order (:meth:`step`).

        Valid with the sum of their costs, or the first edge's answer that is not valid.
        """
        total = 0.0
        for a, b in zip(states, states[1:], strict=False):
            e = self.step(a, b, should_stop=should_stop)
            if not e.valid:
                return e
            total += e.cost
        return Evaluation(Status.VALID, total)


@dataclass(frozen=True)
class Found(Generic[P]):
    """The outcome of a lazy search (:func:`lazy_search`).

    Attributes:
        status: ``VALID``: ``path`` passed its checks; ``INVALID``: there is no path;
            ``STOPPED``: the termination condition stopped the search first.
        path: the path found (``None`` unless valid).
    """

    status: Status
    path: P | None = None


def lazy_search(cheapest: Callable[[], Found[P]], check: Callable[[P], Status],
                should_stop: Stop) -> Found[P]:
    """Search, check, remove, repeat: the lazy loop of the search and of the optimiser.

    ``cheapest()`` gives the cheapest path over the edges not known invalid (optimistic
    costs for the unchecked ones); ``check(path)`` checks its unchecked edges, recording
    what it learns (an invalid edge removed, a real cost in place of an estimate), and says
    ``VALID`` when the path stands as found, ``INVALID`` when it must be searched again, or
    ``STOPPED``. Runs until a path stands, none is left, or ``should_stop()``.
    """
    while not should_stop():
        found = cheapest()
        if found.status is not Status.VALID or found.path is None:
            return found
        status = check(found.path)
        if status is not Status.INVALID:
            return found if status is Status.VALID else Found(status)
    return Found(Status.STOPPED)
