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

from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.refinement import PieceRefiner
from pivot_ompl.checking.rotation_sweeps import UNCHECKED, Clearance, RotationSweeps
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.pivoting.steering import PivotSequence, PivotSteering
from pivot_ompl.se2 import Pose
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
        #: the kernel: rotations' bounds and sweeps, clearances measured lazily
        self.sweeps = RotationSweeps(model, world, tolerance=tolerance)
        self._refiner = PieceRefiner(model, steering, tolerance, self.sweeps.rotations,
                                     self._bound_of, self.sweeps.measured)

    def reach(self, grasp: int) -> tuple[float, float]:
        """Farthest points (m) of the box and of the holding robot from a pivot corner."""
        return self.sweeps.reach[grasp]

    def in_bounds(self, car: Pose, grasp: int, with_robot: bool, bulge_b: float,
                  bulge_r: float) -> bool:
        """Whether the box's (and robot's) corners at ``car`` keep the bulges from the sides.

        See :meth:`~pivot_ompl.checking.rotation_sweeps.RotationSweeps.in_bounds`.
        """
        return self.sweeps.in_bounds(car, grasp, with_robot, bulge_b, bulge_r)

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

        sweeps = self.sweeps
        db = dr = UNCHECKED
        if self.world.has_obstacles:
            db, dr = sweeps.start(ca, grasp, with_robot)
            if db.value <= 0 or dr.value <= 0:
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
            why, ends = sweeps.rotations(piece.start, piece.rotations, grasp, with_robot, db, dr)
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
        sweeps = self.sweeps
        db = dr = UNCHECKED
        why = ""
        if self.world.has_obstacles:
            db, dr = sweeps.start(ca, grasp, True)
            why = "collides at the start" if db.value <= 0 or dr.value <= 0 else ""
        if not why:
            why, _ = sweeps.rotations(ca, rotations, grasp, True, db, dr)
        if why:
            return EdgeResult(False, PivotSequence(ca, cb, (), length, 0), length, why)
        return EdgeResult(True, PivotSequence(ca, cb, rotations, length, 0), length)

    def _bound_of(self, car: Pose, grasp: int, with_robot: bool, db: Clearance,
                  dr: Clearance) -> tuple[float, float]:
        """:meth:`_clearance_bound` of measured clearances (the refiner's)."""
        return self._clearance_bound(car, grasp, with_robot, db.value, dr.value)

    def _clearance_bound(self, car: Pose, grasp: int, with_robot: bool, db: float,
                         dr: float) -> tuple[float, float]:
        """``(min(alpha_max, c / r), c)``, least over the bodies at ``car``.

        ``c``: the clearance ``db`` or ``dr``, or the bounds' margin where it is smaller;
        ``r``: the body's reach from a pivot corner.
        """
        m, w = self.model, self.world
        r_box, r_rob = self.sweeps.reach[grasp]
        least = min(db, w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))))
        bound = least / r_box
        if with_robot:
            c_rob = min(dr, w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)))
            bound, least = min(bound, c_rob / r_rob), min(least, c_rob)
        return max(0.0, min(self.steering.alpha_max, bound)), least
