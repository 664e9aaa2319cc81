"""``check`` trusts only the scene: its parameters, its goal; absurd numbers cost no time."""

from __future__ import annotations

import dataclasses
import math
import time

import pytest
from factories import make_scene

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.validity.plan_check import check_plan

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

SCENE = make_scene()  # alpha_max pi/8, hrp2 standoff, 8 x 6 m, start (1.5, 3, 0), goal (6, 3, 0)


def steer_plan(*, alpha_max: float = SCENE.alpha_max, standoff: float | None = None,
               goal=SCENE.goal, status: str = "exact") -> Plan:
    m = SCENE.model
    model = BoxGraspModel(m.object_size, m.robot_footprint,
                          m.standoff if standoff is None else standoff, m.robot_height)
    steering = PivotSteering(turning_radius=SCENE.turning_radius, alpha_max=alpha_max)
    phase = transfer_phase(model, steering, [SCENE.start, goal], 0)
    return Plan("test", status, model.object_size, model.robot_footprint, model.standoff,
                alpha_max, SCENE.start, [phase])


def test_honest_plan_passes():
    rep = check_plan(steer_plan(), SCENE)
    assert rep.ok, rep.problems


def test_plan_with_its_own_large_alpha_max_fails():
    plan = steer_plan(alpha_max=1.5)
    assert max(abs(s.angle) for s in plan.phases[0].steps) > SCENE.alpha_max
    rep = check_plan(plan, SCENE)
    assert not rep.ok
    assert any("alpha_max" in p and "differs" in p for p in rep.problems)
    assert any("> alpha_max 0.392699" in p for p in rep.problems)


def test_plan_with_its_own_standoff_fails():
    rep = check_plan(steer_plan(standoff=1.0), SCENE)
    assert any("standoff" in p for p in rep.problems)
    assert any("not grasp 0 of the object" in p for p in rep.problems)


@pytest.mark.parametrize("status", ["approximate", "none"])
def test_status_other_than_exact_fails(status):
    rep = check_plan(steer_plan(status=status), SCENE)
    assert any("status" in p for p in rep.problems)


def test_plan_that_stops_short_of_the_goal_fails():
    for status in ("exact", "approximate"):
        rep = check_plan(steer_plan(goal=(4.0, 3.0, 0.0), status=status), SCENE)
        assert any("scene goal" in p for p in rep.problems)


def test_absurd_rotation_is_reported_without_sweeping():
    """A 1e4 rad turn about a true pivot stays in a large floor: it used to be swept (hang)."""
    scene = make_scene(bounds=[-100.0, -100.0, 100.0, 100.0], obstacles=[
        {"type": "cylinder", "center": [90.0, 90.0], "radius": 0.5, "height": 1.0}])
    plan = steer_plan()
    ph = plan.phases[0]
    assert isinstance(ph, TransferPhase)
    st = ph.steps[0]
    huge = TransferStep(st.pivot, 1e4, st.object, st.robot)
    plan.phases[0] = dataclasses.replace(ph, steps=(huge, *ph.steps[1:]))
    t0 = time.perf_counter()
    rep = check_plan(plan, scene)
    assert time.perf_counter() - t0 < 3.0
    assert any("> alpha_max" in p for p in rep.problems)


def test_walk_far_outside_the_bounds_is_reported_without_sweeping():
    plan = steer_plan()
    end = plan.object_end
    m = SCENE.model
    a, b = m.robot_pose(end, 0), m.robot_pose(end, 2)
    walk = TransitPhase(0, 2, (a, (5e3, 5e3, 0.0), (-5e3, 5e3, 1.0), b), end)
    plan.phases.append(walk)
    t0 = time.perf_counter()
    rep = check_plan(plan, SCENE)
    assert time.perf_counter() - t0 < 5.0
    assert "phases[1].robot_path[1]: the robot leaves the bounds" in rep.problems


def test_without_a_scene_the_plan_parameters_are_used():
    plan = steer_plan(alpha_max=math.pi / 4)
    assert check_plan(plan).ok


def test_a_plan_ending_at_the_goal_turned_by_pi_is_refused():
    """Regression: the planner once wrote the goal as its half turn (the same placement of the
    symmetric box under another name); plans must reach the goal exactly as the scene says."""
    import math

    from pivot_ompl.planfile import Plan, TransferPhase

    scene = make_scene(goal=[1.5, 3.0, math.pi])  # the start turned by pi, nothing to move
    m = scene.model
    plan = Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, scene.start,
                [TransferPhase(0, m.robot_pose(scene.start, 0), (), scene.start)])
    rep = check_plan(plan, scene)
    assert not rep.ok and any("ends at" in p for p in rep.problems)
