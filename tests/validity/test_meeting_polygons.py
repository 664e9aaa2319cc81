"""Meeting hulls as polygons, many pairs at once: the very polygons GEOS's convex hulls give.

:func:`~pivot_ompl.validity.minkowski.meeting_polygons` serves the polygon relaxation
(:func:`~pivot_ompl.analysis.regrasp_bound.free_cover`), whose bound is a proof: each pair's
polygon must have exactly the vertices of :func:`~pivot_ompl.validity.footprints.
meeting_hulls`'s hull, whatever the pieces' orientation, the bodies' repetition or the order.
"""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.validity.footprints import meeting_hulls
from pivot_ompl.validity.minkowski import meeting_polygons


def _convex(rng: np.random.Generator, sides: int, size: float) -> np.ndarray:
    """A random convex polygon's vertices (counter-clockwise or clockwise)."""
    pts = rng.uniform(-size, size, (sides + 3, 2))
    ring = np.asarray(shapely.MultiPoint(pts).convex_hull.exterior.coords)[:-1]
    return ring if rng.uniform() < 0.5 else ring[::-1].copy()


def _vertices(geom: shapely.Geometry) -> set[tuple[float, float]]:
    return {tuple(p) for p in shapely.get_coordinates(geom.exterior)}


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_each_polygon_has_the_vertices_of_the_convex_hull(seed):
    rng = np.random.default_rng(seed)
    pieces = [_convex(rng, int(rng.integers(1, 6)), 1.0) + rng.uniform(-5, 5, 2)
              for _ in range(10)]
    bodies = [_convex(rng, int(rng.integers(1, 12)), 0.5) for _ in range(3)]
    pairs = [(k, b) for b in bodies for k in pieces]
    got = meeting_polygons([k for k, _ in pairs], [b for _, b in pairs])
    assert len(got) == len(pairs)
    for poly, (k, b) in zip(got, pairs, strict=True):
        want = meeting_hulls([k], b)[0]
        assert poly.geom_type == "Polygon" and poly.is_valid
        assert _vertices(poly) == _vertices(want)
        assert abs(poly.area - want.area) <= 1e-12 * max(1.0, want.area)


def test_no_pairs_give_no_polygons():
    assert len(meeting_polygons([], [])) == 0


def test_pairs_with_vertices_on_an_edge_line_are_geos_hulls_too():
    # a wall box with vertices along its sides and a rounded body: sums whose differences
    # lie on an edge's line (uncertifiable, summed by GEOS) are still the hulls' polygons
    rng = np.random.default_rng(7)
    t = np.linspace(0.0, 1.0, 6)[:-1]
    corners = np.array([[0.0, 0.0], [3.0, 0.0], [3.0, 0.2], [0.0, 0.2]])
    wall = np.concatenate([a + np.outer(t, b - a) for a, b in
                           zip(corners, np.roll(corners, -1, axis=0), strict=True)])
    body = np.asarray(shapely.box(-0.4, -0.15, 0.4, 0.15).buffer(0.03, quad_segs=4)
                      .exterior.coords)[:-1]
    turns = rng.uniform(-np.pi, np.pi, 8)
    bodies = [body @ np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
              for a in [0.0, np.pi / 2, *turns]]
    got = meeting_polygons([wall] * len(bodies), bodies)
    for poly, b in zip(got, bodies, strict=True):
        want = meeting_hulls([wall], b)[0]
        assert _vertices(poly) == _vertices(want)
