"""Regrasps slid along the transfers beside them: valid, same ends, never costlier."""

from __future__ import annotations

import math

from factories import open_floor_checker
from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.regrasp_slide import SlideStats, slide_regrasps

START = (1.0, 3.0, 0.0)
GOAL = (7.0, 3.0, 0.0)


def _checker(**extra):
    return open_floor_checker(START, GOAL, **extra)


def _grasps(states):
    return [g for k, (_, g) in enumerate(states) if k == 0 or g != states[k - 1][1]]


def test_a_regrasp_off_the_way_slides_to_a_cheaper_pose():
    """Grasp 0 at the start, 1 at the goal (one regrasp needed), the regrasp 2 m aside."""
    ck = _checker()
    mid = (4.0, 5.0, 0.8)
    states = [(START, 0), (mid, 0), (mid, 1), (GOAL, 1)]
    w = CostModel()
    before = Evaluator(ck, w).path(states)
    assert before.valid, before.reason
    stats = SlideStats()
    out = slide_regrasps(ck, states, costs=w, should_stop=lambda: False, start_grasp=0,
                         end_grasp=1, stats=stats, distances=(0.5, 1.0, 2.0), reach=4.0)
    after = Evaluator(ck, w).path(out)
    assert after.valid
    assert stats.regrasps == 1 and stats.offered > 0
    assert after.cost < before.cost - 1.0
    assert stats.seconds_saved > 1.0
    assert out[0] == states[0] and out[-1] == states[-1]
    assert _grasps(out) == [0, 1]
    # the regrasp moved: the box is not turned to the old regrasp pose
    assert all(p != mid for p, _ in out)


@settings(max_examples=6, deadline=None)
@given(hs.floats(1.5, 6.5), hs.floats(0.5, 5.5), hs.floats(-math.pi, math.pi),
       hs.sampled_from([1, 2, 3]))
def test_the_result_is_valid_with_the_same_ends_and_never_costlier(x, y, yaw, g):
    ck = _checker()
    mid = (x, y, yaw)
    states = [(START, 0), (mid, 0), (mid, g), (GOAL, g)]
    w = CostModel()
    e = Evaluator(ck, w).path(states)
    if not e.valid:
        return
    out = slide_regrasps(ck, states, costs=w, should_stop=lambda: False, start_grasp=0,
                         end_grasp=g)
    after = Evaluator(ck, w).path(out)
    assert after.valid
    assert after.cost <= e.cost + 1e-9
    assert out[0] == states[0] and out[-1] == states[-1]
    assert out[-1][1] == g


def test_a_path_without_regrasps_and_a_stopped_run_are_returned_as_they_were():
    ck = _checker()
    plain = [(START, 0), ((4.0, 5.0, 0.8), 0), (GOAL, 0)]
    assert slide_regrasps(ck, plain, costs=CostModel(), should_stop=lambda: False) == plain
    mid = (4.0, 5.0, 0.8)
    states = [(START, 0), (mid, 0), (mid, 1), (GOAL, 1)]
    assert slide_regrasps(ck, states, costs=CostModel(), should_stop=lambda: True) == states
