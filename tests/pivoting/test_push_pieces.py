"""The steering on straight pushes: no piece of near-zero rotations at the end of a push."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.pivoting.steering import PivotSteering

ALPHA = math.pi / 8


@settings(max_examples=200, deadline=None, derandomize=True)
@given(length=hs.floats(0.3, 3.0), heading=hs.floats(-math.pi, math.pi),
       half_length=hs.sampled_from([0.2, 0.4]))
def test_a_push_has_no_rotation_below_a_fifth_of_the_bound(length, heading, half_length):
    """A push at least one piece long ends in two balanced pieces, not a sliver.

    A push 0.7804 m long (edge 0.4 m) ended in two rotations of 0.01 and 0.0003 deg: the
    longest piece fell just short of the goal and the rest was a piece of its own (each
    rotation a pivot the robot must make, a walk with no step in it).
    """
    st = PivotSteering(turning_radius=2.0, alpha_max=ALPHA)
    goal = (length * math.cos(heading), length * math.sin(heading), heading)
    seq = st.convert((0.0, 0.0, heading), goal, half_length=half_length)
    end = seq.end
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9
    assert min(abs(r.angle) for r in seq.rotations) >= 0.2 * ALPHA


def test_the_push_that_ended_in_a_sliver():
    st = PivotSteering(turning_radius=2.0, alpha_max=ALPHA)
    seq = st.convert((0.0, 0.0, 0.0), (0.7804216394516166, 0.0, 0.0), half_length=0.2)
    assert min(abs(r.angle) for r in seq.rotations) >= 0.2 * ALPHA
    assert len(seq.rotations) == 13  # as many as with the sliver
