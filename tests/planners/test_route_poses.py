"""Object poses along a box route: the box's centre passes the corners, the car spins or pushes."""

from __future__ import annotations

import math

from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.base.problem import make_problem
from pivot_ompl.planners.route_poses import NO_MOVE, route_poses
from pivot_ompl.se2 import wrap_angle

START = (1.0, 3.0, 0.0)
GOAL = (7.0, 3.0, 0.0)


def _checker():
    scene = make_scene(start=list(START), goal=list(GOAL), bounds=[-1.0, -1.0, 9.0, 7.0])
    return make_problem(scene).checker


CHECKER = _checker()

points = hs.tuples(hs.floats(0.0, 8.0), hs.floats(0.0, 6.0))
poses = hs.tuples(hs.floats(0.0, 8.0), hs.floats(0.0, 6.0), hs.floats(-math.pi, math.pi))


@settings(max_examples=60, deadline=None)
@given(poses, poses, hs.lists(points, min_size=0, max_size=4), hs.sampled_from([0, 1, 2, 3]),
       hs.booleans())
def test_spins_and_straight_legs_whose_box_passes_every_kept_corner(a, b, inner, grasp, back):
    m = CHECKER.model
    out = route_poses(CHECKER, a, b, grasp, [a[:2], *inner, b[:2]], back=back, spin=True)
    assert out[0] == a and out[-1] == b
    cars = [m.car_pose(q, grasp) for q in out]
    for k, (u, v) in enumerate(zip(cars, cars[1:], strict=False), start=1):
        moved = math.hypot(v[0] - u[0], v[1] - u[1])
        if moved <= NO_MOVE:
            continue  # a turn in place of the car
        assert abs(wrap_angle(v[2] - u[2])) < 1e-9 or k == len(out) - 1  # a straight push
        way = math.atan2(v[1] - u[1], v[0] - u[0])
        assert abs(wrap_angle(way - u[2] - (math.pi if back else 0.0))) < 1e-6 or \
            k == len(out) - 1
        if k < len(out) - 1:  # the push ends with the box on a corner, or on b's car
            on_corner = any(math.dist(out[k][:2], p) < 1e-6 for p in inner)
            assert on_corner or math.dist(v[:2], cars[-1][:2]) < 1e-6


def test_leaving_a_pose_backwards_the_box_reaches_the_corner_without_a_detour():
    """The car 0.4 m behind the box (grasp 0): a corner 1 m ahead of the box along the pull."""
    m = CHECKER.model
    a = (5.0, 3.0, 0.0)  # the box heads +x; pulled towards -x, the car's back to its way
    q = (4.0, 3.0)
    b = (2.0, 4.0, 0.0)
    out = route_poses(CHECKER, a, b, 0, [a[:2], q, b[:2]], back=True, spin=True)
    # never forwards first: every box centre lies at x <= the start's
    assert all(p[0] <= a[0] + 1e-9 for p in out)
    assert any(math.dist(p[:2], q) < 1e-6 for p in out)
    car = m.car_pose(out[1], 0)
    assert math.isclose(car[2] % (2 * math.pi), 0.0, abs_tol=1e-6) or \
        math.isclose(car[2] % (2 * math.pi), 2 * math.pi, abs_tol=1e-6)
