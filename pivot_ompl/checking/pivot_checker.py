"""The pure-Python validity core: states, pivot edges (transfer) and walks (transit).

OMPL's validators (:mod:`pivot_ompl.base.validity_checker`,
:mod:`pivot_ompl.base.motion_validator`) and our planners both ask this object, so every edge
is converted and checked once (cached) whichever component asks first.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

from pivot_ompl.errors import Interrupted
from pivot_ompl.pivoting.kinematics import LEFT, Rotation
from pivot_ompl.pivoting.steering import PivotSequence, PivotSteering
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose, rotate_about
from pivot_ompl.transit.planner import INVALID_WALK, WalkPlanner, WalkResult
from pivot_ompl.validity.certify import SWEEP_TOLERANCE, certify
from pivot_ompl.validity.collision import CollisionWorld

log = logging.getLogger(__name__)

#: Spacing (m) of the poses that :meth:`PivotChecker.path_free` tests along a car's path.
PREFILTER_STEP = 0.25

#: A colliding piece is converted again with the rotation bound times each of these factors
#: in turn (half-octave steps down to alpha_max/8): the largest rotations that pass are kept.
REFINE_FACTORS = tuple(2.0 ** (-0.5 * k) for k in range(1, 7))


def _swept_clearance(dist: Callable[[Pose], float], base: Pose, pivot: tuple[float, float],
                     angle: float) -> Callable[[float], float]:
    """Clearance at fraction ``s`` of the rotation of ``base`` by ``angle`` about ``pivot``."""
    return lambda s: dist(rotate_about(base, pivot, s * angle))


@dataclass(frozen=True)
class EdgeResult:
    """A transfer edge (same grasp) checked.

    Attributes:
        valid: the pivot sequence is collision-free and inside the bounds.
        sequence: the pivot rotations (car poses) of the edge.
        length: Reeds-Shepp length of the edge (m).
        reason: why it is invalid (``""`` if valid).
    """

    valid: bool
    sequence: PivotSequence
    length: float
    reason: str = ""


@dataclass
class MotionCounters:
    """Counts of motion checks (OMPL's own counters stay 0 for Python validators)."""

    valid: int = 0
    invalid: int = 0
    cache_hits: int = 0
    #: pieces of edges converted again with smaller rotations because they collided
    refined_pieces: int = 0


@dataclass
class PivotChecker:
    """States, transfer edges and transit walks of one scene.

    Args:
        scene: the planning problem.
        seed: seed of the walk roadmap's generator.
        tolerance: swept-check tolerance (m): no point of a body moves farther than this
            between two certified samples.
    """

    scene: Scene
    seed: int = 0
    tolerance: float = SWEEP_TOLERANCE
    world: CollisionWorld = field(init=False)
    steering: PivotSteering = field(init=False)
    walker: WalkPlanner = field(init=False)
    counters: MotionCounters = field(default_factory=MotionCounters, init=False)
    #: Termination condition of the current solve (set by planners; polled by the steering).
    should_stop: Callable[[], bool] | None = field(default=None, init=False)

    def __post_init__(self) -> None:
        """Build the collision world, the steering method and the walk planner."""
        s = self.scene
        self.model = s.model
        self.world = CollisionWorld.from_scene(s)
        self.steering = PivotSteering(turning_radius=s.turning_radius, alpha_max=s.alpha_max)
        self.walker = WalkPlanner(s.model, self.world, s.walk, tolerance=self.tolerance)
        self._edges: dict[tuple, EdgeResult] = {}
        self._walks: dict[tuple, WalkResult] = {}
        # reach of each body from a pivot corner, per grasp: bounds rotation sweeps
        self._reach: dict[int, tuple[float, float]] = {}
        for g in range(4):
            car = (0.0, 0.0, 0.0)
            a = self.model.pivots(car, g)[LEFT]
            box = self.model.object_corners(self.model.object_from_car(car, g))
            rob = self.model.held_corners(self.model.robot_from_car(car, g), g)
            self._reach[g] = (max(math.hypot(x - a[0], y - a[1]) for x, y in box),
                              max(math.hypot(x - a[0], y - a[1]) for x, y in rob))

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
                  step: float = PREFILTER_STEP) -> bool:
        """Cheap test run before :meth:`transfer`: the box (and robot) free along the path.

        Poses every ``step`` m along the car's Reeds-Shepp path from ``obj_a`` to ``obj_b``
        at ``grasp`` (not its ends) are tested. The pivot sequence stays close to that path
        but not on it, so this is a filter, not a proof either way: a ``True`` still needs
        :meth:`transfer`, and a ``False`` may (rarely, grazing an obstacle) refuse an edge
        whose pivots would pass. It costs a few state tests, where a colliding edge's full
        check converts its colliding piece again at up to four rotation bounds.
        """
        m = self.model
        ca, cb = m.car_pose(obj_a, grasp), m.car_pose(obj_b, grasp)
        n = int(self.steering.rs.distance(ca, cb) / step)
        return n < 2 or self.cars_free(ca, cb, grasp, [k / n for k in range(1, n)],
                                       with_robot=with_robot)

    def cars_free(self, car_a: Pose, car_b: Pose, grasp: int, ts: Sequence[float], *,
                  with_robot: bool = True) -> bool:
        """The box (and robot) free at fractions ``ts`` of the car's Reeds-Shepp path."""
        m = self.model
        cars = self.steering.rs.sample(car_a, car_b, list(ts))
        if with_robot:
            return all(self.state_valid(m.object_from_car(c, grasp), grasp) for c in cars)
        return all(self.box_valid(m.object_from_car(c, grasp)) for c in cars)

    def transfer(self, obj_a: Pose, obj_b: Pose, grasp: int, *,
                 with_robot: bool = True) -> EdgeResult:
        """Check the pivot sequence moving the box from ``obj_a`` to ``obj_b`` at ``grasp``.

        With ``with_robot=False`` only the box is checked (the object roadmap of the
        Visibility PRM, where the robot is considered separately). An edge whose check is
        stopped by :attr:`should_stop` is invalid and not cached (a later solve checks it).
        """
        try:
            return self._cached(self._edges, (obj_a, obj_b, grasp, with_robot),
                                lambda: self._transfer(obj_a, obj_b, grasp, with_robot))
        except Interrupted:
            length = self.steering.rs.distance(obj_a, obj_b)
            return EdgeResult(False, PivotSequence(obj_a, obj_b, (), length, 0), length,
                              "interrupted by the termination condition")

    def _cached(self, cache: dict, key: tuple, compute: Callable[[], Any]) -> Any:
        """A motion result from ``cache``, or computed, stored and counted."""
        hit = cache.get(key)
        if hit is not None:
            self.counters.cache_hits += 1
            return hit
        res = compute()
        cache[key] = res
        if res.valid:
            self.counters.valid += 1
        else:
            self.counters.invalid += 1
        return res

    def _transfer(self, obj_a: Pose, obj_b: Pose, grasp: int, with_robot: bool) -> EdgeResult:
        """Check the edge piece by piece, refining only a piece that collides."""
        m = self.model
        return self._check(m.car_pose(obj_a, grasp), m.car_pose(obj_b, grasp), grasp,
                           with_robot)

    def _check(self, ca: Pose, cb: Pose, grasp: int, with_robot: bool) -> EdgeResult:
        """Bounds and certified sweeps rotation by rotation, stopping at the first failure.

        The steering's pieces are checked in order. Where a piece's rotations collide or
        leave the bounds, that piece alone (the same stretch of the Reeds-Shepp path, from
        the same pose) is converted again with the rotation bound reduced by half-octave steps
        (:data:`REFINE_FACTORS`), down to ``alpha_max / 8``: smaller rotations hug the path
        closer (the topological property); the rest of the edge keeps full rotations.
        """
        m, w = self.model, self.world
        r_box, r_rob = self._reach[grasp]
        obstacles = w.has_obstacles
        ell = m.edge_half_length(grasp)
        steering = self.steering
        length = steering.rs.distance(ca, cb)

        def box_d(car: Pose) -> float:
            return w.box_distance(m.object_from_car(car, grasp))

        def rob_d(car: Pose) -> float:
            return w.held_distance(m.robot_from_car(car, grasp), grasp)

        def in_bounds(car: Pose, bulge_b: float, bulge_r: float) -> bool:
            if w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))) < bulge_b:
                return False
            return not with_robot or \
                w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)) >= bulge_r

        def fail(reason: str) -> EdgeResult:
            return EdgeResult(False, PivotSequence(ca, cb, (), length, 0), length, reason)

        def check_rotations(prev: Pose, rots: tuple[Rotation, ...], db: float, dr: float,
                            ) -> tuple[str, float, float]:
            """``(failure, clearances at the end)``; failure ``""`` when all pass."""
            for rot in rots:
                bulge = 1.0 - math.cos(0.5 * rot.angle)
                if not (in_bounds(prev, r_box * bulge, r_rob * bulge)
                        and in_bounds(rot.car, r_box * bulge, r_rob * bulge)):
                    return "leaves the bounds", db, dr
                if obstacles:
                    base, piv, ang = prev, rot.pivot, rot.angle
                    db_end = box_d(rot.car)
                    if not certify(_swept_clearance(box_d, base, piv, ang), r_box * abs(ang),
                                   tolerance=self.tolerance, d0=db, d1=db_end).valid:
                        return "box collides", db, dr
                    db = db_end
                    if with_robot:
                        dr_end = rob_d(rot.car)
                        if not certify(_swept_clearance(rob_d, base, piv, ang),
                                       r_rob * abs(ang), tolerance=self.tolerance, d0=dr,
                                       d1=dr_end).valid:
                            return "robot collides", db, dr
                        dr = dr_end
                prev = rot.car
            return "", db, dr

        db = dr = math.inf
        if obstacles:
            db = box_d(ca)
            dr = rob_d(ca) if with_robot else math.inf
            if db <= 0 or dr <= 0:
                return fail("collides at the start")
        checked: list[Rotation] = []
        pieces = steering.iter_pieces(ca, cb, half_length=ell, should_stop=self.should_stop)
        reply: tuple[Pose, Rotation | None] | None = None
        while True:
            try:
                piece = pieces.send(reply) if reply is not None else next(pieces)
            except StopIteration:
                break
            reply = None
            why, db1, dr1 = check_rotations(piece.start, piece.rotations, db, dr)
            for factor in REFINE_FACTORS:  # refine this piece only
                if not why:
                    break
                fine: list[Rotation] = []
                for sub in steering.iter_pieces(
                        ca, cb, half_length=ell, should_stop=self.should_stop,
                        span=(piece.t0, piece.t1), origin=piece.start,
                        alpha_max=steering.alpha_max * factor):
                    fine.extend(sub.rotations)
                why, db1, dr1 = check_rotations(piece.start, tuple(fine), db, dr)
                if not why:
                    self.counters.refined_pieces += 1
                    checked.extend(fine)
                    end = fine[-1].car if fine else piece.start
                    reply = (end, fine[-1] if fine else None)
            if why:
                return fail(f"{why} during rotation {len(checked)} "
                            f"(path {piece.t0:.3f}..{piece.t1:.3f})")
            if reply is None:
                checked.extend(piece.rotations)
            db, dr = db1, dr1
        # merge rotations about one corner exactly as PivotSteering.convert does: the merged
        # rotation sweeps the union of the two checked sweeps
        merged: list[Rotation] = []
        for r in checked:
            steering._append(merged, r)
        seq = PivotSequence(ca, cb, tuple(merged), length, 0)
        return EdgeResult(True, seq, length)

    # -- transit -------------------------------------------------------------------------
    def transit(self, obj: Pose, from_grasp: int, to_grasp: int) -> WalkResult:
        """The robot's walk between two grasps of the box resting at ``obj`` (cached).

        A walk whose search is stopped by :attr:`should_stop` is invalid and not cached.
        """
        try:
            return self._cached(self._walks, (obj, from_grasp, to_grasp),
                                lambda: self.walker.plan(obj, from_grasp, to_grasp,
                                                         should_stop=self.should_stop))
        except Interrupted:
            return INVALID_WALK

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
