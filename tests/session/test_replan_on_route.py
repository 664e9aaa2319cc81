"""Replanning from where the plan being executed put the box, inside a tight gap."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.stored import StoredMotions, passing_rest
from pivot_ompl.planfile import TransferPhase, load_plan
from pivot_ompl.planners.repair import repair_route
from pivot_ompl.scene import BoxObstacle, load_scene
from pivot_ompl.session import PlanningSession
from pivot_ompl.session_inputs import route_of_plan
from pivot_ompl.validity.plan_check import check_plan

pytestmark = pytest.mark.timed  # a time budget: run alone

DATA = Path(__file__).parent.parent / "data" / "replan"
#: A generated walls scene and a plan of it (seed 0) whose box passes a gap 0.63 m wide in
#: the middle wall narrow side first, pushed with grasp 2, to the regrasp pose in the gap.
SCENE, PLAN = DATA / "walls_1.yaml", DATA / "walls_1_plan.json"
#: The step of the first transfer phase (grasp 2) where the box is in the gap.
IN_GAP_STEP = 45
#: A block dropped behind the robot there (the replanning benchmark's event at this point).
BEHIND = BoxObstacle(center=(7.152261090236488, 3.682076790829491), size=(0.3, 0.3),
                     yaw=0.0, height=1.0)


def _in_gap() -> tuple[tuple[float, float, float], int]:
    ph = load_plan(PLAN).phases[0]
    assert isinstance(ph, TransferPhase)
    return ph.steps[IN_GAP_STEP].object, ph.grasp


def test_in_the_gap_no_repair_starts_but_the_plans_own_rest_of_the_edge_passes():
    scene, plan = load_scene(SCENE), load_plan(PLAN)
    route = route_of_plan(plan)
    box, grasp = _in_gap()
    checker = PivotChecker(scene)
    assert checker.state_valid(box, grasp)
    # no new pivot sequence starts here: no join of the route can be reached from the box
    assert repair_route(checker, route, box, grasp).path is None
    rest = passing_rest(plan, route, box, grasp)
    assert len(rest) == 1
    (start, end, g), steps = next(iter(rest.items()))
    assert start == box and g == grasp and (end, grasp) in route
    assert 0 < len(steps) < len(plan.phases[0].steps)  # type: ignore[union-attr]
    offered = StoredMotions()
    offered.transfers.update(rest)
    checker = PivotChecker(scene)
    checker.offer(offered)
    res = checker.transfer(box, end, grasp)
    assert res.valid and len(res.sequence.rotations) <= len(steps)
    assert repair_route(checker, route, box, grasp).path is not None


def test_a_pose_off_the_plan_has_no_rest():
    plan = load_plan(PLAN)
    box, grasp = _in_gap()
    off = (box[0] + 1e-3, box[1], box[2])
    assert passing_rest(plan, route_of_plan(plan), off, grasp) == {}
    assert passing_rest(plan, route_of_plan(plan), box, 3 - grasp) == {}


@pytest.mark.parametrize("dropped", [False, True])
def test_a_replan_from_the_plans_pose_in_the_gap_goes_on_with_the_plan(dropped):
    scene = load_scene(SCENE)
    box, grasp = _in_gap()
    added = [BEHIND] if dropped else []
    session = PlanningSession(scene, seed=0, executing=load_plan(PLAN))
    res = session.replan(box=box, grasp=grasp, add_obstacles=added, time_limit=60.0)
    assert res.solved and res.roadmap.get("repaired")
    changed = dataclasses.replace(scene, start=box, obstacles=scene.obstacles + tuple(added))
    assert check_plan(res.plan, changed).ok
