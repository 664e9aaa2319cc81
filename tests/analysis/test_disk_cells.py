"""The disk relaxation's cells: only the cells near some obstacle piece's box are queried."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from factories import make_scene, shipped

from pivot_ompl.analysis import plan_bounds
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.validity.footprints import piece_bounds


def _polygons(rng: np.random.Generator, n: int) -> list[np.ndarray]:
    """``n`` random convex pieces (turned boxes and triangles) on an 8 x 6 m floor."""
    out = []
    for _ in range(n):
        c, yaw = rng.uniform((0.0, 0.0), (8.0, 6.0)), rng.uniform(-math.pi, math.pi)
        if rng.uniform() < 0.5:
            w, h = rng.uniform(0.02, 1.5, size=2)
            pts = np.array([(-w, -h), (w, -h), (w, h), (-w, h)]) / 2.0
        else:
            a = np.sort(rng.uniform(0.0, 2.0 * math.pi, size=3))
            pts = rng.uniform(0.1, 0.8) * np.column_stack([np.cos(a), np.sin(a)])
        rot = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
        out.append(c + pts @ rot.T)
    return out


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("distance", [0.0, 0.07, 0.31])
def test_every_cell_within_the_distance_of_a_piece_is_near_its_box(seed, distance):
    raster = FloorRaster((0.0, 0.0, 8.0, 6.0), min_cell=0.05, max_cells=20_000)
    pieces = _polygons(np.random.default_rng(seed), 12)
    near = plan_bounds.near_boxes(raster, piece_bounds(pieces), distance)
    points = shapely.points(raster.gx.ravel(), raster.gy.ravel())
    within = np.zeros(raster.shape, dtype=bool).ravel()
    for p in pieces:
        within |= shapely.dwithin(points, shapely.Polygon(p), distance)
    within = within.reshape(raster.shape)
    assert within.any() and not near.all()
    assert not (within & ~near).any()


@pytest.mark.parametrize("name", ["fig10", "cluttered_room", "turned"])
def test_the_cells_are_those_of_a_query_of_every_cell(monkeypatch, name):
    scene = shipped(name) if name != "turned" else make_scene(obstacles=[
        {"type": "box", "center": [4.0, 3.0], "size": [0.2, 4.0], "yaw": 0.4, "height": 1.0},
        {"type": "cylinder", "center": [2.0, 4.5], "radius": 0.3, "height": 1.0}])
    for cells in (5_000, 50_000):
        raster, mask = plan_bounds.disk_cells(scene, max_cells=cells)
        with monkeypatch.context() as m:
            m.setattr(plan_bounds, "near_boxes",
                      lambda raster, boxes, distance: np.ones(raster.shape, dtype=bool))
            _, every = plan_bounds.disk_cells(scene, max_cells=cells)
        assert mask.any() and not mask.all()
        assert np.array_equal(mask, every)
