"""Touching box obstacles merged into one: the same floor in fewer pieces."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
import shapely
from factories import make_scene, sliced
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, PolygonObstacle
from pivot_ompl.validity import merge
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_footprints
from pivot_ompl.validity.merge import merge_boxes

#: Grid (m) of the unions compared: GEOS's floating overlay can lose a piece whose side is
#: shared with another's to round-off only (a rotated cut).
GRID = 1e-11


def _union(obstacles):
    return shapely.union_all(obstacle_footprints(list(obstacles)), grid_size=GRID)


def _difference_area(a, b):
    return shapely.symmetric_difference(_union(a), _union(b), grid_size=GRID).area


def _guillotine(rect, cuts, rng):
    """``rect`` ``(u0, v0, u1, v1)`` cut ``cuts`` times, each piece across a random axis."""
    pieces = [rect]
    for _ in range(cuts):
        k = int(rng.integers(len(pieces)))
        u0, v0, u1, v1 = pieces.pop(k)
        t = float(rng.uniform(0.1, 0.9))
        if rng.random() < 0.5:
            m = u0 + t * (u1 - u0)
            pieces += [(u0, v0, m, v1), (m, v0, u1, v1)]
        else:
            m = v0 + t * (v1 - v0)
            pieces += [(u0, v0, u1, m), (u0, m, u1, v1)]
    return pieces


def _box(piece, yaw, turns, height=1.0):
    """The piece (in the frame of ``yaw``) as a box of yaw ``yaw + turns pi/2``."""
    u0, v0, u1, v1 = piece
    c, s = math.cos(yaw), math.sin(yaw)
    u, v = 0.5 * (u0 + u1), 0.5 * (v0 + v1)
    size = (u1 - u0, v1 - v0) if turns % 2 == 0 else (v1 - v0, u1 - u0)
    return BoxObstacle((c * u - s * v, s * u + c * v), size, yaw + turns * 0.5 * math.pi, height)


@st.composite
def cut_rectangles(draw):
    """Boxes cut from a few rectangles apart from each other, and how many rectangles."""
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    yaw = draw(st.sampled_from([0.0, None]))
    yaw = float(rng.uniform(-math.pi, math.pi)) if yaw is None else yaw
    n = draw(st.integers(1, 3))
    boxes = []
    for k in range(n):
        u0 = 10.0 * k + float(rng.uniform(0.0, 1.0))
        v0 = float(rng.uniform(-3.0, 3.0))
        rect = (u0, v0, u0 + float(rng.uniform(0.3, 8.0)), v0 + float(rng.uniform(0.3, 4.0)))
        for p in _guillotine(rect, draw(st.integers(0, 12)), rng):
            boxes.append(_box(p, yaw, int(rng.integers(-2, 3))))
    order = rng.permutation(len(boxes))
    return [boxes[i] for i in order], n


@settings(max_examples=150, deadline=None)
@given(cut_rectangles())
def test_cut_rectangles_merge_back_to_the_same_floor(case):
    boxes, rectangles = case
    merged = merge_boxes(boxes)
    assert len(merged) <= len(boxes)
    assert _difference_area(boxes, merged) < 1e-9
    assert len(merged) == rectangles  # a guillotine cut always undoes itself


@pytest.mark.parametrize("k,m", [(1, 1), (1, 5), (4, 1), (3, 7), (20, 30)])
@pytest.mark.parametrize("yaw", [0.0, 0.7, -2.0])
def test_a_grid_of_unit_cells_is_one_box(k, m, yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    cells = [BoxObstacle((c * (i + 0.5) - s * (j + 0.5), s * (i + 0.5) + c * (j + 0.5)),
                         (1.0, 1.0), yaw, 2.0) for i in range(k) for j in range(m)]
    (one,) = merge_boxes(cells)
    assert isinstance(one, BoxObstacle)
    assert sorted(one.size) == pytest.approx(sorted((k, m)))
    assert one.height == 2.0
    assert _difference_area(cells, [one]) < 1e-9


def test_heights_or_yaws_that_differ_are_not_merged():
    a = BoxObstacle((0.5, 0.5), (1.0, 1.0), 0.0, 1.0)
    higher = BoxObstacle((1.5, 0.5), (1.0, 1.0), 0.0, 1.5)
    assert merge_boxes([a, higher]) == [a, higher]
    turned = BoxObstacle((1.5, 0.5), (1.0, 1.0), 1e-6, 1.0)  # touching, slightly turned
    assert merge_boxes([a, turned]) == [a, turned]
    quarter = BoxObstacle((1.5, 0.5), (1.0, 1.0), 0.5 * math.pi, 1.0)  # the same square
    (one,) = merge_boxes([a, quarter])
    assert one.size == pytest.approx((2.0, 1.0)) and one.center == pytest.approx((1.0, 0.5))


def test_boxes_of_other_extents_and_other_obstacles_pass_unchanged():
    a = BoxObstacle((0.5, 0.5), (1.0, 1.0), 0.0, 1.0)
    b = BoxObstacle((0.5, 1.6), (1.0, 1.2), 0.0, 1.0)  # shares a's top side: merged
    shorter = BoxObstacle((1.5, 0.4), (1.0, 0.8), 0.0, 1.0)  # touches a, half a side
    apart = BoxObstacle((0.5, 3.0), (1.0, 0.5), 0.0, 1.0)  # b's extent, with a gap
    cyl = CylinderObstacle((5.0, 5.0), 0.5, 1.0)
    poly = PolygonObstacle(((6.0, 0.0), (7.0, 0.0), (7.0, 1.0)), 1.0)
    out = merge_boxes([cyl, a, shorter, poly, b, apart])
    assert out[0] is cyl and out[2] is shorter and out[3] is poly and out[4] is apart
    assert out[1] == BoxObstacle((0.5, 1.1), (1.0, 2.2), 0.0, 1.0)


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 2**32 - 1))
def test_the_world_measures_merged_boxes_as_their_pieces(seed):
    rng = np.random.default_rng(seed)
    walls = [BoxObstacle((float(x), float(y)), (float(a), float(b)), float(t), 1.0)
             for x, y, a, b, t in zip(rng.uniform(1, 9, 4), rng.uniform(1, 5, 4),
                                      rng.uniform(0.1, 3, 4), rng.uniform(0.1, 3, 4),
                                      rng.uniform(-math.pi, math.pi, 4), strict=True)]
    scene = dataclasses.replace(make_scene(bounds=[0, 0, 10, 6]),
                                obstacles=tuple(sliced(walls, 3)))
    merged = CollisionWorld.from_scene(scene, clearance=0.0)
    assert len(merged.obstacles) < len(scene.obstacles)
    pieces = CollisionWorld(scene.model, scene.bounds)
    for o in scene.obstacles:
        pieces.add_obstacle(o)
    pieces.setup()
    for x, y, yaw in zip(rng.uniform(0, 10, 40), rng.uniform(0, 6, 40),
                         rng.uniform(-math.pi, math.pi, 40), strict=True):
        q = (float(x), float(y), float(yaw))
        # coal's GJK stops at 1e-6 relative to the distance (the disk's distances to the walls
        # and to their slices already differ by ~2e-6 at 2 m)
        got = [(w.box_distance(q), w.robot_distance(q), w.held_distance(q, 1),
                w.turning_disk_distance(*q[:2])) for w in (merged, pieces)]
        for a, b in zip(*got, strict=True):
            if max(a, b) > 1e-6:
                assert a == pytest.approx(b, abs=2e-6 * (1.0 + abs(b)))
            else:  # both hit (a penetration depth may differ)
                assert a <= 1e-6 and b <= 1e-6


def test_the_merge_polls_on_a_large_floor():
    cells = [BoxObstacle((i + 0.5, j + 0.5), (1.0, 1.0), 0.0, 1.0)
             for i in range(120) for j in range(100)]
    calls = []
    (one,) = merge_boxes(cells, should_stop=lambda: calls.append(1) or False)
    assert one.size == pytest.approx((120.0, 100.0))
    assert len(calls) >= len(cells) // merge.POLL_BOXES  # within a pass, not only between
    calls.clear()
    with pytest.raises(Interrupted):
        merge_boxes(cells, should_stop=lambda: calls.append(1) or len(calls) > 3)
    scene = dataclasses.replace(make_scene(), obstacles=tuple(cells))
    calls.clear()
    with pytest.raises(Interrupted):  # before the world builds its first obstacle
        CollisionWorld.from_scene(scene, should_stop=lambda: calls.append(1) or len(calls) > 3)


def test_a_tuple_merged_again_is_handed_its_kept_merge_as_a_new_list():
    # a plan merges the scene's tuple half a dozen times (30 ms each on a building of 5000
    # walls): a tuple merged once is answered from what was kept, without work (a stop
    # asked at once is not even polled); another tuple, even equal, is merged itself
    from pivot_ompl.scene import BoxObstacle
    from pivot_ompl.validity.merge import merge_boxes

    walls = tuple(BoxObstacle((0.5 + i, 0.0), (1.0, 0.2), 0.0, 1.0) for i in range(6))
    first = merge_boxes(walls)
    assert len(first) == 1
    again = merge_boxes(walls, should_stop=lambda: True)
    assert again == first and again is not first
    again.clear()  # the caller's list: the kept merge is untouched
    assert merge_boxes(walls) == first
    with pytest.raises(Interrupted):  # an equal tuple, another object: merged itself
        merge_boxes(tuple(list(walls)), should_stop=lambda: True)
    assert merge_boxes(list(walls)) == first
