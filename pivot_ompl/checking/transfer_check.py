"""A transfer edge checked: its pivot sequence inside the bounds and certified collision-free.

The steering (:class:`~pivot_ompl.pivoting.steering.PivotSteering`) cuts the car's
Reeds-Shepp path into pieces, each solved by up to three rotations that end exactly on the
path. Rotation by rotation, the box and the robot must stay inside the bounds (their farthest
points bulge out by ``r (1 - cos(alpha/2))`` mid-rotation) and their swept volumes must be
certified free (:func:`~pivot_ompl.validity.certify.certify`: a point moves at most
``r |alpha|``, ``r`` the body's reach from the pivot corner).

Where a piece fails, that piece alone is converted again with smaller rotations, as large
as pass (:class:`~pivot_ompl.checking.refinement.PieceRefiner`, whose docstring says how
they are chosen and why the conversion is complete); the rest of the edge keeps full
rotations.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.refinement import PieceRefiner
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import LEFT, Rotation
from pivot_ompl.pivoting.steering import PivotSequence, PivotSteering
from pivot_ompl.se2 import Pose, rotate_about
from pivot_ompl.validity.certify import certify
from pivot_ompl.validity.collision import CollisionWorld


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
        #: per grasp, the farthest corner (m) of the box and of the holding robot from the car
        self._spread: dict[int, tuple[float, float]] = {}
        for g in range(4):
            car = (0.0, 0.0, 0.0)
            a = model.pivots(car, g)[LEFT]
            box = model.object_corners(model.object_from_car(car, g))
            rob = model.held_corners(model.robot_from_car(car, g), g)
            self._reach[g] = (max(math.hypot(x - a[0], y - a[1]) for x, y in box),
                              max(math.hypot(x - a[0], y - a[1]) for x, y in rob))
            self._spread[g] = (max(math.hypot(x, y) for x, y in box),
                               max(math.hypot(x, y) for x, y in rob))
        self._refiner = PieceRefiner(model, steering, tolerance, self._rotations,
                                     self._clearance_bound)

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
        reply: tuple[Pose, Rotation | None, float] | None = None
        while True:
            try:
                piece = pieces.send(reply) if reply is not None else next(pieces)
            except StopIteration:
                break
            reply = None
            why, ends = self._rotations(piece.start, piece.rotations, grasp, with_robot, db, dr)
            if why:
                fine, why, ends, reached = self._refiner.refine(
                    ca, cb, piece, grasp, with_robot, (db, dr), should_stop,
                    checked[-1] if checked else None)
                if why:
                    return fail(f"{why} during rotation {len(checked)} "
                                f"(path {piece.t0:.3f}..{piece.t1:.3f})")
                self._refined()
                checked.extend(fine)
                reply = (fine[-1].car if fine else piece.start, fine[-1] if fine else None,
                         reached)
            else:
                checked.extend(piece.rotations)
            db, dr = ends
        # rotations about one corner merged exactly as PivotSteering.convert merges them: the
        # merged rotation sweeps the union of the two checked sweeps
        merged: list[Rotation] = []
        for r in checked:
            steering.append_merged(merged, r)
        return EdgeResult(True, PivotSequence(ca, cb, tuple(merged), length, 0), length)

    def check_given(self, ca: Pose, cb: Pose, rotations: tuple[Rotation, ...],
                    grasp: int) -> EdgeResult:
        """Given rotations (made earlier) from car pose ``ca`` to ``cb``, checked.

        Checked as :meth:`check` checks its own, against the scene as it is now: rotation by
        rotation, the box and the robot inside the bounds and their sweeps certified. The
        rotations must chain from ``ca`` (each about a pivot corner of the car it
        starts from, within the rotation bound) and end at ``cb``: the caller makes sure.
        """
        length = self.steering.paths.distance(ca, cb)
        db = dr = math.inf
        why = ""
        if self.world.has_obstacles:
            db, dr = self._box_d(ca, grasp), self._rob_d(ca, grasp)
            why = "collides at the start" if db <= 0 or dr <= 0 else ""
        if not why:
            why, _ = self._rotations(ca, rotations, grasp, True, db, dr)
        if why:
            return EdgeResult(False, PivotSequence(ca, cb, (), length, 0), length, why)
        return EdgeResult(True, PivotSequence(ca, cb, rotations, length, 0), length)

    def _clearance_bound(self, car: Pose, grasp: int, with_robot: bool, db: float,
                         dr: float) -> tuple[float, float]:
        """``(min(alpha_max, c / r), c)``, least over the bodies at ``car``.

        ``c``: the clearance ``db`` or ``dr``, or the bounds' margin where it is smaller;
        ``r``: the body's reach from a pivot corner.
        """
        m, w = self.model, self.world
        r_box, r_rob = self._reach[grasp]
        least = min(db, w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))))
        bound = least / r_box
        if with_robot:
            c_rob = min(dr, w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)))
            bound, least = min(bound, c_rob / r_rob), min(least, c_rob)
        return max(0.0, min(self.steering.alpha_max, bound)), least

    def _box_d(self, car: Pose, grasp: int) -> float:
        return self.world.box_distance(self.model.object_from_car(car, grasp))

    def _rob_d(self, car: Pose, grasp: int) -> float:
        return self.world.held_distance(self.model.robot_from_car(car, grasp), grasp)

    def in_bounds(self, car: Pose, grasp: int, with_robot: bool, bulge_b: float,
                   bulge_r: float) -> bool:
        """Whether the box's (and robot's) corners at ``car`` keep the bulges from the sides.

        Accepted at once when the car keeps a body's farthest corner (:attr:`_spread`) plus
        its bulge from every side (a corner is no farther from a side than that); else the
        corners are placed and measured.
        """
        m, w = self.model, self.world
        x0, y0, x1, y1 = w.bounds
        margin = min(car[0] - x0, x1 - car[0], car[1] - y0, y1 - car[1])
        s_box, s_rob = self._spread[grasp]
        if margin - s_box >= bulge_b and (not with_robot or margin - s_rob >= bulge_r):
            return True
        if w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))) < bulge_b:
            return False
        return not with_robot or \
            w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)) >= bulge_r

    @staticmethod
    def _swept(dist: Callable[[Pose, int], float], base: Pose, rot: Rotation, grasp: int,
               reach: float, d0: float, tol: float, *, last: bool) -> float | None:
        """The body's clearance at the rotation's end, or ``None`` if its sweep is not free.

        ``dist``: the body's clearance at a car pose; ``reach``: its farthest point from the
        pivot (a point moves at most ``reach |angle|``); ``d0``: its clearance at ``base``,
        or a positive lower bound of it. Not ``last`` (another rotation follows in the same
        check), a sweep whose ``d0`` exceeds the farthest any point moves is free with no
        query, and its end keeps at least ``d0 - reach |angle|`` (a lower bound, returned);
        the ``last`` rotation's end clearance is always measured. A lower bound for ``d0``
        never changes whether a sweep passes: :func:`~pivot_ompl.validity.certify.certify`
        then bisects only intervals the exact clearance would have accepted as free.
        """
        lipschitz = reach * abs(rot.angle)
        if not last and d0 > lipschitz:
            return d0 - lipschitz

        def at(s: float) -> float:
            return dist(rotate_about(base, rot.pivot, s * rot.angle), grasp)

        d1 = dist(rot.car, grasp)
        ok = certify(at, lipschitz, tolerance=tol, d0=d0, d1=d1).valid
        return d1 if ok else None

    def _rotations(self, prev: Pose, rots: tuple[Rotation, ...], grasp: int, with_robot: bool,
                   db: float, dr: float) -> tuple[str, tuple[float, float]]:
        """``(failure, clearances at the end)``; failure ``""`` when every rotation passes.

        The clearances between rotations may be lower bounds (:meth:`_swept`); those returned
        at the end, where the next check or a refinement starts, are measured.
        """
        r_box, r_rob = self._reach[grasp]
        obstacles = self.world.has_obstacles
        tol = self.tolerance
        for i, rot in enumerate(rots):
            last = i == len(rots) - 1
            bulge = 1.0 - math.cos(0.5 * rot.angle)
            if not (self.in_bounds(prev, grasp, with_robot, r_box * bulge, r_rob * bulge)
                    and self.in_bounds(rot.car, grasp, with_robot, r_box * bulge,
                                        r_rob * bulge)):
                return "leaves the bounds", (db, dr)
            if obstacles:
                db_end = self._swept(self._box_d, prev, rot, grasp, r_box, db, tol, last=last)
                if db_end is None:
                    return "box collides", (db, dr)
                db = db_end
                if with_robot:
                    dr_end = self._swept(self._rob_d, prev, rot, grasp, r_rob, dr, tol,
                                         last=last)
                    if dr_end is None:
                        return "robot collides", (db, dr)
                    dr = dr_end
            prev = rot.car
        return "", (db, dr)
