"""The lattice's spacing on a large floor: snapped down onto an occupancy map's grid."""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.planners.routes.lattice_spacing import MAX_CELLS, SNAP_CELLS, lattice_spacing
from pivot_ompl.scene import Scene
from pivot_ompl.validity.assembly_field import CELL_BOXES, AssemblyField, least_boxes
from pivot_ompl.validity.cell_stencil import STENCIL_CELLS
from pivot_ompl.validity.collision import CollisionWorld

BOXES = 4 * CELL_BOXES + 40  # enough for a field at twice the map's cell


def _floor(cell: float, side: float, seed: int, *,
           on_grid: bool = True) -> tuple[Scene, CollisionWorld]:
    """A ``side`` m square floor with map-like boxes of whole ``cell`` cells (or just off them)."""
    rng = np.random.default_rng(seed)
    n = int(side / cell) - 4
    shift = 0.0 if on_grid else 0.37 * cell
    boxes = []
    for _ in range(BOXES):
        ix, iy = int(rng.integers(0, n)), int(rng.integers(0, n))
        w, h = int(rng.integers(1, 4)), int(rng.integers(1, 4))
        boxes.append({"type": "box", "center": [(ix + 0.5 * w) * cell + shift,
                                                (iy + 0.5 * h) * cell + shift],
                      "size": [w * cell, h * cell], "height": 1.0})
    scene = make_scene(bounds=[0.0, 0.0, side, side], obstacles=boxes,
                       start=[0.5 * side, 0.5 * side, 0.0], goal=[0.5 * side, 0.5 * side, 0.0])
    return scene, CollisionWorld.from_scene(scene)


@settings(max_examples=10, deadline=None)
@given(cell=st.sampled_from([0.025, 0.05, 0.06, 0.1]), side=st.floats(52.0, 90.0),
       seed=st.integers(0, 2**16))
def test_a_map_floor_gets_the_largest_whole_multiple_of_its_cell_below_the_sized_spacing(
        cell, side, seed):
    _, world = _floor(cell, side, seed)
    sized = math.sqrt(side * side / MAX_CELLS)
    assert sized > 0.1
    spacing = lattice_spacing(world, 0.1)
    k = math.floor(sized / cell + 1e-9)  # the largest whole multiple not above the sized
    snaps = (k * cell >= 0.1 and side * side <= SNAP_CELLS * (k * cell) ** 2
             and side * side <= STENCIL_CELLS * cell * cell and BOXES >= least_boxes(k))
    assert spacing == (k * cell if snaps else sized)
    if snaps:  # on the map's lines, not above the sized spacing, within the positions' cap
        assert 0.1 <= spacing <= sized < spacing + cell
        assert side * side <= SNAP_CELLS * spacing * spacing


def test_the_office_sized_floor_snaps_to_its_cell_and_its_field_takes_no_sum():
    scene, world = _floor(0.1, 58.0, 3)  # 3 364 m^2 of bounds: sized 0.116 m, like the office
    spacing = lattice_spacing(world, 0.1)
    assert spacing == 0.1
    field = AssemblyField(scene.model, world, spacing)
    assert field.pieces == []  # every box met by the stencil, none summed


def test_a_floor_off_any_grid_keeps_its_sized_spacing():
    _, world = _floor(0.1, 58.0, 3, on_grid=False)
    assert lattice_spacing(world, 0.1) == math.sqrt(58.0 * 58.0 / MAX_CELLS)


def test_a_small_floor_keeps_the_asked_spacing():
    _, world = _floor(0.05, 20.0, 1)
    assert lattice_spacing(world, 0.1) == 0.1
