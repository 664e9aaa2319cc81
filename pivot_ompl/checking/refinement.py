"""Which smaller rotations replace a piece of a transfer edge that failed its checks.

:class:`~pivot_ompl.checking.transfer_check.TransferCheck` converts an edge's Reeds-Shepp path
piece by piece at the full rotation bound; where a piece fails, that piece alone (the same
stretch of the path, from the pose reached) is converted again by :class:`PieceRefiner`, and
the rest of the edge keeps full rotations.

The stretch is converted **sub-piece by sub-piece, each with the largest rotation bound that
passes its own checks** (a sub-piece is the longest piece of the path that three rotations
within the bound reach from the pose reached, as the steering makes them, preferring
rotations that merge into the one before): the half-octave rungs below ``alpha_max``
(:data:`LADDER_STEPS`, down to the bound the clearance gives, below) from the top, and where
a rung passes and the one above it failed, the largest passing bound is bisected (in log)
between them (:data:`REFINE_BISECTIONS` times: within a sixteenth of an octave). So the
rotations follow the clearance along the stretch (a slot's entry, middle and exit each take
the largest rotations their own room allows, not the tightest spot's), every sub-piece's
rotations are checked exactly as any other, and the last sub-piece runs on past the piece's
end where the path goes on (no short sub-piece of small rotations where a refined piece meets
the next). Below the ladder come the **bounds chosen from the clearance** ``c`` (beyond the
kept clearance, the bounds' margin included) that the box and the robot have at the
sub-piece's start, which is a pose of the path: first ``alpha = c / r`` (no rotation moves a
point farther than ``c``), then :data:`SAFE_SHARE` of it, which cannot fail: three rotations
move no point farther than ``3 r alpha < c``.

Completeness (resolution ``c_min = max(tolerance, MIN_CLEARANCE)``): a Reeds-Shepp path
whose bodies keep at least ``c_min`` beyond the kept clearance at every pose (and inside the
bounds) is converted into a valid pivot sequence: every sub-piece starts on the path with
``c >= c_min``, so its last bound ``SAFE_SHARE c_min / r`` is positive, and its rotations are
certified by the clearance alone (no tolerance used). A path that comes closer than ``c_min``
at a sub-piece's start is reported as such. The larger bounds only shorten the work and
lengthen the rotations; they may accept a rotation with the sweep check's ``tolerance``.
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

__all__ = ["CREEP", "LADDER_STEPS", "MIN_CLEARANCE", "REFINE_BISECTIONS", "SAFE_SHARE",
           "PieceRefiner", "Refined"]

#: Where a rung passes and the one above it failed, the largest bound that passes is bisected
#: (in log) between them this many times: within ``2 ** (-0.5 / 2 ** n)`` of the largest.
REFINE_BISECTIONS = 3

#: A sub-piece tries its predecessor's bound, and this factor above it where that passes
#: (an eighth of an octave: the room changes little from one sub-piece to the next).
CREEP = 2.0 ** 0.125

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


def _largest_passing(attempt: Callable[[float], Checked], bounds: list[float],
                     failed: float | None) -> tuple[float, Checked]:
    """The largest of ``bounds`` (descending) whose sub-piece passes, bisected upwards.

    ``attempt(alpha)`` converts and checks one sub-piece with rotations within ``alpha``;
    ``failed``: a bound above ``bounds[0]`` known to fail, if any. Where a bound passes and
    a larger one failed, the largest passing bound between them is bisected (in log,
    :data:`REFINE_BISECTIONS` times). ``(bound, its check)``; the last bound's failed check
    when none passes.
    """
    done: Checked | None = None
    for alpha in bounds:
        done = attempt(alpha)
        if done[1]:
            failed = alpha
            continue
        if failed is not None:
            for _ in range(REFINE_BISECTIONS):
                mid = math.sqrt(alpha * failed)
                more = attempt(mid)
                if more[1]:
                    failed = mid
                else:
                    alpha, done = mid, more
        return alpha, done
    assert done is not None  # noqa: S101 - bounds is never empty
    return bounds[-1], done


class _Stretch(NamedTuple):
    """The failed piece of the path ``ca -> cb`` being converted again, and its checks."""

    ca: Pose
    cb: Pose
    piece: Piece
    grasp: int
    with_robot: bool
    should_stop: Stop


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
            needs the measured values).
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
        floor = max(self.tolerance, MIN_CLEARANCE)
        t, current, prev = piece.t0, piece.start, before
        fine: list[Rotation] = []
        last: float | None = None  # the previous sub-piece's bound
        while t < piece.t1:
            clear = self.measure(clear, grasp)
            bound, least = self.clearance_bound(current, grasp, with_robot, *clear)
            if least < floor:
                return Refined(fine, f"path within {least:.4f} m of an obstacle or side",
                               clear, t)
            last, (sub, why, ends) = self._sub_piece(
                _Stretch(ca, cb, piece, grasp, with_robot, should_stop), t, current, prev,
                clear, bound, last)
            if why:
                return Refined(fine, why, clear, t)
            fine.extend(sub.rotations)
            if sub.rotations:
                current, prev = sub.rotations[-1].car, sub.rotations[-1]
            t, clear = sub.t1, ends
        return Refined(fine, "", clear, t)

    def _sub_piece(self, at: _Stretch, t: float, current: Pose, prev: Rotation | None,
                   clear: Clearances, bound: float,
                   last: float | None) -> tuple[float, Checked]:
        """The next sub-piece from parameter ``t`` (pose ``current``) and its bound.

        ``bound``: the bound the clearance gives there; ``last``: the previous sub-piece's
        bound (``None`` for the stretch's first). The previous bound first, and a step of
        :data:`CREEP` above it where it passes (the room changes little from one sub-piece
        to the next); else the ladder's rungs below it down to ``bound``, then ``bound`` and
        its safe share (:func:`_largest_passing`, bisected); each sub-piece runs on past the
        piece's end where the path goes on, and where a larger bound's sub-piece failed past
        the end and the one found does not reach it, the largest of those bounds whose
        sub-piece ending on the piece's end passes is taken instead. ``(bound, check)``.
        """
        piece = at.piece
        amax = self.steering.alpha_max
        far = min(1.0, piece.t1 + (piece.t1 - piece.t0))
        crossed: list[float] = []  # bounds whose sub-piece failed past the piece's end

        def convert(alpha: float, end: float) -> Checked:
            pieces = self.steering.iter_pieces(
                at.ca, at.cb, half_length=self.model.edge_half_length(at.grasp),
                should_stop=at.should_stop, span=(t, end), origin=current, alpha_max=alpha,
                previous=prev)
            sub = next(pieces)
            pieces.close()
            why, ends = self.rotations(current, sub.rotations, at.grasp, at.with_robot, *clear)
            return sub, why, ends

        def running_on(alpha: float) -> Checked:
            done = convert(alpha, far)
            if done[1] and done[0].t1 > piece.t1:
                crossed.append(alpha)
            return done

        ladder = [amax * 2.0 ** (-0.5 * k) for k in range(LADDER_STEPS + 1)]
        if t == piece.t0:  # the piece is the stretch's first sub-piece at alpha_max: failed
            tries, failed = ladder[1:], amax
        else:  # alpha_max (the room may open), then from the rung above the last bound
            top = min((a for a in ladder if a > CREEP * (last or 0.0)), default=amax)
            tries, failed = ladder[:1] + [a for a in ladder[1:] if a <= top], None
        bounds = [a for a in tries if a > bound] + \
            [a for a in (bound, SAFE_SHARE * bound) if a > 0.0]
        found = _largest_passing(running_on, bounds, failed)
        alpha, done = found
        if crossed and (done[1] or done[0].t1 < piece.t1):
            for larger in sorted(crossed, reverse=True):  # ending on the piece's end
                end_on = convert(larger, piece.t1)
                if not end_on[1]:
                    return larger, end_on
        return alpha, done
