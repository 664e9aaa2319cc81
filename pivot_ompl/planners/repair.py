"""Local repair of a plan's route from an observed state (replanning without a search).

A route is the path of ``(object pose, grasp)`` states a plan was made of (a plan's ``route``
field): consecutive states of one grasp are a transfer edge, a grasp change at one pose a walk.
When the box is observed off the route (a drift, a slip) or the obstacles changed,
:func:`repair_route` keeps what it can of the route:

1. every edge of the route from the observed pose's nearest point on is checked against the
   scene as it is now (:class:`~pivot_ompl.checking.pivot_checker.PivotChecker`, as a fresh
   plan's edges are; a warm checker answers from its cache);
2. join points are taken along the route's transfer edges (every ``repair.join_step`` m of their
   Reeds-Shepp paths, and the route's states); the nearest (box centres) to the observed pose
   marks the progress made, and joins are tried from it on, in route order;
3. the first join point, from the nearest on and at most :data:`JOIN_AHEAD` m further along
   the route, after the last edge the change made invalid, that the box can be pivoted to
   directly from the observed pose (one checked transfer edge) gives the repaired route: the
   join edge, the rest of the join point's edge (checked), and the route's edges after it;
   then a few joins the cheap filter refused and a few behind the nearest point (a box that
   slipped into a corner backs up);
4. when no direct join passes, a short RRT-Connect at the join point's grasp
   (:class:`~pivot_ompl.planners.single_grasp.SingleGraspConnect`, ``repair.detour_checks``
   motion checks) to each of a few join points further on gives the detour.

It gives up (``INVALID``) when no join point qualifies: the caller plans afresh. No edge is kept
unchecked against the current obstacles, and the route ends where it ended (the goal).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.evaluation import Evaluator, Found, Status
from pivot_ompl.planners.improve import Budget, improve
from pivot_ompl.planners.repair_config import RepairConfig
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.single_grasp import SingleGraspConnect
from pivot_ompl.se2 import Pose

log = logging.getLogger(__name__)

State = tuple[Pose, int]
Stop = Callable[[], bool]
STOPPED: Found[RouteRepair] = Found(Status.STOPPED)

#: How far along the route (m) past the nearest join point joins are tried.
JOIN_AHEAD = 3.0
#: Direct joins refused by the cheap filter (:meth:`PivotChecker.path_free`) checked anyway,
#: nearest first.
REFUSED_CHECKED = 6
#: A join point this close (m and rad) to the observed pose is the observed pose itself.
SAME_POSE = 1e-9


@dataclass(frozen=True)
class JoinPoint:
    """A point of the route: ``pose`` at ``grasp`` on edge ``edge`` at fraction ``t``.

    The repaired route from it is ``(pose, grasp)``, then ``route[edge + 1:]``; ``t == 1``
    (the state ``route[edge + 1]`` itself) needs no checked rest of the edge.
    """

    edge: int
    t: float
    pose: Pose
    grasp: int
    along: float  # route length (m) from the route's start to this point


@dataclass(frozen=True)
class RouteRepair:
    """The outcome of :func:`repair_route`.

    Attributes:
        states: the repaired route, from the observed state to the route's end.
        joined: the route edge whose point the observed pose was joined to.
        tried: join edges checked (the direct transfers tried).
        kept_edges: edges of the old route kept (checked against the current scene).
    """

    states: list[State]
    joined: int
    tried: int
    kept_edges: int


def route_of(states: Sequence[Sequence[float]]) -> list[State]:
    """A route from its stored form, ``[[x, y, yaw, grasp], ...]``."""
    return [((float(s[0]), float(s[1]), float(s[2])), int(s[3])) for s in states]


def stored_route(route: Sequence[State]) -> list[list[float]]:
    """The route as the plan file stores it, ``[[x, y, yaw, grasp], ...]``."""
    return [[q[0], q[1], q[2], g] for q, g in route]


def join_points(checker: PivotChecker, route: Sequence[State], *,
                step: float = RepairConfig.join_step,
                should_stop: Stop | None = None) -> list[JoinPoint] | None:
    """Points along the route's transfer edges every ``step`` m, in route order.

    ``None`` when ``should_stop()`` became true (polled every 256 edges: a route of
    200 000 states is walked within a time limit).
    """
    m, paths = checker.model, checker.steering.paths
    out = [JoinPoint(-1, 1.0, route[0][0], route[0][1], 0.0)] if route else []
    along = 0.0
    for i, ((qa, ga), (qb, gb)) in enumerate(zip(route, route[1:], strict=False)):
        if should_stop is not None and i % 256 == 255 and should_stop():
            return None
        if ga != gb:  # a walk at one pose: its end is a join point at the new grasp
            out.append(JoinPoint(i, 1.0, qb, gb, along))
            continue
        ca, cb = m.car_pose(qa, ga), m.car_pose(qb, ga)
        length = paths.distance(ca, cb)
        n = max(1, math.ceil(length / step))
        ts = [k / n for k in range(1, n)]
        for t, car in zip(ts, paths.sample(ca, cb, ts), strict=True):
            out.append(JoinPoint(i, t, m.object_from_car(car, ga), ga, along + t * length))
        along += length
        out.append(JoinPoint(i, 1.0, qb, gb, along))
    return out


def repair_route(checker: PivotChecker, route: Sequence[State], box: Pose,
                 grasp: int | None = None, *, should_stop: Stop | None = None,
                 ahead: float = JOIN_AHEAD, seed: int = 0,
                 config: RepairConfig | None = None) -> Found[RouteRepair]:
    """The route repaired from the box observed at ``box`` (see the module docstring).

    Args:
        checker: the checker of the scene as it is now (obstacles changed included).
        route: the old route; its last state is the goal.
        box: the observed object pose.
        grasp: the grasp the robot holds the box with: join points at it are preferred
            (the nearest is sought among them when the route has any); ``None``: any.
        should_stop: polled between checks and passed to them.
        ahead: how far along the route past the nearest join point joins are tried (m).
        seed: seed of the short searches' generator.
        config: the repair's parameters (join step, detours; default ``RepairConfig()``).

    Returns:
        ``VALID`` with the repaired route; ``INVALID`` when no join point qualifies (or
        the box is not free at ``box``); ``STOPPED``.
    """
    stop = should_stop or (lambda: False)
    evaluate = Evaluator(checker, CostModel())
    route = list(route)
    if len(route) < 2 or not checker.box_valid(box):
        return Found(Status.INVALID)
    cfg = config or RepairConfig()
    points = join_points(checker, route, step=cfg.join_step, should_stop=stop)
    if points is None:
        return Found(Status.STOPPED)
    m, paths = checker.model, checker.steering.paths
    held = [p for p in points if p.grasp == grasp] if grasp is not None else []

    def gap(p: JoinPoint) -> float:
        return paths.distance(m.car_pose(box, p.grasp), m.car_pose(p.pose, p.grasp))

    nearest = min(held or points, key=lambda p: math.hypot(p.pose[0] - box[0],
                                                           p.pose[1] - box[1]))
    first = nearest.edge + 1  # the first route state kept
    last_invalid = first - 1
    for i in range(max(0, first), len(route) - 1):
        if stop():
            return STOPPED
        status = evaluate.step(route[i], route[i + 1], should_stop=stop).status
        if status is Status.STOPPED:
            return STOPPED
        if status is Status.INVALID:
            last_invalid = i
    past = [p for p in points if p.along >= nearest.along and p.edge >= last_invalid]
    ahead_of = [p for p in past if p.along <= past[0].along + ahead] if past else []
    tried = 0
    refused: list[JoinPoint] = []
    for p in ahead_of:  # direct joins, nearest first, those the cheap filter passes
        if stop():
            return STOPPED
        at_join = gap(p) <= SAME_POSE
        if not at_join and not checker.path_free(box, p.pose, p.grasp):
            refused.append(p)
            continue
        tried += 1
        rep = _joined(evaluate, route, box, [box, p.pose], p, stop, tried, at_join)
        if rep.status is not Status.INVALID:
            return rep
    behind = [p for p in reversed(points) if nearest.along - ahead <= p.along < nearest.along
              and p.edge >= last_invalid]
    for p in refused[:REFUSED_CHECKED] + behind[:REFUSED_CHECKED]:
        # the filter may refuse an edge that passes; a box stuck ahead may have to back up
        if stop():
            return STOPPED
        tried += 1
        rep = _joined(evaluate, route, box, [box, p.pose], p, stop, tried, False)
        if rep.status is not Status.INVALID:
            return rep
    rng = np.random.default_rng(seed)
    for p in _detour_targets(ahead_of, cfg):  # short searches at the route's grasp
        if stop():
            return STOPPED
        rrt = SingleGraspConnect(checker, box, p.pose, p.grasp, rng)
        found = rrt.run(cfg.detour_checks, stop)
        tried += rrt.checks
        if found.status is Status.STOPPED:
            return STOPPED
        if found.path is not None:
            rep = _joined(evaluate, route, box, found.path, p, stop, tried, False)
            if rep.status is not Status.INVALID:
                return rep
    log.info("route not repaired: no join point within %.1f m (%d join edges checked, "
             "last invalid edge %d)", ahead, tried, last_invalid)
    return Found(Status.INVALID)


def _detour_targets(points: Sequence[JoinPoint], cfg: RepairConfig) -> list[JoinPoint]:
    """Join points ``cfg.detour_spacing`` m apart along the route after the first of ``points``.

    ``cfg.detour_targets`` of them at most.
    """
    out: list[JoinPoint] = []
    for p in points:
        if not out or p.along >= out[-1].along + cfg.detour_spacing:
            out.append(p)
    return out[1:cfg.detour_targets + 1] if len(out) > 1 else out


def _joined(evaluate: Evaluator, route: Sequence[State], box: Pose, poses: Sequence[Pose],
            p: JoinPoint, stop: Stop, tried: int, at_join: bool) -> Found[RouteRepair]:
    """The route joined at ``p`` through ``poses`` (box first, ``p.pose`` last).

    Every edge of ``poses`` and the rest of ``p``'s edge are checked (``INVALID`` when one
    fails, ``STOPPED``); ``at_join``: the box is at the join point already (no join edge).
    """
    g = p.grasp
    if not evaluate.checker.state_valid(p.pose, g):
        return Found(Status.INVALID)
    states: list[State] = [(box, g)]
    if not at_join:
        for a, b in zip(poses, poses[1:], strict=False):
            status = evaluate.transfer(a, b, g, should_stop=stop).status
            if status is not Status.VALID:
                return Found(status)
            states.append((b, g))
    nxt = p.edge + 1
    if p.t < 1.0:
        status = evaluate.step(states[-1], route[nxt], should_stop=stop).status
        if status is not Status.VALID:
            return Found(status)
    states.extend(route[nxt + 1:] if p.t >= 1.0 else route[nxt:])
    log.info("route repaired: joined edge %d at %.2f through %d poses (%d checks)", p.edge,
             p.t, len(poses), tried)
    return Found(Status.VALID, RouteRepair(states, p.edge, tried, len(route) - 1 - max(nxt, 0)))


def polish(checker: PivotChecker, states: list[State], config: RegraspConfig, *,
           should_stop: Stop, checks_per_state: int | None = None,
           lattice: bool = False, new: int | None = None, kept: int | None = None,
           start_grasp: int | None = None) -> list[State]:
    """A repaired route improved as a found path is (:func:`~.improve.improve`).

    The same steps and cost model as the regrasp planner's (lattice re-routing when
    ``lattice``, then the optimiser; as ``config.optimiser`` enables them), each within a
    budget of ``checks_per_state`` motion checks per state polished (cache hits free):
    valid, same ends, never costlier than ``states``. With ``new`` (the repair's own states,
    first in ``states``; the rest is the old route, polished when it was planned), only the
    first ``new + kept`` states are polished, to the same last state, grasp included; the
    rest is kept as it is. ``start_grasp``: the grasp the robot holds the box with
    (``states`` starts with it, and so does the result; a walk to another is priced);
    ``None``: any.
    """
    cfg = config.optimiser
    if not cfg.enabled:
        return states
    if checks_per_state is None:
        checks_per_state = config.repair.polish_checks_per_state
    if kept is None:
        kept = config.repair.polish_kept
    head = len(states) if new is None else min(len(states), new + kept)
    budget = Budget(per_state=checks_per_state, minimum=cfg.min_checks)
    grid = TransferLattice(checker, config.cost) if lattice and cfg.routes else None
    part = improve(checker, states[:head], config, should_stop=should_stop, routes=budget,
                   optimiser=budget, start_grasp=start_grasp,
                   end_grasp=states[head - 1][1] if head < len(states) else None,
                   lattice=grid)
    if head < len(states):
        return (part if part[-1] == states[head - 1] else states[:head]) + states[head:]
    return part
