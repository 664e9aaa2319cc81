"""The grid rasteriser of convex footprints against shapely's point-in-polygon test."""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.validity.footprints import grid_inside


@given(seed=st.integers(0, 100_000), k=st.integers(3, 12), clockwise=st.booleans())
@settings(max_examples=200, deadline=None)
def test_grid_inside_matches_contains_xy(seed, k, clockwise):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-2.0, 2.0, (k, 2)) * rng.uniform(0.05, 1.0, 2)
    hull = shapely.convex_hull(shapely.multipoints(pts))
    if hull.geom_type != "Polygon":
        return
    if clockwise != (not shapely.is_ccw(hull.exterior)):
        hull = shapely.Polygon(np.asarray(hull.exterior.coords)[::-1])
    res = float(rng.uniform(0.03, 0.3))
    xs = float(rng.uniform(-3, -2)) + res * np.arange(int(5.0 / res))
    ys = float(rng.uniform(-3, -2)) + res * np.arange(int(5.5 / res))
    x, y = np.meshgrid(xs, ys, indexing="ij")
    want = shapely.contains_xy(hull, x, y)
    got = np.zeros_like(want)
    cols, rows, inside = grid_inside(hull, xs, ys)
    got[cols, rows] = inside
    assert np.array_equal(got, want)


def test_grid_inside_of_an_axis_aligned_square_and_a_thin_diagonal():
    xs = ys = np.arange(10) * 0.1
    square = shapely.box(0.25, 0.35, 0.55, 0.75)  # vertical edges: the bounding box's sides
    cols, rows, inside = grid_inside(square, xs, ys)
    assert (cols, rows) == (slice(3, 6), slice(4, 8)) and inside.all()
    thin = shapely.Polygon([(0.0, 0.01), (0.9, 0.91), (0.9, 0.89), (0.0, -0.01)])
    cols, rows, inside = grid_inside(thin, xs, ys)
    got = np.zeros((10, 10), dtype=bool)
    got[cols, rows] = inside
    assert np.array_equal(np.argwhere(got), [[i, i] for i in range(1, 9)])
    assert not grid_inside(shapely.LineString([(0, 0), (1, 1)]).convex_hull, xs, ys)[2].any()
