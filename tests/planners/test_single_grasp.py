"""The single-grasp RRT-Connect tried before the multiplexed search."""

from __future__ import annotations

import numpy as np
from factories import shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planners.evaluation import Found, Status
from pivot_ompl.planners.single_grasp import SingleGraspConnect
from pivot_ompl.validity.plan_check import check_plan


def test_connects_the_cluttered_room_with_one_grasp():
    scene = shipped("cluttered_room")
    checker = PivotChecker(scene)
    rrt = SingleGraspConnect(checker, scene.start, scene.goal, 0, np.random.default_rng(0))
    found = rrt.run(200, lambda: False)
    assert found.status is Status.VALID and found.path is not None
    poses = found.path
    assert poses[0] == scene.start and poses[-1] == scene.goal and len(poses) > 2
    before = checker.counters.valid + checker.counters.invalid
    plan = path_to_plan(scene, checker, [(q, 0) for q in poses])
    # every edge was checked in the direction the plan follows it (both trees)
    assert checker.counters.valid + checker.counters.invalid == before
    assert plan.regrasps == 0 and check_plan(plan, scene).ok


def test_stops_at_its_budget_where_a_regrasp_is_needed():
    scene = shipped("fig10")
    rrt = SingleGraspConnect(PivotChecker(scene), scene.start, scene.goal, 0,
                             np.random.default_rng(0))
    assert rrt.run(15, lambda: False) == Found(Status.INVALID)  # the budget ran out
    assert rrt.checks == 15
    # the condition stops it: said as such, not as a failure
    assert rrt.run(20, lambda: True) == Found(Status.STOPPED) and rrt.checks == 15


def test_an_extension_through_an_obstacle_costs_no_pivot_check():
    # the direct edge crosses fig10's walls: refused by the cheap test, counted as a check
    scene = shipped("fig10")
    checker = PivotChecker(scene)
    rrt = SingleGraspConnect(checker, scene.start, scene.goal, 0, np.random.default_rng(0))
    assert rrt.run(1, lambda: False).status is Status.INVALID and rrt.checks == 1
    assert checker.counters.valid + checker.counters.invalid == 0

