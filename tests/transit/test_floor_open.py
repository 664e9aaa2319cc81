"""A block's open positions decided cheaply first are those rasterised at every yaw.

:meth:`FloorGrid.open_block` skips positions surely closed at every yaw and tries the yaws a
block at a time with the pieces near positions still undecided; its answer must be, bit for
bit, the or of :meth:`FloorGrid.fits_index` over every open yaw (every piece rasterised at
every yaw over the whole floor).
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from pivot_ompl import import_map
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.resources import data_path
from pivot_ompl.transit.floor_grid import OPEN_YAWS
from pivot_ompl.transit.floor_open import body_disks, piece_distances


def _every_yaw(grid):
    return np.logical_or.reduce([grid.fits_index(k) for k in range(len(OPEN_YAWS))], axis=0)


def _by_blocks(grid, tile):
    out = np.zeros((grid.nx, grid.ny), dtype=bool)
    for x0 in range(0, grid.nx, tile):
        for y0 in range(0, grid.ny, tile):
            wx, wy = slice(x0, min(grid.nx, x0 + tile)), slice(y0, min(grid.ny, y0 + tile))
            out[wx, wy] = grid.open_block(wx, wy)
    return out


def _scenes():
    return [generate("building", 0, params=GeneratorParams(rooms=3)).scene,
            generate("building", 2, params=GeneratorParams(rooms=4, layout="corridor")).scene,
            generate("clutter", 1).scene, generate("walls", 3).scene]


@pytest.mark.parametrize("index", range(4))
def test_open_blocks_are_every_yaw_rasterised(index):
    scene = _scenes()[index]
    grid = PivotChecker(scene).walker.field.grid
    got = _by_blocks(grid, 16)
    want = _every_yaw(PivotChecker(scene).walker.field.grid)
    assert want.any() and not want.all()
    assert np.array_equal(got, want)


def test_open_blocks_of_a_real_map_are_every_yaw_rasterised():
    scene = import_map(data_path("scenes/maps/aws_small_house/map.yaml"),
                       start=(-6.0, -3.0, 0.0), goal=(7.0, -1.0, 0.5 * np.pi)).scene
    grid = PivotChecker(scene).walker.field.grid
    got = _by_blocks(grid, 64)
    fresh = PivotChecker(scene).walker.field.grid
    assert grid.stats.pairs_summed < len(grid.pieces) * len(OPEN_YAWS) // 2  # fewer sums
    assert np.array_equal(got, _every_yaw(fresh))


def test_piece_distances_are_shapely_distances():
    rng = np.random.default_rng(5)
    pieces = [shapely.get_coordinates(shapely.box(*c, c[0] + w, c[1] + h))[:-1]
              for c, w, h in zip(rng.uniform(0, 3, (6, 2)), rng.uniform(0.05, 1, 6),
                                 rng.uniform(0.05, 1, 6), strict=True)]
    pieces.append(np.array([[1.0, 1.0], [2.0, 1.2], [1.4, 2.0]]))
    boxes = np.array([[*p.min(axis=0), *p.max(axis=0)] for p in pieces])
    xs = ys = np.linspace(-0.5, 4.0, 46)
    got = piece_distances(pieces, boxes, xs, ys, 0.4)
    polys = shapely.union_all([shapely.Polygon(p) for p in pieces])
    want = shapely.distance(polys, shapely.points(np.stack(np.meshgrid(xs, ys, indexing="ij"),
                                                           axis=-1))).reshape(46, 46)
    near = want <= 0.4
    assert near.any() and (~near).any()
    assert np.allclose(got[near], want[near], atol=1e-12)
    assert (got[~near] > 0.4).all()


def test_body_disks_lie_inside_the_body():
    body = np.array([[-0.28, -0.44], [0.34, -0.44], [0.34, 0.44], [-0.28, 0.44]])
    offsets, radii = body_disks(body, 0.1)
    shape = shapely.Polygon(body)
    for (i, j), r in zip(offsets.tolist(), radii.tolist(), strict=True):
        assert shape.contains(shapely.Point(0.1 * i, 0.1 * j).buffer(r, quad_segs=16))
    assert radii[0] == pytest.approx(0.28 - 1e-6)  # at offset (0, 0), 0.28 from the back
