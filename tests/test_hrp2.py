"""Our HRP-2 URDF (robots/hrp2/hrp2.urdf) loaded with pinocchio: mass, sizes, frames, limits."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
import pytest

from pivot_ompl import hrp2
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.hrp2 import (
    FRAMES,
    HALF_SITTING,
    derived_floor_geometry,
    half_sitting_configuration,
    hrp2_floor_geometry,
    load_pinocchio_model,
)


@pytest.fixture(scope="module")
def model():
    return load_pinocchio_model()


def frame_pos(model, q, name):
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    return data.oMf[model.getFrameId(name)].translation.copy()


def test_urdf_file_is_located_from_the_package():
    path = hrp2.urdf_path()
    assert path.is_file()
    assert path.parent.name == "hrp2" and path.parent.parent.name == "robots"


def test_preset_constants_match_the_urdf():
    """One source per fact: the planning constants agree with the model they stand for."""
    d = derived_floor_geometry()
    assert hrp2.HEIGHT == pytest.approx(d["height"], abs=5e-3)
    depth, width = hrp2.FOOTPRINT
    assert d["zero_pose_depth"] <= depth and d["width"] <= width
    # the grasp model and the scene defaults take the preset, not copies of it
    m = BoxGraspModel((0.8, 0.6, 1.3))
    assert (m.robot_footprint, m.standoff, m.robot_height) == (hrp2.FOOTPRINT, hrp2.STANDOFF,
                                                               hrp2.HEIGHT)
    model = load_pinocchio_model()
    geom = pin.buildGeomFromUrdf(model, str(hrp2.urdf_path()), pin.GeometryType.COLLISION)
    for side in "LR":  # the sole plate: the foot's thin (3 cm) box
        boxes = [2 * np.asarray(g.geometry.halfSide) for g in geom.geometryObjects
                 if g.name.startswith(f"{side}LEG_LINK5") and hasattr(g.geometry, "halfSide")]
        soles = [b for b in boxes if b[2] == pytest.approx(0.03)]
        assert len(soles) == 1
        assert tuple(soles[0][:2]) == pytest.approx(hrp2.SOLE_SIZE)


def test_dofs(model):
    revolute = [n for n in model.names[2:]]
    assert len(revolute) == 30  # legs 12, chest 2, head 2, arms 12, grippers 2
    assert model.nq == 37 and model.nv == 36
    assert set(HALF_SITTING) == set(revolute)


def test_total_mass(model):
    mass = sum(i.mass for i in model.inertias)
    assert mass == pytest.approx(56.037, abs=0.01)  # the published link masses
    assert abs(mass - 58.0) / 58.0 < 0.04  # published 58 kg with batteries


def test_inertias_are_physical(model):
    for name, inertia in zip(model.names, model.inertias, strict=True):
        if inertia.mass == 0:
            continue
        ev = np.linalg.eigvalsh(inertia.inertia)
        assert ev.min() > 0, name
        assert ev[0] + ev[1] >= ev[2] - 1e-9, name  # triangle inequality


def test_frames_present(model):
    for name in FRAMES:
        assert model.existFrame(name), name


def test_heights_and_leg_lengths(model):
    q0 = pin.neutral(model)
    sole = frame_pos(model, q0, "left_foot")
    waist = frame_pos(model, q0, "trunk")
    assert waist[2] - sole[2] == pytest.approx(0.705, abs=1e-6)  # 0.3 + 0.3 + 0.105
    data = model.createData()
    pin.forwardKinematics(model, data, q0)
    hip = data.oMi[model.getJointId("LLEG_JOINT2")].translation
    knee = data.oMi[model.getJointId("LLEG_JOINT3")].translation
    ankle = data.oMi[model.getJointId("LLEG_JOINT4")].translation
    assert np.linalg.norm(hip - knee) == pytest.approx(0.300, abs=1e-9)
    assert np.linalg.norm(knee - ankle) == pytest.approx(math.hypot(0.3, 0.035), abs=1e-9)
    assert ankle[2] - sole[2] == pytest.approx(0.105, abs=1e-9)
    # soles 0.21 m apart, arms 0.5 m shoulder to wrist
    assert frame_pos(model, q0, "left_foot")[1] - frame_pos(model, q0, "right_foot")[1] == \
        pytest.approx(0.21, abs=1e-9)
    sh = data.oMi[model.getJointId("RARM_JOINT0")].translation
    wr = data.oMi[model.getJointId("RARM_JOINT5")].translation
    assert np.linalg.norm(sh - wr) == pytest.approx(0.5, abs=1e-9)


def test_standing_height_and_size():
    d = derived_floor_geometry()
    assert d["height"] == pytest.approx(1.56, abs=0.01)  # 1.539 published (head bumps 1.56)
    assert d["zero_pose_depth"] == pytest.approx(0.355, abs=0.01)
    assert d["zero_pose_width"] == pytest.approx(0.621, abs=0.02)


def test_half_sitting(model):
    q = half_sitting_configuration(model)
    assert frame_pos(model, q, "left_foot")[2] == pytest.approx(0.0, abs=1e-9)
    assert q[2] == pytest.approx(0.6487, abs=1e-3)  # published half-sitting waist height
    lo, hi = model.lowerPositionLimit[7:], model.upperPositionLimit[7:]
    assert np.all(q[7:] >= lo) and np.all(q[7:] <= hi)
    data = model.createData()
    com = pin.centerOfMass(model, data, q)
    mid = 0.5 * (frame_pos(model, q, "left_foot") + frame_pos(model, q, "right_foot"))
    assert abs(com[0] - mid[0]) < 0.03 and abs(com[1] - mid[1]) < 0.01  # balanced
    assert com[2] == pytest.approx(0.809, abs=0.01)


def test_grip_point_in_the_hand(model):
    q0 = pin.neutral(model)
    wrist = model.getJointId("LARM_JOINT5")
    data = model.createData()
    pin.framesForwardKinematics(model, data, q0)
    d = data.oMf[model.getFrameId("left_hand")].translation - data.oMi[wrist].translation
    assert d == pytest.approx([0.0, 0.0, -0.15], abs=1e-9)


def test_floor_geometry_for_scenes():
    g = hrp2_floor_geometry()
    depth, width = g["footprint"]
    d = derived_floor_geometry()
    assert (depth, width) == (0.40, 0.70) and g["standoff"] == 0.25
    assert d["zero_pose_depth"] <= depth <= 0.45 and d["width"] <= width <= 0.75
    assert g["height"] == pytest.approx(1.56, abs=0.01)


def test_arm_constants_match_the_urdf():
    """The planner's arm envelope constants hold HRP-2's shoulders and wrists (pinocchio)."""
    d = hrp2.derived_arm_geometry()
    assert hrp2.SHOULDER_XY[0] == pytest.approx(d["shoulder_x"], abs=1e-3)
    assert hrp2.SHOULDER_XY[1] == pytest.approx(d["shoulder_y"], abs=1e-3)
    assert d["shoulder"] <= hrp2.SHOULDER_ENVELOPE <= d["shoulder"] + 0.03
    assert d["wrist"] <= hrp2.HAND_ENVELOPE <= d["wrist"] + 0.03


def test_walking_envelope_holds_every_link_in_half_sitting():
    """Every collision primitive's floor projection lies inside the walking envelope.

    In half-sitting the shanks' cylinders reach 0.23 m ahead of the sole midpoint, beyond the
    footprint's 0.20 m; walking reaches further (swing knee, trunk sway), which
    ``tests/wholebody`` measures on motions.
    """

    from pivot_ompl.wholebody.envelope import outline_points

    model = hrp2.load_pinocchio_model()
    geom = pin.buildGeomFromUrdf(model, str(hrp2.urdf_path()), pin.GeometryType.COLLISION)
    data, gdata = model.createData(), geom.createData()
    pin.framesForwardKinematics(model, data, hrp2.half_sitting_configuration(model))
    pin.updateGeometryPlacements(model, data, geom, gdata)
    mid = 0.5 * (data.oMf[model.getFrameId("left_foot")].translation
                 + data.oMf[model.getFrameId("right_foot")].translation)
    pts = np.vstack([(M.rotation @ outline_points(o.geometry).T).T + M.translation - mid
                     for o, M in zip(geom.geometryObjects, gdata.oMg, strict=True)])
    ahead, behind, side = hrp2.WALK_ENVELOPE
    assert pts[:, 0].max() > 0.5 * hrp2.FOOTPRINT[0]  # the footprint alone would not do
    assert pts[:, 0].max() <= ahead and -pts[:, 0].min() <= behind
    assert np.abs(pts[:, 1]).max() <= side
