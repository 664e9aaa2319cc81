"""coal collision world: obstacles as prisms, triangulated polygons, clearances."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.se2 import triangulate
from pivot_ompl.validity.certify import certify
from pivot_ompl.validity.collision import CollisionWorld


def area(pts, tri):
    (ax, ay), (bx, by), (cx, cy) = (pts[i] for i in tri)
    return 0.5 * abs((bx - ax) * (cy - ay) - (cx - ax) * (by - ay))


@pytest.mark.parametrize("pts", [
    ((0, 0), (2, 0), (2, 2), (1, 1), (0, 2)),               # notch
    ((0, 0), (3, 0), (3, 1), (1, 1), (1, 3), (0, 3)),       # L shape
    ((0, 2), (0, 0), (2, 0), (2, 2)),                       # clockwise square
])
def test_triangulation_covers_polygon(pts):
    tris = triangulate(pts)
    assert len(tris) == len(pts) - 2
    n = len(pts)
    poly = 0.5 * abs(sum(pts[i][0] * pts[(i + 1) % n][1] - pts[(i + 1) % n][0] * pts[i][1]
                         for i in range(n)))
    assert sum(area(pts, t) for t in tris) == pytest.approx(poly)


def test_nonconvex_polygon_notch_is_free():
    s = make_scene(obstacles=[{"type": "polygon", "points": [[3, 1], [6, 1], [6, 5], [4.5, 2.2],
                                                             [3, 5]], "height": 1.0}],
                   start=[1, 1, 0], goal=[7, 5, 0])
    w = CollisionWorld.from_scene(s)
    # inside the notch above the V the box is free, on the solid part it collides
    assert w.box_distance((4.5, 4.5, 0.0)) > 0
    assert w.box_distance((4.5, 1.5, 0.0)) < 0


def test_distances_match_geometry():
    s = make_scene(obstacles=[{"type": "box", "center": [5, 3], "size": [1, 1], "height": 1},
                              {"type": "cylinder", "center": [2, 5], "radius": 0.5,
                               "height": 1}])
    w = CollisionWorld.from_scene(s, clearance=0.0)
    kept = CollisionWorld.from_scene(s)  # distances beyond the kept clearance
    assert kept.box_distance((3.0, 3.0, 0.0)) == pytest.approx(1.1 - kept.clearance, abs=1e-6)
    assert kept.clearance == 0.01
    # box 0.8 wide (x) at x=3: its face at 3.4, obstacle face at 4.5
    assert w.box_distance((3.0, 3.0, 0.0)) == pytest.approx(1.1, abs=1e-6)
    # nearest is the cylinder: 5 - 0.5 - (3 + 0.3) = 1.2 (the box obstacle is 2.1 away)
    assert w.box_distance((2.0, 3.0, 0.0)) == pytest.approx(1.2, abs=1e-6)
    d = w.box_distance((2.0, 3.5, 0.0))  # cylinder above: 5 - 0.5 - (3.5 + 0.3)
    assert d == pytest.approx(0.7, abs=1e-6)


def test_certify_is_conservative():
    """A seeded random check: certified motions never pass through an obstacle sample."""
    s = make_scene(obstacles=[{"type": "box", "center": [4, 3], "size": [0.5, 0.5], "height": 1}])
    w = CollisionWorld.from_scene(s)
    rng = np.random.default_rng(5)
    for _ in range(100):
        a = np.array([rng.uniform(2, 6), rng.uniform(1.5, 4.5), rng.uniform(-math.pi, math.pi)])
        b = a + rng.normal(0, 0.6, 3)
        lip = np.hypot(*(b - a)[:2]) + 0.5 * math.hypot(0.8, 0.6) * abs(b[2] - a[2])

        def at(t, a=a, b=b):
            return tuple(a + t * (b - a))

        res = certify(lambda t: w.box_distance(at(t)), lip, tolerance=0.002)
        if res.valid:
            assert all(w.box_distance(at(t)) > -0.002 for t in np.linspace(0, 1, 200))


def test_rotated_collinear_vertices_build_a_world():
    """fig10's polygon has three collinear vertices; turned by 30 degrees the round-off left
    a flat triangle (doubled area 6e-16 m^2) whose prism crashed coal (segfault)."""
    pts = [(5.8, 2.2), (6.8, 2.2), (6.8, 3.4), (6.3, 2.8), (5.8, 3.4)]
    c, s = math.cos(math.radians(30)), math.sin(math.radians(30))
    rot = [(6 + c * (x - 6) - s * (y - 3.5), 3.5 + s * (x - 6) + c * (y - 3.5)) for x, y in pts]
    tris = triangulate(rot)
    assert all(area(rot, t) > 1e-9 for t in tris)
    n = len(rot)
    poly = 0.5 * abs(sum(rot[i][0] * rot[(i + 1) % n][1] - rot[(i + 1) % n][0] * rot[i][1]
                         for i in range(n)))
    assert sum(area(rot, t) for t in tris) == pytest.approx(poly)
    scene = make_scene(obstacles=[{"type": "polygon", "points": [list(p) for p in rot],
                                   "height": 1.0}], start=[1, 1, 0], goal=[7, 5, 0])
    assert CollisionWorld.from_scene(scene).box_distance((1.0, 1.0, 0.0)) > 0


def test_walking_body_reaches_as_far_as_the_knees(monkeypatch):
    """Regression: the demo's robot side-stepped past a wall end it cleared with its footprint.

    The first fig10, t = 1407.8 s: robot at (8.21, 5.40) facing -y, the wall's end at
    y = 5.19; the footprint's front (0.20 m ahead) cleared it, a bent knee (0.30 m ahead) was
    75 mm inside.
    """
    import dataclasses

    from factories import shipped

    from pivot_ompl.humanoids import PROFILES

    scene = shipped("fig10_narrow")
    robot = (8.21, 5.40, -0.5 * math.pi)
    ahead, behind, half = scene.model.walking_extent()
    assert ahead >= 0.30 and behind >= 0.26 and half >= 0.42
    assert CollisionWorld.from_scene(scene).robot_distance(robot) < 0.0
    # the footprint alone (the walking body before) passed the same pose
    monkeypatch.setitem(PROFILES, "hrp2",
                        dataclasses.replace(PROFILES["hrp2"], walk_envelope=(0.0, 0.0, 0.0)))
    assert CollisionWorld.from_scene(scene).robot_distance(robot) > 0.0


def test_transforms_do_not_share_the_scratch_arrays():
    """``placement`` fills scratch arrays: each transform must keep its own copy."""
    from pivot_ompl.validity.collision import placement

    a = placement(1.0, 2.0, 0.3, 0.5)
    b = placement(-4.0, 7.0, -1.2, 0.1)
    assert a.getTranslation().tolist() == [1.0, 2.0, 0.5]
    assert a.getRotation()[0, 0] == math.cos(0.3) and a.getRotation()[1, 0] == math.sin(0.3)
    assert b.getTranslation().tolist() == [-4.0, 7.0, 0.1]


FIG10 = shipped("fig10")


@settings(max_examples=200, deadline=None)
@given(x=st.floats(-1.0, 13.0), y=st.floats(-1.0, 8.0), yaw=st.floats(-4.0, 4.0))
def test_the_walking_body_bounds_margin_in_closed_form_is_the_corners(x, y, yaw):
    scene = FIG10
    w = CollisionWorld.from_scene(scene)
    corners = w.bounds_margin(scene.model.robot_corners((x, y, yaw)))
    assert w.robot_bounds_margin((x, y, yaw)) == pytest.approx(corners, abs=1e-12)
