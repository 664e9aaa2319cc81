"""Whole-body Talos (PlaCo): a short plan made with its profile, its motion and every check."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.humanoids import PROFILES
from pivot_ompl.motionfile import load_motion
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan, TransitPhase
from pivot_ompl.wholebody import generate_motion
from pivot_ompl.wholebody.motion_checks import check_motion
from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.walker import PlacoWalker

TALOS = PROFILES["talos"]
SIZE = (0.8, 0.6, 1.3)


def talos_plan() -> Plan:
    """Three pivots pushing the box 0.2 m forward at grasp 0, then a transit to grasp 1."""
    model = BoxGraspModel(SIZE, TALOS.footprint, TALOS.standoff, TALOS.height, "talos")
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    a, b = (0.0, 0.0, 0.0), (0.2, 0.0, 0.0)
    ph = transfer_phase(model, steering, [a, b], 0)
    end = ph.object_end
    r0, r1 = model.robot_pose(end, 0), model.robot_pose(end, 1)
    back = (r0[0] - 0.1, r0[1], r0[2])
    corner = (r0[0] - 0.1, r1[1], r1[2])
    return Plan("talos-test", "exact", SIZE, TALOS.footprint, TALOS.standoff, math.pi / 8, a,
                [ph, TransitPhase(0, 1, (r0, back, corner, r1), end)], robot_model="talos")


@pytest.fixture(scope="module")
def generated():
    plan = talos_plan()
    motion, stats = generate_motion(plan)
    return plan, motion, stats


def test_talos_motion_passes_every_check_with_its_own_limits(generated, tmp_path):
    plan, motion, stats = generated
    assert motion.model == "talos" and motion.urdf == TALOS.urdf_name
    assert motion.sole_size == TALOS.sole_size
    assert "arm_left_7_joint" in motion.joint_names
    report = check_motion(motion, plan)
    assert report.passed, report.table()
    assert report["zmp"].value >= 0.02  # the target margin
    peaks = report.peaks
    assert peaks is not None
    arm = next(p for p in peaks.joints if p.joint == "arm_left_1_joint")
    assert arm.velocity_limit == pytest.approx(2.7) and arm.accel_limit == 30.0
    leg = next(p for p in peaks.joints if p.joint == "leg_left_4_joint")
    assert leg.velocity_limit == pytest.approx(7.0) and leg.accel_limit == 50.0
    # the file records the model and reads back the same
    back = load_motion(motion.save(tmp_path / "m.npz"))
    assert back.robot_model == "talos" and back.model == "talos"
    assert stats.max_hand_error < 1e-3


def test_talos_joints_held_still_never_move(generated):
    _, motion, _ = generated
    for name, value in TALOS.fixed_joints.items():
        column = motion.q[:, 7 + motion.joint_names.index(name)]
        assert np.allclose(column, value, atol=1e-9), name


def test_talos_stands_at_rest_in_its_upper_posture():
    w = PlacoWalker(WalkSettings.of(TALOS), (0.0, 0.0, 0.0))
    q0 = w.q()
    for _ in range(20):
        T = w.trunk_frame()
        w.tick(0.0, None, T @ w.rest_hands[0], T @ w.rest_hands[1])
    speed = np.abs(w.q()[7:] - q0[7:]) / (20 * w.settings.solver_dt)
    assert speed.max() < 0.01  # rad/s: settled before anything is recorded
    # the shoulder roll stays at the tucked posture, not PlaCo's initial pose's 0.18 rad
    assert w.robot.get_joint("arm_left_2_joint") == pytest.approx(0.02, abs=0.03)
