"""Phases re-planned along the route bound's shortest route: valid, same ends, never costlier."""

from __future__ import annotations

import math

from factories import open_floor_checker
from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.follow_route import FollowStats, follow_route

START = (1.0, 3.0, 0.0)
GOAL = (7.0, 3.0, 0.0)


def _checker(**extra):
    return open_floor_checker(START, GOAL, **extra)


def _phases(states):
    """Grasps in order, and the poses where the grasp changes."""
    return ([g for k, (_, g) in enumerate(states) if k == 0 or g != states[k - 1][1]],
            [p for (p, g), (q, h) in zip(states, states[1:], strict=False) if g != h])


def test_a_detour_in_an_open_room_follows_the_straight_route():
    """Out 2 m to the side and back: the shortest route is straight, and cheaper."""
    ck = _checker()
    states = [(START, 0), ((4.0, 5.0, 0.8), 0), (GOAL, 0)]
    w = CostModel()
    before = Evaluator(ck, w).path(states).cost
    stats = FollowStats()
    out = follow_route(ck, states, costs=w, should_stop=lambda: False, stats=stats)
    after = Evaluator(ck, w).path(out)
    assert after.valid
    assert after.cost < before - 1.0
    assert stats.applied == 1 and stats.seconds_saved > 1.0
    assert out[0] == states[0] and out[-1] == states[-1]
    # the box never strays far from the straight line between the ends
    assert max(abs(p[1] - 3.0) for p, _ in out) < 1.0


@settings(max_examples=6, deadline=None)
@given(hs.floats(1.5, 6.5), hs.floats(0.5, 5.5), hs.floats(-math.pi, math.pi),
       hs.sampled_from([0, 1]))
def test_the_result_is_valid_with_the_same_phases_and_never_costlier(x, y, yaw, g):
    """Any valid path (here: through one waypoint, a regrasp at the goal side)."""
    ck = _checker()
    mid = (x, y, yaw)
    states = [(START, 0), (mid, 0), (mid, g), (GOAL, g)]
    w = CostModel()
    e = Evaluator(ck, w).path(states)
    if not e.valid:
        return
    out = follow_route(ck, states, costs=w, should_stop=lambda: False)
    after = Evaluator(ck, w).path(out)
    assert after.valid
    assert after.cost <= e.cost + 1e-9
    assert out[0] == states[0] and out[-1] == states[-1]
    assert _phases(out) == _phases(states)


def test_stopped_at_once_returns_the_path_as_it_was():
    ck = _checker()
    states = [(START, 0), ((4.0, 5.0, 0.8), 0), (GOAL, 0)]
    out = follow_route(ck, states, costs=CostModel(), should_stop=lambda: True)
    assert out == states


def test_a_zigzag_through_a_door_follows_the_route_through_it():
    """A wall with a 1.6 m door: the route bound's path runs straight through it."""
    wall = [dict(type="box", height=1.0, center=[5.0, 0.6], size=[0.3, 3.2]),
            dict(type="box", height=1.0, center=[5.0, 5.4], size=[0.3, 3.2])]
    ck = _checker(obstacles=wall)
    states = [(START, 0), ((2.5, 4.5, 0.0), 0), ((3.8, 3.0, 0.0), 0), ((6.2, 3.0, 0.0), 0),
              (GOAL, 0)]
    w = CostModel()
    before = Evaluator(ck, w).path(states)
    assert before.valid, before.reason
    out = follow_route(ck, states, costs=w, should_stop=lambda: False)
    after = Evaluator(ck, w).path(out)
    assert after.valid
    assert after.cost < before.cost - 1.0
    assert out[0] == states[0] and out[-1] == states[-1]
