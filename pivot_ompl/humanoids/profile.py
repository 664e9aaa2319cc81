"""A humanoid's profile: everything the planner, the whole body, the checks and the replay read.

A profile is plain data (no pinocchio, no PlaCo at import): the planner's bodies (footprint,
walking envelope, shoulders, standoff, height), the walk (step limits, sole, feet spacing,
CoM height), the whole body's postures and joint groups, and where its URDF is. The URDF a
profile locates always has the frames PlaCo and the checks rely on (:data:`FRAMES`): each
profile module adds them when the robot's own file lacks them. Joint position and velocity
limits are the URDF's own (read by pinocchio where they are used); the acceleration limits
are the profile's.

Profiles are looked up by name (:func:`pivot_ompl.humanoids.profile_of`); ``docs/robots.md``
lists every field with where each value came from.
"""

from __future__ import annotations

import logging
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path

log = logging.getLogger(__name__)

__all__ = ["FRAMES", "HumanoidProfile"]

#: Frame names every consumer relies on: the sole centres, the trunk (PlaCo's
#: ``HumanoidRobot`` needs these three) and the grip points of both hands.
FRAMES = ("left_foot", "right_foot", "trunk", "left_hand", "right_hand")


@dataclass(frozen=True)
class HumanoidProfile:
    """One humanoid (SI units; the robot frame is the sole midpoint, x ahead, z up).

    Attributes:
        name: the name scenes, plans and motions use (``robot: {model: <name>}``).
        title: a human-readable description (maker, source of the model).
        urdf_name: how motion files name the URDF (``motion.urdf``).
        locate_urdf: returns the URDF file with :data:`FRAMES` (called when needed; may raise
            :class:`~pivot_ompl.errors.InputError` when the robot's data is not installed).
        footprint: conservative floor box ``(depth along the heading, width)`` (m).
        standoff: gap between the held face of the box and the footprint's front (m).
        height: the robot's standing height, sole to top of head (m).
        walk_envelope: how far the links reach from the robot pose while walking,
            ``(ahead, behind, to each side)`` (m).
        shoulder_xy: the shoulder joints in half-sitting, ``(x, +/-y)`` (m).
        shoulder_envelope, hand_envelope: half-sides of the floor squares round a shoulder
            joint and round a grip point whose convex hull is the arms' floor body (m).
        step_forward, step_backward, step_lateral: longest step of the sole midpoint (m).
        step_turn: largest yaw change of one step (rad).
        sole_size: sole rectangle ``(length, width)`` centred on the foot frame (m).
        feet_spacing: lateral distance between the sole centres while walking (m).
        com_height: the CoM's height while walking (m).
        foot_dy_out: how far a foot may land outside its nominal place (m).
        foot_dtheta: largest yaw between the two feet (rad).
        half_sitting: the reference posture, joint name -> angle (rad).
        upper_posture: posture targets of the upper body while holding or walking (rad).
        leg_prefixes: joint-name prefixes of the legs (held to :attr:`leg_accel_limit`).
        upper_prefixes: joint-name prefixes of the arms, chest and head (held to
            :attr:`upper_accel_limit`; they only follow the box).
        contact_links: collision-geometry name prefixes allowed to touch the box (hands).
        fixed_joints: joints the whole body holds still at the given angle (rad), such as
            grippers: the solver never moves them.
        locate_solver_urdf: returns the URDF the whole-body solver loads (kinematics and
            inertias, no geometry: quicker to load), or ``None``: :meth:`urdf_path`'s.
        repose_upper: set the upper posture again after PlaCo's initial pose (its
            ``reach_initial_pose`` moves the arms: Talos's shoulder roll from 0.02 to 0.18
            rad, the arms 6 cm wider). HRP-2's motions are made without it.
        settle_time: unrecorded standing time (s, twice) before a motion starts, for the
            upper body to come to rest from its initial posture.
        upper_accel_limit, leg_accel_limit: joint acceleration limits (rad/s²).
        upper_accel: the acceleration the generator drives the upper body with (rad/s²).
        sources: field name -> where its value came from (``docs/robots.md``).
    """

    name: str
    title: str
    urdf_name: str
    locate_urdf: Callable[[], Path] = field(repr=False, compare=False)
    footprint: tuple[float, float]
    standoff: float
    height: float
    walk_envelope: tuple[float, float, float]
    shoulder_xy: tuple[float, float]
    shoulder_envelope: float
    hand_envelope: float
    step_forward: float
    step_backward: float
    step_lateral: float
    step_turn: float
    sole_size: tuple[float, float]
    feet_spacing: float
    com_height: float
    foot_dy_out: float
    foot_dtheta: float
    half_sitting: Mapping[str, float]
    upper_posture: Mapping[str, float]
    leg_prefixes: tuple[str, ...]
    upper_prefixes: tuple[str, ...]
    contact_links: tuple[str, ...]
    fixed_joints: Mapping[str, float] = field(default_factory=dict)
    settle_time: float = 1.0
    repose_upper: bool = False
    locate_solver_urdf: Callable[[], Path] | None = field(default=None, repr=False,
                                                          compare=False)
    upper_accel_limit: float = 30.0
    leg_accel_limit: float = 50.0
    upper_accel: float = 20.0
    sources: Mapping[str, str] = field(default_factory=dict, repr=False, compare=False)

    def urdf_path(self) -> Path:
        """The URDF file (with :data:`FRAMES`)."""
        return self.locate_urdf()

    def cautious_footprint(self, given: tuple[float, float]) -> tuple[float, float]:
        """A footprint ``given`` by a scene, grown where it is smaller than the robot's own."""
        out = (max(given[0], self.footprint[0]), max(given[1], self.footprint[1]))
        if out != tuple(given):
            log.info("robot.footprint %s is smaller than %s's own %s: %s kept", list(given),
                     self.name, list(self.footprint), list(out))
        return out

    def solver_urdf_path(self) -> Path:
        """The URDF the whole-body solver loads (see :attr:`locate_solver_urdf`)."""
        if self.locate_solver_urdf is None:
            return self.locate_urdf()
        return self.locate_solver_urdf()

    def is_leg(self, joint: str) -> bool:
        """Whether ``joint`` is a leg joint."""
        return joint.startswith(self.leg_prefixes)

    def is_upper(self, joint: str) -> bool:
        """Whether ``joint`` is an arm, chest or head joint."""
        return joint.startswith(self.upper_prefixes)

    def leg_posture(self) -> dict[str, float]:
        """Half-sitting of the legs alone."""
        return {k: v for k, v in self.half_sitting.items() if self.is_leg(k)}

    def accel_limit(self, joint: str) -> float:
        """The acceleration limit of ``joint`` (rad/s²)."""
        return self.upper_accel_limit if self.is_upper(joint) else self.leg_accel_limit

    def key_figures(self) -> dict[str, object]:
        """The figures ``pivot-ompl robots`` lists."""
        return {"model": self.name, "title": self.title, "height_m": self.height,
                "footprint_m": list(self.footprint), "standoff_m": self.standoff,
                "walk_envelope_m": list(self.walk_envelope), "sole_m": list(self.sole_size),
                "step_forward_m": self.step_forward, "step_lateral_m": self.step_lateral,
                "step_turn_rad": self.step_turn, "com_height_m": self.com_height}
