"""The route bound's shortest route as a polyline: through free cells only, off the walls."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import route_on
from pivot_ompl.analysis.route_path import FreeField, route_polyline


def _wall_with_gap(gap_y: float) -> FreeField:
    """A 10 x 6 m floor, a wall at x in [4.8, 5.2] with a 1 m gap centred at ``gap_y``."""
    r = FloorRaster((0.0, 0.0, 10.0, 6.0), min_cell=0.1, max_cells=10_000)
    wall = (np.abs(r.gx - 5.0) <= 0.2) & (np.abs(r.gy - gap_y) > 0.5)
    return FreeField.of(r, ~wall)


def _length(poly):
    return sum(math.dist(a, b) for a, b in zip(poly, poly[1:], strict=False))


def _samples(poly, step=0.02):
    for a, b in zip(poly, poly[1:], strict=False):
        k = max(2, math.ceil(math.dist(a, b) / step))
        for t in np.linspace(0.0, 1.0, k):
            yield a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])


@settings(max_examples=40, deadline=None)
@given(hs.floats(1.0, 5.0), hs.floats(0.5, 5.5), hs.floats(0.5, 5.5),
       hs.sampled_from([0.0, 0.2, 0.4]))
def test_the_polyline_runs_through_free_cells_and_is_no_shorter_than_the_bound(
        gap, y0, y1, margin):
    f = _wall_with_gap(gap)
    start, goal = (1.0, y0), (9.0, y1)
    route = route_polyline(f, start, goal, margin=margin)
    assert route is not None
    poly = route.points
    assert poly[0] == start and poly[-1] == goal
    # the simplification only shortens (the cost runs from cell centre to cell centre)
    assert route.cost >= _length(poly) - 2.0 * f.raster.half_diag - 1e-9
    xs, ys = zip(*_samples(poly), strict=True)
    assert f.mask.ravel()[f.cells(np.array(xs), np.array(ys))].all()
    bound = route_on(f.raster, f.mask, (*start, 0.0), (*goal, 0.0))
    assert bound is not None and _length(poly) >= bound - 1e-9


def test_a_margin_keeps_the_route_off_the_wall_where_there_is_room():
    """The gap is 1 m: a 0.4 m margin fits through its middle, the plain route hugs a post."""
    f = _wall_with_gap(3.0)
    plain = route_polyline(f, (1.0, 1.0), (9.0, 1.0), margin=0.0)
    kept = route_polyline(f, (1.0, 1.0), (9.0, 1.0), margin=0.4)
    assert plain is not None and kept is not None
    # the plain route's cost at the margin bounds the search: the same route comes out
    limited = route_polyline(f, (1.0, 1.0), (9.0, 1.0), margin=0.4, via=plain)
    assert limited is not None and limited.points == kept.points
    plain, kept = plain.points, kept.points

    def nearest(poly):
        xs, ys = zip(*_samples(poly), strict=True)
        c = f.cells(np.array(xs), np.array(ys))
        return float(f.clearance.ravel()[c][np.abs(np.array(xs) - 5.0) < 0.5].min())

    assert nearest(plain) < 0.25
    assert nearest(kept) >= 0.4 - f.raster.half_diag
    assert _length(kept) < 1.3 * _length(plain)


def test_no_route_when_an_end_is_walled_in():
    f = _wall_with_gap(3.0)
    assert route_polyline(f, (5.0, 0.5), (9.0, 1.0), margin=0.0) is None
