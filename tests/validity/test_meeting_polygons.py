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
