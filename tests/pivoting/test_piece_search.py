"""The choice between the longest piece and a shorter one whose first rotation merges."""

from __future__ import annotations

import math

from pivot_ompl.pivoting.kinematics import Rotation
from pivot_ompl.pivoting.piece_search import fewer_pivots

CAR = (0.0, 0.0, 0.0)


def _rot(end: int, angle: float) -> Rotation:
    return Rotation(end, (0.0, 0.0), angle, CAR)


def test_a_merging_piece_of_one_rotation_wins_without_dividing_by_zero():
    # regression: the advance per rotation added divided by len(rotations) - 1
    previous = _rot(0, 0.1)
    alpha = math.pi / 8
    longest = (CAR, (_rot(1, 0.3), _rot(0, -0.3), _rot(1, 0.3)))

    def solve(t: float):
        return (CAR, (_rot(0, 0.1),)) if t <= 0.9 else None

    t, piece = fewer_pivots(solve, previous, alpha, 0.0, 1.0, longest)
    assert len(piece[1]) == 1 and 0.0 < t <= 0.9


def test_the_longest_piece_is_kept_when_the_merging_one_advances_too_little():
    previous = _rot(0, 0.1)
    alpha = math.pi / 8
    longest = (CAR, (_rot(1, 0.3), _rot(0, -0.3)))  # two rotations the whole way

    def solve(t: float):  # merges only on the first 0.7 of the way, adding two rotations
        return (CAR, (_rot(0, 0.1), _rot(1, 0.2), _rot(0, 0.2))) if t <= 0.7 else None

    t, piece = fewer_pivots(solve, previous, alpha, 0.0, 1.0, longest)
    assert t == 1.0 and piece is longest
