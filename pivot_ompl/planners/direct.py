"""The regrasp-free tries that end planning at once where one grasp suffices.

Before the object roadmap, its passages and the multiplexed graph are built, two cheap tries
look for a path that keeps one grasp from start to goal (a grasp valid at both ends, the held
one if the robot holds the box):

1. **RRT-Connect** at each such grasp (:class:`~.single_grasp.SingleGraspConnect`), within a
   budget of motion checks shared by the grasps: quick among few obstacles;
2. the held assembly's **lattice** (:class:`~.routes.lattice.TransferLattice`): the grasps
   in the order of their lower bounds (:meth:`~.routes.lattice.TransferLattice.lower_bound`),
   each one's cheapest lattice route until no grasp left can beat the cheapest found, then
   the routes cheapest first, each made real by the cheapest chain of certified transfers
   along it (:func:`~.routes.chain.made_real`); a route that is a detour of the floor's way
   (:meth:`~.routes.lattice.TransferLattice.way_bound`), which the lattice takes where it
   cannot turn in place, is left to the multiplexed search, whose curves do better. The
   lattice follows the connected free space (its components answer at once where start and
   goal are apart), so on a floor of rooms and passages drawn by thousands of wall pieces it
   finds the way the random trees get lost looking for.

Where a band round the floor's shortest way is given (:mod:`.corridor`), the lattice's try
over that band replaces the RRT-Connect's, and the whole lattice's try follows where it
finds nothing. Every transfer of a path returned passed its full check. The tries poll
``should_stop``.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.config import SingleGraspConfig
from pivot_ompl.planners.corridor import band_first
from pivot_ompl.planners.evaluation import Evaluator, Found, Status
from pivot_ompl.planners.routes.chain import made_real
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.single_grasp import SingleGraspConnect
from pivot_ompl.se2 import Pose

Stop = Callable[[], bool]
State = tuple[Pose, int]


@dataclass
class DirectStats:
    """Figures of the regrasp-free tries.

    Attributes:
        checks: motion checks of the RRT-Connect try.
        routes: lattice routes searched (one per grasp at most).
        solved_by: ``"rrt"``, ``"lattice"``, or ``""`` (not solved).
        seconds: time spent in both tries (s).
    """

    checks: int = 0
    routes: int = 0
    solved_by: str = ""
    seconds: float = 0.0


def rrt_path(checker: PivotChecker, start: Pose, goal: Pose, *, grasps: list[int],
             config: SingleGraspConfig, rng: np.random.Generator, should_stop: Stop,
             stats: DirectStats) -> Found[list[State]]:
    """RRT-Connect at each of ``grasps`` in turn, ``config.checks`` motion checks in all.

    ``VALID`` with the path's states, ``INVALID`` when the budget ran out, ``STOPPED``.
    """
    share = max(1, config.checks // len(grasps))
    for g in grasps:
        rrt = SingleGraspConnect(checker, start, goal, g, rng, step=config.step)
        found = rrt.run(share, should_stop)
        stats.checks += rrt.checks
        if found.status is Status.STOPPED:
            return Found(Status.STOPPED)
        if found.path is not None:
            return Found(Status.VALID, [(q, g) for q in found.path])
    return Found(Status.INVALID)


def lattice_path(checker: PivotChecker, lattice: TransferLattice, costs: CostModel,
                 start: Pose, goal: Pose, *, grasps: list[int], weight: float,
                 detour: float = math.inf, run_spacing: int, should_stop: Stop,
                 stats: DirectStats) -> Found[list[State]]:
    """The cheapest certified single-grasp path along a lattice route (module docstring).

    A grasp is routed only while its lower bound is below the cheapest route found so far;
    a route costing more than ``detour`` times the floor's way
    (:meth:`~.routes.lattice.TransferLattice.way_bound`) is left out (the lattice turns only
    in place: where that forces a detour, the curves of the multiplexed search do better);
    the routes are made real cheapest first. ``VALID`` with the path's states, ``INVALID``
    when no route of any grasp passes, ``STOPPED``.
    """
    def bound(g: int) -> float:
        return lattice.lower_bound(start, goal, g)

    evaluate = Evaluator(checker, costs)
    pending = sorted(grasps, key=bound)
    routed: list[tuple[float, int, list[Pose]]] = []
    try:
        while pending or routed:
            while pending and (not routed or bound(pending[0]) < min(routed)[0]):
                g = pending.pop(0)
                poses, cost = lattice.route(start, goal, g, should_stop=should_stop,
                                            weight=weight)
                stats.routes += 1
                if len(poses) >= 2 and math.isfinite(cost) and cost <= detour * \
                        lattice.way_bound(start, goal, g, should_stop=should_stop):
                    routed.append((cost, g, poses))
            if not routed:
                break
            best = min(routed)
            routed.remove(best)
            _, g, poses = best
            found = made_real(evaluate, poses, g, should_stop, spacing=run_spacing,
                              cache=lattice.chains)
            if found.status is Status.STOPPED:
                return Found(Status.STOPPED)
            if found.path is not None:
                return Found(Status.VALID, [(q, g) for q in found.path[0]])
    except Interrupted:
        return Found(Status.STOPPED)
    return Found(Status.INVALID)


def route_weight(config: SingleGraspConfig, area: float) -> float:
    """The lattice's heuristic inflation for a plan's routes on a floor of ``area`` m^2.

    Where the lattice try is made (``config.lattice``, ``area >= config.lattice_area``): its
    ``lattice_weight``, so the re-routing after it (:mod:`.routes.refine`) asks the same
    routes, found once, and searches the others expanding fewer states (the hall: 8 searches
    -> 4, the same plan). Elsewhere ``1``: the lattice's cheapest routes (on small floors the
    inflated routes made some plans dearer, open_fig7 by 11 %).
    """
    return config.lattice_weight if config.lattice and area >= config.lattice_area else 1.0


def direct_path(checker: PivotChecker, start: Pose, goal: Pose, *, grasps: list[int],
                config: SingleGraspConfig, costs: CostModel, rng: np.random.Generator,
                lattice: Callable[[], TransferLattice], run_spacing: int, should_stop: Stop,
                stats: DirectStats,
                band: Callable[[], TransferLattice | None] | None = None) -> list[State]:
    """A regrasp-free path by the two tries in turn (module docstring), or ``[]``.

    ``grasps``: those valid at both ends (and held, if one is). The RRT-Connect draws from its
    own generator (spawned from ``rng``, which it leaves as it was); ``lattice()`` gives the
    lattice, made when first asked (``config.lattice`` off: never). ``band()``, if given,
    a lattice over a band of the floor round its shortest way (:mod:`.corridor`; ``None``:
    no band): where there is one of at most :data:`~.corridor.FIRST_AREA`, its try replaces
    the RRT-Connect's (it finds the route the re-routing would take the RRT-Connect's path
    to, without the RRT-Connect's checks, which on a building's floor often find nothing);
    a longer band's try follows the RRT-Connect's, and the whole lattice's try follows where
    it finds nothing. ``run_spacing``: as :func:`lattice_path`'s.
    """
    if not grasps:
        return []
    t0 = time.perf_counter()

    def lattice_try(over: TransferLattice) -> Found[list[State]]:
        found = lattice_path(checker, over, costs, start, goal, grasps=grasps,
                             weight=config.lattice_weight, detour=config.lattice_detour,
                             run_spacing=run_spacing, should_stop=should_stop, stats=stats)
        stats.solved_by = "lattice" if found.path else ""
        return found

    try:
        found: Found[list[State]] = Found(Status.INVALID)
        over = band() if band is not None and config.lattice else None
        first = over is not None and band_first(over)
        if first:
            assert over is not None
            found = lattice_try(over)
        if not first and config.checks > 0:
            found = rrt_path(checker, start, goal, grasps=grasps, config=config,
                             rng=rng.spawn(1)[0], should_stop=should_stop, stats=stats)
            stats.solved_by = "rrt" if found.path else ""
        if found.status is Status.INVALID and config.lattice and over is not None and not first:
            found = lattice_try(over)
        if found.status is Status.INVALID and config.lattice:
            found = lattice_try(lattice())
        return found.path or []
    finally:
        stats.seconds += time.perf_counter() - t0
