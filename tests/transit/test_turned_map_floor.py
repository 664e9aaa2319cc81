"""A map turned by any angle walks on a floor grid through its own map grid.

The walk planner turns a floor to its walls (:mod:`pivot_ompl.transit.frame`); a map turned
by an angle has its boxes axis-aligned there, on a grid whose lines need not pass through the
frame's corner. The frame's corner is moved onto them, so the boxes are met by a stencil's
dilation of their cells, and those give the positions their Minkowski sums give.
"""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from map_factories import grid_boxes

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import rotate_scene
from pivot_ompl.scene import Scene
from pivot_ompl.transit.floor_grid import OPEN_YAWS, FloorGrid
from pivot_ompl.validity.assembly_field import CELL_BOXES

RES = 0.1


def _map_scene(seed: int) -> Scene:
    """An 8 x 6 m floor of boxes of whole 0.1 m cells (a map's), clear of start and goal."""
    boxes = grid_boxes(seed, CELL_BOXES + 40, cell=RES)
    return make_scene(obstacles=boxes)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(angle=st.floats(0.05, 1.5), seed=st.integers(0, 3))
def test_a_turned_map_s_boxes_are_dilated_and_give_the_sums_positions(angle, seed):
    scene = rotate_scene(_map_scene(seed), angle)
    walker = PivotChecker(scene).walker
    quarter = 0.5 * math.pi
    off = (walker.frame.yaw - angle) % quarter
    assert min(off, quarter - off) < 1e-6  # turned back to the map's own axes
    world = walker.world
    dilated = walker.field.grid
    summed = FloorGrid(scene.model, world, RES, walker.box_margin, cells=False)
    # only the bounds' walls (the old bounds, turned twice, and the frame's) are summed
    assert len(dilated.sums.pieces) <= 8 < len(summed.sums.pieces)
    for k in range(0, len(OPEN_YAWS), 3):
        a, b = dilated.fits_index(k), summed.fits_index(k)
        assert np.array_equal(a, b), (k, int((a != b).sum()))


def test_a_turned_map_walks_on_a_grid_round_its_floor_not_round_its_turned_bounds():
    scene = rotate_scene(_map_scene(0), 0.7)
    b = PivotChecker(scene).walker.world.bounds
    # the 8 x 6 m floor and the held assembly's reach (about 2 m) round it: 12 x 10 m at
    # most; the turned bounds turned back are about 16 x 16 m
    assert (b[2] - b[0]) * (b[3] - b[1]) <= (8.0 + 4.0) * (6.0 + 4.0)
