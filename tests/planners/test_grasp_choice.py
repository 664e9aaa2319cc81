"""Grasp choice: each phase re-routed at the other grasps, the cheapest kept, the path valid."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from factories import shipped

from pivot_ompl.base.path_conversion import path_to_plan
from pivot_ompl.base.problem import make_problem
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.config import OptimiserConfig, RegraspConfig
from pivot_ompl.planners.eliminate import lattice_router
from pivot_ompl.planners.evaluation import Evaluator
from pivot_ompl.planners.grasp_choice import GraspChoiceStats, choose_grasps
from pivot_ompl.planners.regrasp_search import RegraspSearch
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.validity.plan_check import check_plan

SPACING = OptimiserConfig().run_spacing


@pytest.fixture(scope="module")
def corridor():
    """The corridor and the search's path at seed 1 (one phase at grasp 0, which another
    grasp beats).

    Without the re-routing, which now routes a one-phase path at every grasp itself.
    """
    scene = shipped("corridor")
    ck = make_problem(scene).checker
    search = RegraspSearch(ck, scene.start, scene.goal,
                           RegraspConfig().with_values({"optimiser.routes": "false"}),
                           np.random.default_rng(1))
    states = search.run(lambda: False)
    assert {g for _, g in states} == {0}  # the premise: a path at grasp 0
    return scene, ck, states


def test_a_cheaper_grasp_is_chosen_and_the_path_stays_valid(corridor):
    scene, ck, states = corridor
    w = CostModel()
    st = GraspChoiceStats()
    router = lattice_router(ck, TransferLattice(ck, w), w, run_spacing=SPACING)
    out = choose_grasps(ck, states, router=router, should_stop=lambda: False, stats=st)
    assert st.changed >= 1 and st.cost_after < st.cost_before
    assert Evaluator(ck, w).path(out).cost == pytest.approx(st.cost_after)
    assert {g for _, g in out} != {g for _, g in states}
    assert out[0][0] == scene.start and out[-1][0] == scene.goal
    report = check_plan(path_to_plan(scene, ck, out), scene)
    assert report.ok, report.problems


def test_held_start_grasp_and_stop_are_honoured(corridor):
    _scene, ck, states = corridor
    w = CostModel()
    router = lattice_router(ck, TransferLattice(ck, w), w, run_spacing=SPACING)
    held = choose_grasps(ck, states, router=router, should_stop=lambda: False,
                         start_grasp=states[0][1])
    assert held[0][1] == states[0][1]
    assert choose_grasps(ck, states, router=router, should_stop=lambda: True) == states


def test_the_planner_option_keeps_the_path_valid():
    from pivot_ompl.api import plan

    scene = shipped("corridor")
    res = plan(scene, planner="regrasp[optimiser.choose_grasps=true]", time_limit=30.0, seed=0)
    base = plan(scene, planner="regrasp", time_limit=30.0, seed=0)
    assert res.solved and check_plan(res.plan, scene).ok
    assert res.plan.extra["quality"]["cost"] <= base.plan.extra["quality"]["cost"]
    assert dataclasses.replace(RegraspConfig().optimiser).choose_grasps is False
