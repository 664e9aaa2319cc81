"""The held poses' bin regions: built from a parent or a twin, they still miss no valid pose."""

from __future__ import annotations

import math

import numpy as np
import shapely
from factories import make_scene
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.pose_bins import BinRegions, half_turn_twins
from pivot_ompl.analysis.pose_cells import (
    DISK_SIDES,
    ROUND_OFF,
    by_size,
    free_region,
    grown_pieces,
    held_bodies,
    near,
    rotation_core,
)

CLEARANCE = 0.008


def _rect(x: float, y: float, w: float, h: float, yaw: float) -> np.ndarray:
    c, s = math.cos(yaw), math.sin(yaw)
    corners = np.array([(-w, -h), (w, -h), (w, h), (-w, h)]) * 0.5
    return corners @ np.array([[c, s], [-s, c]]) + (x, y)


@settings(max_examples=40, deadline=None)
@given(pieces=st.lists(st.lists(st.tuples(st.floats(-3.0, 3.0), st.floats(-3.0, 3.0)),
                                min_size=3, max_size=7), min_size=1, max_size=8),
       clearance=st.sampled_from([0.0, 0.008, 0.05]))
@example(pieces=[[(0.0, 0.0), (0.0, 0.25), (1.5, -2.0), (-0.5, 1.0)]], clearance=0.0)
# a square and a 20-gon: the square grown has 4 + 16 vertices, the 20-gon's count (a turned
# map's coarse pieces crashed the held poses' gate so)
@example(pieces=[[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)],
                 [(3.0 + math.cos(t), math.sin(t)) for t in np.linspace(0.0, 6.0, 20)]],
         clearance=0.05)
def test_pieces_grown_at_once_are_each_its_hull_summed_with_the_clearance_polygon(pieces,
                                                                                  clearance):
    # the pieces' vertex counts mixed (3 to 7 points, fewer on their hulls): each grown
    # piece, in the pieces' order, is its own hull summed with the disk's inscribed polygon
    hulls = [shapely.MultiPoint(p).convex_hull for p in pieces]
    if min(h.area for h in hulls) < 1e-3:
        return
    r = max(clearance - ROUND_OFF, 0.0)
    a = np.linspace(0.0, 2.0 * math.pi, DISK_SIDES, endpoint=False)
    disk = r * np.stack([np.cos(a), np.sin(a)], axis=1)
    grown = grown_pieces([np.array(p) for p in pieces], clearance)
    assert len(grown) == len(pieces)
    for p, g in zip(pieces, grown, strict=True):
        # each point once: GEOS's hull of repeated points can keep a vertex lying on an edge
        # and come out invalid (the pieces below, at clearance 0)
        points = np.unique((np.array(p)[:, None] + disk[None]).reshape(-1, 2), axis=0)
        want = shapely.MultiPoint(points).convex_hull
        poly = shapely.Polygon(g)
        assert poly.is_valid and poly.exterior.is_ccw
        assert poly.symmetric_difference(want).area < 1e-9


@settings(max_examples=20, deadline=None)
@given(rects=st.lists(st.tuples(st.floats(0.0, 8.0), st.floats(0.0, 6.0), st.floats(0.1, 1.0),
                                st.floats(0.1, 1.0), st.floats(0.0, 3.2)), min_size=1, max_size=12),
       distance=st.floats(0.0, 1.5), prepared=st.booleans())
def test_the_pieces_near_a_room_are_those_within_the_distance_and_the_room_is_left_as_it_came(
        rects, distance, prepared):
    grown = by_size(grown_pieces([_rect(*r) for r in rects], CLEARANCE))
    room = shapely.box(1.0, 1.0, 5.0, 4.0).difference(shapely.box(2.0, 2.0, 3.0, 3.0))
    if prepared:
        shapely.prepare(room)
    kept = near(grown, room, distance)
    assert bool(shapely.is_prepared(room)) is prepared
    for k, stack in grown.items():
        want = shapely.distance(shapely.polygons(stack), room) <= distance
        got = kept.get(k, np.empty((0, k, 2)))
        assert len(got) == int(want.sum()) and np.array_equal(got, stack[want])


def _bodies_at(bodies: list[np.ndarray], x: float, y: float, yaw: float):
    c, s = math.cos(yaw), math.sin(yaw)
    return [shapely.Polygon(b @ np.array([[c, s], [-s, c]]) + (x, y)) for b in bodies]


def test_the_paper_box_grasps_are_each_others_half_turn_twins():
    bodies = held_bodies(make_scene().model)
    assert half_turn_twins(bodies) == [2, 3, 0, 1]
    # a robot off the box's axis has no twin: nothing is borrowed
    lopsided = [[bs[0], bs[1] + (0.0, 0.05 * g)] for g, bs in enumerate(bodies)]
    assert half_turn_twins(lopsided) is None


def test_a_first_bin_is_the_single_bin_computation():
    scene = make_scene()
    pieces = [_rect(3.0, 2.0, 1.0, 0.4, 0.3), _rect(5.0, 4.0, 0.6, 1.2, -0.7)]
    grown = by_size(grown_pieces(pieces, CLEARANCE))
    bodies = held_bodies(scene.model)
    area = shapely.box(0.0, 0.0, 8.0, 6.0)
    a, b = 0.2, 0.4
    got = BinRegions(grown, bodies, area).regions(a, b)
    for g in range(4):
        cores = [rotation_core(body, 0.5 * (b - a)) for body in bodies[g]]
        want = free_region(grown, cores, 0.5 * (a + b), area)
        assert got[g].symmetric_difference(want).area < 1e-9


obstacles = st.lists(st.tuples(st.floats(1.0, 7.0), st.floats(1.0, 5.0), st.floats(0.1, 1.2),
                               st.floats(0.1, 1.2), st.floats(0.0, 3.1)),
                     min_size=1, max_size=6)


@settings(max_examples=12, deadline=None)
@given(rects=obstacles, seed=st.integers(0, 2**16))
def test_every_valid_pose_lies_in_its_bins_region_halved_or_twinned(rects, seed):
    # bins are asked as the proof asks them: a first round, then halves (from the parent)
    # and bins half a turn round (from the twin); a pose whose bodies keep the clearance must
    # lie in the region of every bin holding its yaw, at its grasp
    scene = make_scene()
    pieces = [_rect(*r) for r in rects]
    grown = by_size(grown_pieces(pieces, CLEARANCE))
    bodies = held_bodies(scene.model)
    area = shapely.box(0.0, 0.0, 8.0, 6.0)
    bins = BinRegions(grown, bodies, area)
    width = 2.0 * math.pi / 8
    asked = [(i * width, (i + 1) * width) for i in range(8)]
    for a, b in list(asked[:2]):  # halved twice
        m = 0.5 * (a + b)
        asked += [(a, m), (m, b), (a, 0.5 * (a + m)), (0.5 * (a + m), m)]
    for a, b in list(asked[8:]):  # their twins, half a turn round: borrowed
        asked.append((a + math.pi, b + math.pi))
    for a, b in asked:
        bins.regions(a, b)
    assert bins.computed < len(asked)
    obstacle = shapely.union_all([shapely.Polygon(p) for p in pieces])
    rng = np.random.default_rng(seed)
    for a, b in asked:
        regions = bins.regions(a, b)
        for _ in range(60):
            x, y = rng.uniform(0.0, 8.0), rng.uniform(0.0, 6.0)
            yaw, g = rng.uniform(a, b), int(rng.integers(4))
            placed = _bodies_at(bodies[g], x, y, yaw)
            if min(p.distance(obstacle) for p in placed) < CLEARANCE + 1e-6:
                continue
            if not all(area.buffer(1e-9).covers(p.centroid) for p in placed[:1]):
                continue
            assert regions[g].buffer(1e-7).covers(shapely.Point(x, y)), (a, b, g, x, y, yaw)


def _assert_halves_are_parent_less_own_sums(grown, bodies, area, a: float, b: float) -> list:
    """Each half of bin ``(a, b)``, built from its parent, is exactly the parent's region met
    with the half's own single-bin region; returns the parent's regions."""
    bins = BinRegions(grown, bodies, area)
    parent = bins.regions(a, b)
    for lo, hi in ((a, 0.5 * (a + b)), (0.5 * (a + b), b)):
        got = bins.regions(lo, hi)
        for g in range(4):
            cores = [rotation_core(body, 0.5 * (hi - lo)) for body in bodies[g]]
            want = parent[g].intersection(free_region(grown, cores, 0.5 * (lo + hi), area))
            assert got[g].symmetric_difference(want).area < 1e-9, (lo, hi, g)
    return parent


def test_a_halved_bin_of_a_floor_of_rooms_is_its_parent_less_its_own_sums():
    # the parent's region falls into parts (rooms, the walls closed at the parent's yaws);
    # each part loses only the sums that meet it
    scene = make_scene()
    walls = [_rect(2.7, 1.2, 0.1, 2.4, 0.0), _rect(2.7, 4.9, 0.1, 2.2, 0.0),
             _rect(5.4, 1.5, 0.1, 3.0, 0.0), _rect(5.4, 5.2, 0.1, 1.6, 0.0),
             _rect(1.2, 3.0, 0.5, 0.5, 0.4), _rect(4.0, 2.0, 0.3, 0.8, 1.1),
             _rect(7.0, 4.0, 0.6, 0.3, 2.0)]
    parents = _assert_halves_are_parent_less_own_sums(
        by_size(grown_pieces(walls, CLEARANCE)), held_bodies(scene.model),
        shapely.box(0.0, 0.0, 8.2, 6.0), 0.0, 2.0 * math.pi / 16)
    assert max(len(getattr(r, "geoms", [r])) for r in parents) >= 2


@settings(max_examples=10, deadline=None)
@given(rects=obstacles)
def test_a_halved_bin_is_its_parent_less_the_halfs_own_sums(rects):
    # built from its parent (the box's sums joined once for every grasp)
    scene = make_scene()
    _assert_halves_are_parent_less_own_sums(
        by_size(grown_pieces([_rect(*r) for r in rects], CLEARANCE)), held_bodies(scene.model),
        shapely.box(0.0, 0.0, 8.0, 6.0), 0.3, 0.3 + 2.0 * math.pi / 8)
