"""A transfer edge checked: its pivot sequence inside the bounds and certified collision-free.

The steering (:class:`~pivot_ompl.pivoting.steering.PivotSteering`) cuts the car's
Reeds-Shepp path into pieces, each solved by up to three rotations that end exactly on the
path. Rotation by rotation, the box and the robot must stay inside the bounds (their farthest
points bulge out by ``r (1 - cos(alpha/2))`` mid-rotation) and their swept volumes must be
certified free (:func:`~pivot_ompl.validity.certify.certify`: a point moves at most
``r |alpha|``, ``r`` the body's reach from the pivot corner).

Where a piece fails, that piece alone (the same stretch of the path, from the pose reached)
is converted again; the rest of the edge keeps full rotations:

1. with the rotation bound reduced in half-octave steps (:data:`REFINE_FACTORS`) while it
   stays above the bound the clearance gives (below): a few large rotations get round an
   obstacle that only a rotation's bulge touched;
2. else **sub-piece by sub-piece**, each with the largest bound that passes: the half-octave
   rungs below ``alpha_max`` (:data:`LADDER_STEPS`, from one rung above the last sub-piece's
   down to the clearance bound; each sub-piece's rotations checked exactly as any other), so
   only the stretch near the obstacle takes small rotations and those only as small as the
   sweep needs; below them the **bound chosen from the clearance** ``c`` (beyond
   the kept clearance, the bounds' margin included) that the box and the robot have at the
   sub-piece's start, which is a pose of the path: first ``alpha = c / r`` (no rotation moves
   a point farther than ``c``: through a slot with ``c`` of slack the box's yaw swings by
   about ``alpha / 2``, so its far corners sweep ``depth sin(alpha / 2) < c / 2`` sideways),
   then :data:`SAFE_SHARE` of it, which cannot fail: three rotations move no point farther
   than ``3 r alpha < c``.

Completeness (resolution ``c_min = max(tolerance, MIN_CLEARANCE)``): a Reeds-Shepp path
whose bodies keep at least ``c_min`` beyond the kept clearance at every pose (and inside the
bounds) is converted into a valid pivot sequence: every sub-piece starts on the path with
``c >= c_min``, so its bound ``SAFE_SHARE c_min / r`` is positive, and its rotations are
certified by the clearance alone (no tolerance used). A path that comes closer than ``c_min``
at a sub-piece's start is reported as such. Step 1 only shortens the work; it may accept a
rotation with the sweep check's ``tolerance``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.checking.rotation_sweeps import UNCHECKED, Clearance, RotationSweeps
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.pivoting.steering import Piece, PivotSequence, PivotSteering
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.collision import CollisionWorld

#: A failing piece is converted again with the rotation bound times each of these factors
#: in turn (half-octave steps down to alpha_max/8) while the bound stays above the one the
#: clearance gives: the largest rotations that pass are kept.
REFINE_FACTORS = tuple(2.0 ** (-0.5 * k) for k in range(1, 7))

#: Share of the clearance bound ``c / r`` that certainly passes (three rotations of it move
#: no point farther than ``0.9 c``).
SAFE_SHARE = 0.3

#: Half-octave steps below alpha_max that a sub-piece's bound may take above the clearance
#: bound (down to alpha_max/128): the largest that passes the checks is kept.
LADDER_STEPS = 14

#: A sub-piece and its check: the failure (``""`` if it passed) and the end clearances.
_Checked = tuple[Piece, str, tuple[Clearance, Clearance]]

#: Least clearance (m, beyond the kept one) a path must keep to be converted sub-piece by
#: sub-piece (at least the sweep check's tolerance): the resolution of the refinement.
MIN_CLEARANCE = 0.001


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
        reply: tuple[Pose, Rotation | None] | None = None
        while True:
            try:
                piece = pieces.send(reply) if reply is not None else next(pieces)
            except StopIteration:
                break
            reply = None
            why, ends = sweeps.rotations(piece.start, piece.rotations, grasp, with_robot, db, dr)
            if why:
                fine, why, ends = self._refine(ca, cb, piece, grasp, with_robot, db, dr,
                                               should_stop, checked[-1] if checked else None)
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

    def _refine(self, ca: Pose, cb: Pose, piece: Piece, grasp: int, with_robot: bool,
                db: Clearance, dr: Clearance, should_stop: Callable[[], bool] | None,
                before: Rotation | None) -> tuple[list[Rotation], str,
                                                  tuple[Clearance, Clearance]]:
        """The piece converted again with smaller rotations until they pass (module docstring).

        ``before``: the edge's last rotation before the piece (pieces prefer merging into it).
        Returns the rotations, ``""`` (or the last failure) and the end clearances.
        """
        steering = self.steering
        ell = self.model.edge_half_length(grasp)
        db, dr = self.sweeps.measured((db, dr), grasp)
        by_clearance, _ = self._clearance_bound(piece.start, grasp, with_robot, db.value,
                                                dr.value)
        firsts: dict[float, _Checked] = {}  # each bound's first sub-piece and its check
        for factor in REFINE_FACTORS:
            alpha = steering.alpha_max * factor
            if alpha <= by_clearance:
                break
            # checked sub-piece by sub-piece (as one sequence: each from where the last ended,
            # with its clearances), the rest not converted once one fails
            fine: list[Rotation] = []
            at, ends, why = piece.start, (db, dr), ""
            for sub in steering.iter_pieces(ca, cb, half_length=ell, should_stop=should_stop,
                                            span=(piece.t0, piece.t1), origin=piece.start,
                                            alpha_max=alpha, previous=before):
                why, ends = self.sweeps.rotations(at, sub.rotations, grasp, with_robot, *ends)
                if alpha not in firsts:
                    firsts[alpha] = (sub, why, ends)
                if why:
                    break
                fine.extend(sub.rotations)
                at = sub.rotations[-1].car if sub.rotations else at
            if not why:
                return fine, "", ends
        return self._by_clearance(ca, cb, piece, grasp, with_robot, (db, dr), should_stop,
                                  before, firsts)

    def _by_clearance(self, ca: Pose, cb: Pose, piece: Piece, grasp: int, with_robot: bool,
                      clear: tuple[Clearance, Clearance],
                      should_stop: Callable[[], bool] | None,
                      before: Rotation | None, firsts: dict[float, _Checked],
                      ) -> tuple[list[Rotation], str, tuple[Clearance, Clearance]]:
        """The piece's stretch, sub-piece by sub-piece, each bounded by its start's clearance.

        ``firsts``: by rotation bound, the first sub-piece :meth:`_refine` converted from the
        piece's start and its check (the same conversion and check, from the same measured
        clearances, as the first sub-piece's here: not done again; a ladder rung is the
        bound of the same half-octave factor, the same number).
        Returns the rotations, ``""`` (or the failure) and the end clearances.
        """
        steering = self.steering
        ell = self.model.edge_half_length(grasp)
        t, current = piece.t0, piece.start
        fine: list[Rotation] = []
        floor = max(self.tolerance, MIN_CLEARANCE)
        ladder = [steering.alpha_max * 2.0 ** (-0.5 * k) for k in range(LADDER_STEPS + 1)]
        rung = 1  # the ladder's rung to try first (alpha_max failed): one above the last pass
        while t < piece.t1:
            clear = self.sweeps.measured(clear, grasp)
            bound, least = self._clearance_bound(current, grasp, with_robot, clear[0].value,
                                                 clear[1].value)
            if least < floor:
                return fine, f"path within {least:.4f} m of an obstacle or side", clear
            why = "no sub-piece"
            tries = [(k, a) for k, a in enumerate(ladder) if k >= rung and a > bound]
            tries += [(len(ladder), bound), (len(ladder), SAFE_SHARE * bound)]
            for k, alpha in tries:
                known = firsts.get(alpha) if t == piece.t0 else None
                if known is not None:
                    sub, why, ends = known
                else:
                    pieces = steering.iter_pieces(ca, cb, half_length=ell,
                                                  should_stop=should_stop, span=(t, piece.t1),
                                                  origin=current, alpha_max=alpha,
                                                  previous=fine[-1] if fine else before)
                    sub = next(pieces)
                    pieces.close()
                    why, ends = self.sweeps.rotations(current, sub.rotations, grasp,
                                                      with_robot, *clear)
                if not why:
                    rung = max(0, k - 1)
                    break
            if why:
                return fine, why, clear
            fine.extend(sub.rotations)
            current = sub.rotations[-1].car if sub.rotations else current
            t, clear = sub.t1, ends
        return fine, "", clear

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
