"""The whole-body motion of a replanned plan starts where the box and the robot were observed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import shipped

from pivot_ompl.planfile import TransferPhase
from pivot_ompl.session import PlanningSession
from pivot_ompl.wholebody.footsteps import planar, stance_pose
from pivot_ompl.wholebody.generator import WholeBodyGenerator


class _Stop(Exception):
    pass


def _first_sample(plan):
    """The first sample's box pose and robot pose (generation stopped after one unit)."""
    import pinocchio as pin

    from pivot_ompl.resources import URDF_RELPATH, data_path

    def stop(fraction, label):
        raise _Stop(label)

    gen = WholeBodyGenerator(plan, progress=stop)
    with pytest.raises(_Stop):
        gen.run()
    rec = gen.recorder
    frame = rec.box[0]  # the box's frame, rows of [R | p]
    assert np.allclose(frame[2, :3], (0.0, 0.0, 1.0), atol=1e-9)  # resting flat
    box = (float(frame[0, 3]), float(frame[1, 3]), math.atan2(frame[1, 0], frame[0, 0]))
    model = pin.buildModelFromUrdf(str(data_path(URDF_RELPATH, field="urdf")),
                                   pin.JointModelFreeFlyer())
    data = model.createData()
    pin.framesForwardKinematics(model, data, rec.q[0])
    left, right = (data.oMf[model.getFrameId(f)].homogeneous for f in ("left_foot", "right_foot"))
    assert abs(planar(left)[2] - planar(right)[2]) < 1e-6  # feet side by side
    return box, stance_pose(left, right, gen.settings)


def _close(a, b, tol=2e-3):
    return math.dist(a[:2], b[:2]) < tol and abs(math.remainder(a[2] - b[2], 2 * math.pi)) < tol


@pytest.fixture(scope="module")
def session_and_drift():
    s = PlanningSession(shipped("slot"), seed=0)
    first = s.plan(time_limit=30.0)
    assert first.solved
    ph = [p for p in first.plan.phases if isinstance(p, TransferPhase)][-1]
    q = ph.steps[-3].object  # near the goal: a short replanned plan
    return s, ph.grasp, (q[0] + 0.05 * math.cos(q[2]), q[1] + 0.05 * math.sin(q[2]),
                         q[2] + math.radians(5))


def test_a_replanned_motion_starts_at_the_observed_box_and_the_held_grasp(session_and_drift):
    s, grasp, box = session_and_drift
    res = s.replan(box=box, grasp=grasp, time_limit=30.0)
    assert res.solved
    got_box, got_robot = _first_sample(res.plan)
    assert _close(got_box, box), (got_box, box)
    m = s.scene.model  # the scene's grasp geometry
    assert _close(got_robot, m.robot_pose(box, grasp)), (got_robot, m.robot_pose(box, grasp))


def test_a_replanned_motion_with_the_box_at_rest_starts_where_the_robot_stood(session_and_drift):
    s, _, box = session_and_drift
    robot = (box[0] - 1.0, box[1] - 0.6, 0.3)
    res = s.replan(box=box, robot=robot, time_limit=30.0)
    assert res.solved and res.plan.extra["observed_robot"] == pytest.approx(robot)
    got_box, got_robot = _first_sample(res.plan)
    assert _close(got_box, box)
    assert _close(got_robot, robot), (got_robot, robot)
    assert np.isfinite(got_robot).all()


@pytest.mark.parametrize("bad", [[1.0, 2.0], [1.0, "x", 0.0], [1.0, 2.0, float("nan")], {}])
def test_a_malformed_observed_robot_is_named(bad):
    from pivot_ompl.errors import InputError
    from pivot_ompl.planfile import Plan
    from pivot_ompl.wholebody.plan_start import observed_robot

    p = Plan("t", "exact", (0.4, 0.4, 0.4), (0.4, 0.7), 0.25, math.pi / 8, (0.0, 0.0, 0.0), [],
             extra={"observed_robot": bad})
    with pytest.raises(InputError) as e:
        observed_robot(p)
    assert e.value.field == "observed_robot"
    assert observed_robot(Plan("t", "exact", (0.4, 0.4, 0.4), (0.4, 0.7), 0.25, math.pi / 8,
                               (0.0, 0.0, 0.0), [])) is None
