"""Replanning from where the plan being executed put the box, inside a tight gap."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.checking.stored import StoredMotions, passing_rest
from pivot_ompl.generate.transform import RigidMap, transform_scene
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase, load_plan
from pivot_ompl.planners.repair import repair_route
from pivot_ompl.scene import BoxObstacle, load_scene
from pivot_ompl.session import PlanningSession
from pivot_ompl.session_inputs import route_of_plan
from pivot_ompl.validity.plan_check import check_plan

pytestmark = pytest.mark.timed  # a time budget: run alone

DATA = Path(__file__).parent.parent / "data" / "replan"
#: A generated walls scene and a plan of it (seed 0, `plan(scene, time_limit=30, seed=0)`; made
#: again when the planner's checks change) whose box passes a gap 0.63 m wide in
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


def _turned(plan: Plan, f: RigidMap) -> Plan:
    """``plan`` carried by the rotation ``f`` (its poses, pivots and route)."""
    phases: list[TransferPhase | TransitPhase] = []
    for ph in plan.phases:
        if isinstance(ph, TransitPhase):
            phases.append(dataclasses.replace(ph, robot_path=tuple(map(f.pose, ph.robot_path)),
                                              object_pose=f.pose(ph.object_pose)))
        else:
            steps = tuple(dataclasses.replace(s, pivot=f.point(s.pivot), object=f.pose(s.object),
                                              robot=f.pose(s.robot)) for s in ph.steps)
            phases.append(dataclasses.replace(ph, robot_start=f.pose(ph.robot_start), steps=steps,
                                              object_start=f.pose(ph.object_start),
                                              rs_path=tuple(map(f.pose, ph.rs_path))))
    route = [[*f.pose(tuple(q[:3])), q[3]] for q in plan.extra["route"]]
    return dataclasses.replace(plan, start=f.pose(plan.start), phases=phases,
                               extra={**plan.extra, "route": route})


@pytest.mark.parametrize("angle", [0.0, 1.0])
def test_in_the_gap_no_repair_starts_but_the_plans_own_rest_of_the_edge_passes(angle):
    scene, plan = load_scene(SCENE), load_plan(PLAN)
    box, grasp = _in_gap()
    if angle:  # a turned copy: nothing depends on the walls' direction
        f = RigidMap(angle, (4.5, 3.5))
        scene, plan, box = transform_scene(scene, f, name=scene.name), _turned(plan, f), \
            f.pose(box)
    route = route_of_plan(plan)
    checker = PivotChecker(scene)
    assert checker.state_valid(box, grasp)
    # no new pivot sequence starts here: no join of the route can be reached from the box
    assert repair_route(checker, route, box, grasp).path is None
    rest = passing_rest(plan, route, box, grasp)
    assert len(rest) == 1
    (start, end, g), steps = next(iter(rest.items()))
    assert start == box and g == grasp and (end, grasp) in route
    first = plan.phases[0]
    assert isinstance(first, TransferPhase) and 0 < len(steps) < len(first.steps)
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
