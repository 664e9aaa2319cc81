"""Detours straightened by turns in place: cheaper, shorter, valid, same ends and grasps."""

from __future__ import annotations

import math

from factories import make_scene
from hypothesis import given, settings
from hypothesis import strategies as hs

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.straighten import StraightenStats, straighten
from pivot_ompl.quality import plan_quality
from pivot_ompl.validity.plan_check import check_plan

START = (2.0, 3.0, 0.0)


def _problem(goal):
    scene = make_scene(start=list(START), goal=list(goal), bounds=[-1.0, -1.0, 9.0, 7.0])
    return scene, make_problem(scene).checker


def _route(scene, ck, states, *, shortcut: bool = True):
    return plan_quality(path_to_plan(scene, ck, states, shortcut=shortcut))["route_length"]


def test_a_looping_reeds_shepp_transfer_becomes_turn_push_turn():
    """3 m ahead, turned by a quarter turn: the 2 m turning radius loops; turning does not."""
    goal = (5.0, 3.4, 0.5 * math.pi)
    scene, ck = _problem(goal)
    states = [(START, 0), (goal, 0)]
    w = CostModel()
    before = Evaluator(ck, w).path(states).cost
    stats = StraightenStats()
    out = straighten(ck, states, costs=w, should_stop=lambda: False, stats=stats)
    after = Evaluator(ck, w).path(out).cost
    assert stats.applied >= 1 and after < 0.8 * before, (before, after)
    assert out[0] == states[0] and out[-1] == states[-1]
    assert {g for _, g in out} == {0}
    plan = path_to_plan(scene, ck, out)
    rep = check_plan(plan, scene)
    assert rep.ok, rep.problems
    # the box's route: about the straight line, not the loop (compared as converted: the
    # phases' shortening, tested on its own, also tightens the loop's arcs)
    assert _route(scene, ck, out, shortcut=False) < 0.8 * _route(scene, ck, states,
                                                                 shortcut=False)
    assert _route(scene, ck, out) < 1.45 * math.hypot(goal[0] - START[0], goal[1] - START[1])


def test_a_detour_over_several_waypoints_is_cut_across():
    """A zigzag of three transfers is replaced as a whole (not only neighbours)."""
    goal = (6.5, 3.0, 0.0)
    scene, ck = _problem(goal)
    states = [(START, 0), ((3.5, 4.5, 0.6), 0), ((5.0, 1.5, -0.6), 0), (goal, 0)]
    w = CostModel()
    assert math.isfinite(Evaluator(ck, w).path(states).cost)
    out = straighten(ck, states, costs=w, should_stop=lambda: False)
    assert Evaluator(ck, w).path(out).cost < 0.7 * Evaluator(ck, w).path(states).cost
    assert not {q for q, _ in states[1:-1]} & {q for q, _ in out}  # both detours gone
    assert check_plan(path_to_plan(scene, ck, out), scene).ok


def test_stopped_at_once_returns_the_input():
    goal = (5.0, 3.4, 0.5 * math.pi)
    _, ck = _problem(goal)
    states = [(START, 0), (goal, 0)]
    assert straighten(ck, states, costs=CostModel(), should_stop=lambda: True) == states


@settings(max_examples=8, deadline=None)
@given(x=hs.floats(2.5, 7.0), y=hs.floats(1.0, 5.0), yaw=hs.floats(-math.pi, math.pi),
       grasp=hs.sampled_from([0, 1]))
def test_never_costlier_always_valid(x, y, yaw, grasp):
    goal = (x, y, yaw)
    scene, ck = _problem(goal)
    w = CostModel()
    states = [(START, grasp), (goal, grasp)]
    before = Evaluator(ck, w).path(states).cost
    if not math.isfinite(before):
        return
    out = straighten(ck, states, costs=w, should_stop=lambda: False, max_tries=4)
    assert out[0] == states[0] and out[-1] == states[-1]
    assert all(g == grasp for _, g in out)
    assert Evaluator(ck, w).path(out).cost <= before + 1e-9
    assert check_plan(path_to_plan(scene, ck, out), scene).ok
