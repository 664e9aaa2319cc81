"""Boxes on the grid's lines met by a stencil's dilation of their cells: the same assembly
field as their Minkowski sums rasterised (an imported occupancy map's walls at the field's
resolution)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.validity.assembly_field import CELL_BOXES, FIELD_YAWS, AssemblyField
from pivot_ompl.validity.cell_stencil import STENCIL_CELLS, grid_cell, map_cell
from pivot_ompl.validity.footprints import obstacle_pieces

RES = 0.1


def _box(ix: int, iy: int, w: int, h: int) -> dict:
    """A box of ``w x h`` cells whose lower-left corner is grid position ``(ix, iy)``."""
    return {"type": "box", "center": [(ix + 0.5 * w) * RES, (iy + 0.5 * h) * RES],
            "size": [w * RES, h * RES], "height": 1.0}



def _same_fields(dilated: AssemblyField, summed: AssemblyField) -> int:
    """Assert the two fields equal at every parity and yaw; the open positions counted."""
    opened = 0
    for parity in (0, 1):
        for k in range(len(FIELD_YAWS)):
            a, b = dilated.fits(parity, k), summed.fits(parity, k)
            assert np.array_equal(a, b), (parity, k, int((a != b).sum()))
            opened += int(a.sum())
    return opened

@settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@example(206)  # a seed whose boxes once reached past the grid's last line
@example(661)  # a seed whose overlapping boxes were once fewer than CELL_BOXES pieces
@given(st.integers(0, 2**32 - 1))
def test_boxes_on_the_grid_lines_dilated_are_the_boxes_summed(seed):
    rng = np.random.default_rng(seed)
    boxes: list[dict] = []
    while len(boxes) < CELL_BOXES + 60:  # inside the grid, clear of the start and goal
        b = _box(int(rng.integers(0, 76)), int(rng.integers(0, 56)),
                 int(rng.integers(1, 4)), int(rng.integers(1, 4)))
        if all(abs(b["center"][0] - x) > 0.9 or abs(b["center"][1] - 3.0) > 0.9
               for x in (1.5, 6.0)):
            boxes.append(b)
    # and a few pieces that are not: off the lines, turned
    boxes += [{"type": "box", "center": [4.03, 1.17], "size": [0.33, 0.21], "height": 1.0},
              {"type": "box", "center": [5.5, 4.5], "size": [0.4, 0.2], "yaw": 0.3,
               "height": 1.0}]
    checker = PivotChecker(make_scene(obstacles=boxes))
    dilated = AssemblyField(checker.model, checker.world, RES)
    summed = AssemblyField(checker.model, checker.world, RES, cells=False)
    assert len(dilated.pieces) <= 2 < len(summed.pieces)  # only those two summed
    opened = _same_fields(dilated, summed)
    assert 0 < opened < 2 * len(FIELD_YAWS) * dilated.nx * dilated.ny  # some closed, some open


@settings(max_examples=2, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32 - 1))
def test_boxes_on_a_map_grid_of_half_the_field_s_spacing_dilated_are_the_boxes_summed(seed):
    rng = np.random.default_rng(seed)
    half = RES / 2
    boxes: list[dict] = []
    while len(boxes) < 4 * CELL_BOXES + 60:  # the map's cells: every second line the field's
        ix, iy = int(rng.integers(0, 152)), int(rng.integers(0, 112))
        w, h = int(rng.integers(1, 6)), int(rng.integers(1, 6))
        b = {"type": "box", "center": [(ix + 0.5 * w) * half, (iy + 0.5 * h) * half],
             "size": [w * half, h * half], "height": 1.0}
        if all(abs(b["center"][0] - x) > 0.9 or abs(b["center"][1] - 3.0) > 0.9
               for x in (1.5, 6.0)):
            boxes.append(b)
    checker = PivotChecker(make_scene(obstacles=boxes))
    assert map_cell(obstacle_pieces(checker.world.obstacles), checker.world.bounds,
                    least=CELL_BOXES) == pytest.approx(half)
    dilated = AssemblyField(checker.model, checker.world, RES)
    summed = AssemblyField(checker.model, checker.world, RES, cells=False)
    assert not dilated.pieces and len(summed.pieces) >= 4 * CELL_BOXES  # none summed
    opened = _same_fields(dilated, summed)
    assert 0 < opened < 2 * len(FIELD_YAWS) * dilated.nx * dilated.ny


def test_a_map_grid_is_found_only_through_the_bounds_corner():
    boxes = [_box(3 * i % 70, 2 * i % 50, 1 + i % 3, 1 + i % 2) for i in range(CELL_BOXES)]
    pieces = obstacle_pieces(PivotChecker(make_scene(obstacles=boxes)).world.obstacles)
    assert grid_cell(pieces, (0.0, 0.0), least=CELL_BOXES) == pytest.approx(RES)
    assert grid_cell(pieces, (0.03, 0.0), least=CELL_BOXES) is None  # lines off the corner
    assert grid_cell(pieces, (0.0, 0.0), least=CELL_BOXES + 1) is None  # too few boxes


def test_a_map_grid_of_more_cells_than_the_stencil_reads_is_not_dilated():
    boxes = [_box(3 * i % 70, 2 * i % 50, 1 + i % 3, 1 + i % 2) for i in range(CELL_BOXES)]
    pieces = obstacle_pieces(PivotChecker(make_scene(obstacles=boxes)).world.obstacles)
    side = RES * math.sqrt(STENCIL_CELLS)  # as many cells as the stencil reads at most
    assert map_cell(pieces, (0.0, 0.0, side - 1.0, side), least=CELL_BOXES) == pytest.approx(RES)
    assert map_cell(pieces, (0.0, 0.0, side + 1.0, side), least=CELL_BOXES) is None


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**16), resolution=st.sampled_from([0.025, 0.05, 0.1]))
def test_a_stencils_runs_are_the_cells_a_body_overlaps(seed, resolution):
    """Each column's maximal runs of cells whose interior the body's interior overlaps."""
    import shapely

    from pivot_ompl.validity.cell_stencil import stencil

    rng = np.random.default_rng(seed)
    hull = shapely.convex_hull(shapely.MultiPoint(rng.uniform(-0.6, 0.6, (6, 2))))
    if hull.area < 1e-4:
        return
    body = shapely.orient_polygons(hull)
    runs = stencil(np.asarray(body.exterior.coords)[:-1], resolution)
    got = {(a, j) for a, j0, j1 in runs for j in range(j0, j1 + 1)}
    lo = np.floor(np.asarray(body.bounds[:2]) / resolution).astype(int) - 2
    hi = np.ceil(np.asarray(body.bounds[2:]) / resolution).astype(int) + 2
    want = {(a, j) for a in range(lo[0], hi[0] + 1) for j in range(lo[1], hi[1] + 1)
            if body.intersection(shapely.box(a * resolution, j * resolution, (a + 1) * resolution,
                                             (j + 1) * resolution)).area > 1e-12}
    assert got == want
    assert runs == sorted(runs)  # column by column, each column's runs upwards
    ends = {(a, j1 + 1) for a, _, j1 in runs}
    assert not any((a, j0) in ends for a, j0, _ in runs)  # maximal: no run joins the next


@settings(max_examples=4, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 2**32 - 1), parity=st.sampled_from([0, 1]))
def test_a_restricted_field_dilated_is_the_whole_fields_within_its_area(seed, parity):
    """The stencil read only over the area's rows and columns: the same grids there."""
    rng = np.random.default_rng(seed)
    # boxes of 1-3 cells in slots 4 cells apart (none touches another: none merged), clear of
    # the start and the goal, enough of them for the stencil
    slots = [(i, j) for i in range(0, 76, 4) for j in range(0, 56, 4)
             if all(abs(0.1 * i + 0.2 - x) > 1.1 or abs(0.1 * j + 0.2 - 3.0) > 1.1
                    for x in (1.5, 6.0))]
    boxes = [_box(*slots[k], int(rng.integers(1, 4)), int(rng.integers(1, 4)))
             for k in rng.permutation(len(slots))[:CELL_BOXES + 10]]
    checker = PivotChecker(make_scene(obstacles=boxes))
    whole = AssemblyField(checker.model, checker.world, RES)
    area = np.zeros((whole.nx, whole.ny), dtype=bool)
    for _ in range(3):  # an area of three blocks, apart or not
        x0, y0 = int(rng.integers(0, whole.nx)), int(rng.integers(0, whole.ny))
        area[x0:x0 + int(rng.integers(1, 30)), y0:y0 + int(rng.integers(1, 30))] = True
    for part_area in (area, np.zeros_like(area)):
        part = AssemblyField(checker.model, checker.world, RES)
        part.restrict(part_area)
        assert not part.pieces  # every box dilated: the stencil alone decides
        for k in range(0, len(FIELD_YAWS), 5):
            assert np.array_equal(part.fits(parity, k), whole.fits(parity, k) & part_area)
