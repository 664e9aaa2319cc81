"""The walking floor on an occupancy map's grid: its boxes met by a stencil's dilation of their
cells give the positions their Minkowski sums give, over the whole floor and tile by tile."""

from __future__ import annotations

import numpy as np
import pytest
from factories import make_scene
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from map_factories import grid_boxes

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.transit.floor_grid import OPEN_YAWS, FloorGrid
from pivot_ompl.validity.assembly_field import CELL_BOXES

RES = 0.1


def _map_floor(seed: int) -> PivotChecker:
    """An 8 x 6 m floor of boxes of whole 0.1 m cells, and two pieces off the grid."""
    boxes = grid_boxes(seed, CELL_BOXES + 60, cell=RES)
    boxes += [{"type": "box", "center": [4.03, 1.17], "size": [0.33, 0.21], "height": 1.0},
              {"type": "box", "center": [5.5, 4.5], "size": [0.4, 0.2], "yaw": 0.3,
               "height": 1.0}]
    return PivotChecker(make_scene(obstacles=boxes))


@pytest.fixture(scope="module")
def grids():
    ck = _map_floor(5)
    return (FloorGrid(ck.model, ck.world, RES, 0.05),
            FloorGrid(ck.model, ck.world, RES, 0.05, cells=False))


def test_the_map_boxes_are_dilated_and_only_the_others_summed(grids):
    dilated, summed = grids
    assert len(dilated.sums.pieces) == 2 < len(summed.sums.pieces) == len(summed.pieces)
    assert len(dilated.pieces) == len(summed.pieces)  # every piece, whichever way it is met


def test_every_yaw_over_the_whole_floor_is_the_sums(grids):
    dilated, summed = grids
    closed = 0
    for k in range(len(OPEN_YAWS)):
        a, b = dilated.fits_index(k), summed.fits_index(k)
        assert np.array_equal(a, b), (k, int((a != b).sum()))
        closed += int((~a).sum())
    assert closed > 0


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(x0=st.integers(0, 70), y0=st.integers(0, 50), w=st.integers(1, 40),
       h=st.integers(1, 40))
def test_a_block_anywhere_is_the_sums(grids, x0, y0, w, h):
    dilated, summed = grids
    wx = slice(x0, min(dilated.nx, x0 + w))
    wy = slice(y0, min(dilated.ny, y0 + h))
    a, b = dilated.open_block(wx, wy), summed.open_block(wx, wy)
    assert np.array_equal(a, b), int((a != b).sum())
    whole = np.logical_or.reduce([summed.fits_index(k) for k in range(len(OPEN_YAWS))])
    assert np.array_equal(a, whole[wx, wy])
