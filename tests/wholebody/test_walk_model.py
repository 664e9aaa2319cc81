"""The scene's walk model reaches the whole-body generator: its step limits bound the motion."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from pivot_ompl.cli.main import main
from pivot_ompl.errors import InputError
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.motionfile import SUPPORT_DOUBLE, Motion
from pivot_ompl.pivoting.steering import PivotSteering
from pivot_ompl.pivoting.transfer import transfer_phase
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose
from pivot_ompl.wholebody import motion as whole_body
from pivot_ompl.wholebody.footsteps import planar, relative
from pivot_ompl.wholebody.settings import WalkSettings

SIZE = (0.8, 0.4, 1.0)


def _push(length: float) -> Plan:
    model = BoxGraspModel(SIZE, standoff=0.25)
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    a, b = (0.0, 0.0, 0.0), (length, 0.0, 0.0)
    ph = transfer_phase(model, steering, [a, b], 0)
    return Plan("test", "exact", SIZE, (0.40, 0.70), 0.25, math.pi / 8, a, [ph])


def _double_supports(motion: Motion) -> list[tuple[Pose, Pose]]:
    """The sole poses (left, right) in the middle of every double support."""
    import pinocchio as pin

    from pivot_ompl.resources import data_path

    model = pin.buildModelFromUrdf(str(data_path(motion.urdf, field="urdf")),
                                   pin.JointModelFreeFlyer())
    data = model.createData()
    ids = [model.getFrameId("left_foot"), model.getFrameId("right_foot")]
    double = np.asarray(motion.support) == SUPPORT_DOUBLE
    edges = np.flatnonzero(np.diff(np.concatenate(([0], double.astype(int), [0]))))
    out = []
    for a, b in zip(edges[::2], edges[1::2], strict=True):
        pin.framesForwardKinematics(model, data, motion.q[(a + b) // 2])
        left, right = (planar(data.oMf[i].homogeneous) for i in ids)
        out.append((left, right))
    return out


def _robot_pose(left: Pose, right: Pose) -> Pose:
    return (0.5 * (left[0] + right[0]), 0.5 * (left[1] + right[1]),
            left[2] + 0.5 * math.remainder(right[2] - left[2], 2 * math.pi))


@pytest.mark.parametrize("forward", [0.15, 0.10])
def test_pivot_walk_steps_keep_within_the_scene_forward_limit(forward):
    motion, _ = whole_body.generate_motion(_push(0.6), walk=WalkParameters(step_forward=forward))
    stances = _double_supports(motion)
    landings, poses = [], [_robot_pose(*stances[0])]
    for before, after in zip(stances, stances[1:], strict=False):
        moved = [k for k in (0, 1) if math.dist(before[k][:2], after[k][:2]) > 1e-4]
        assert len(moved) == 1  # one foot steps between two double supports
        k = moved[0]
        landings.append(relative(after[1 - k], after[k])[0])  # ahead of the support foot
        poses.append(_robot_pose(*after))
    tol = 1e-4  # the feet track their targets as hard tasks
    assert len(landings) >= 0.6 / forward
    assert max(landings) <= forward + tol
    assert max(relative(a, b)[0] for a, b in zip(poses, poses[1:], strict=False)) <= forward + tol


def test_walk_model_or_settings_not_both():
    with pytest.raises(InputError, match="not both"):
        whole_body.generate_motion(_push(0.3), walk=WalkParameters(), settings=WalkSettings())


def test_animate_passes_the_scene_walk_model(tmp_path, monkeypatch):
    doc = {"name": "t", "bounds": [-2, -2, 3, 2], "object": {"size": list(SIZE)},
           "robot": {"walk": {"step_forward": 0.1, "step_turn": 0.2}},
           "start": [0.0, 0.0, 0.0], "goal": [0.6, 0.0, 0.0]}
    scene = tmp_path / "scene.yaml"
    scene.write_text(yaml.safe_dump(doc))
    plan = _push(0.3).to_json(tmp_path / "plan.json")
    seen = []

    def fake(plan, *, walk=None, dt=None, **kwargs):  # noqa: ANN001, ANN003, ANN202
        seen.append((walk, dt))
        raise InputError("test", 0, "stop after the walk model is seen")

    monkeypatch.setattr(whole_body, "generate_motion", fake)
    args = ["animate", str(plan), "--out", str(tmp_path / "m.npz"), "--scene", str(scene),
            "--no-progress"]
    assert main(args) == 2 and len(seen) == 1
    walk, dt = seen[0]
    assert (walk.step_forward, walk.step_turn) == (0.1, 0.2) and dt == 0.005
    assert main([*args, "--tick", "0.01"]) == 2 and seen[-1][1] == 0.01
    assert main([*args, "--tick", "0.05"]) == 2 and len(seen) == 2  # refused before the work
    assert main([*args, "--substeps", "9"]) == 2 and len(seen) == 2
    assert main([*args, "--substeps", "0"]) == 2 and len(seen) == 2


def test_a_longer_tick_samples_the_motion_at_it():
    motion, stats = whole_body.generate_motion(_push(0.3), dt=0.01)
    assert motion.dt == pytest.approx(0.01) and stats.samples == len(motion.t)
    assert stats.samples == 2 * (stats.ticks - 1) + 1  # one QP every two samples
    with pytest.raises(InputError, match="tick"):
        whole_body.generate_motion(_push(0.3), dt=0.0)


def test_one_qp_per_sample_on_request():
    """``substeps=1``: every sample is a solver configuration; same duration as with 2."""
    one, s1 = whole_body.generate_motion(_push(0.3), dt=0.01, substeps=1)
    two, s2 = whole_body.generate_motion(_push(0.3), dt=0.01)
    assert s1.ticks == len(one.t) and one.dt == pytest.approx(0.01)
    assert abs(s1.duration - s2.duration) <= 0.05 * s1.duration
    for bad in (0, 9, 1.5, True):
        with pytest.raises(InputError, match="substeps"):
            whole_body.generate_motion(_push(0.3), substeps=bad)
