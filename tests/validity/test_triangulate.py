"""Polygons collide exactly as drawn: repeated, collinear, clockwise, thin and large ones."""

from __future__ import annotations

import math

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import PolygonObstacle
from pivot_ompl.se2 import triangulate
from pivot_ompl.validity.collision import CollisionWorld


def _star(rng: np.random.Generator, n: int, thin: float) -> list[tuple[float, float]]:
    """A simple star-shaped polygon (n vertices), its radii in [thin, 1]."""
    angles = np.sort(rng.uniform(0, 2 * math.pi, n))
    radii = rng.uniform(thin, 1.0, n)
    return [(float(r * math.cos(a)), float(r * math.sin(a)))
            for a, r in zip(angles, radii, strict=True)]


def _spoil(rng: np.random.Generator, pts: list, repeats: int, collinear: int) -> list:
    """Insert repeated consecutive vertices and collinear midpoints (shapely: still valid)."""
    pts = list(pts)
    for _ in range(collinear):
        k = int(rng.integers(len(pts)))
        a, b = pts[k], pts[(k + 1) % len(pts)]
        t = float(rng.uniform(0.1, 0.9))
        pts.insert(k + 1, (a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])))
    for _ in range(repeats):
        k = int(rng.integers(len(pts)))
        pts.insert(k, pts[k])
    return pts


def _area(a, b, c) -> float:
    return 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**31), n=st.integers(3, 40), repeats=st.integers(0, 3),
       collinear=st.integers(0, 3), clockwise=st.booleans(), thin=st.sampled_from([0.5, 1e-3]))
def test_triangles_cover_the_polygon_exactly(seed, n, repeats, collinear, clockwise, thin):
    rng = np.random.default_rng(seed)
    pts = _spoil(rng, _star(rng, n, thin), repeats, collinear)
    if clockwise:
        pts = pts[::-1]
    poly = shapely.Polygon(pts)
    if not poly.is_valid or poly.area < 1e-9:
        return
    tris = triangulate(pts)
    areas = [_area(*(pts[k] for k in t)) for t in tris]
    assert all(a > 0 for a in areas)  # counter-clockwise, none flat
    assert math.isclose(sum(areas), poly.area, rel_tol=1e-9, abs_tol=1e-12)
    union = shapely.union_all([shapely.Polygon([pts[k] for k in t]) for t in tris])
    assert union.symmetric_difference(poly).area <= 1e-9 * max(1.0, poly.area)


def test_a_repeated_vertex_still_collides():
    """The box inside a square drawn with a repeated corner is in collision."""
    square = ((2.0, 2.0), (4.0, 2.0), (4.0, 2.0), (4.0, 4.0), (2.0, 4.0))
    assert len(triangulate(square)) == 2
    world = CollisionWorld(BoxGraspModel((0.8, 0.4, 1.0)), (0.0, 0.0, 8.0, 8.0))
    world.add_obstacle(PolygonObstacle(square, 1.0))
    world.setup()
    assert world.box_distance((3.0, 3.0, 0.3)) <= 0
    assert world.box_distance((6.5, 6.5, 0.0)) > 1.0


def test_many_vertices_and_near_zero_area():
    """A 10 000-point polygon and a 1 mm sliver: exact area, in one pass."""
    rng = np.random.default_rng(3)
    big = _star(rng, 10_000, 0.5)
    assert math.isclose(sum(_area(*(big[k] for k in t)) for t in triangulate(big)),
                        shapely.Polygon(big).area, rel_tol=1e-9)
    sliver = [(0.0, 0.0), (10.0, 0.0), (10.0, 0.001), (5.0, 0.001), (0.0, 0.001)]
    assert math.isclose(sum(_area(*(sliver[k] for k in t)) for t in triangulate(sliver)),
                        0.01, rel_tol=1e-9)
