"""Axis-aligned rectangles rasterised and measured at once: the per-piece answers, exactly."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from factories import make_scene

from pivot_ompl.analysis import plan_bounds, raster_cover
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.rect_cells import (
    axis_rectangles,
    near_rectangles,
    near_turned_rectangles,
    rect_cells,
    turned_rectangles,
)
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation


def _rectangles(rng: np.random.Generator, n: int, h: float) -> list[np.ndarray]:
    """``n`` axis-aligned rectangles on a 6 x 5 m floor: on cell edges, a hair off, or anywhere.

    Corners in either turn and starting at any corner; some thinner than a cell.
    """
    out = []
    for _ in range(n):
        lo = rng.integers(-3, 100, size=2) * h
        size = rng.integers(0, 30, size=2) * h + rng.choice([0.0, 0.3 * h, 3.0 * h])
        kind = rng.integers(0, 4)
        jitter = (0.0, 1e-10, 1e-8, 1e-6 * h)[kind] * rng.choice([-1.0, 1.0], size=4)
        x0, y0 = lo + jitter[:2]
        x1, y1 = lo + size + jitter[2:]
        if rng.uniform() < 0.2:
            x0, y0, x1, y1 = rng.uniform(-0.2, 5.5, size=4)
        pts = np.array([(x0, y0), (x1, y0), (x1, y1), (x0, y1)])
        if rng.uniform() < 0.5:
            pts = pts[::-1]
        out.append(np.roll(pts, int(rng.integers(0, 4)), axis=0))
    return out


def _one_by_one(raster: FloorRaster, pieces: list[np.ndarray], monkeypatch) -> np.ndarray:
    """The per-piece corner test of every piece (no piece taken as a rectangle)."""
    with monkeypatch.context() as m:
        m.setattr(raster_cover, "axis_rectangles",
                  lambda pieces: np.zeros(len(pieces), dtype=bool))
        return raster_cover.obstacle_cells(raster, pieces)


@pytest.mark.parametrize("seed", range(6))
@pytest.mark.parametrize("h", [0.05, 0.1, 0.03])
def test_rectangles_fill_the_cells_the_corner_test_fills(seed, h, monkeypatch):
    rng = np.random.default_rng(seed)
    origin = (-0.1, 0.05) if seed % 2 else (0.0, 0.0)
    raster = FloorRaster((origin[0], origin[1], origin[0] + 6.0, origin[1] + 5.0),
                         min_cell=h, max_cells=10**6)
    pieces = _rectangles(rng, 60, h)
    assert axis_rectangles(pieces).all()
    expected = _one_by_one(raster, pieces, monkeypatch)
    assert expected.any()
    assert np.array_equal(rect_cells(raster, np.array(pieces), raster_cover.EPS), expected)
    assert np.array_equal(raster_cover.obstacle_cells(raster, pieces), expected)


def test_turned_pieces_are_not_taken_for_rectangles(monkeypatch):
    a = math.radians(20.0)
    turned = np.array([(0.0, 0.0), (math.cos(a), math.sin(a)),
                       (math.cos(a) - math.sin(a), math.sin(a) + math.cos(a)),
                       (-math.sin(a), math.cos(a))]) + 1.0
    triangle = np.array([(3.0, 3.0), (4.5, 3.0), (3.0, 4.5)])
    square = np.array([(0.5, 3.0), (1.5, 3.0), (1.5, 4.0), (0.5, 4.0)])
    pieces = [turned, triangle, square]
    assert axis_rectangles(pieces).tolist() == [False, False, True]
    raster = FloorRaster((0.0, 0.0, 6.0, 5.0), min_cell=0.05, max_cells=10**6)
    cells = raster_cover.obstacle_cells(raster, pieces)
    assert np.array_equal(cells, _one_by_one(raster, pieces, monkeypatch))
    for piece in pieces:  # the cell at each piece's centroid is inside it
        assert cells[raster.index(*piece.mean(axis=0))]


def _assert_brackets(raster: FloorRaster, pieces: list[np.ndarray], cells: np.ndarray,
                     distance: float, surely: np.ndarray, maybe: np.ndarray) -> None:
    """``(surely, maybe)`` bracket GEOS's answer: within ``distance`` of some piece or not."""
    points = shapely.points(raster.gx.ravel()[cells], raster.gy.ravel()[cells])
    within = np.zeros(len(cells), dtype=bool)
    for p in pieces:
        within |= shapely.dwithin(points, shapely.Polygon(p), distance)
    assert within.any() and not within.all()
    assert not (surely & ~within).any()  # surely: within by GEOS too
    assert not (within & ~maybe).any()  # every cell within is a maybe
    if distance > 0:  # few left to GEOS (at 0 every cell inside a piece is)
        assert (maybe & ~surely).sum() <= 0.01 * len(cells)


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("distance", [0.0, 0.07, 0.1375])
def test_near_rectangles_bracket_the_exact_distance(seed, distance):
    rng = np.random.default_rng(seed)
    raster = FloorRaster((0.0, 0.0, 6.0, 5.0), min_cell=0.05, max_cells=20_000)
    pieces = _rectangles(rng, 25, raster.cell)
    boxes = np.array([[p[:, 0].min(), p[:, 1].min(), p[:, 0].max(), p[:, 1].max()]
                      for p in pieces])
    cells = np.flatnonzero(rng.uniform(size=raster.shape).ravel() < 0.8)
    surely, maybe = near_rectangles(raster, boxes, cells, distance)
    _assert_brackets(raster, pieces, cells, distance, surely, maybe)


def test_rectangles_of_any_direction_are_told_from_other_pieces():
    a = math.radians(20.0)
    turned = np.array([(0.0, 0.0), (math.cos(a), math.sin(a)),
                       (math.cos(a) - 2 * math.sin(a), math.sin(a) + 2 * math.cos(a)),
                       (-2 * math.sin(a), 2 * math.cos(a))]) + 1.0
    rhombus = np.array([(0.0, 0.0), (1.0, 0.0), (1.5, 1.0), (0.5, 1.0)])
    triangle = np.array([(3.0, 3.0), (4.5, 3.0), (3.0, 4.5)])
    square = np.array([(0.5, 3.0), (1.5, 3.0), (1.5, 4.0), (0.5, 4.0)])
    flat = np.array([(0.5, 3.0), (1.5, 3.0), (1.5, 3.0), (0.5, 3.0)])
    pieces = [turned, rhombus, triangle, square, flat, turned[::-1]]
    assert turned_rectangles(pieces).tolist() == [True, False, False, True, False, True]


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("distance", [0.0, 0.07, 0.1375])
def test_near_turned_rectangles_bracket_the_exact_distance(seed, distance):
    rng = np.random.default_rng(seed)
    raster = FloorRaster((0.0, 0.0, 6.0, 5.0), min_cell=0.05, max_cells=20_000)
    pieces = []
    for _ in range(25):  # rectangles of any size and direction, corners in either turn
        a, (w, h) = rng.uniform(0.0, math.pi), rng.uniform(0.01, 1.5, size=2)
        c, u, v = rng.uniform(0.0, 6.0, size=2), np.array([math.cos(a), math.sin(a)]), \
            np.array([-math.sin(a), math.cos(a)])
        p = np.array([c - w * u - h * v, c + w * u - h * v, c + w * u + h * v,
                      c - w * u + h * v]) * 0.5 + 0.5 * c
        pieces.append(np.roll(p[::int(rng.choice([-1, 1]))], int(rng.integers(0, 4)), axis=0))
    assert turned_rectangles(pieces).all()
    cells = np.flatnonzero(rng.uniform(size=raster.shape).ravel() < 0.8)
    surely, maybe = near_turned_rectangles(raster, np.array(pieces), cells, distance)
    _assert_brackets(raster, pieces, cells, distance, surely, maybe)


def test_disk_cells_with_turned_pieces_are_the_exact_query(monkeypatch):
    """Rectangles and a turned box and cylinder: the same cells as GEOS asked of every cell."""
    scene = make_scene(obstacles=[
        {"type": "box", "center": [4.0, 3.0], "size": [0.2, 4.0], "yaw": 0.4, "height": 1.0},
        {"type": "box", "center": [2.0, 1.5], "size": [1.0, 0.3], "yaw": 0.0, "height": 1.0},
        {"type": "box", "center": [6.05, 4.5], "size": [0.5, 1.1], "yaw": 0.0, "height": 1.0},
        {"type": "cylinder", "center": [2.0, 4.5], "radius": 0.3, "height": 1.0}])
    for cells in (5_000, 50_000):
        raster, mask = plan_bounds.disk_cells(scene, max_cells=cells)
        with monkeypatch.context() as m:
            for name in ("near_rectangles", "near_turned_rectangles"):  # GEOS for every cell
                m.setattr(plan_bounds, name, lambda raster, boxes, idx, distance: (
                    np.zeros(len(idx), dtype=bool), np.ones(len(idx), dtype=bool)))
            _, every = plan_bounds.disk_cells(scene, max_cells=cells)
        assert mask.any() and not mask.all()
        assert np.array_equal(mask, every)


def test_the_walk_reads_the_free_cells_within_the_disk():
    """Every free cell whose centre lies within the disk (plus half a diagonal), none else,
    also for disks at and beyond the floor's edge."""
    scene = make_scene(obstacles=[
        {"type": "box", "center": [4.0, 3.0], "size": [0.2, 4.0], "yaw": 0.4, "height": 1.0}])
    walk = WalkRelaxation(scene, width=0.1, tolerance=0.002, clearance=0.01)
    r = walk.raster
    rng = np.random.default_rng(3)
    x0, y0, x1, y1 = scene.bounds
    for _ in range(200):
        x, y = rng.uniform((x0 - 0.5, y0 - 0.5), (x1 + 0.5, y1 + 0.5))
        rad = float(rng.choice([0.0, 0.03, 0.2, 0.71]))
        ii, jj = walk._cells(x, y, rad)
        within = (np.hypot(r.gx - x, r.gy - y) <= rad + r.half_diag) & walk.free
        got = np.zeros(r.shape, dtype=bool)
        got[ii, jj] = True
        assert np.array_equal(got, within)
