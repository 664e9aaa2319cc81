"""The pure-Python validity core: states, pivot edges (transfer) and walks (transit).

OMPL's validators (:mod:`pivot_ompl.base.validity_checker`,
:mod:`pivot_ompl.base.motion_validator`) and our planners both ask this object, so every edge
is converted and checked once (cached) whichever component asks first.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from pivot_ompl.analysis.wall_frame import floor_bounds, walls_facing
from pivot_ompl.checking.path_poses import POLL_POSES as POLL_POSES
from pivot_ompl.checking.path_poses import PathPoses
from pivot_ompl.checking.shared_results import SharedResults, shared_results
from pivot_ompl.checking.stored import StoredMotions, stored_rotations, stored_walk
from pivot_ompl.checking.transfer_check import EdgeResult, TransferCheck
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.scene import Obstacle, Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.transit.frame import frame_of
from pivot_ompl.transit.planner import WalkPlanner, WalkResult
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_footprint

__all__ = ["EdgeResult", "MotionCounters", "PivotChecker"]

log = logging.getLogger(__name__)

#: Spacing (m) of the poses that :meth:`PivotChecker.path_free` tests along a car's path.
PREFILTER_STEP = 0.25



@dataclass
class MotionCounters:
    """Counts of motion checks (OMPL's own counters stay 0 for Python validators)."""

    valid: int = 0
    invalid: int = 0
    cache_hits: int = 0
    #: pieces of edges converted again with smaller rotations because they collided
    refined_pieces: int = 0


class PivotChecker:
    """States, transfer edges and transit walks of one scene, with their caches.

    Args:
        scene: the geometry checked (obstacles, bounds, box, robot, steering); a checker
            serves every problem on it, whatever their start (a replan from an observed
            pose keeps the checker and its caches). A change of obstacles needs a new
            checker (:meth:`adopt` takes over what it can).
        seed: kept for callers that record it (the checks are deterministic).
        tolerance: swept-check tolerance (m): no point of a body moves farther than this
            between two certified samples.
        share: take and give the results of the checkers of the same scene
            (:mod:`~pivot_ompl.checking.shared_results`: the same results, counted as
            computed, so a later plan of a scene is the same plan, checked faster).

    Attributes:
        scene, model: the scene and its box and robot geometry.
        world: the collision world (obstacles and bounds).
        steering: the pivot steering of the scene's turning radius and rotation bound.
        walker: the walk planner (transit).
        transfers: the pivot sequences' checks.
        counters: motion checks computed, valid and invalid, and cache hits.
    """

    scene: Scene
    seed: int
    tolerance: float
    model: BoxGraspModel
    world: CollisionWorld
    steering: PivotSteering
    walker: WalkPlanner
    transfers: TransferCheck
    counters: MotionCounters

    def __init__(self, scene: Scene, *, seed: int = 0, tolerance: float = SWEEP_TOLERANCE,
                 should_stop: Callable[[], bool] | None = None, share: bool = True) -> None:
        """Build the collision world, the steering method and the walk planner.

        Raises:
            Interrupted: ``should_stop()`` became true while the world was built.
        """
        self.scene, self.seed, self.tolerance = scene, seed, tolerance
        self.model = scene.model
        self.world = CollisionWorld.from_scene(scene, should_stop=should_stop)
        self.steering = PivotSteering(turning_radius=scene.turning_radius,
                                      alpha_max=scene.alpha_max)
        yaw = walls_facing(scene, should_stop)
        within = floor_bounds(scene, yaw, frame_of(self.world, yaw=yaw).centre,
                              should_stop=should_stop) if yaw else None
        self.walker = WalkPlanner(scene.model, self.world, scene.walk, tolerance=tolerance,
                                  should_stop=should_stop, yaw=yaw, within=within)
        self.counters = MotionCounters()
        self._edges: dict[tuple, EdgeResult] = {}
        self._walks: dict[tuple, WalkResult] = {}
        self._offered = StoredMotions()
        self._shared: SharedResults | None = shared_results(
            scene, tolerance=tolerance, clearance=self.world.clearance) if share else None
        self.transfers = TransferCheck(self.model, self.world, self.steering,
                                       tolerance=tolerance, refined=self._count_refined)
        self._poses = PathPoses(self.model, self.world, self.steering.paths,
                                self.transfers.sweeps.spread)

    @property
    def edges(self) -> Mapping[tuple, EdgeResult]:
        """The transfers checked so far (read-only), by ``(a, b, grasp, with_robot)``."""
        return MappingProxyType(self._edges)

    def _count_refined(self) -> None:
        self.counters.refined_pieces += 1

    # -- states --------------------------------------------------------------------------
    def box_valid(self, obj: Pose) -> bool:
        """The box alone at ``obj`` is inside the bounds and collision-free."""
        return self.world.box_in_bounds(obj) and self.world.box_distance(obj) > 0.0

    def robot_valid(self, obj: Pose, grasp: int) -> bool:
        """The robot holding the box at ``obj`` with ``grasp`` is inside bounds and free."""
        r = self.model.robot_pose(obj, grasp)
        return self.world.held_in_bounds(r, grasp) and self.world.held_distance(r, grasp) > 0.0

    def state_valid(self, obj: Pose, grasp: int) -> bool:
        """Box and robot at ``grasp`` inside the bounds and collision-free."""
        return self.box_valid(obj) and self.robot_valid(obj, grasp)

    def clearance(self, obj: Pose, grasp: int) -> float:
        """Smallest distance (m) of box or robot to obstacles or to the bounds' sides."""
        r = self.model.robot_pose(obj, grasp)
        w = self.world
        return min(w.box_distance(obj), w.held_distance(r, grasp),
                   w.bounds_margin(self.model.object_corners(obj)),
                   w.bounds_margin(self.model.held_corners(r, grasp)))

    # -- transfer ------------------------------------------------------------------------
    def path_free(self, obj_a: Pose, obj_b: Pose, grasp: int, *, with_robot: bool = True,
                  step: float = PREFILTER_STEP,
                  should_stop: Callable[[], bool] | None = None) -> bool:
        """Cheap test run before :meth:`transfer`: the box (and robot) free along the path.

        Poses every ``step`` m along the car's Reeds-Shepp path from ``obj_a`` to ``obj_b``
        at ``grasp`` (not its ends) are tested. The pivot sequence stays close to that path
        but not on it, so this is a filter, not a proof either way: a ``True`` still needs
        :meth:`transfer`, and a ``False`` may (rarely, grazing an obstacle) refuse an edge
        whose pivots would pass. It costs a few state tests, where a colliding edge's full
        check converts its colliding piece again at up to four rotation bounds.

        Raises:
            Interrupted: ``should_stop()`` became true (polled every :data:`POLL_POSES`
                poses) before the answer was known.
        """
        m = self.model
        ca, cb = m.car_pose(obj_a, grasp), m.car_pose(obj_b, grasp)
        n = int(self.steering.paths.distance(ca, cb) / step)
        return n < 2 or self.cars_free(ca, cb, grasp, [k / n for k in range(1, n)],
                                       with_robot=with_robot, should_stop=should_stop)

    def cars_free(self, car_a: Pose, car_b: Pose, grasp: int, ts: Sequence[float], *,
                  with_robot: bool = True,
                  should_stop: Callable[[], bool] | None = None) -> bool:
        """The box (and robot) free at fractions ``ts`` of the car's Reeds-Shepp path.

        A body free by the clearance carried from the last pose
        (:mod:`~pivot_ompl.checking.path_poses`) is not queried again: the answer is still
        every pose's :meth:`state_valid` (or :meth:`box_valid`).

        Raises:
            Interrupted: ``should_stop()`` became true (polled every :data:`POLL_POSES`
                poses) before the answer was known.
        """
        return self._poses.free(car_a, car_b, grasp, ts, with_robot=with_robot,
                                should_stop=should_stop)

    def transfer(self, obj_a: Pose, obj_b: Pose, grasp: int, *, with_robot: bool = True,
                 should_stop: Callable[[], bool] | None = None) -> EdgeResult:
        """Check the pivot sequence moving the box from ``obj_a`` to ``obj_b`` at ``grasp``.

        With ``with_robot=False`` only the box is checked (the object roadmap of the
        Visibility PRM, where the robot is considered separately). ``should_stop`` is polled
        by the steering once per path piece.

        Raises:
            Interrupted: ``should_stop()`` stopped the check before it knew: the edge is
                neither valid nor invalid, and nothing is cached (a later call checks it).
                The planners ask through :class:`~pivot_ompl.planners.evaluation.Evaluator`,
                which answers ``STOPPED``.
        """
        m = self.model

        def compute() -> EdgeResult:
            ca, cb = m.car_pose(obj_a, grasp), m.car_pose(obj_b, grasp)
            offered = self._offered.transfers.get((obj_a, obj_b, grasp)) if with_robot \
                else None
            if offered is not None:
                rots = stored_rotations(m, ca, cb, offered, grasp,
                                        alpha_max=self.steering.alpha_max)
                res = self.transfers.check_given(ca, cb, rots, grasp) if rots else None
                if res is not None and res.valid:
                    return res
            return self.transfers.check(ca, cb, grasp, with_robot=with_robot,
                                        should_stop=should_stop)

        return self._cached(self._edges, (obj_a, obj_b, grasp, with_robot), compute,
                            self._shared.edges if self._shared else None)

    def _cached(self, cache: dict, key: tuple, compute: Callable[[], Any],
                shared: dict | None = None) -> Any:
        """A motion result from ``cache``, or computed, stored and counted.

        ``shared``: the scene's other checkers' results; one found there is taken as if
        computed (stored and counted alike).
        """
        hit = cache.get(key)
        if hit is not None:
            self.counters.cache_hits += 1
            return hit
        res = None if shared is None else shared.get(key)
        if res is None:
            res = compute()
            if shared is not None and self._shared is not None:
                self._shared.room()
                shared[key] = res
        cache[key] = res
        if res.valid:
            self.counters.valid += 1
        else:
            self.counters.invalid += 1
        return res

    # -- a changed scene -------------------------------------------------------------------
    def offer(self, stored: StoredMotions) -> None:
        """Motions made earlier (a plan file's), tried first when their edges are first asked.

        An offered motion is checked as this checker checks its own (see
        :mod:`pivot_ompl.checking.stored`); it is the edge's result only if it passes, else
        the edge is computed as without it. The checker keeps its results to itself from
        then on (they may differ from the scene's other checkers').
        """
        self._offered = stored
        self._shared = None

    def adopt(self, old: PivotChecker, *, added: Sequence[Obstacle] = (),
              removed: Sequence[Obstacle] = ()) -> int:
        """Take over ``old``'s checked motions that a change of obstacles cannot have changed.

        ``old`` checked the same scene but for ``added`` obstacles it did not have and
        ``removed`` ones it had (box, robot and bounds the same). A motion found valid stays
        valid unless the region it sweeps meets an added obstacle (the region: round every
        pivot of a transfer, the farthest point of box and holding robot from the car plus
        the half-edge; round every pose of a walk, the walking robot's turning radius; grown
        by the clearance and the tolerance); one found invalid stays invalid unless an
        obstacle was removed. Returns how many were taken over.
        """
        boxes = [obstacle_footprint(o).bounds for o in added]
        grow = self.world.clearance + self.tolerance
        kept = 0
        for key, res in old._edges.items():
            if res.valid:
                reach = self.spin_radius(key[2]) + self.model.edge_half_length(key[2])
                pts = [res.sequence.start[:2], *(r.pivot for r in res.sequence.rotations)]
                if _meets(pts, reach + grow, boxes):
                    continue
            elif removed:
                continue
            self._edges[key] = res
            kept += 1
        reach = self.model.robot_radius()
        for key, walk in old._walks.items():
            if walk.valid:
                if _meets([p[:2] for p in walk.robot_path], reach + grow, boxes):
                    continue
            elif removed:
                continue
            self._walks[key] = walk
            kept += 1
        return kept

    # -- transit -------------------------------------------------------------------------
    def transit(self, obj: Pose, from_grasp: int, to_grasp: int, *,
                should_stop: Callable[[], bool] | None = None) -> WalkResult:
        """The robot's walk between two grasps of the box resting at ``obj`` (cached).

        Raises:
            Interrupted: ``should_stop()`` stopped the walk's search before it knew (nothing
                cached; see :meth:`transfer`).
        """
        def compute() -> WalkResult:
            offered = self._offered.walks.get((obj, from_grasp, to_grasp))
            if offered is not None:
                w = self.walker
                res = stored_walk(w.certifier, self.model, w.walk, obj, from_grasp, to_grasp,
                                  offered)
                if res is not None:
                    return res
            return self.walker.plan(obj, from_grasp, to_grasp, should_stop=should_stop)

        return self._cached(self._walks, (obj, from_grasp, to_grasp), compute,
                            self._shared.walks if self._shared else None)

    def spin_radius(self, grasp: int) -> float:
        """Farthest point (m) of the box and the holding robot from the car at ``grasp``."""
        m = self.model
        car = (0.0, 0.0, 0.0)
        pts = m.object_corners(m.object_from_car(car, grasp)) + \
            m.held_corners(m.robot_from_car(car, grasp), grasp)
        return max(math.hypot(x, y) for x, y in pts)

    def turned(self, obj: Pose, grasp: int, *, margin: float) -> Pose | None:
        """The box turned round with the robot, if the assembly has room to turn in place.

        The car of ``(obj, grasp)`` spins by pi about its own position (the path
        :class:`~pivot_ompl.pivoting.curves.CarPaths` gives two car poses at one position):
        the box swings round to the robot's other side. Returns the object pose reached, or
        ``None`` unless the disk the assembly sweeps (radius :meth:`spin_radius` plus
        ``margin``) is inside the bounds and clear of the obstacles, and the state reached
        is valid. A cheap sufficient test (one query): the turn's pivot sequence is still
        checked by :meth:`transfer`.
        """
        m, w = self.model, self.world
        cx, cy, h = m.car_pose(obj, grasp)
        r = self.spin_radius(grasp) + margin
        x0, y0, x1, y1 = w.bounds
        if min(cx - x0, x1 - cx, cy - y0, y1 - cy) < r or w.disk_distance(cx, cy, r) <= 0:
            return None
        turned = m.object_from_car((cx, cy, h + math.pi), grasp)
        return turned if self.state_valid(turned, grasp) else None

    def explain(self, obj: Pose) -> str:
        """Why each grasp is invalid at object pose ``obj`` (for error messages)."""
        w, m = self.world, self.model
        if not w.box_in_bounds(obj):
            return "the box leaves the bounds"
        if w.box_distance(obj) <= 0:
            return "the box collides with an obstacle"
        parts = []
        for g in range(4):
            r = m.robot_pose(obj, g)
            if not w.held_in_bounds(r, g):
                parts.append(f"grasp {g}: robot leaves the bounds")
            elif w.held_distance(r, g) <= 0:
                parts.append(f"grasp {g}: robot collides")
        return "; ".join(parts) or "valid"


def _meets(points: Sequence[Sequence[float]], radius: float,
           boxes: Sequence[tuple[float, float, float, float]]) -> bool:
    """Whether the bounding box of ``points`` grown by ``radius`` meets one of ``boxes``."""
    if not boxes or not points:
        return False
    xs = [p[0] for p in points]
    ys = [p[1] for p in points]
    x0, x1, y0, y1 = min(xs) - radius, max(xs) + radius, min(ys) - radius, max(ys) + radius
    return any(b[0] <= x1 and x0 <= b[2] and b[1] <= y1 and y0 <= b[3] for b in boxes)
