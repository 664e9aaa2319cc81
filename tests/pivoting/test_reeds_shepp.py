"""Our Reeds-Shepp wrapper against OMPL's own space: distances, sub-paths, the compound space."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene
from ompl import base as ob

from pivot_ompl.base.problem import make_problem
from pivot_ompl.pivoting.reeds_shepp import ReedsShepp

R = 2.0


def pairs(n: int, seed: int):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        a = (*rng.uniform(-5, 5, 2), rng.uniform(-math.pi, math.pi))
        b = (*rng.uniform(-5, 5, 2), rng.uniform(-math.pi, math.pi))
        yield tuple(map(float, a)), tuple(map(float, b))


def ompl_distance(a, b) -> float:
    space = ob.ReedsSheppStateSpace(R)
    bounds = ob.RealVectorBounds(2)
    bounds.setLow(-10)
    bounds.setHigh(10)
    space.setBounds(bounds)
    s1, s2 = space.allocState(), space.allocState()
    for s, p in ((s1, a), (s2, b)):
        s.setXY(p[0], p[1])
        s.setYaw(p[2])
    return space.distance(s1, s2)


def test_distance_is_ompls():
    rs = ReedsShepp(turning_radius=R)
    for a, b in pairs(200, seed=1):
        assert rs.distance(a, b) == pytest.approx(ompl_distance(a, b), abs=1e-12)


def test_known_lengths():
    rs = ReedsShepp(turning_radius=R)
    assert rs.distance((0, 0, 0), (3, 0, 0)) == pytest.approx(3.0)       # straight ahead
    assert rs.distance((0, 0, 0), (-3, 0, 0)) == pytest.approx(3.0)      # straight back
    # a quarter turn on the circle of radius R
    assert rs.distance((0, 0, 0), (R, R, math.pi / 2)) == pytest.approx(R * math.pi / 2)


def test_interpolation_runs_along_a_path_as_long_as_the_distance():
    """Sampled finely, the path's arc length is the distance, its curvature at most 1/R, and it
    joins the two poses (a shortest path's sub-paths are not always shortest in OMPL's solver,
    so only the path itself is compared)."""
    rs = ReedsShepp(turning_radius=R)
    ts = list(np.linspace(0.0, 1.0, 2001))
    for a, b in pairs(60, seed=2):
        d = rs.distance(a, b)
        pts = np.array(rs.sample(a, b, ts))
        assert pts[0] == pytest.approx(a, abs=1e-9)
        assert pts[-1][:2] == pytest.approx(b[:2], abs=1e-9)
        assert math.remainder(pts[-1][2] - b[2], 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
        steps = np.hypot(*np.diff(pts[:, :2], axis=0).T)
        assert steps.sum() == pytest.approx(d, rel=1e-3)
        turn = np.abs(np.remainder(np.diff(pts[:, 2]) + math.pi, 2 * math.pi) - math.pi)
        assert np.all(turn <= d / (len(ts) - 1) / R * (1 + 1e-6) + 1e-12)  # per arc step
        assert rs.sample(a, b, [0.5]) == [rs.interpolate(a, b, 0.5)]


def test_compound_space_distance_is_rs_of_object_poses_plus_grasp_weight():
    problem = make_problem(make_scene(bounds=[-6, -6, 8, 6]))
    space, si = problem.space, problem.si
    rs = ReedsShepp(turning_radius=problem.scene.turning_radius)
    s1, s2 = si.allocState(), si.allocState()
    for a, b in pairs(50, seed=3):
        problem_states = ((s1, a, 1), (s2, b, 3))
        for s, p, g in problem_states:
            s[0].setXY(p[0], p[1])
            s[0].setYaw(p[2])
            s[1].value = g
        assert space.distance(s1, s2) == pytest.approx(rs.distance(a, b) + 2.0, abs=1e-9)
