"""HRP-2's profile: its constants, and the model shipped in ``robots/hrp2/``.

One source for the robot's planning geometry (footprint, standoff, height), its sole size and
half-sitting posture; ``tests/test_hrp2.py`` checks the constants against the URDF.

``robots/hrp2/hrp2.urdf`` is our own primitive-geometry model written from the published
kinematic and inertial facts (see ``robots/hrp2/README.md``). Its frames ``left_foot`` /
``right_foot`` (sole centres), ``trunk`` (waist) and ``left_hand`` / ``right_hand`` (grip
points) are fixed links, so pinocchio and PlaCo both find them.
"""

from __future__ import annotations

import functools
import logging
import math
from typing import TYPE_CHECKING

from pivot_ompl.humanoids.profile import FRAMES, HumanoidProfile
from pivot_ompl.resources import URDF_RELPATH, urdf_path

if TYPE_CHECKING:
    import numpy as np

log = logging.getLogger(__name__)

__all__ = ["FOOTPRINT", "FRAMES", "HALF_SITTING", "HAND_ENVELOPE", "HEIGHT", "PROFILE",
           "SHOULDER_ENVELOPE", "SHOULDER_XY", "UPPER_POSTURE", "FOOT_DY_OUT",
           "FOOT_DTHETA", "SOLE_SIZE", "STANDOFF",
           "STEP_BACKWARD", "STEP_FORWARD", "STEP_LATERAL", "STEP_TURN", "URDF_RELPATH",
           "WALK_ENVELOPE",
           "derived_arm_geometry", "derived_floor_geometry", "half_sitting_configuration",
           "hrp2_floor_geometry", "load_pinocchio_model", "urdf_path"]

#: Conservative robot floor bounding box (depth along heading, width) used by the planners (m).
FOOTPRINT = (0.40, 0.70)
#: Gap between the held face of the box and the front of the robot's bounding box (m).
STANDOFF = 0.25
#: Height of the robot's bounding volume (m): the URDF's zero-pose standing height, sole to
#: top of head (the published 1.539 m; our primitive head box stands 2 cm higher).
HEIGHT = 1.56

#: Step limits of the walk pattern (robot frame, one step): forward, backward and lateral
#: displacement of the sole midpoint (m) and yaw change (rad). The whole-body generator's
#: PlaCo walk uses them, and they set the planner's walking costs (its cost of a motion is
#: proportional to the number of steps it takes): the values with which HRP-2 motions of
#: every shipped scene pass ``check-motion`` (ZMP margin, no foot sliding, joint limits).
STEP_FORWARD = 0.15
STEP_BACKWARD = 0.08
STEP_LATERAL = 0.06
STEP_TURN = 0.25

#: Shoulder joints in the robot frame (sole midpoint, x forward) in half-sitting: ``(x, +/-y)``
#: (m); :func:`derived_arm_geometry` measures them on the URDF.
SHOULDER_XY = (0.016, 0.25)
#: Half-sides (m) of the floor squares round a shoulder joint and round a grip point that
#: the arms' floor envelope (their convex hull) is made of: the largest half floor
#: diagonal of the shoulder's and of the wrist's collision primitives
#: (:func:`derived_arm_geometry`), plus room for the elbow's outward bend and the wrists'
#: swing as the hands reach and release, measured on whole-body motions
#: (:func:`pivot_ompl.wholebody.envelope.floor_excursion`: wrists 7.7 mm past a 0.07 m
#: hand envelope on fig10).
SHOULDER_ENVELOPE = 0.11
HAND_ENVELOPE = 0.085

#: HRP-2's walking envelope: how far (m) its links reach from the robot pose (sole midpoint)
#: while it walks, ``(ahead, behind, to each side)``, measured on whole-body motions relative
#: to the path the planner certifies (:func:`pivot_ompl.wholebody.envelope.floor_excursion`):
#: ahead, the bent knee of a swing leg (the shank's collision cylinder reaches 0.23 m in
#: half-sitting, 0.30 m mid-swing) and the wrists (0.31 m); behind, the chest's back
#: (0.26 m); to each side, the shoulders as the trunk sways over each support foot (0.405 m
#: walking, 0.422 m holding the box). Ahead also holds the walker's yaw tracking while it turns
#: through a door (a wrist 12 mm past a 0.31 m envelope, fig10 seed 1). A scene's footprint
#: larger than this envelope (more cautious) is kept
#: (:meth:`pivot_ompl.grasp.BoxGraspModel.walking_extent`).
WALK_ENVELOPE = (0.33, 0.27, 0.43)

#: Sole rectangle (length along the foot's x, width) in m, centred on the sole frame.
SOLE_SIZE = (0.241, 0.138)

#: HRP-2 half-sitting posture (rad), the nominal reference posture.
HALF_SITTING: dict[str, float] = {
    **{f"{s}LEG_JOINT{i}": v for s in "RL"
       for i, v in enumerate((0.0, 0.0, -0.453786, 0.872665, -0.418879, 0.0))},
    "CHEST_JOINT0": 0.0, "CHEST_JOINT1": 0.0, "HEAD_JOINT0": 0.0, "HEAD_JOINT1": 0.0,
    **{f"RARM_JOINT{i}": v for i, v in
       enumerate((0.261799, -0.174533, 0.0, -0.523599, 0.0, 0.0, 0.174533))},
    **{f"LARM_JOINT{i}": v for i, v in
       enumerate((0.261799, 0.174533, 0.0, -0.523599, 0.0, 0.0, 0.174533))},
}

#: Posture targets of the upper body: chest and head upright, upper arms slightly inward
#: (shoulder roll 0.15 rad) and elbows bent 0.9 rad, so that the arms stay inside the 0.70 m
#: wide floor box while the trunk sways over the feet.
UPPER_POSTURE = {k: v for k, v in HALF_SITTING.items() if not k.startswith(("RLEG", "LLEG"))}
UPPER_POSTURE.update({"RARM_JOINT0": 0.15, "LARM_JOINT0": 0.15, "RARM_JOINT1": 0.15,
                      "LARM_JOINT1": -0.15, "RARM_JOINT3": -0.5, "LARM_JOINT3": -0.5})

#: How far a foot may land outside its nominal place beside the support foot (m): 9 deg of
#: hip roll per leg, of HRP-2's 35 deg outward.
FOOT_DY_OUT = 0.18
#: Largest yaw between the two feet (rad), split between the two hip yaw joints (each
#: limited to 30 deg inward).
FOOT_DTHETA = 0.40

PROFILE = HumanoidProfile(
    name="hrp2",
    title="HRP-2 (Kawada/AIST): our primitive-geometry model from the published facts",
    urdf_name=URDF_RELPATH, locate_urdf=urdf_path,
    footprint=FOOTPRINT, standoff=STANDOFF, height=HEIGHT, walk_envelope=WALK_ENVELOPE,
    shoulder_xy=SHOULDER_XY, shoulder_envelope=SHOULDER_ENVELOPE,
    hand_envelope=HAND_ENVELOPE, step_forward=STEP_FORWARD, step_backward=STEP_BACKWARD,
    step_lateral=STEP_LATERAL, step_turn=STEP_TURN, sole_size=SOLE_SIZE, feet_spacing=0.20,
    com_height=0.79, foot_dy_out=FOOT_DY_OUT, foot_dtheta=FOOT_DTHETA,
    half_sitting=HALF_SITTING, upper_posture=UPPER_POSTURE,
    leg_prefixes=("RLEG", "LLEG"), upper_prefixes=("RARM", "LARM", "CHEST", "HEAD"),
    contact_links=("RARM_LINK5", "RARM_LINK6", "LARM_LINK5", "LARM_LINK6"),
    sources={
        "footprint": "measured on the URDF (derived_floor_geometry) plus arm swing and steps",
        "standoff": "chosen: grip points where the arms hold the inclined box, elbows bent",
        "height": "measured: URDF zero pose, sole to top of head (published 1.539 m)",
        "walk_envelope": "measured on whole-body motions (wholebody.envelope)",
        "shoulder_xy": "measured on the URDF (derived_arm_geometry)",
        "shoulder_envelope": "URDF collision primitives plus measured elbow bend",
        "hand_envelope": "URDF collision primitives plus measured wrist swing",
        "steps": "measured: the largest with which every shipped scene passes check-motion",
        "sole_size": "URDF: the foot's 3 cm sole box",
        "feet_spacing": "chosen: the walker's setting, checked by check-motion",
        "com_height": "chosen: the walker's setting (knees bent), checked by check-motion",
        "half_sitting": "HRP-2's published half-sitting (../shared/hrp2)",
        "joint limits": "URDF (position, velocity)",
        "accel limits": "written down: torque at the URDF's efforts (joint_peaks docstring)",
    })


def load_pinocchio_model():  # noqa: ANN201 - pinocchio types are untyped
    """The pinocchio model of HRP-2 with a free-flyer root (nq = 37, nv = 36)."""
    import pinocchio as pin

    return pin.buildModelFromUrdf(str(urdf_path()), pin.JointModelFreeFlyer())


def half_sitting_configuration(model) -> np.ndarray:  # noqa: ANN001
    """Pinocchio configuration in half-sitting with the soles on the floor at the origin."""
    import numpy as np
    import pinocchio as pin

    q = pin.neutral(model)
    for name, value in HALF_SITTING.items():
        q[model.joints[model.getJointId(name)].idx_q] = value
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    sole_z = data.oMf[model.getFrameId("left_foot")].translation[2]
    q[2] -= sole_z
    return np.asarray(q)


@functools.lru_cache(maxsize=1)
def derived_floor_geometry() -> dict[str, float]:
    """Measure the model's floor bounding box, height and reach in half-sitting.

    Returns a dict with ``depth``/``width`` of the collision primitives' floor projection
    (half-sitting, arms alongside the body, relative to the midpoint of the sole centres),
    ``front``/``back`` (m ahead of / behind that midpoint), ``height`` (zero pose, sole to
    top of head), ``reach`` (horizontal distance from the sole midpoint to a grip point with
    the arms straight forward) and ``zero_pose_depth``/``zero_pose_width`` (all joints
    zero, standing straight).
    """
    import numpy as np
    import pinocchio as pin

    model = load_pinocchio_model()
    geom = pin.buildGeomFromUrdf(model, str(urdf_path()), pin.GeometryType.COLLISION)
    data, gdata = model.createData(), geom.createData()

    def corners(q: np.ndarray) -> np.ndarray:
        pin.updateGeometryPlacements(model, data, geom, gdata, q)
        pts = []
        for obj, placement in zip(geom.geometryObjects, gdata.oMg, strict=True):
            g = obj.geometry
            if hasattr(g, "halfSide"):
                h = np.asarray(g.halfSide)
            else:  # cylinder along local z
                h = np.array([g.radius, g.radius, g.halfLength])
            for sx in (-1, 1):
                for sy in (-1, 1):
                    for sz in (-1, 1):
                        pts.append(placement.act(h * np.array([sx, sy, sz])))
        return np.array(pts)

    q = half_sitting_configuration(model)
    for side in "RL":  # arms alongside the body (the walking rest posture)
        q[model.joints[model.getJointId(f"{side}ARM_JOINT1")].idx_q] = 0.0
    pin.framesForwardKinematics(model, data, q)
    mid = 0.5 * (data.oMf[model.getFrameId("left_foot")].translation
                 + data.oMf[model.getFrameId("right_foot")].translation)
    pts = corners(q) - mid
    q0 = pin.neutral(model)
    pin.framesForwardKinematics(model, data, q0)
    sole0 = data.oMf[model.getFrameId("left_foot")].translation[2]
    pts0 = corners(q0)
    top = pts0[:, 2].max() - sole0
    qf = q.copy()
    for side in "RL":
        qf[model.joints[model.getJointId(f"{side}ARM_JOINT0")].idx_q] = -0.5 * math.pi
        qf[model.joints[model.getJointId(f"{side}ARM_JOINT3")].idx_q] = 0.0
    pin.framesForwardKinematics(model, data, qf)
    reach = data.oMf[model.getFrameId("right_hand")].translation[0] - mid[0]
    return {"depth": float(np.ptp(pts[:, 0])), "width": float(np.ptp(pts[:, 1])),
            "front": float(pts[:, 0].max()), "back": float(-pts[:, 0].min()),
            "height": float(top), "reach": float(reach),
            "zero_pose_depth": float(np.ptp(pts0[:, 0])),
            "zero_pose_width": float(np.ptp(pts0[:, 1]))}


@functools.lru_cache(maxsize=1)
def derived_arm_geometry() -> dict[str, float]:
    """Measure the arms on the URDF (half-sitting, relative to the sole midpoint).

    Returns ``shoulder_x``, ``shoulder_y`` (the right and left shoulder joints' mean ahead
    of and half-spacing across the sole midpoint, m), ``shoulder`` and ``wrist`` (the
    largest half floor diagonal of the collision primitives of the shoulder links
    ``*ARM_LINK0..1`` and of the wrist and fingers ``*ARM_LINK5..6``, m).
    """
    import numpy as np
    import pinocchio as pin

    model = load_pinocchio_model()
    data = model.createData()
    geom = pin.buildGeomFromUrdf(model, str(urdf_path()), pin.GeometryType.COLLISION)
    q = half_sitting_configuration(model)
    pin.framesForwardKinematics(model, data, q)
    mid = 0.5 * (data.oMf[model.getFrameId("left_foot")].translation
                 + data.oMf[model.getFrameId("right_foot")].translation)
    sh = [data.oMi[model.getJointId(f"{s}ARM_JOINT0")].translation - mid for s in "RL"]
    widest = {"shoulder": 0.0, "wrist": 0.0}
    for obj in geom.geometryObjects:
        part = ("shoulder" if any(f"ARM_LINK{i}" in obj.name for i in (0, 1)) else
                "wrist" if any(f"ARM_LINK{i}" in obj.name for i in (5, 6)) else "")
        if part:
            g = obj.geometry
            h = np.asarray(g.halfSide) if hasattr(g, "halfSide") else np.array([g.radius] * 2)
            widest[part] = max(widest[part], float(np.hypot(h[0], h[1])))
    return {"shoulder_x": float(0.5 * (sh[0][0] + sh[1][0])),
            "shoulder_y": float(0.5 * (sh[1][1] - sh[0][1])), **widest}


def hrp2_floor_geometry() -> dict[str, object]:
    """Robot floor geometry for scenes.

    Returns ``{"footprint": (depth, width), "standoff": s, "height": h}`` (m).

    The footprint is a conservative box around the measured half-sitting floor projection
    (see :func:`derived_floor_geometry`: 0.355 x 0.62 m in the zero pose, matching the published
    0.355 x 0.621 m; 0.44 x 0.61 m in half-sitting, where the bounding-box primitives of the
    bent knees overstate the depth by a few cm) with room for the arm swing and the feet's
    lateral steps: 0.40 x 0.70 m. The standoff (0.25 m, held face to the front of that box)
    puts the grip points where the arms hold the inclined box with bent elbows. ``height``
    is the measured zero-pose standing height.
    """
    d = derived_floor_geometry()
    depth, width = FOOTPRINT
    if d["zero_pose_depth"] > depth or d["width"] > width:  # pragma: no cover - sanity
        log.warning("measured robot floor box %.3f x %.3f exceeds the footprint %s",
                    d["zero_pose_depth"], d["width"], FOOTPRINT)
    return {"footprint": FOOTPRINT, "standoff": STANDOFF,
            "height": round(float(d["height"]), 3)}
