"""The motions a plan file stores, read by route edge, to be checked again before any use.

A new process replanning a plan file (``pivot-ompl replan``) has no checked motions; the plan
being executed holds every motion of its route: each transfer edge's pivot rotations and each
walk's key poses. :func:`stored_motions` reads them by route edge;
:meth:`~pivot_ompl.checking.pivot_checker.PivotChecker.offer` gives them to the checker,
which, when an offered edge is first asked, checks the stored motion against the scene as it
is now with its own checks (:func:`stored_rotations` and
:meth:`~pivot_ompl.checking.transfer_check.TransferCheck.check_given` for a transfer: the
rotations chain about the supporting edge's ends within the rotation bound and end at the
edge's end, inside the bounds, sweeps certified; :func:`stored_walk` for a walk: it joins the
two grasp poses and each straight motion is certified as the walk planner certifies its own).
A stored motion that passes is the edge's result; one that fails is not used (the edge is
converted or the walk planned again, as without it).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import ANGLE_TOL, Rotation
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.transit.clearance import WalkClearance
from pivot_ompl.transit.lattice import motion_cost
from pivot_ompl.transit.planner import WalkResult

log = logging.getLogger(__name__)

State = tuple[Pose, int]
#: A stored rotation: its pivot corner (m) and signed angle (rad).
StoredStep = tuple[tuple[float, float], float]

#: How close (m and rad) a stored motion must come to the poses of its route edge.
POSE_TOL = 1e-6


@dataclass
class StoredMotions:
    """A plan's motions by route edge.

    Attributes:
        transfers: ``(object start, object end, grasp)`` -> the edge's rotations.
        walks: ``(object pose, from grasp, to grasp)`` -> the walk's robot key poses.
    """

    transfers: dict[tuple[Pose, Pose, int], tuple[StoredStep, ...]] = field(
        default_factory=dict)
    walks: dict[tuple[Pose, int, int], tuple[Pose, ...]] = field(default_factory=dict)

    def __len__(self) -> int:
        """Edges stored."""
        return len(self.transfers) + len(self.walks)


def _close(a: Sequence[float], b: Sequence[float], tol: float = POSE_TOL) -> bool:
    return abs(a[0] - b[0]) <= tol and abs(a[1] - b[1]) <= tol and \
        abs(wrap_angle(a[2] - b[2])) <= tol


def _cut(before: Pose, pivot: tuple[float, float], angle: float,
         target: Pose) -> float | None:
    """The part of a rotation (rad) that brings the object from ``before`` to ``target``.

    ``None`` unless ``target`` lies strictly inside the rotation by ``angle`` about ``pivot``
    (a plan merges two edges' rotations about one corner where they meet: the route's pose
    between them is passed mid-rotation).
    """
    part = wrap_angle(target[2] - before[2])
    if angle == 0.0 or not 0.0 < part / angle < 1.0:
        return None
    return part if _close(rotate_about(before, pivot, part), target) else None


def stored_motions(plan: Plan, route: Sequence[State]) -> StoredMotions:
    """The motions of ``plan`` by edge of its ``route`` (the plan's ``route`` field).

    A transfer phase's steps are split among the route's edges of its grasp where the object
    reaches each edge's end; a step that passes an edge's end mid-rotation (two edges'
    rotations about one corner merged where they meet) is cut there in two. Where the steps
    do not pass an edge's end (a run of rotations replaced by fewer across it), the edges up
    to the next state of the route they pass are not read. Reading stops at the first phase
    that does not match the route (what was read before is kept).
    """
    out = StoredMotions()
    i = 0
    for ph in plan.phases:
        if isinstance(ph, TransitPhase):
            if i + 1 >= len(route) or (route[i][1], route[i + 1][1]) != \
                    (ph.from_grasp, ph.to_grasp) or not _close(route[i][0], ph.object_pose):
                break
            out.walks[(route[i][0], ph.from_grasp, ph.to_grasp)] = tuple(ph.robot_path)
            i += 1
            continue
        assert isinstance(ph, TransferPhase)  # noqa: S101 - the two kinds of phase
        # (pivot, angle, object pose after): cut where an edge ends mid-rotation
        steps = [(s.pivot, s.angle, s.object) for s in ph.steps]
        before, k = ph.object_start, 0
        while k < len(steps) and i + 1 < len(route) and \
                route[i][1] == route[i + 1][1] == ph.grasp:
            k0, target = k, route[i + 1][0]
            while k < len(steps) and not _close(steps[k][2], target):
                pivot, angle, after = steps[k]
                part = _cut(before, pivot, angle, target)
                if part is not None:
                    steps[k:k + 1] = [(pivot, part, target), (pivot, angle - part, after)]
                    break
                before = after
                k += 1
            if k == len(steps):
                # a run of rotations replaced across the edge's end (the plan's shortened
                # phases): the steps pass a later state of the route or none
                j, k = _passed(steps, route, i + 1, k0, ph.grasp)
                if j is None:
                    log.debug("stored transfer of edge %d does not reach its end", i)
                    return out
                log.debug("stored transfers of edges %d..%d not read: their ends are "
                          "not passed", i, j - 1)
                i = j
                before = steps[k][2]
                k += 1
                continue
            before = steps[k][2]
            k += 1
            out.transfers[(route[i][0], target, ph.grasp)] = tuple(
                (p, a) for p, a, _ in steps[k0:k])
            i += 1
        if k < len(steps):
            break
    return out


def passing_rest(plan: Plan, route: Sequence[State], obj: Pose, grasp: int | None, *,
                 should_stop: Callable[[], bool] | None = None,
                 ) -> dict[tuple[Pose, Pose, int], tuple[StoredStep, ...]]:
    """The rest of each transfer of ``plan`` that passes the object pose ``obj``, by edge.

    A box observed where the plan put it (after one of a transfer phase's rotations, or
    partway through one) goes on with the phase's next rotations, up to the first state of
    ``route`` (the plan's route) of the phase's grasp they reach: the result maps ``(obj,
    that state's pose, grasp)`` to them (a rotation passed partway cut at ``obj``), for the
    phases of ``grasp`` (``None``: of any grasp) whose rotations pass within
    :data:`POSE_TOL` of ``obj``. Offered to a checker, such a rest is checked as any stored
    motion. It matters where the box passes a gap within the refinement's resolution
    (:data:`~pivot_ompl.checking.refinement.MIN_CLEARANCE`) of its sides: no new pivot
    sequence can start at such a pose, and the rest is then its only transfer.
    ``should_stop`` is polled every :data:`POLL_STEPS` steps; stopped, nothing is returned.
    """
    out: dict[tuple[Pose, Pose, int], tuple[StoredStep, ...]] = {}
    ends: dict[int, _RouteStates] = {}
    for ph in plan.phases:
        if not isinstance(ph, TransferPhase) or grasp is not None and ph.grasp != grasp:
            continue
        before: Pose = ph.object_start
        rest: list[StoredStep] | None = None
        for k, st in enumerate(ph.steps):
            if k % POLL_STEPS == 0 and should_stop is not None and should_stop():
                return {}
            if _close(before, obj):
                rest, first = [], k
                break
            part = _cut(before, st.pivot, st.angle, obj)
            if part is not None:
                rest, first = [(st.pivot, st.angle - part)], k + 1
                break
            before = st.object
        if rest is None:
            continue
        if ph.grasp not in ends:
            ends[ph.grasp] = _RouteStates([q for q, g in route if g == ph.grasp])
        for st in ph.steps[first:]:
            rest.append((st.pivot, st.angle))
            end = ends[ph.grasp].at(st.object)
            if end is not None:
                out[(obj, end, ph.grasp)] = tuple(rest)
                break
    return out


#: Steps of a plan's phases between two polls of :func:`passing_rest`'s stop.
POLL_STEPS = 1000


class _RouteStates:
    """Route poses found by pose (within :data:`POSE_TOL`), sorted by ``x`` once."""

    def __init__(self, poses: Sequence[Pose]) -> None:
        self.poses = list(poses)
        xs = np.array([q[0] for q in self.poses], dtype=float)
        self.order = np.argsort(xs, kind="stable")
        self.xs = xs[self.order]

    def at(self, q: Pose) -> Pose | None:
        """The first pose (in route order) within :data:`POSE_TOL` of ``q``, or ``None``."""
        lo = int(np.searchsorted(self.xs, q[0] - POSE_TOL, side="left"))
        hi = int(np.searchsorted(self.xs, q[0] + POSE_TOL, side="right"))
        near = sorted(int(i) for i in self.order[lo:hi])
        return next((self.poses[i] for i in near if _close(self.poses[i], q)), None)


def _passed(steps: Sequence[tuple[tuple[float, float], float, Pose]],
            route: Sequence[State], first: int, k0: int,
            grasp: int) -> tuple[int | None, int]:
    """The first route state ``j >= first`` of the phase that a step ``k >= k0`` reaches.

    Returns ``(j, k)``, or ``(None, k0)`` if the steps reach none.
    """
    j = first
    while j < len(route) and route[j][1] == grasp:
        for k in range(k0, len(steps)):
            if _close(steps[k][2], route[j][0]):
                return j, k
        j += 1
    return None, k0


def stored_rotations(model: BoxGraspModel, ca: Pose, cb: Pose, steps: Sequence[StoredStep],
                     grasp: int, *, alpha_max: float) -> tuple[Rotation, ...] | None:
    """Stored rotations as the pivot sequence from car pose ``ca`` to ``cb``, or ``None``.

    Each rotation turns about one end of the supporting edge of the car it starts from (the
    end nearest the stored pivot, within :data:`POSE_TOL`), by at most ``alpha_max``; the last
    ends at ``cb`` within :data:`POSE_TOL`. ``None`` when they do not.
    """
    car, out = ca, []
    for pivot, angle in steps:
        if abs(angle) > alpha_max + ANGLE_TOL:
            return None
        ends = model.pivots(car, grasp)
        end = min((0, 1), key=lambda e: math.hypot(ends[e][0] - pivot[0],
                                                   ends[e][1] - pivot[1]))
        if math.hypot(ends[end][0] - pivot[0], ends[end][1] - pivot[1]) > POSE_TOL:
            return None
        car = rotate_about(car, ends[end], angle)
        out.append(Rotation(end, ends[end], angle, car))
    return tuple(out) if _close(car, cb) else None


def stored_walk(clearance: WalkClearance, model: BoxGraspModel, walk: WalkParameters,
                obj: Pose, from_grasp: int, to_grasp: int,
                path: Sequence[Pose]) -> WalkResult | None:
    """A stored walk round the box resting at ``obj``, certified, or ``None``.

    The path must start at the grasp pose of ``from_grasp`` and end at that of ``to_grasp``
    (within :data:`POSE_TOL`; the exact grasp poses are used); each straight motion between
    its key poses (linear yaw) is certified free of the obstacles, the bounds and the resting
    box kept the walk planner's margin away, as the walk planner certifies its own
    (:meth:`~pivot_ompl.transit.clearance.WalkClearance.segment_free`).
    """
    start, goal = model.robot_pose(obj, from_grasp), model.robot_pose(obj, to_grasp)
    if len(path) < 2 or not _close(path[0], start) or not _close(path[-1], goal):
        return None
    keys: list[Pose] = [start, *((p[0], p[1], p[2]) for p in path[1:-1]), goal]
    moves = list(zip(keys, keys[1:], strict=False))
    if not all(clearance.segment_free(a, b, obj) for a, b in moves):
        return None
    return WalkResult(True, tuple(keys), sum(math.hypot(b[0] - a[0], b[1] - a[1])
                                             for a, b in moves),
                      sum(motion_cost(a, b, walk) for a, b in moves))
