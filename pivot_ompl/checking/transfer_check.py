"""A transfer edge checked: its pivot sequence inside the bounds and certified collision-free.

The steering (:class:`~pivot_ompl.pivoting.steering.PivotSteering`) cuts the car's
Reeds-Shepp path into pieces, each solved by up to three rotations. Rotation by rotation, the
box and the robot must stay inside the bounds (their farthest points bulge out by
``r (1 - cos(alpha/2))`` mid-rotation) and their swept volumes must be certified free
(:func:`~pivot_ompl.validity.certify.certify`: a point moves at most ``r |alpha|``). Where a
piece fails, that piece alone (the same stretch of the path, from the pose reached) is
converted again with the rotation bound reduced in half-octave steps
(:data:`REFINE_FACTORS`) down to ``alpha_max / 8``: smaller rotations hug the path (the
topological property); the rest of the edge keeps full rotations.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import LEFT, Rotation
from pivot_ompl.pivoting.steering import Piece, PivotSequence, PivotSteering
from pivot_ompl.se2 import Pose, rotate_about
from pivot_ompl.validity.certify import certify
from pivot_ompl.validity.collision import CollisionWorld

#: A failing piece is converted again with the rotation bound times each of these factors
#: in turn (half-octave steps down to alpha_max/8): the largest rotations that pass are kept.
REFINE_FACTORS = tuple(2.0 ** (-0.5 * k) for k in range(1, 7))


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


class TransferCheck:
    """Checks pivot sequences of one scene (see the module docstring).

    Args:
        model: box and robot geometry.
        world: obstacles and bounds.
        steering: the pivot steering.
        tolerance: swept-check tolerance (m).
        refined: called once per piece that needed smaller rotations (a counter).
    """

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, steering: PivotSteering,
                 *, tolerance: float, refined: Callable[[], None]) -> None:
        """Checks with these parts; each body's reach from a pivot corner, per grasp."""
        self.model, self.world, self.steering = model, world, steering
        self.tolerance = tolerance
        self._refined = refined
        self._reach: dict[int, tuple[float, float]] = {}
        for g in range(4):
            car = (0.0, 0.0, 0.0)
            a = model.pivots(car, g)[LEFT]
            box = model.object_corners(model.object_from_car(car, g))
            rob = model.held_corners(model.robot_from_car(car, g), g)
            self._reach[g] = (max(math.hypot(x - a[0], y - a[1]) for x, y in box),
                              max(math.hypot(x - a[0], y - a[1]) for x, y in rob))

    def reach(self, grasp: int) -> tuple[float, float]:
        """Farthest points (m) of the box and of the holding robot from a pivot corner."""
        return self._reach[grasp]

    def check(self, ca: Pose, cb: Pose, grasp: int, *, with_robot: bool,
              should_stop: Callable[[], bool] | None) -> EdgeResult:
        """The edge between car poses ``ca`` and ``cb`` at ``grasp``, piece by piece.

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per path piece).
        """
        steering = self.steering
        ell = self.model.edge_half_length(grasp)
        length = steering.paths.distance(ca, cb)

        def fail(reason: str) -> EdgeResult:
            return EdgeResult(False, PivotSequence(ca, cb, (), length, 0), length, reason)

        db = dr = math.inf
        if self.world.has_obstacles:
            db = self._box_d(ca, grasp)
            dr = self._rob_d(ca, grasp) if with_robot else math.inf
            if db <= 0 or dr <= 0:
                return fail("collides at the start")
        checked: list[Rotation] = []
        pieces = steering.iter_pieces(ca, cb, half_length=ell, should_stop=should_stop)
        reply: tuple[Pose, Rotation | None] | None = None
        while True:
            try:
                piece = pieces.send(reply) if reply is not None else next(pieces)
            except StopIteration:
                break
            reply = None
            why, ends = self._rotations(piece.start, piece.rotations, grasp, with_robot, db, dr)
            if why:
                fine, why, ends = self._refine(ca, cb, piece, grasp, with_robot, db, dr,
                                               should_stop)
                if why:
                    return fail(f"{why} during rotation {len(checked)} "
                                f"(path {piece.t0:.3f}..{piece.t1:.3f})")
                self._refined()
                checked.extend(fine)
                reply = (fine[-1].car if fine else piece.start, fine[-1] if fine else None)
            else:
                checked.extend(piece.rotations)
            db, dr = ends
        # rotations about one corner merged exactly as PivotSteering.convert merges them: the
        # merged rotation sweeps the union of the two checked sweeps
        merged: list[Rotation] = []
        for r in checked:
            steering.append_merged(merged, r)
        return EdgeResult(True, PivotSequence(ca, cb, tuple(merged), length, 0), length)

    def _refine(self, ca: Pose, cb: Pose, piece: Piece, grasp: int, with_robot: bool,
                db: float, dr: float, should_stop: Callable[[], bool] | None,
                ) -> tuple[list[Rotation], str, tuple[float, float]]:
        """The piece converted again with smaller rotation bounds until its rotations pass.

        Returns the rotations, ``""`` (or the last failure) and the end clearances.
        """
        steering = self.steering
        ell = self.model.edge_half_length(grasp)
        why, ends = "no refinement", (db, dr)
        fine: list[Rotation] = []
        for factor in REFINE_FACTORS:
            fine = []
            for sub in steering.iter_pieces(ca, cb, half_length=ell, should_stop=should_stop,
                                            span=(piece.t0, piece.t1), origin=piece.start,
                                            alpha_max=steering.alpha_max * factor):
                fine.extend(sub.rotations)
            why, ends = self._rotations(piece.start, tuple(fine), grasp, with_robot, db, dr)
            if not why:
                break
        return fine, why, ends

    def _box_d(self, car: Pose, grasp: int) -> float:
        return self.world.box_distance(self.model.object_from_car(car, grasp))

    def _rob_d(self, car: Pose, grasp: int) -> float:
        return self.world.held_distance(self.model.robot_from_car(car, grasp), grasp)

    def _in_bounds(self, car: Pose, grasp: int, with_robot: bool, bulge_b: float,
                   bulge_r: float) -> bool:
        m, w = self.model, self.world
        if w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))) < bulge_b:
            return False
        return not with_robot or \
            w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)) >= bulge_r

    @staticmethod
    def _swept(dist: Callable[[Pose, int], float], base: Pose, rot: Rotation, grasp: int,
               reach: float, d0: float, tol: float) -> float | None:
        """The body's clearance at the rotation's end, or ``None`` if its sweep is not free.

        ``dist``: the body's clearance at a car pose; ``reach``: its farthest point from the
        pivot (a point moves at most ``reach |angle|``); ``d0``: its clearance at ``base``.
        """
        def at(s: float) -> float:
            return dist(rotate_about(base, rot.pivot, s * rot.angle), grasp)

        d1 = dist(rot.car, grasp)
        ok = certify(at, reach * abs(rot.angle), tolerance=tol, d0=d0, d1=d1).valid
        return d1 if ok else None

    def _rotations(self, prev: Pose, rots: tuple[Rotation, ...], grasp: int, with_robot: bool,
                   db: float, dr: float) -> tuple[str, tuple[float, float]]:
        """``(failure, clearances at the end)``; failure ``""`` when every rotation passes."""
        r_box, r_rob = self._reach[grasp]
        obstacles = self.world.has_obstacles
        tol = self.tolerance
        for rot in rots:
            bulge = 1.0 - math.cos(0.5 * rot.angle)
            if not (self._in_bounds(prev, grasp, with_robot, r_box * bulge, r_rob * bulge)
                    and self._in_bounds(rot.car, grasp, with_robot, r_box * bulge,
                                        r_rob * bulge)):
                return "leaves the bounds", (db, dr)
            if obstacles:
                db_end = self._swept(self._box_d, prev, rot, grasp, r_box, db, tol)
                if db_end is None:
                    return "box collides", (db, dr)
                db = db_end
                if with_robot:
                    dr_end = self._swept(self._rob_d, prev, rot, grasp, r_rob, dr, tol)
                    if dr_end is None:
                        return "robot collides", (db, dr)
                    dr = dr_end
            prev = rot.car
        return "", (db, dr)
