"""Held poses valid at every yaw of their bins: a sound hull; the proof tried where it may prove."""

from __future__ import annotations

import logging
import math

import numpy as np
import pytest
import shapely
from corner_factories import corner_slot
from factories import clear_lane_boxes, floor_with_clear_lane, make_scene, ragged_wall
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.late_proof import HELD_POSES, NOTHING_TO_PROVE, LateProof
from pivot_ompl.analysis.pose_cells import free_region
from pivot_ompl.analysis.pose_inner import EveryYawRegions, joined_at_every_yaw, swept_hull
from pivot_ompl.analysis.pose_proof import HeldParts, proof_estimate, prove_no_plan
from pivot_ompl.scene.shared import keep_shared, shared_value
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.merge import merge_boxes

points = st.lists(st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)), min_size=3, max_size=8)


@settings(max_examples=60, deadline=None)
@given(body=points, half=st.floats(0.0, 0.6))
@example(body=[(0.0, 1.0), (1.0, 1.0), (2.3774398992331143e-183, 0.0)], half=0.5)
def test_the_swept_hull_holds_the_body_turned_by_every_yaw_of_its_bin(body, half):
    pts = np.array(body)
    hull = shapely.orient_polygons(shapely.MultiPoint(pts).convex_hull)
    if hull.area < 1e-3:
        return
    ccw = np.asarray(hull.exterior.coords)[:-1]
    swept = shapely.Polygon(swept_hull(ccw, half)).buffer(1e-9)
    assert swept.is_valid
    for t in np.linspace(-half, half, 97):
        c, s = math.cos(t), math.sin(t)
        assert swept.contains(shapely.Polygon(ccw @ np.array([[c, s], [-s, c]])))



@pytest.mark.parametrize(("door", "joined"), [(1.2, True), (0.9, False)])
def test_a_wall_of_many_pieces_is_passed_at_every_yaw_through_a_wide_door_only(door, joined):
    scene = ragged_wall(door)
    assert len(merge_boxes(scene.obstacles)) > 90  # a piece a strip
    assert joined_at_every_yaw(scene) is joined


@settings(max_examples=8, deadline=None)
@given(door=st.floats(0.6, 1.6), seed=st.integers(0, 99), i=st.integers(0, 15))
def test_every_yaw_regions_are_the_free_region_of_the_swept_bodies(door, seed, i):
    # the regions built per bin (the box's sums joined once for every grasp, only the sums
    # near a region joined, the half-turn twin borrowed) are the set one union of every
    # piece's sums with the swept hulls leaves
    parts = HeldParts(ragged_wall(door, seed), KEEP_CLEARANCE, None)
    grown, area = parts.bins.grown, parts.area
    regions = EveryYawRegions(grown, parts.bodies, area)
    for j in (i, i + 16):  # the second, half a turn on, is the first's twin
        a, b = 2.0 * math.pi * j / 32, 2.0 * math.pi * (j + 1) / 32
        for g, got in enumerate(regions.regions(a, b)):
            want = free_region(grown, [swept_hull(body, 0.5 * (b - a)) for body in parts.bodies[g]],
                               0.5 * (a + b), area)
            assert got.symmetric_difference(want).area < 1e-9
            assert len(getattr(got, "geoms", [got])) == len(getattr(want, "geoms", [want]))
    assert regions.computed == 1


@settings(max_examples=5, deadline=None)
@given(door=st.floats(0.5, 1.6), seed=st.integers(0, 99))
@example(door=0.8, seed=0)  # no plan: the proof proves it
@example(door=1.2, seed=0)
def test_where_a_many_piece_wall_is_joined_at_every_yaw_the_proof_never_proves(door, seed):
    scene = ragged_wall(door, seed)
    if joined_at_every_yaw(scene):
        assert prove_no_plan(scene).apart is False  # joined at the finest bins


@settings(max_examples=6, deadline=None)
@given(boxes=clear_lane_boxes(10))
def test_a_floor_with_a_plan_is_joined_at_every_yaw_and_never_proven(boxes):
    scene = floor_with_clear_lane(boxes)  # the box pivots straight along the lane
    assert joined_at_every_yaw(scene) is True
    assert prove_no_plan(scene).apart is not True


def test_no_chain_valid_at_every_yaw_where_the_proof_proves():
    scene = corner_slot(0.90, 0.92)
    assert joined_at_every_yaw(scene) is False
    assert prove_no_plan(scene).apart is True
    # room to turn, but a 0.95 m slot (3.5 cm a side) admits no pose turned through a whole
    # 11.25-degree bin: the proof's coarse bins join there, these do not
    assert joined_at_every_yaw(corner_slot(3.0, 0.95)) is False


def test_a_stopped_search_answers_nothing():
    assert joined_at_every_yaw(make_scene(), should_stop=lambda: True) is None


def test_past_its_estimate_the_held_proof_runs_to_held_end_where_it_may_prove():
    scene = corner_slot(0.90, 0.92)
    guess = proof_estimate(scene)  # the held poses' proof's estimate
    keep_shared(scene, NOTHING_TO_PROVE, True)  # as where the poses' relaxation joins
    end = 1.0 + 0.9 * guess
    shut = LateProof(scene, begin=0.0, end=100.0, explain_end=end, clock=lambda: 1.0)
    assert shut() is False and shared_value(scene, HELD_POSES) is None  # does not fit
    late = LateProof(scene, begin=0.0, end=100.0, explain_end=end, clock=lambda: 1.0,
                     held_end=1.0 + guess)  # half the estimate fits before held_end
    assert late() is True
    assert "held poses" in late.proof.reason and "0.92 m" in late.proof.reason


def test_where_poses_valid_at_every_yaw_join_the_held_proof_is_not_run(caplog):
    scene = make_scene()  # an empty floor
    late = LateProof(scene, begin=0.0, end=100.0, clock=lambda: 1.0)
    with caplog.at_level(logging.DEBUG, logger="pivot_ompl.analysis.pose_proof"):
        assert late() is False
    assert not [r for r in caplog.records if "held poses, round" in r.getMessage()]
    assert shared_value(scene, HELD_POSES) is False  # kept: nothing it could prove
