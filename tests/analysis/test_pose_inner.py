"""Held poses valid at every yaw of their bins: a sound hull; the proof tried where it may prove."""

from __future__ import annotations

import logging
import math

import numpy as np
import shapely
from corner_factories import corner_slot
from factories import clear_lane_boxes, floor_with_clear_lane, make_scene
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.late_proof import HELD_POSES, NOTHING_TO_PROVE, LateProof
from pivot_ompl.analysis.pose_inner import joined_at_every_yaw, swept_hull
from pivot_ompl.analysis.pose_proof import proof_estimate, prove_no_plan
from pivot_ompl.scene.shared import keep_shared, shared_value

points = st.lists(st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)), min_size=3, max_size=8)


@settings(max_examples=60, deadline=None)
@given(body=points, half=st.floats(0.0, 0.6))
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
