"""Whole body: a free walk (side and back steps, turning while walking) passes check-motion."""

from __future__ import annotations

import dataclasses
import math

import pytest
from factories import shipped

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan, TransitPhase
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.validity.plan_check import check_plan
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.motion_checks import check_motion


def _local(a: Pose, b: Pose) -> tuple[float, float]:
    """Displacement a -> b in the robot frame at the middle yaw (forward, left)."""
    mid = a[2] + 0.5 * wrap_angle(b[2] - a[2])
    ex, ey = b[0] - a[0], b[1] - a[1]
    return (math.cos(mid) * ex + math.sin(mid) * ey, -math.sin(mid) * ex + math.cos(mid) * ey)


@pytest.fixture(scope="module")
def plan():
    """A 0.2 m push at grasp 0 in the door scene, then the planner's walk to grasp 1."""
    scene = shipped("door")
    ck = PivotChecker(scene)
    m = scene.model
    a, b = (3.6, 4.2, 0.0), (3.8, 4.2, 0.0)
    ph = transfer_phase(m, ck.steering, [a, b], 0)
    walk = ck.transit(ph.object_end, 0, 1)
    assert walk.valid
    plan = Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, a, [ph, TransitPhase(0, 1, walk.robot_path, ph.object_end)])
    # the check carries the pose chain from the scene's start: the scene starts at a here
    rep = check_plan(plan, dataclasses.replace(scene, start=a))
    assert [p for p in rep.problems if "scene" not in p] == []  # not the scene's goal
    return plan


def test_walk_steps_sideways_or_backward(plan):
    path = plan.phases[1].robot_path
    moves = [_local(a, b) for a, b in zip(path, path[1:], strict=False)]
    assert any(dx < -1e-3 or abs(dy) > abs(dx) + 1e-3 for dx, dy in moves), path


def test_whole_body_free_walk_passes_check_motion(plan):
    motion, _ = generate_motion(plan)
    rep = check_motion(motion, plan)
    assert rep.passed, rep.table()
