"""The grid rasteriser of convex footprints against shapely's point-in-polygon test."""

from __future__ import annotations

import math

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.validity.footprints import meeting_hulls, obstacle_pieces, piece_polygons
from pivot_ompl.validity.minkowski import meeting_edges
from pivot_ompl.validity.rasters import grid_inside, grid_union


@given(seed=st.integers(0, 100_000), k=st.integers(3, 12), clockwise=st.booleans())
@settings(max_examples=200, deadline=None)
def test_grid_inside_matches_contains_xy(seed, k, clockwise):
    rng = np.random.default_rng(seed)
    pts = rng.uniform(-2.0, 2.0, (k, 2)) * rng.uniform(0.05, 1.0, 2)
    hull = shapely.convex_hull(shapely.multipoints(pts))
    if hull.geom_type != "Polygon":
        return
    if clockwise != (not shapely.is_ccw(hull.exterior)):
        hull = shapely.Polygon(np.asarray(hull.exterior.coords)[::-1])
    res = float(rng.uniform(0.03, 0.3))
    xs = float(rng.uniform(-3, -2)) + res * np.arange(int(5.0 / res))
    ys = float(rng.uniform(-3, -2)) + res * np.arange(int(5.5 / res))
    x, y = np.meshgrid(xs, ys, indexing="ij")
    want = shapely.contains_xy(hull, x, y)
    got = np.zeros_like(want)
    cols, rows, inside = grid_inside(hull, xs, ys)
    got[cols, rows] = inside
    assert np.array_equal(got, want)


def test_grid_inside_of_an_axis_aligned_square_and_a_thin_diagonal():
    xs = ys = np.arange(10) * 0.1
    square = shapely.box(0.25, 0.35, 0.55, 0.75)  # vertical edges: the bounding box's sides
    cols, rows, inside = grid_inside(square, xs, ys)
    assert (cols, rows) == (slice(3, 6), slice(4, 8)) and inside.all()
    thin = shapely.Polygon([(0.0, 0.01), (0.9, 0.91), (0.9, 0.89), (0.0, -0.01)])
    cols, rows, inside = grid_inside(thin, xs, ys)
    got = np.zeros((10, 10), dtype=bool)
    got[cols, rows] = inside
    assert np.array_equal(np.argwhere(got), [[i, i] for i in range(1, 9)])
    assert not grid_inside(shapely.LineString([(0, 0), (1, 1)]).convex_hull, xs, ys)[2].any()


def _random_piece(rng: np.random.Generator) -> np.ndarray:
    c = rng.uniform(-2.0, 2.0, 2)
    kind = rng.integers(3)
    if kind == 0:  # a rectangle, often axis-aligned (edges parallel to the body's)
        w, h = rng.uniform(0.05, 1.0, 2)
        a = [0.0, math.pi / 2, float(rng.uniform(0.0, 6.3))][rng.integers(3)]
        rot = np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        return c + np.array([[-w, -h], [w, -h], [w, h], [-w, h]]) @ rot.T
    if kind == 1:  # an inscribed 24-gon, edges parallel to the body's at some yaws
        a = np.linspace(0.0, 2 * math.pi, 24, endpoint=False)
        r = rng.uniform(0.05, 0.5)
        return np.column_stack([c[0] + r * np.cos(a), c[1] + r * np.sin(a)])
    return c + rng.uniform(-1.0, 1.0, (3, 2))  # a triangle, either orientation


@given(seed=st.integers(0, 100_000))
@settings(max_examples=150, deadline=None)
def test_meeting_edges_rasterised_as_the_hulls_one_by_one(seed):
    rng = np.random.default_rng(seed)
    pieces = [_random_piece(rng) for _ in range(int(rng.integers(1, 6)))]
    body = shapely.Polygon([(-0.2, -0.3), (0.3, -0.3), (0.3, 0.3), (-0.2, 0.3)])
    body = np.asarray(body.buffer(0.05, quad_segs=4).exterior.coords)[:-1]
    yaw = [0.0, math.pi / 2, math.pi / 8 * int(rng.integers(16)), float(rng.uniform(0, 6.3))][
        rng.integers(4)]
    turned = body @ np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]).T
    res = float(rng.choice([0.025, 0.05, 0.1]))
    xs = -3.0 + res * np.arange(int(6.0 / res))
    ys = -3.1 + res * np.arange(int(6.3 / res))
    want = np.zeros((len(xs), len(ys)), dtype=bool)
    for hull in meeting_hulls(pieces, turned):
        cols, rows, inside = grid_inside(hull, xs, ys)
        want[cols, rows] |= inside
    groups = rng.integers(0, 2, len(pieces))
    got = grid_union(meeting_edges(pieces, [turned] * len(pieces)), xs, ys, groups=groups,
                     n_groups=2)
    assert np.array_equal(got[0] | got[1], want)
    for hull, g in zip(meeting_hulls(pieces, turned), groups, strict=True):
        cols, rows, inside = grid_inside(hull, xs, ys)
        assert got[g][cols, rows][inside].all()


def test_meeting_edges_certified_hull_has_the_geos_vertices():
    piece = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.5], [0.0, 0.5]])
    body = np.array([[-0.1, -0.1], [0.1, -0.1], [0.1, 0.1], [-0.1, 0.1]])
    edges = meeting_edges([piece], [body])
    got = {tuple(v) for v in edges.start[0][edges.used[0]]}
    hull = meeting_hulls([piece], body)[0]
    assert got == {tuple(v) for v in shapely.get_coordinates(hull.exterior)}
    assert len(got) == 4  # the collinear differences dropped, as GEOS does


@given(seed=st.integers(0, 100_000), tilt=st.floats(1e-15, 1e-6))
@settings(max_examples=100, deadline=None)
def test_meeting_edges_vertices_are_the_geos_hull_vertices_with_nearly_parallel_edges(
        seed, tilt):
    rng = np.random.default_rng(seed)
    pieces = [_random_piece(rng) for _ in range(3)]
    body = np.array([[-0.2, -0.3], [0.3, -0.3], [0.3, 0.3], [-0.2, 0.3]])
    yaw = math.pi / 2 * int(rng.integers(4)) + tilt * float(rng.choice([-1.0, 1.0]))
    turned = body @ np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]).T
    edges = meeting_edges(pieces, [turned] * len(pieces))
    for i, hull in enumerate(meeting_hulls(pieces, turned)):
        want = {tuple(v) for v in shapely.get_coordinates(hull.exterior)}
        got = edges.start[i][edges.used[i]]
        assert len(got) == len(want) and {tuple(v) for v in got} == want


def test_grid_union_leaves_out_grid_points_on_the_edges():
    # binary fractions: the hull's edges lie exactly on grid rows and columns
    xs = ys = np.arange(16) * 0.25
    piece = np.array([[1.0, 1.0], [2.5, 1.0], [2.5, 2.0], [1.0, 2.0]])
    tilted = np.array([[2.0, 2.5], [3.0, 2.5], [2.5, 3.5]])  # slanted edges through points
    body = np.array([[-0.25, -0.25], [0.25, -0.25], [0.25, 0.25], [-0.25, 0.25]])
    got = grid_union(meeting_edges([piece, tilted], [body, body]), xs, ys,
                     groups=np.array([0, 1]), n_groups=2)
    want = np.zeros((2, 16, 16), dtype=bool)
    for g, hull in enumerate(meeting_hulls([piece, tilted], body)):
        cols, rows, inside = grid_inside(hull, xs, ys)
        want[g][cols, rows] = inside
    assert np.array_equal(got, want)
    assert np.array_equal(np.argwhere(got[0]), [[i, j] for i in range(4, 11) for j in range(4, 9)])


def _with_a_repeated_vertex(piece: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    k = int(rng.integers(len(piece)))
    return np.insert(piece, k, piece[k], axis=0)


@given(seed=st.integers(0, 100_000), tilt=st.floats(0.0, 1e-6))
@settings(max_examples=150, deadline=None)
def test_meeting_edges_without_certificate_rasterise_as_the_certified(seed, tilt):
    rng = np.random.default_rng(seed)
    pieces = [_random_piece(rng) for _ in range(int(rng.integers(1, 6)))]
    pieces = [_with_a_repeated_vertex(p, rng) if rng.random() < 0.3 else p for p in pieces]
    body = shapely.Polygon([(-0.2, -0.3), (0.3, -0.3), (0.3, 0.3), (-0.2, 0.3)])
    body = np.asarray(body.buffer(0.05, quad_segs=int(rng.integers(0, 3))).exterior.coords)[:-1]
    yaw = [math.pi / 2 * int(rng.integers(4)) + tilt, math.pi / 8 * int(rng.integers(16)),
           float(rng.uniform(0, 6.3))][rng.integers(3)]
    turned = body @ np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]]).T
    res = float(rng.choice([0.025, 0.05, 0.1]))
    xs = -3.0 + res * np.arange(int(6.0 / res))
    ys = -3.1 + res * np.arange(int(6.3 / res))
    bodies = [turned] * len(pieces)
    want = grid_union(meeting_edges(pieces, bodies), xs, ys)
    got = grid_union(meeting_edges(pieces, bodies, certify=False), xs, ys)
    assert np.array_equal(got, want)


def test_meeting_edges_without_certificate_refuse_a_vanishing_edge():
    # a rectangle with its last vertex twice: the zero-length edge has no normal, and the
    # merged normals alone would put the sum's vertices in the wrong order
    piece = np.array([[1.0, 1.0], [2.5, 1.0], [2.5, 2.0], [1.0, 2.0], [1.0, 2.0]])
    square = np.array([[-0.25, -0.25], [0.25, -0.25], [0.25, 0.25], [-0.25, 0.25]])
    xs = ys = np.arange(16) * 0.25
    for yaw in (0.0, 0.3, math.pi / 4):
        c, s = math.cos(yaw), math.sin(yaw)
        body = square @ np.array([[c, -s], [s, c]]).T
        got = grid_union(meeting_edges([piece], [body], certify=False), xs, ys)
        assert np.array_equal(got, grid_union(meeting_edges([piece], [body]), xs, ys))


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 2**32 - 1))
def test_pieces_bounds_and_centres_stacked_by_size_are_each_piece_s_own(seed):
    # stacked by vertex count (5000 wall boxes in a few numpy calls): each piece's box,
    # mean and central symmetry must be those it has alone, whatever the other pieces
    from pivot_ompl.validity.footprints import piece_bounds, symmetric_centres

    rng = np.random.default_rng(seed)
    pieces = []
    for _ in range(int(rng.integers(0, 30))):
        if rng.uniform() < 0.5:  # a turned rectangle: centrally symmetric
            w, d, a = rng.uniform(0.05, 3.0), rng.uniform(0.05, 3.0), rng.uniform(0, np.pi)
            rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
            box = np.array([[-w, -d], [w, -d], [w, d], [-w, d]]) / 2 @ rot.T
            pieces.append(box + rng.uniform(-20, 20, 2))
        else:
            pieces.append(rng.uniform(-5, 5, (int(rng.integers(1, 7)), 2)))
    bounds = piece_bounds(pieces)
    centres, symmetric = symmetric_centres(pieces)
    assert bounds.shape == (len(pieces), 4) and centres.shape == (len(pieces), 2)
    for i, p in enumerate(pieces):
        assert np.array_equal(bounds[i], [*p.min(axis=0), *p.max(axis=0)])
        c = p.mean(axis=0)
        assert np.array_equal(centres[i], c)
        mirrored = np.abs((2.0 * c - p)[:, None, :] - p[None, :, :]).max(axis=2).min(axis=1)
        assert symmetric[i] == (mirrored.max() <= 1e-9 * max(1.0, float(np.abs(p - c).max())))


def test_the_pieces_polygons_are_those_of_each_piece_in_its_order():
    from factories import make_scene

    scene = make_scene(obstacles=[
        {"type": "box", "center": [4.0, 3.0], "size": [0.2, 4.0], "yaw": 0.4, "height": 1.0},
        {"type": "cylinder", "center": [2.0, 4.5], "radius": 0.3, "height": 1.0},
        {"type": "polygon", "points": [[5, 1], [7, 1], [7, 2], [6, 1.5], [5, 2]],
         "height": 1.0},
        {"type": "box", "center": [1.0, 1.0], "size": [0.5, 0.3], "yaw": 0.0, "height": 1.0}])
    pieces = obstacle_pieces(scene.obstacles)
    assert len({len(p) for p in pieces}) >= 3  # triangles, boxes and a cylinder's polygon
    got = piece_polygons(pieces)
    assert len(got) == len(pieces)
    for p, g in zip(pieces, got, strict=True):
        assert shapely.to_wkb(g) == shapely.to_wkb(shapely.Polygon(p))
    assert len(piece_polygons([])) == 0
