"""The held poses' proof's estimate from the pieces it sums, read off the scene's floor.

:func:`~pivot_ompl.analysis.pose_proof.proof_estimate` needs only the scene: every obstacle
piece, summed at :data:`~pivot_ompl.analysis.pose_proof.ESTIMATED_BINS` bins (the whole
proof's upper figure, what a caller without a floor reads). The proof itself sums first only
the pieces near the room's narrow passages where they are few enough
(:func:`~pivot_ompl.analysis.pose_proof.prove_no_plan`): on the lab door's 1506 boxes 167
pieces, its proof 2.3 s of CPU against the 19.3 s estimated from every piece.
:func:`held_estimate` counts the pieces of that first try on a built
:class:`~pivot_ompl.analysis.pose_floor.HeldFloor` (its pieces near the room and near the
passages, kept by the floor for the proof that follows: about 0.1 s on the lab's floor) and
prices them at the same cost per piece, bin and grasp, with a cost per bin
(:data:`SECONDS_PER_BIN`) that a few pieces' proof does not hide: 2.8 s for the lab door's
2.3 s.

Where the passages' try runs, the estimate is the try's: the cost of an answer "apart"
there. Joined there, the proof starts again with every piece and costs the try's and
:func:`~pivot_ompl.analysis.pose_proof.proof_estimate`'s: the late proof
(:mod:`~pivot_ompl.analysis.late_proof`) reads this estimate only where every way from start
to goal passes a gap narrower than the held assembly (most often no plan), the every-piece
one elsewhere.
"""

from __future__ import annotations

from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_proof import (
    ESTIMATED_BINS,
    SECONDS_PER_PIECE,
    count_pieces,
    passages_try,
    proof_estimate,
)
from pivot_ompl.grasp import GRASPS

#: Largest share of the pieces near the room held by the passages' try for its estimate to
#: stand for the proof's (:func:`held_estimate`): the lab door's try holds 14 % of them and
#: ends its proof; the office's (every way passing gaps narrower than the held assembly, a
#: plan with two regrasps) 41 %, and joins start and goal: a proof admitted by the try's
#: estimate there would cost its search the held window for nothing.
TRY_SHARE = 0.25
#: Time (s) of one bin's regions and chain search besides its pieces' sums, every grasp
#: together (about 10 ms: proofs of a few pieces on 0.05 m map floors took 9-16 ms a bin;
#: the lab door's 167 pieces 41 ms a bin, 11 ms of it this).
SECONDS_PER_BIN = 0.01


def pieces_seconds(pieces: int) -> float:
    """Estimated time (s) of a proof summing ``pieces`` pieces (:data:`ESTIMATED_BINS` bins)."""
    return ESTIMATED_BINS * (SECONDS_PER_BIN + len(GRASPS) * pieces * SECONDS_PER_PIECE)


def held_estimate(floor: HeldFloor) -> float:
    """Estimated time (s) of :func:`~pivot_ompl.analysis.pose_proof.prove_no_plan` on ``floor``.

    ``floor``: the scene's floor at the proof's clearance (its pieces near the room and near
    the passages are counted, and kept for the proof). Where the proof's passages' try runs
    on at most :data:`TRY_SHARE` of the pieces, the try's (:func:`pieces_seconds` of its
    pieces: an answer "apart" there ends the proof, the module docstring); else
    :func:`~pivot_ompl.analysis.pose_proof.proof_estimate`.
    """
    tried = passages_try(floor, floor.clearance)
    if tried is not None and (
            count_pieces(tried) <= TRY_SHARE * count_pieces(floor.near_room(floor.clearance))):
        return pieces_seconds(count_pieces(tried))
    return proof_estimate(floor.scene)
