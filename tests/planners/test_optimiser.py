"""The path optimiser: cheaper paths by the cost model, valid paths, termination honoured."""

from __future__ import annotations

import dataclasses
import math
import time

import pytest
from factories import make_scene, shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem
from pivot_ompl.cost import CostModel, DurationModel
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.optimiser import OptimiseStats, optimise, optimise_over
from pivot_ompl.validity.plan_check import check_plan

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

START, GOAL = (1.5, 3.0, 0.0), (6.5, 3.0, 0.0)


def _zigzag_with_regrasps():
    """A valid but wasteful open-floor path: detours, a regrasp there and back, a chain."""
    # floor to the left of the start: the holding robot's body turns round behind it
    scene = make_scene(start=list(START), goal=list(GOAL), bounds=[-1.0, 0.0, 8.0, 6.0])
    problem = make_problem(scene)
    ck = problem.checker
    w1, w2, w3 = (2.5, 4.2, 0.5), (4.0, 1.8, -0.4), (5.2, 4.0, 0.3)
    states = [(START, 0), (w1, 0), (w1, 1), (w1, 0), (w2, 0), (w2, 2), (w2, 3), (w3, 3),
              (GOAL, 3)]
    assert math.isfinite(Evaluator(ck, CostModel()).path(states).cost), "the input must be valid"
    return scene, ck, states


def _regrasps(states):
    return sum(1 for a, b in zip(states, states[1:], strict=False) if a[1] != b[1])


def test_optimiser_cuts_pivots_and_regrasps_and_stays_valid():
    scene, ck, states = _zigzag_with_regrasps()
    w = CostModel()
    stats = OptimiseStats()
    out = optimise(ck, states, should_stop=lambda: False, costs=w, stats=stats)
    before, after = Evaluator(ck, w).path(states).cost, Evaluator(ck, w).path(out).cost
    assert after <= before and stats.cost_after == after and stats.optimal
    # open floor: one straight push at one grasp, the waste and every regrasp gone
    assert _regrasps(out) == 0 and len(out) == 2
    assert out[0][0] == START and out[-1][0] == GOAL
    plan = path_to_plan(scene, ck, out)
    rep = check_plan(plan, scene)
    assert rep.ok, rep.problems
    pivots_before = path_to_plan(scene, ck, states).pivots
    assert plan.pivots < 0.6 * pivots_before, (plan.pivots, pivots_before)


def test_regrasps_kept_where_needed_and_rules_hold():
    """On the slot scene a regrasp is needed: the optimised path keeps a valid one."""
    from pivot_ompl.api import plan

    scene = shipped("slot")
    res = plan(scene, planner="regrasp", time_limit=60.0, seed=0)
    assert res.solved and res.regrasps >= 1
    assert check_plan(res.plan, scene).ok


def test_grasp_is_chosen_by_the_cost():
    """A move along the box's y axis: sideways for grasp 0, a straight push for grasp 1."""
    a, b = (2.0, 1.5, 0.0), (2.0, 4.5, 0.0)
    scene = make_scene(start=list(a), goal=list(b))
    ck = make_problem(scene).checker
    states = [(a, 2), (b, 2)]  # sideways at grasp 2 (grasp 0 would leave the bounds)
    free = CostModel(regrasp=0.0, durations=DurationModel(per_transfer=0.0, per_transit=0.0,
                                                          per_walk_m=0.0))
    cheap = optimise(ck, states, should_stop=lambda: False, costs=free)
    moving = {a_[1] for a_, b_ in zip(cheap, cheap[1:], strict=False) if a_[1] == b_[1]}
    assert moving <= {1, 3}  # the push, no sideways manoeuvre
    assert Evaluator(ck, free).path(cheap).cost < 0.5 * Evaluator(ck, free).path(states).cost
    assert check_plan(path_to_plan(scene, ck, cheap), scene).ok
    # a regrasp priced above the pivots it saves is not taken (start at grasp 0 only)
    ck2 = make_problem(scene).checker
    dear = optimise(ck2, states, should_stop=lambda: False, grasps=(0, 2),
                    costs=CostModel(regrasp=1000.0))
    assert _regrasps(dear) == 0


def test_termination_condition_is_honoured():
    _scene, ck, states = _zigzag_with_regrasps()
    t0 = time.perf_counter()
    stats = OptimiseStats()
    out = optimise(ck, states, should_stop=lambda: True, stats=stats)
    assert time.perf_counter() - t0 < 0.5
    # no new edge is checked; the input's own edges still allow dropping the round trip
    assert stats.transfers_checked == stats.walks_checked == 0 and stats.rounds == 0
    assert Evaluator(ck, CostModel()).path(out).cost <= Evaluator(ck, CostModel()).path(states).cost
    calls = []

    def stop():
        calls.append(1)
        return len(calls) > 3

    out = optimise(ck, states, should_stop=stop)
    assert math.isfinite(Evaluator(ck, CostModel()).path(out).cost)
    assert Evaluator(ck, CostModel()).path(out).cost <= Evaluator(ck, CostModel()).path(states).cost


def test_walks_are_computed_only_for_paths_whose_transfers_hold():
    """The transfers of a candidate path are checked before its walks: with every transfer
    but the input's own refused, no walk but the input's own is ever computed (in path order
    the regrasp at the first waypoint of a candidate would be walked before its transfer)."""
    scene = make_scene(start=list(START), goal=list(GOAL))
    ck = make_problem(scene).checker
    mid = (4.0, 3.0, 0.0)
    states = [(START, 0), (mid, 0), (mid, 1), (GOAL, 1)]
    own = {(START, mid, 0), (mid, GOAL, 1)}
    walks: list[tuple] = []
    transfer, transit = ck.transfer, ck.transit

    def only_own(a, b, g, **kw):
        res = transfer(a, b, g, **kw)
        return res if (a, b, g) in own else dataclasses.replace(res, valid=False)

    def logged(obj, g, h, **kw):
        walks.append((obj, g, h))
        return transit(obj, g, h, **kw)

    ck.transfer, ck.transit = only_own, logged
    out = optimise(ck, states, should_stop=lambda: False)
    assert out == states
    assert set(walks) == {(mid, 0, 1)}


def test_no_shortcut_beyond_the_reach():
    """Shortcuts span at most ``reach`` between the box's centres; the input's own transfers
    stay whatever their length (open floor: with the default reach it goes straight)."""
    _scene, ck, states = _zigzag_with_regrasps()
    out = optimise(ck, states, should_stop=lambda: False, reach=2.0)
    own = {(a[0], b[0]) for a, b in zip(states, states[1:], strict=False)}
    for a, b in zip(out, out[1:], strict=False):
        if a[1] == b[1] and (a[0], b[0]) not in own:
            assert math.dist(a[0][:2], b[0][:2]) <= 2.0
    assert Evaluator(ck, CostModel()).path(out).cost <= Evaluator(ck, CostModel()).path(states).cost
    straight = optimise(ck, states, should_stop=lambda: False)
    assert len(straight) == 2  # 5 m apart: one shortcut within the default reach


def test_optimise_over_passes_waypoints_the_path_did_not_and_links_far_ones():
    """A detour given, a pose on the straight way offered: the result passes it, cheaper.

    The offered poses are 5 m from each other, beyond the reach: only ``links`` joins them.
    """
    scene = make_scene(start=[0.5, 3.0, 0.0], goal=[10.5, 3.0, 0.0],
                       bounds=[-1.0, -1.0, 12.0, 7.0])
    ck = make_problem(scene).checker
    a, detour, mid, b = (0.5, 3.0, 0.0), (5.5, 5.5, 0.0), (5.5, 3.0, 0.0), (10.5, 3.0, 0.0)
    poses = [a, mid, detour, b]
    path = [(0, 0), (2, 0), (3, 0)]
    w = CostModel()
    given = Evaluator(ck, w).path([(poses[i], g) for i, g in path]).cost
    assert math.isfinite(given)
    out = optimise_over(ck, poses, path, should_stop=lambda: False, costs=w, grasps=(0,),
                        reach=1.0, start_grasp=0, end_grasp=0, links=((0, 1), (1, 3)))
    assert [p for p, _ in out] == [a, mid, b]
    assert Evaluator(ck, w).path(out).cost < given
    unlinked = optimise_over(ck, poses, path, should_stop=lambda: False, costs=w,
                             grasps=(0,), reach=1.0, start_grasp=0, end_grasp=0)
    assert mid not in [p for p, _ in unlinked]
