"""The edge turned about a corner: the scalar turn and the rotation record agree."""

from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.pivoting.kinematics import LEFT, edge_turn, end_point, forward, solve_piece
from pivot_ompl.pivoting.spin_chain import rotate_edge

coordinates = st.floats(-50.0, 50.0, allow_nan=False)
headings = st.floats(-4.0 * math.pi, 4.0 * math.pi, allow_nan=False)
angles = st.floats(-math.pi, math.pi, allow_nan=False)


def _close(a: tuple[float, ...], b: tuple[float, ...]) -> bool:
    return len(a) == len(b) and all(abs(u - v) <= 1e-12 for u, v in zip(a, b, strict=True))


@settings(max_examples=500)
@given(x=coordinates, y=coordinates, h=headings, end=st.sampled_from([LEFT, 1 - LEFT]),
       ell=st.floats(0.05, 1.5), angle=angles)
def test_the_scalar_turn_is_the_rotations_record(x, y, h, end, ell, angle):
    # edge_turn (the lead search's form: no record, the angle's cosine and sine given)
    # reaches the pose and pivot of rotate_edge's record; the pivot is the corner turned
    # about, before and after the turn (it does not move), and the three-rotation forward
    # map with one rotation agrees
    px, py, reached = edge_turn(x, y, h, end, ell, angle, math.cos(angle), math.sin(angle))
    r = rotate_edge((x, y, h), end, angle, ell)
    assert r.end == end and r.angle == angle
    assert _close(r.pivot, (px, py)) and _close(r.car, reached)
    assert _close(end_point((x, y, h), ell, end), (px, py))
    assert _close(end_point(reached, ell, end), (px, py))
    assert _close(forward((x, y, h), ell, end, (angle, 0.0, 0.0)), reached)


@settings(max_examples=300)
@given(x=coordinates, y=coordinates, h=headings, ell=st.floats(0.05, 1.5),
       move=st.tuples(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.floats(-1.0, 1.0)),
       previous=st.booleans())
def test_the_steerings_rotations_are_the_edge_turns(x, y, h, ell, move, previous):
    # solve_piece writes edge_turn's arithmetic out in its inner loop: each rotation it gives
    # is, to the bit, the edge turned about its corner from the car reached before
    alpha_max = math.pi / 8
    start = (x, y, h)
    goal = (x + move[0] * ell, y + move[1] * ell, h + move[2] * alpha_max)
    before = rotate_edge(start, LEFT, 0.1, ell) if previous else None
    ok, rotations = solve_piece(start, goal, ell, alpha_max, previous=before)
    car = start
    for r in rotations:
        px, py, reached = edge_turn(*car, r.end, ell, r.angle, math.cos(r.angle),
                                    math.sin(r.angle))
        assert r.pivot == (px, py) and r.car == reached
        car = reached
    assert ok or not rotations

