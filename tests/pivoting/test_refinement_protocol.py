"""A local refinement tells the steering where its rotations ended on the path."""

from __future__ import annotations

import math

from pivot_ompl.pivoting.steering import PivotSteering

CA, CB = (0.0, 0.0, 0.0), (2.0, 0.5, 0.3)


def test_the_next_piece_starts_at_the_parameter_sent_back():
    steering = PivotSteering(turning_radius=1.0, alpha_max=math.pi / 8)
    pieces = steering.iter_pieces(CA, CB, half_length=0.2)
    first = next(pieces)
    t = first.t1 + 0.5 * (first.t1 - first.t0)  # the refinement ran on past the piece
    reached = steering.paths.interpolate(CA, CB, t)
    second = pieces.send((reached, None, t))
    assert second.t0 == t and second.start == reached
    assert second.t1 > t


def test_a_reply_without_a_parameter_ends_on_the_piece():
    steering = PivotSteering(turning_radius=1.0, alpha_max=math.pi / 8)
    pieces = steering.iter_pieces(CA, CB, half_length=0.2)
    first = next(pieces)
    second = pieces.send((first.target, None))
    assert second.t0 == first.t1 and second.start == first.target
