"""Which smaller rotations replace a piece of a transfer edge that failed its checks.

:class:`~pivot_ompl.checking.transfer_check.TransferCheck` converts an edge's Reeds-Shepp path
piece by piece at the full rotation bound; where a piece fails, that piece alone (the same
stretch of the path, from the pose reached) is converted again by :class:`PieceRefiner`, and
the rest of the edge keeps full rotations:

1. with the rotation bound reduced in half-octave steps (:data:`REFINE_FACTORS`) while it
   stays above the bound the clearance gives (below): a few large rotations get round an
   obstacle that only a rotation's bulge touched. Where a factor passes, the largest bound
   that passes is bisected (in log) between it and the factor above that failed
   (:data:`REFINE_BISECTIONS` times): the rotations are as large as the clearance allows
   within a sixteenth of an octave, so a narrow passage takes few pivots. The stretch's last
   sub-piece is the longest its bound solves, running past the piece's end where the path
   goes on, unless it fails there (then it ends on the piece's end): no short sub-piece of
   small rotations where a refined piece meets the next;
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

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import NamedTuple

from pivot_ompl.checking.rotation_sweeps import Clearance
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.pivoting.steering import Piece, PivotSteering
from pivot_ompl.se2 import Pose

__all__ = ["LADDER_STEPS", "MIN_CLEARANCE", "REFINE_BISECTIONS", "REFINE_FACTORS",
           "SAFE_SHARE", "PieceRefiner", "Refined"]

#: A failing piece is converted again with the rotation bound times each of these factors
#: in turn (half-octave steps down to alpha_max/8) while the bound stays above the one the
#: clearance gives: the largest rotations that pass are kept.
REFINE_FACTORS = tuple(2.0 ** (-0.5 * k) for k in range(1, 7))

#: Where a factor passes (the one above failed), the largest bound that passes is bisected
#: (in log) between them this many times: within ``2 ** (-0.5 / 2 ** n)`` of the largest.
REFINE_BISECTIONS = 3

#: Share of the clearance bound ``c / r`` that certainly passes (three rotations of it move
#: no point farther than ``0.9 c``).
SAFE_SHARE = 0.3

#: Half-octave steps below alpha_max that a sub-piece's bound may take above the clearance
#: bound (down to alpha_max/128): the largest that passes the checks is kept.
LADDER_STEPS = 14

#: Least clearance (m, beyond the kept one) a path must keep to be converted sub-piece by
#: sub-piece (at least the sweep check's tolerance): the resolution of the refinement.
MIN_CLEARANCE = 0.001

#: The box's and the robot's clearances (each measured, or a lower bound carried on).
Clearances = tuple[Clearance, Clearance]
#: ``(pose, rotations, grasp, with_robot, box clearance, robot clearance)`` -> ``(failure or
#: "", clearances at the end)``: the transfer check's rotation-by-rotation check.
RotationsCheck = Callable[[Pose, tuple[Rotation, ...], int, bool, Clearance, Clearance],
                          tuple[str, Clearances]]
#: ``(car, grasp, with_robot, box clearance, robot clearance)`` (measured) -> ``(bound from
#: the clearance (rad), least clearance (m))``.
ClearanceBound = Callable[[Pose, int, bool, Clearance, Clearance], tuple[float, float]]
#: ``(clearances, grasp)`` -> the clearances, each measured where it was a lower bound.
Measure = Callable[[Clearances, int], Clearances]
Stop = Callable[[], bool] | None
#: A sub-piece and its check: the failure (``""`` if it passed) and the end clearances.
Checked = tuple[Piece, str, Clearances]


def as_measured(clear: Clearances, grasp: int) -> Clearances:
    """The clearances as they are (a check whose clearances are always measured)."""
    return clear


class Refined(NamedTuple):
    """A failed piece's stretch converted again.

    Attributes:
        rotations: the rotations that passed, in order (all of them when ``reason`` is "").
        reason: ``""``, or why the stretch could not be converted.
        clearances: the box's and robot's clearances where the rotations end.
        reached: the path's parameter reached (the piece's end, or past it).
    """

    rotations: list[Rotation]
    reason: str
    clearances: Clearances
    reached: float


@dataclass(frozen=True)
class PieceRefiner:
    """Converts a failed piece again with smaller rotations (see the module docstring).

    Args:
        model: box and robot geometry.
        steering: the pivot steering (its rotation bound is the full one).
        tolerance: the sweep check's tolerance (m).
        rotations: the transfer check's rotation-by-rotation check.
        clearance_bound: the rotation bound the clearance at a car pose gives.
        measure: the clearances measured where they are lower bounds (the clearance bound
            and a sub-piece's bound need the measured values).
    """

    model: BoxGraspModel
    steering: PivotSteering
    tolerance: float
    rotations: RotationsCheck
    clearance_bound: ClearanceBound
    measure: Measure = as_measured

    def refine(self, ca: Pose, cb: Pose, piece: Piece, grasp: int, with_robot: bool,
               clear: Clearances, should_stop: Stop, before: Rotation | None) -> Refined:
        """The piece of the path ``ca -> cb`` converted with smaller rotations that pass.

        ``clear``: the clearances at the piece's start; ``before``: the edge's last rotation
        before the piece (pieces prefer merging into it).
        """
        amax = self.steering.alpha_max
        clear = self.measure(clear, grasp)
        by_clearance, _ = self.clearance_bound(piece.start, grasp, with_robot, *clear)
        firsts: dict[float, Checked] = {}  # each bound's first sub-piece and its check
        failed = amax  # the smallest bound known to fail: the piece's own
        for factor in REFINE_FACTORS:
            alpha = amax * factor
            if alpha <= by_clearance:
                break
            done = self._uniform(ca, cb, piece, grasp, with_robot, clear, should_stop,
                                 before, alpha, firsts)
            if not done.reason:
                for _ in range(REFINE_BISECTIONS):  # the largest bound lies between
                    mid = math.sqrt(alpha * failed)
                    more = self._uniform(ca, cb, piece, grasp, with_robot, clear,
                                         should_stop, before, mid, None)
                    if more.reason:
                        failed = mid
                    else:
                        alpha, done = mid, more
                return done
            failed = alpha
        return self._by_clearance(ca, cb, piece, grasp, with_robot, clear, should_stop,
                                  before, firsts)

    def _uniform(self, ca: Pose, cb: Pose, piece: Piece, grasp: int, with_robot: bool,
                 clear: Clearances, should_stop: Stop, before: Rotation | None, alpha: float,
                 firsts: dict[float, Checked] | None) -> Refined:
        """The piece's stretch converted with rotations bounded by ``alpha`` and checked.

        Sub-piece by sub-piece (each from where the last ended, with its clearances), the
        rest not converted once one fails; the last runs past the piece's end unless it
        fails there (module docstring). ``firsts``: where each bound's first sub-piece
        inside the piece and its check are recorded.
        """
        fine: list[Rotation] = []
        at, ends, t, prev = piece.start, clear, piece.t0, before
        far = min(1.0, piece.t1 + (piece.t1 - piece.t0))
        while True:
            why, sub = "", None
            for sub in self.steering.iter_pieces(
                    ca, cb, half_length=self.model.edge_half_length(grasp),
                    should_stop=should_stop, span=(t, far), origin=at, alpha_max=alpha,
                    previous=prev):
                why, got = self.rotations(at, sub.rotations, grasp, with_robot, *ends)
                if firsts is not None and sub.t0 == piece.t0 and sub.t1 <= piece.t1:
                    firsts.setdefault(alpha, (sub, why, got))
                if why:
                    break
                fine.extend(sub.rotations)
                if sub.rotations:
                    at, prev = sub.rotations[-1].car, sub.rotations[-1]
                ends, t = got, sub.t1
                if t >= piece.t1:
                    return Refined(fine, "", ends, t)
            if why and sub is not None and far > piece.t1 and sub.t1 > piece.t1:
                far = piece.t1  # failed past the piece's end: ends on it instead
                continue
            return Refined(fine, why, ends, t)

    def _by_clearance(self, ca: Pose, cb: Pose, piece: Piece, grasp: int, with_robot: bool,
                      clear: Clearances, should_stop: Stop, before: Rotation | None,
                      firsts: dict[float, Checked]) -> Refined:
        """The piece's stretch, sub-piece by sub-piece, each bounded by its start's clearance.

        ``firsts``: by rotation bound, the first sub-piece :meth:`refine` converted from the
        piece's start and its check (the same conversion and check, from the same measured
        clearances, as the first sub-piece's here: not done again; a ladder rung is the
        bound of the same half-octave factor, the same number).
        """
        steering = self.steering
        ell = self.model.edge_half_length(grasp)
        t, current = piece.t0, piece.start
        fine: list[Rotation] = []
        floor = max(self.tolerance, MIN_CLEARANCE)
        ladder = [steering.alpha_max * 2.0 ** (-0.5 * k) for k in range(LADDER_STEPS + 1)]
        rung = 1  # the ladder's rung to try first (alpha_max failed): one above the last pass
        while t < piece.t1:
            clear = self.measure(clear, grasp)
            bound, least = self.clearance_bound(current, grasp, with_robot, *clear)
            if least < floor:
                return Refined(fine, f"path within {least:.4f} m of an obstacle or side",
                               clear, t)
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
                    why, ends = self.rotations(current, sub.rotations, grasp, with_robot,
                                               *clear)
                if not why:
                    rung = max(0, k - 1)
                    break
            if why:
                return Refined(fine, why, clear, t)
            fine.extend(sub.rotations)
            current = sub.rotations[-1].car if sub.rotations else current
            t, clear = sub.t1, ends
        return Refined(fine, "", clear, t)
