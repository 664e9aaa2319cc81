"""Talos's profile (PAL Robotics; the ``example-robot-data`` model, the ``talos`` extra).

Where each value comes from (``docs/robots.md`` has the table):

* from the URDF (``talos_reduced.urdf``): the joints, their position and velocity limits
  (read by pinocchio where used), the sole (the foot collision mesh ``ankle_X_collision.stl``
  spans 0.2208 x 0.1344 m, :data:`~pivot_ompl.humanoids.talos_data.SOLE_CENTRE`), the
  height (1.756 m, zero pose, sole to top of the head mesh), the shoulders (``arm_*_2_joint``,
  where the upper arm hangs from, at x -0.014 m, y +/-0.291 m in half-sitting);
* from the SRDF (``talos.srdf``): ``half_sitting`` (read when first used, so the profile
  imports without the package);
* measured on the URDF (pinocchio, the collision meshes' vertices): the
  collision meshes' floor box in half-sitting, x from -0.199 to +0.213 m, y +/-0.38 m (the
  upper arms hang outside the 0.45 m wide torso), hence the 0.50 x 0.80 m footprint;
* measured on whole-body motions (:mod:`pivot_ompl.wholebody.envelope`): the walking
  envelope;
* written down (neither file says them): the step limits and the legs' ranges per step
  (HRP-2's, which Talos's longer legs and wider joint ranges exceed: kept as the cautious
  choice, and checked by ``check-motion``), the CoM height while walking (1.7 cm under
  the half-sitting CoM, 0.877 m, so the knees stay bent), the feet spacing (HRP-2's 0.20 m:
  the hips are 0.17 m apart, the soles 0.134 m wide), the acceleration limits (the same
  30 / 50 rad/s² as HRP-2's; ``docs/robots.md`` compares them with Talos's efforts), the
  standoff (HRP-2's: the grips stay within the arms' reach, checked by the generator).
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Iterator, Mapping

from pivot_ompl.humanoids.profile import HumanoidProfile
from pivot_ompl.humanoids.talos_data import (
    half_sitting_from_srdf,
    talos_solver_urdf,
    talos_urdf,
)

__all__ = ["PROFILE", "URDF_NAME"]

#: How motion files name Talos's URDF (resolved through the installed package).
URDF_NAME = "example-robot-data/robots/talos_data/robots/talos_reduced.urdf"

#: Upper-body posture targets that differ from half-sitting (left arm; the right arm mirrors
#: the first three): upper arms along the body (shoulder yaw 0, roll 0.02 rad: the roll's
#: limit is 0, the arm hanging straight), forearms turned in (upper-arm twist -0.5 rad) and
#: the elbows bent 0.5 rad: the arms' narrowest (collision meshes within y +/-0.383 m, the
#: hands at +/-0.20 m) so that the hands and grippers stay inside the walking envelope.
_ARM_POSTURE = {1: 0.0, 2: 0.02, 3: -0.5, 4: -0.5}


@functools.cache
def _half_sitting() -> dict[str, float]:
    return half_sitting_from_srdf()


@functools.cache
def _upper_posture() -> dict[str, float]:
    out = {k: v for k, v in _half_sitting().items() if not k.startswith("leg_")}
    for i, v in _ARM_POSTURE.items():
        out[f"arm_left_{i}_joint"] = v
        out[f"arm_right_{i}_joint"] = -v if i in (1, 2, 3) else v
    return out


class _Lazy(Mapping[str, float]):
    """A posture read from the installed package when first used."""

    def __init__(self, load: Callable[[], dict[str, float]]) -> None:
        self._load = load

    def __getitem__(self, key: str) -> float:
        return self._load()[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._load())

    def __len__(self) -> int:
        return len(self._load())


PROFILE = HumanoidProfile(
    name="talos",
    title="Talos (PAL Robotics): example-robot-data 6 talos_reduced, Apache-2.0",
    urdf_name=URDF_NAME, locate_urdf=talos_urdf,
    footprint=(0.50, 0.80), standoff=0.25, height=1.76,
    walk_envelope=(0.36, 0.27, 0.475),
    shoulder_xy=(-0.014, 0.291), shoulder_envelope=0.22, hand_envelope=0.09,
    step_forward=0.15, step_backward=0.08, step_lateral=0.06, step_turn=0.25,
    sole_size=(0.2208, 0.1344), feet_spacing=0.20, com_height=0.86,
    foot_dy_out=0.18, foot_dtheta=0.40,
    half_sitting=_Lazy(_half_sitting), upper_posture=_Lazy(_upper_posture),
    leg_prefixes=("leg_left", "leg_right"),
    upper_prefixes=("arm_", "torso_", "head_", "gripper_"),
    contact_links=("gripper_left", "gripper_right", "wrist_left", "wrist_right",
                   "arm_left_7", "arm_right_7"),
    fixed_joints={"gripper_left_joint": 0.0, "gripper_right_joint": 0.0,
                  "torso_2_joint": 0.006761},
    settle_time=3.0, repose_upper=True,
    locate_solver_urdf=talos_solver_urdf,
    sources={
        "footprint": "measured: URDF collision meshes in half-sitting (x -0.199..0.213, "
                     "y +/-0.38 m), rounded up",
        "standoff": "written down: HRP-2's (grips within reach, checked by the generator)",
        "height": "URDF: zero pose, sole to top of head 1.756 m",
        "walk_envelope": "measured on the fig10 motion (wholebody.envelope): an upper arm "
                         "14 mm past a 0.46 m side while walking",
        "shoulder_xy": "URDF: arm_*_2_joint in half-sitting",
        "shoulder_envelope": "measured on whole-body motions: the upper arms flare to "
                             "y +/-0.51 m as the hands hold the box (wholebody.envelope)",
        "hand_envelope": "URDF: the gripper's collision meshes, half floor diagonal",
        "steps": "written down: HRP-2's, checked by check-motion",
        "sole_size": "URDF: foot collision mesh ankle_X_collision.stl",
        "feet_spacing": "written down: HRP-2's 0.20 m (hips 0.17 m apart)",
        "com_height": "measured: 1.7 cm under the half-sitting CoM (0.877 m)",
        "half_sitting": "SRDF: group state half_sitting",
        "fixed_joints": "written down: the grippers closed (URDF upper limit 0), never moved; "
                        "the torso pitch at the SRDF's half-sitting (left free, the chest "
                        "leaned back 0.14 rad and 6 cm out of the walking envelope)",
        "settle_time": "measured: the arms still swing at 2 rad/s after 1 s, at rest after 3 s",
        "joint limits": "URDF (position, velocity)",
        "accel limits": "written down: HRP-2's 30 / 50 rad/s² (see docs/robots.md)",
    })
