"""The planar convex hull: counter-clockwise, its vertices among the points, all points inside."""

import numpy as np
import pytest
import shapely

from pivot_ompl.wholebody.hull import convex_hull


def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float((x * np.roll(y, -1) - np.roll(x, -1) * y).sum())


def test_hull_of_two_soles_is_counter_clockwise_and_contains_every_point():
    rng = np.random.default_rng(3)
    pts = np.vstack([rng.uniform(0.0, 0.5, (20, 2)),
                     [[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]]])
    hull = convex_hull(pts)
    assert _signed_area(hull) == pytest.approx(0.5)
    assert len(hull) == len({tuple(p) for p in hull})  # not closed, no repeat
    assert all(any(np.allclose(v, p) for p in pts) for v in hull)
    poly = shapely.Polygon(hull)
    assert all(poly.buffer(1e-12).covers(shapely.Point(p)) for p in pts)


def test_collinear_points_have_no_hull():
    with pytest.raises(ValueError, match="no area"):
        convex_hull(np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]))
