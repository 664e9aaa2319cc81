"""Coarse pieces: every obstacle piece inside one of them; the every-yaw regions only shrink."""

from __future__ import annotations

import math

import numpy as np
import shapely
from factories import ragged_wall
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.pose_cells import free_region
from pivot_ompl.analysis.pose_coarse import coarse_pieces
from pivot_ompl.analysis.pose_inner import EveryYawRegions, swept_hull
from pivot_ompl.analysis.pose_proof import HeldParts
from pivot_ompl.validity.collision import KEEP_CLEARANCE

#: pixel maps: cells of a 5 cm grid, some occupied
pixels = st.lists(st.tuples(st.integers(0, 15), st.integers(0, 15)), min_size=1, max_size=60,
                  unique=True)


def _boxes(cells: list[tuple[int, int]], size: float = 0.05) -> list[np.ndarray]:
    unit = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    return [size * (unit + np.array(c, dtype=float)) for c in cells]


@settings(max_examples=40, deadline=None)
@given(cells=pixels, tolerance=st.sampled_from([0.0, 0.005, 0.01, 0.05]))
def test_every_piece_lies_inside_a_convex_coarse_piece(cells, tolerance):
    pieces = _boxes(cells)
    coarse = coarse_pieces(pieces, tolerance=tolerance)
    assert 1 <= len(coarse) <= len(pieces)
    polygons = [shapely.Polygon(c) for c in coarse]
    for p in polygons:
        assert p.is_valid and p.exterior.is_ccw
        assert abs(p.convex_hull.area - p.area) < 1e-12
    for piece in pieces:
        body = shapely.Polygon(piece)
        assert any(p.buffer(1e-9).contains(body) for p in polygons)


def test_a_row_of_boxes_along_a_wall_becomes_one_piece():
    row = _boxes([(k, 0) for k in range(40)])  # a 2 m wall of 5 cm pixels
    (piece,) = coarse_pieces(row)
    wall = shapely.box(0.0, 0.0, 2.0, 0.05)
    assert shapely.Polygon(piece).symmetric_difference(wall).area < 1e-12


@settings(max_examples=6, deadline=None)
@given(door=st.floats(0.6, 1.6), seed=st.integers(0, 99), i=st.integers(0, 31))
def test_every_yaw_regions_of_the_coarse_pieces_lie_inside_the_exact_ones(door, seed, i):
    # a many-piece wall: the gate's regions (from coarse pieces) hold no position that the
    # exact pieces' swept sums exclude, so its parts are valid at every yaw of their bin
    parts = HeldParts(ragged_wall(door, seed), KEEP_CLEARANCE, None, regions=EveryYawRegions)
    exact = parts.floor.near_room(KEEP_CLEARANCE)
    assert sum(map(len, parts.bins.grown.values())) < sum(map(len, exact.values()))
    a, b = 2.0 * math.pi * i / 32, 2.0 * math.pi * (i + 1) / 32
    for g, got in enumerate(parts.bins.regions(a, b)):
        want = free_region(exact, [swept_hull(body, 0.5 * (b - a)) for body in parts.bodies[g]],
                           0.5 * (a + b), parts.area)
        assert got.difference(want).area < 1e-9
