"""The room's narrow passages: the held poses' proof sums the pieces near them first."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from corner_factories import ragged_slot
from factories import shipped
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis import pose_proof
from pivot_ompl.analysis.pose_bins import BinRegions
from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_passages import diameter, passages
from pivot_ompl.analysis.pose_proof import MOTION_CLEARANCE, HeldParts, prove_no_plan
from pivot_ompl.scene import Scene, scene_from_dict

DOOR_Y = 4.0


def _box(x0: float, y0: float, x1: float, y1: float) -> dict:
    return {"type": "box", "center": [0.5 * (x0 + x1), 0.5 * (y0 + y1)],
            "size": [x1 - x0, y1 - y0], "yaw": 0.0, "height": 2.0}


def two_rooms(seed: int, *, door: float = 0.7, closet: bool = True) -> Scene:
    """Two 6 x 8 m rooms joined by a door ``door`` m wide in a wall 0.2 m deep, the start in
    one, the goal in the other; the floor's top and bottom walls in 0.25 m strips ragged by
    up to 5 cm (``seed``) so that no two merge, and with ``closet`` a closet 1 m wide and
    1.5 m deep off the start's room (a dead end)."""
    rng = np.random.default_rng(seed)
    walls = [_box(-0.3, -0.3, 0.0, 8.3), _box(12.0, -0.3, 12.3, 8.3),
             _box(5.9, 0.0, 6.1, DOOR_Y - 0.5 * door), _box(5.9, DOOR_Y + 0.5 * door, 6.1, 8.0)]
    for x in np.arange(0.0, 12.0, 0.25):
        walls.append(_box(float(x), -0.3, float(x) + 0.25, float(rng.uniform(0.0, 0.05))))
        walls.append(_box(float(x), 8.0 - float(rng.uniform(0.0, 0.05)), float(x) + 0.25, 8.3))
    if closet:  # carved out of a thick left wall: its sides and back
        walls[0] = _box(-2.0, -0.3, -1.5, 8.3)
        walls += [_box(-1.5, -0.3, 0.0, 1.0), _box(-1.5, 2.0, 0.0, 8.3)]
    doc = {"name": f"two_rooms_{seed}", "bounds": [-2.0, -0.3, 12.3, 8.3],
           "object": {"size": [0.8, 0.4, 1.0]}, "start": [3.0, 4.0, 0.0],
           "goal": [9.0, 4.0, 0.0], "obstacles": walls}
    return scene_from_dict(doc, source="<test>")


def _half_width(floor: HeldFloor) -> float:
    return 0.5 * diameter(floor.bodies) - floor.radius


def test_the_passages_are_the_narrow_ways_between_start_and_goal_not_dead_ends():
    scene = two_rooms(0)
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    ends = [(scene.start[0], scene.start[1]), (scene.goal[0], scene.goal[1])]
    found = passages(floor.area, _half_width(floor), ends)
    assert len(found) == 1  # the door; not the closet, a dead end off the start's room
    assert found[0].distance(shapely.Point(6.0, DOOR_Y)) < 1e-6
    assert found[0].distance(shapely.Point(-0.75, 1.5)) > 1.0
    # the room has the closet: the room's narrow parts that are no passage were dropped
    assert floor.area.covers(shapely.Point(-0.75, 1.5))


def _built(monkeypatch: pytest.MonkeyPatch) -> list[BinRegions]:
    """Every BinRegions built from now on."""
    built: list[BinRegions] = []
    init = BinRegions.__init__

    def kept(self, *args, **kwargs) -> None:  # noqa: ANN001, ANN002, ANN003
        init(self, *args, **kwargs)
        built.append(self)

    monkeypatch.setattr(BinRegions, "__init__", kept)
    return built


def test_the_proof_sums_only_the_passages_pieces_where_they_keep_start_and_goal_apart(
        monkeypatch):
    scene = two_rooms(1)
    built = _built(monkeypatch)
    proof = prove_no_plan(scene)
    assert proof.apart is True
    every, door = built  # the regions of every piece, then of the door's
    pieces = [sum(len(s) for s in b.grown.values()) for b in (every, door)]
    assert pieces[1] < 0.2 * pieces[0]
    assert (every.computed, door.computed) == (0, door.computed) and door.computed > 0


def test_where_the_passages_pieces_join_start_and_goal_every_piece_decides(monkeypatch):
    scene = two_rooms(2)
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    everything = floor.near_room(MOTION_CLEARANCE)
    far = min(everything)  # a few pieces of one size: not the door's jambs alone
    monkeypatch.setattr(HeldFloor, "passages_near_room",
                        lambda self, clearance: {far: everything[far][:1]})
    built = _built(monkeypatch)
    proof = prove_no_plan(scene, floor=floor)
    assert proof.apart is True
    every, tried = built
    assert tried.computed > 0 and every.computed > 0  # tried, joined, then every piece


scenes = st.one_of(
    st.builds(two_rooms, st.integers(0, 99), door=st.floats(0.5, 1.6),
              closet=st.booleans()),
    st.builds(ragged_slot, st.integers(0, 99), slot=st.floats(0.85, 1.0), pieces=st.just(24)))


@settings(max_examples=6, deadline=None)
@given(scene=scenes, where=st.integers(0, 63), width=st.sampled_from([8, 32, 128]))
@example(scene=two_rooms(3, door=1.0), where=24, width=32)
def test_the_passages_parts_hold_every_piece_s_parts(scene, where, width):
    floor = HeldFloor(scene, MOTION_CLEARANCE, None)
    narrow = floor.passages_near_room(MOTION_CLEARANCE)
    a = 2.0 * math.pi * (where % width) / width
    b = a + 2.0 * math.pi / width
    fewer = HeldParts(scene, MOTION_CLEARANCE, None, floor=floor, pieces=narrow).of(a, b)
    every = HeldParts(scene, MOTION_CLEARANCE, None, floor=floor).of(a, b)
    for mine, all_pieces in zip(fewer, every, strict=True):
        held = shapely.union_all(mine) if mine else shapely.Polygon()
        for part in all_pieces:
            assert part.difference(held).area < 1e-9


@settings(max_examples=4, deadline=None)
@given(scene=scenes)
@example(scene=two_rooms(4, door=0.7))  # apart: the door's pieces prove it
@example(scene=two_rooms(5, door=1.0))  # joined: the held box passes the door
def test_the_passages_first_change_no_answer(scene):
    with pytest.MonkeyPatch.context() as m:
        m.setattr(pose_proof, "PASSAGE_SHARE", 0.0)  # every piece at once
        alone = prove_no_plan(scene).apart
    assert prove_no_plan(scene).apart is alone


def test_the_passages_proof_gives_way_after_its_bins(monkeypatch):
    scene = two_rooms(6, door=1.0)  # a plan passes the door: the passages' parts join
    monkeypatch.setattr(pose_proof, "PASSAGE_BINS", 3)
    built = _built(monkeypatch)
    assert prove_no_plan(scene).apart is False
    every, tried = built
    assert tried.computed == 3 and every.computed > 3


def test_a_small_floor_is_proven_with_every_piece_at_once(monkeypatch):
    built, asked = _built(monkeypatch), []
    monkeypatch.setattr(HeldFloor, "passages_near_room",
                        lambda self, clearance: asked.append(clearance) or {})
    prove_no_plan(shipped("door"))  # 14 pieces near its room
    assert len(built) == 1 and not asked  # its passages not even sought


def test_an_apart_proofs_reach_holds_the_start_and_not_the_goal():
    scene = two_rooms(7)
    proof = prove_no_plan(scene)
    assert proof.apart is True and proof.reached
    reach = proof.start_reach
    assert reach is not None and reach.covers(shapely.Point(scene.start[:2]))
    assert not reach.intersects(shapely.Point(scene.goal[:2]))
    assert reach.symmetric_difference(shapely.union_all(proof.reached)).area < 1e-9
