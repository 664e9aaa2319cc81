"""Slots read from the scene's geometry, and the box poses seeded along them."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene, shipped, two_rooms
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import RigidMap, mirror_scene, rotate_scene
from pivot_ompl.planners.config import RegraspConfig, SamplingConfig
from pivot_ompl.planners.objects.slots import find_passages, passage_poses
from pivot_ompl.planners.regrasp_search import RegraspSearch

#: fig10's slot widths window: the box's 0.4 m side and 1 cm a side, up to the walking body's
#: 0.60 m depth, 1 cm a side and 10 cm of play
WINDOW = {"min_width": 0.42, "max_width": 0.72}


def _slots(scene):
    return sorted(find_passages(scene, **WINDOW), key=lambda p: p.center)


def test_fig10_has_two_slots_centred_in_its_walls():
    slots = _slots(shipped("fig10"))
    assert [p.center for p in slots] == [pytest.approx((3.55, 1.5)), pytest.approx((8.95, 5.5))]
    for p in slots:
        assert p.axis == pytest.approx(0.0, abs=1e-9)
        assert p.width == pytest.approx(0.62)
        assert p.length == pytest.approx(0.5)  # the walls' thickness


def _same_axis(a: float, b: float) -> bool:
    return abs(math.remainder(a - b, math.pi)) < 1e-6


@settings(max_examples=12, deadline=None)
@given(angle=st.floats(-math.pi, math.pi), mirror=st.booleans())
def test_slots_move_with_the_scene(angle, mirror):
    # no direction of the world is preferred: a rotated or mirrored copy has the image slots
    scene = shipped("fig10")
    centre = (0.5 * (scene.bounds[0] + scene.bounds[2]), 0.5 * (scene.bounds[1] + scene.bounds[3]))
    copy = mirror_scene(scene, angle) if mirror else rotate_scene(scene, angle)
    f = RigidMap(angle, centre, mirror)
    found = find_passages(copy, **WINDOW)
    for p in _slots(scene):
        cx, cy = f.point(p.center)
        match = [q for q in found if math.hypot(q.center[0] - cx, q.center[1] - cy) < 1e-6
                 and _same_axis(q.axis, f.yaw(p.axis))]
        assert len(match) == 1, (p, found)
        assert match[0].width == pytest.approx(p.width)
        assert match[0].length == pytest.approx(p.length)


def test_each_slot_gets_a_seeded_node_where_the_box_can_be_let_go():
    # the poses seeded along a slot include one inside it where the robot holds the box from
    # either side (grasps k and k + 2): the regrasp the slot forces
    scene = shipped("fig10")
    ck = PivotChecker(scene, seed=0)
    for slot in _slots(scene):
        poses = [q for q in passage_poses(slot, reach=0.8, spacing=0.1, approach=(0.4,))
                 if ck.box_valid(q)]
        both = [q for q in poses for k in (0, 1) if ck.state_valid(q, k)
                and ck.state_valid(q, k + 2)]
        assert both, slot


@pytest.mark.parametrize(("kind", "scene", "count", "least"), [
    ("slot", lambda: shipped("fig10"), 2, 21), ("door", lambda: two_rooms(1.7), 1, 6)])
def test_the_planner_seeds_its_roadmap_along_the_slots_and_doors(kind, scene, count, least):
    scene = scene()
    ck = PivotChecker(scene, seed=0)
    search = RegraspSearch(ck, scene.start, scene.goal, RegraspConfig(),
                           np.random.default_rng(0))
    search.prepare(lambda: False)
    assert getattr(search.stats, f"{kind}s") >= count
    seeded = [search.roadmap[i] for i in search.roadmap.of_kind(kind)]
    assert len(seeded) == getattr(search.stats, f"{kind}_nodes") >= least
    assert all(ck.box_valid(q) for q in seeded)
    off = RegraspSearch(ck, scene.start, scene.goal,
                        RegraspConfig(sampling=SamplingConfig(**{f"{kind}s": False})),
                        np.random.default_rng(0))
    off.prepare(lambda: False)
    assert not off.roadmap.of_kind(kind)


def test_a_row_of_specks_gives_the_gaps_between_neighbours_only():
    # 150 round specks in a row, 0.5 m apart: each gap between neighbours is a passage; the
    # gap to the next but one has a speck across it (blocked), whichever batch of pairs it
    # falls in
    side, gap, n = 0.1, 0.5, 150
    width = 4.0 + n * (side + gap)
    specks = [{"type": "cylinder", "center": [2.0 + k * (side + gap), 5.0], "radius": 0.5 * side,
               "height": 1.0} for k in range(n)]
    scene = make_scene(bounds=[0.0, 0.0, width, 10.0], obstacles=specks)
    found = find_passages(scene, min_width=0.3, max_width=1.3)
    assert len(found) == n - 1
    assert all(p.width == pytest.approx(gap, abs=1e-3) for p in found)
    xs = sorted(p.center[0] for p in found)
    assert xs == pytest.approx([2.0 + (k + 0.5) * (side + gap) for k in range(n - 1)])
