"""The steering on Reeds-Shepp arcs: few pivots, as a car turning alternates unequal rotations."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.se2 import wrap_angle

ALPHA = math.pi / 8
RADIUS = 2.0


def _arc_ideal(length, ell):
    """Fewest rotations along an arc of the turning radius: pairs ``a``, ``-b`` with
    ``l (a + b)`` of way and ``a - b`` of turn per pair, ``a = alpha_max``."""
    k = RADIUS / ell
    b = ALPHA * (k - 1.0) / (k + 1.0)
    return 2.0 * length / (ell * (ALPHA + b))


def test_a_quarter_turn_arc_needs_near_the_fewest_rotations():
    st = PivotSteering(turning_radius=RADIUS, alpha_max=ALPHA)
    goal = (RADIUS, RADIUS, 0.5 * math.pi)  # a quarter of the turning circle
    seq = st.convert((0.0, 0.0, 0.0), goal, half_length=0.2)
    ideal = _arc_ideal(0.5 * math.pi * RADIUS, 0.2)
    # three rotations a piece (the longest pieces, none merging) took 57: 1.29 x
    assert len(seq.rotations) <= 1.1 * ideal, (len(seq.rotations), ideal)
    assert max(abs(r.angle) for r in seq.rotations) <= ALPHA + 1e-9
    end = seq.end
    assert math.hypot(end[0] - goal[0], end[1] - goal[1]) < 1e-9
    assert abs(wrap_angle(end[2] - goal[2])) < 1e-9


@settings(max_examples=30, deadline=None)
@given(x=hs.floats(-3.0, 3.0), y=hs.floats(-3.0, 3.0), h=hs.floats(-math.pi, math.pi),
       ell=hs.floats(0.15, 0.45))
def test_goal_reached_exactly_within_the_bound(x, y, h, ell):
    st = PivotSteering(turning_radius=RADIUS, alpha_max=ALPHA)
    seq = st.convert((0.0, 0.0, 0.0), (x, y, h), half_length=ell)
    end = seq.end
    assert math.hypot(end[0] - x, end[1] - y) < 1e-8
    assert abs(wrap_angle(end[2] - h)) < 1e-8
    assert all(abs(r.angle) <= ALPHA + 1e-9 for r in seq.rotations)
    # consecutive rotations about one corner were merged wherever they could be
    assert all(a.end != b.end or abs(a.angle + b.angle) > ALPHA
               for a, b in zip(seq.rotations, seq.rotations[1:], strict=False))
