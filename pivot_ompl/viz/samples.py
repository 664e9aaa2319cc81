"""Small self-made inputs for trying and testing the viewer without the planner or HRP-2.

:func:`write_samples` writes into a folder: a scene with one obstacle of each kind, a short
plan (transfer, transit, transfer), a tiny two-legged URDF of primitives and a synthetic
motion ``.npz`` following the motion-file contract (:mod:`pivot_ompl.motionfile`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from pivot_ompl.resources import URDF_RELPATH, urdf_path

TINY_URDF = """<?xml version="1.0"?>
<robot name="tiny">
  <material name="blue"><color rgba="0.3 0.4 0.8 1"/></material>
  <link name="base_link">
    <visual><geometry><box size="0.2 0.3 0.4"/></geometry><material name="blue"/></visual>
  </link>
  <link name="head"><visual><geometry><sphere radius="0.1"/></geometry></visual></link>
  <joint name="neck" type="fixed"><parent link="base_link"/><child link="head"/>
    <origin xyz="0 0 0.3"/></joint>
{legs}
  <link name="arm"><visual><origin xyz="0.15 0 0"/>
    <geometry><box size="0.3 0.06 0.06"/></geometry></visual></link>
  <joint name="shoulder" type="revolute"><parent link="base_link"/><child link="arm"/>
    <origin xyz="0.1 0.2 0.15"/><axis xyz="0 1 0"/>
    <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
</robot>
"""

_LEG = """  <link name="{s}_leg"><visual><origin xyz="0 0 -0.2"/>
    <geometry><cylinder radius="0.04" length="0.4"/></geometry></visual></link>
  <joint name="{s}_hip" type="revolute"><parent link="base_link"/><child link="{s}_leg"/>
    <origin xyz="0 {y} -0.2"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <link name="{s}_foot"><visual><geometry><box size="0.2 0.1 0.02"/></geometry></visual>
  </link>
  <joint name="{s}_ankle" type="revolute"><parent link="{s}_leg"/><child link="{s}_foot"/>
    <origin xyz="0 0 -0.4"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
"""

TINY_JOINTS = ("left_hip", "left_ankle", "right_hip", "right_ankle", "shoulder")

SCENE_YAML = """name: sample
bounds: [-2.0, -2.0, 4.0, 4.0]
object: {size: [0.8, 0.6, 1.3]}
obstacles:
  - {type: box, center: [2.5, -1.0], size: [0.6, 0.4], yaw: 0.3, height: 1.0}
  - {type: cylinder, center: [-1.0, 2.5], radius: 0.3, height: 0.8}
  - {type: polygon, points: [[3.0, 2.0], [3.8, 2.0], [3.8, 3.5], [3.4, 2.6], [3.0, 3.5]],
     height: 1.2}
start: [0.0, 0.0, 0.0]
goal: [1.0, 0.5, 0.3]
"""


@dataclass(frozen=True)
class Samples:
    """Paths of the files written by :func:`write_samples`."""

    scene: Path
    plan: Path
    urdf: Path
    motion: Path


def tiny_urdf() -> str:
    """A 7-link robot of boxes, cylinders and a sphere with feet named like PlaCo's."""
    legs = "".join(_LEG.format(s=s, y=y) for s, y in (("left", 0.1), ("right", -0.1)))
    return TINY_URDF.format(legs=legs)


def sample_plan():
    """A short plan: transfer at grasp 0, a walk to grasp 1, transfer at grasp 1."""
    from pivot_ompl.grasp import BoxGraspModel
    from pivot_ompl.pivoting.steering import PivotSteering
    from pivot_ompl.pivoting.transfer import transfer_phase
    from pivot_ompl.planfile import Plan, TransitPhase

    model = BoxGraspModel((0.8, 0.6, 1.3))
    steering = PivotSteering(turning_radius=2.0, alpha_max=math.pi / 8)
    ph = transfer_phase(model, steering, [(0.0, 0.0, 0.0), (1.0, 0.5, 0.3)], 0)
    obj = ph.object_end
    r0, r1 = ph.robot_end, model.robot_pose(obj, 1)
    mid = (0.5 * (r0[0] + r1[0]) - 0.3, 0.5 * (r0[1] + r1[1]) - 0.3, 0.5 * (r0[2] + r1[2]))
    walk = TransitPhase(0, 1, (r0, mid, r1), obj)
    ph2 = transfer_phase(model, steering, [obj, (obj[0] + 0.6, obj[1] + 0.8, obj[2] + 0.4)], 1)
    return Plan("sample", "exact", (0.8, 0.6, 1.3), (0.4, 0.7), 0.25, math.pi / 8,
                (0.0, 0.0, 0.0), [ph, walk, ph2])


def sample_motion_arrays(*, duration: float = 4.0, dt: float = 0.005) -> dict[str, np.ndarray]:
    """Arrays of a synthetic motion of the tiny robot.

    It stands still for 1 s, then walks along +x turning left, pushing the box (inclined by
    5 deg about its y axis) while its legs and arm swing.
    """
    t = np.arange(0.0, duration + 1e-9, dt)
    n = len(t)
    s = np.clip((t - 1.0) / max(duration - 1.0, 1e-9), 0.0, 1.0)
    q = np.zeros((n, 7 + len(TINY_JOINTS)))
    q[:, 0] = 1.2 * s
    q[:, 2] = 0.82
    yaw = 0.4 * s
    q[:, 5], q[:, 6] = np.sin(yaw / 2), np.cos(yaw / 2)
    swing = np.where(t > 1.0, 0.4 * np.sin(2 * np.pi * (t - 1.0)), 0.0)
    q[:, 7], q[:, 8], q[:, 9], q[:, 10] = swing, -swing, -swing, swing
    q[:, 11] = -1.2 * s
    box = np.zeros((n, 7))
    box[:, 0] = q[:, 0] + 0.9 * np.cos(yaw)
    box[:, 1] = 0.9 * np.sin(yaw)
    box[:, 2] = 0.65
    tilt = math.radians(5.0)
    # yaw about z, then tilt about the box's y: quaternion product (xyzw)
    cz, sz, cy, sy = np.cos(yaw / 2), np.sin(yaw / 2), math.cos(tilt / 2), math.sin(tilt / 2)
    box[:, 3], box[:, 4], box[:, 5], box[:, 6] = -sz * sy, cz * sy, sz * cy, cz * cy
    com = np.c_[q[:, 0], q[:, 1], np.full(n, 0.8)]
    return {"t": t, "q": q, "joint_names": np.array(TINY_JOINTS), "box": box, "com": com,
            "zmp": com[:, :2].copy(), "support": np.zeros(n, dtype=int),
            "phase": np.zeros(n, dtype=int), "box_size": np.array([0.8, 0.6, 1.3]),
            "sole_size": np.array([0.2, 0.1])}


def write_samples(folder: str | Path, *, duration: float = 4.0) -> Samples:
    """Write the sample scene, plan, URDF and motion into ``folder``; return their paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    scene = folder / "sample.yaml"
    scene.write_text(SCENE_YAML)
    plan = sample_plan().to_json(folder / "plan.json")
    urdf = folder / "tiny.urdf"
    urdf.write_text(tiny_urdf())
    arrays: dict[str, Any] = sample_motion_arrays(duration=duration)
    motion = folder / "motion.npz"
    np.savez(motion, urdf=np.array(str(urdf)), scene=np.array("sample"), **arrays)
    return Samples(scene, plan, urdf, motion)


def write_urdf_motion(folder: str | Path, urdf: str | Path, *, duration: float = 2.0,
                      dt: float = 0.005) -> Path:
    """A synthetic motion ``.npz`` of any URDF robot, in pinocchio's joint order.

    The motion names the shipped model as ``robots/hrp2/hrp2.urdf``; another ``urdf`` by its
    path (give it to the replay explicitly). The robot (free-flyer root 0.6 m up) moves
    0.2 m/s along +x while every joint swings by 0.2 rad; the box stays 0.8 m ahead of it.
    Needs pinocchio.
    """
    import pinocchio as pin

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    model = pin.buildModelFromUrdf(str(urdf), pin.JointModelFreeFlyer())
    names = list(model.names[2:])
    t = np.arange(0.0, duration + 1e-9, dt)
    q = np.tile(pin.neutral(model), (len(t), 1))
    q[:, 0] = 0.2 * t
    q[:, 2] = 0.6
    q[:, 7:] = 0.2 * np.sin(t[:, None] + np.arange(len(names)))
    box = np.zeros((len(t), 7))
    box[:, 0], box[:, 2], box[:, 6] = q[:, 0] + 0.8, 0.65, 1.0
    path = folder / f"{Path(urdf).stem}_motion.npz"
    shipped = Path(urdf).resolve() == urdf_path().resolve()
    name = URDF_RELPATH if shipped else str(urdf)  # a foreign model is passed to the replay
    np.savez(path, t=t, q=q, joint_names=np.array(names), urdf=np.array(name), box=box,
             box_size=np.array([0.8, 0.6, 1.3]))
    return path
