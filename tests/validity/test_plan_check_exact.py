"""``check --exact``: a motion that dips into the kept clearance between two samples is refused.

The default sweep accepts any motion whose bodies move at most the tolerance between two
checked samples that are clear; the exact check passes only motions proven clear at every
instant, the certificate the planner itself gives its motions.
"""

from __future__ import annotations

import math

import pytest
import yaml
from factories import PAPER_BOX, make_scene

from pivot_ompl.cli.main import main
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.se2 import rotate_about
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE, CollisionWorld
from pivot_ompl.validity.plan_check import check_plan

#: Which of the back corners grazes (the one the first rotation swings away from).
SIDE = 1
#: How deep (m) the walking body's corner dips into the kept clearance halfway through.
DIP = 2e-5


def _dipping_case():  # noqa: ANN202
    """A plan whose robot first turns in place, its back corner grazing a 1 mm box halfway.

    The turn moves no point by more than 0.98 of twice the tolerance, so the default check
    samples only its ends; the box sits where the corner's rounded clearance reaches it by
    ``DIP`` at the middle of the turn and misses it at both ends.
    """
    base = make_scene()
    m = base.model
    robot = m.robot_pose(base.start, 0)
    behind = sorted(m.robot_corners(robot), key=lambda p: math.dist(p, base.goal[:2]))[2:]
    corner = behind[SIDE]
    turn = 0.98 * 2.0 * SWEEP_TOLERANCE / m.robot_radius()
    towards = math.atan2(corner[1] - robot[1], corner[0] - robot[0]) + 0.5 * turn
    half = 5e-4
    reach = math.dist(corner, robot[:2]) + KEEP_CLEARANCE + half - DIP
    centre = [robot[0] + reach * math.cos(towards), robot[1] + reach * math.sin(towards)]
    grazed = [{"type": "box", "center": centre, "size": [2 * half, 2 * half], "height": 1.0,
               "yaw": towards}]
    scene = make_scene(obstacles=grazed)
    steering = PivotSteering(turning_radius=scene.turning_radius, alpha_max=scene.alpha_max)
    carry = transfer_phase(m, steering, [scene.start, scene.goal], 0)
    turned = (robot[0], robot[1], robot[2] + turn)
    walk = TransitPhase(0, 0, (robot, turned, robot), scene.start)
    plan = Plan("test", "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, scene.start, [walk, carry])
    return scene, plan, robot, turned, grazed


def test_the_turn_grazes_the_box_halfway_and_misses_it_at_both_ends():
    scene, _, robot, turned, _ = _dipping_case()
    world = CollisionWorld.from_scene(scene)
    middle = (robot[0], robot[1], 0.5 * (robot[2] + turned[2]))
    assert world.robot_distance(robot) > 0.0
    assert world.robot_distance(turned) > 0.0
    assert world.robot_distance(middle) < -0.5 * DIP


def test_the_sampling_check_passes_the_dip_and_the_exact_check_refuses_it():
    scene, plan, *_ = _dipping_case()
    assert check_plan(plan, scene).ok  # the tolerance's sampling: documented, not a proof
    rep = check_plan(plan, scene, exact=True)
    assert not rep.ok
    assert rep.problems[0].startswith("phases[0].robot_path[0]: the walking robot collides")


def test_the_exact_check_passes_the_plan_without_the_dip():
    scene, plan, *_ = _dipping_case()
    clear = make_scene()
    assert check_plan(plan, clear, exact=True).ok
    assert not check_plan(plan, scene, exact=True).ok


@pytest.mark.parametrize("exact", [False, True])
def test_the_cli_check_exits_by_the_chosen_certificate(tmp_path, exact):
    scene, plan, _, _, grazed = _dipping_case()
    scene_file = tmp_path / "scene.yaml"
    doc = {"name": "grazed", "bounds": list(scene.bounds), "object": {"size": list(PAPER_BOX)},
           "start": list(scene.start), "goal": list(scene.goal), "obstacles": grazed}
    scene_file.write_text(yaml.safe_dump(doc))
    plan_file = plan.to_json(tmp_path / "plan.json")
    args = ["check", str(scene_file), str(plan_file)] + (["--exact"] if exact else [])
    assert main(args) == (1 if exact else 0)


def _grazed_rotation():  # noqa: ANN202
    """A one-rotation plan whose box corner farthest from the pivot grazes a 1 mm post halfway.

    The corner moves 0.98 of twice the tolerance, so the default check samples the rotation
    only at its ends; returns the scene, the plan, and the box poses before, halfway, after.
    """
    base = make_scene()
    m = base.model
    start = base.start
    car = m.car_pose(start, 0)
    pivot = m.pivots(car, 0)[0]
    corner = max(m.object_corners(start), key=lambda p: math.dist(p, pivot))
    reach = math.dist(corner, pivot)
    angle = 0.98 * 2.0 * SWEEP_TOLERANCE / reach
    towards = math.atan2(corner[1] - pivot[1], corner[0] - pivot[0]) + 0.5 * angle
    half = 5e-4
    out = reach + KEEP_CLEARANCE + half - DIP
    centre = [pivot[0] + out * math.cos(towards), pivot[1] + out * math.sin(towards)]
    end = m.object_from_car(rotate_about(car, pivot, angle), 0)
    halfway = m.object_from_car(rotate_about(car, pivot, 0.5 * angle), 0)
    scene = make_scene(goal=list(end), obstacles=[
        {"type": "box", "center": centre, "size": [2 * half, 2 * half], "height": 1.0,
         "yaw": towards}])
    step = TransferStep(pivot, angle, end, m.robot_pose(end, 0))
    carry = TransferPhase(0, m.robot_pose(start, 0), (step,), start)
    plan = Plan("test", "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, start, [carry])
    return scene, plan, (start, halfway, end)


def test_a_rotation_grazing_a_post_halfway_passes_sampling_and_fails_the_exact_check():
    scene, plan, (start, halfway, end) = _grazed_rotation()
    world = CollisionWorld.from_scene(scene)
    assert world.box_distance(start) > 0.0 and world.box_distance(end) > 0.0
    assert world.box_distance(halfway) < -0.5 * DIP
    assert check_plan(plan, scene).ok
    rep = check_plan(plan, scene, exact=True)
    assert rep.problems == ["phases[0].steps[0]: box collides (rotation fraction 0.500)"]
