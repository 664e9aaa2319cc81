"""The passage search's quick test that start and goal share a region: sound, and used."""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from factories import make_scene, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.passage import PassageOnce, blocking_passage
from pivot_ompl.analysis.passage_reach import share_region

SEAL = 1e-6
BOUNDS = (0.0, 0.0, 8.0, 6.0)


def _slabs(bounds: tuple[float, float, float, float]) -> list:
    x0, y0, x1, y1 = bounds
    return [shapely.box(x0 - 1, y0 - 1, x1 + 1, y0), shapely.box(x0 - 1, y1, x1 + 1, y1 + 1),
            shapely.box(x0 - 1, y0, x0, y1), shapely.box(x1, y0, x1 + 1, y1)]


def _same_region(walls: list, gaps: np.ndarray, start: tuple[float, float],
                 goal: tuple[float, float]) -> bool:
    """The union's answer (the reference): start and goal in one part of the free floor."""
    solid = shapely.union_all(walls + list(shapely.buffer(gaps, SEAL)))
    free = shapely.box(*BOUNDS).difference(solid)
    parts = [g for g in getattr(free, "geoms", [free]) if not g.is_empty]
    where = [[k for k, g in enumerate(parts) if g.intersects(shapely.Point(p))]
             for p in (start, goal)]
    return bool(where[0]) and where[0] == where[1]


rect = st.tuples(st.floats(0.0, 7.5), st.floats(0.0, 5.5), st.floats(0.05, 3.0),
                 st.floats(0.05, 3.0))
seg = st.tuples(st.floats(0.0, 8.0), st.floats(0.0, 6.0), st.floats(0.0, 8.0),
                st.floats(0.0, 6.0))
point = st.tuples(st.floats(0.05, 7.95), st.floats(0.05, 5.95))


@settings(max_examples=150, deadline=None)
@given(rects=st.lists(rect, max_size=12), segs=st.lists(seg, max_size=6), start=point,
       goal=point, cell=st.sampled_from([0.1, 0.2, 0.35]))
def test_a_region_shared_by_the_raster_is_shared_by_the_union(rects, segs, start, goal, cell):
    walls = [shapely.box(x, y, x + w, y + h) for x, y, w, h in rects] + _slabs(BOUNDS)
    gaps = shapely.linestrings([[(a, b), (c, d)] for a, b, c, d in segs]) if segs \
        else np.array([], dtype=object)
    if any(w.distance(shapely.Point(p)) < 1e-3 for w in walls for p in (start, goal)):
        return  # an end inside or on a wall: the passage search never asks that
    if share_region(walls, gaps, BOUNDS, start, goal, cell=cell, seal=SEAL):
        assert _same_region(walls, gaps, start, goal)


def test_an_open_floor_and_a_wall_with_a_door_are_found_joined():
    walls = _slabs(BOUNDS)
    assert share_region(walls, np.array([], dtype=object), BOUNDS, (1.0, 3.0), (7.0, 3.0),
                        cell=0.2, seal=SEAL)
    door = walls + [shapely.box(4.0, 0.0, 4.2, 2.5), shapely.box(4.0, 3.5, 4.2, 6.0)]
    assert share_region(door, np.array([], dtype=object), BOUNDS, (1.0, 3.0), (7.0, 3.0),
                        cell=0.2, seal=SEAL)
    sealed = shapely.linestrings([[(4.1, 2.5), (4.1, 3.5)]])  # the door closed as a gap
    assert not share_region(door, sealed, BOUNDS, (1.0, 3.0), (7.0, 3.0), cell=0.2, seal=SEAL)


def _pieced_wall(slot_y: float, slot: float, pieces: int):
    """A wall across x = 4.1 with one slot, cut into ``pieces`` boxes a side, 1 cm cracks
    between them (a map's wall: boxes that do not merge, cracks no body passes)."""
    lo, hi = slot_y - 0.5 * slot, slot_y + 0.5 * slot
    doc = []
    for a, b in ((0.0, lo), (hi, 6.0)):
        for k in range(pieces):
            y0, y1 = a + k * (b - a) / pieces, a + (k + 1) * (b - a) / pieces
            y0, y1 = (y0, y1) if pieces == 1 else (y0 + (0.005 if k else 0.0),
                                                    y1 - (0.005 if k < pieces - 1 else 0.0))
            doc.append({"type": "box", "center": [4.1, 0.5 * (y0 + y1)], "size": [0.2, y1 - y0],
                        "yaw": 0.0, "height": 2.0})
    return make_scene(obstacles=doc)


@pytest.mark.parametrize(("slot_y", "slot"), [(2.0, 0.5), (4.5, 0.3), (3.0, 1.2)])
def test_a_wall_of_many_pieces_gives_the_passage_of_a_wall_of_one(slot_y, slot):
    # 20 pieces a side, 40 cracks: the quick test is tried (few cells a piece) before the union
    many, one = _pieced_wall(slot_y, slot, 20), _pieced_wall(slot_y, slot, 1)
    p, q = blocking_passage(many), blocking_passage(one)
    if slot >= 1.0:  # a door the held assembly passes: no passage blocks
        assert p is None and q is None
        return
    assert p is not None and q is not None
    assert p.width == pytest.approx(q.width, abs=1e-9) == pytest.approx(slot, abs=1e-9)
    assert p.center == pytest.approx(q.center, abs=1e-6)


def test_the_shipped_scenes_keep_their_answers():
    assert blocking_passage(shipped("fig10")) is None
    p = blocking_passage(shipped("enclosed"))
    assert p is not None and p.center is None


def test_the_passage_is_searched_once_unless_a_search_was_stopped():
    once = PassageOnce(_pieced_wall(2.0, 0.5, 1))
    assert once(should_stop=lambda: True) is None  # stopped: nothing known, nothing kept
    p = once()
    assert p is not None and p.width == pytest.approx(0.5)
    assert once(should_stop=lambda: True) is p  # known: not searched again
