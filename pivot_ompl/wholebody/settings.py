"""Walking and solver parameters of the whole-body generator, and their scene walk model."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from pivot_ompl.humanoids import DEFAULT_MODEL, HumanoidProfile, profile_of
from pivot_ompl.wholebody.lipm import omega

if TYPE_CHECKING:
    from pivot_ompl.scene import WalkParameters

log = logging.getLogger(__name__)

_DEFAULT = profile_of(DEFAULT_MODEL)
#: The default model's legs: how far a foot may land outside its nominal place (m) and the
#: largest yaw between the two feet (rad) (:attr:`HumanoidProfile.foot_dy_out`, ``foot_dtheta``).
FOOT_DY_OUT = _DEFAULT.foot_dy_out
FOOT_DTHETA = _DEFAULT.foot_dtheta


@dataclass(frozen=True)
class WalkSettings:
    """Walking and solver parameters (SI units).

    Attributes:
        dt: motion sampling period (s).
        substeps: samples per solver tick: one QP every ``substeps * dt``
            (:attr:`solver_dt`); the samples between are those of the quadratic B-spline of
            the solver's configurations (:mod:`pivot_ompl.wholebody.blend`). 1: one QP per
            sample.
        single_support_duration: duration of a step's single support (s).
        single_support_timesteps: LIPM samples per single support.
        double_support_ratio: double support duration / single support duration (0.14 s
            after 0.7 s: HRP-2's own walking pattern generator, jrl-umi3218/jrl-walkgen,
            runs 0.7 s single and 0.1 s to 0.2 s double supports; 0.1 s passes the checks
            too but, where a shoulder reaches its joint limit while the box turns, drives
            an arm to 96 % of its velocity limit on the fig10 demo, against 89 % at 0.14 s).
        startend_double_support_ratio: same, for the first and last double supports.
        com_height: CoM height while walking (m).
        foot_height: swing foot apex (m).
        feet_spacing: lateral distance between the sole centres (m).
        max_dx_forward, max_dx_backward: how far a foot may land ahead of / behind its
            nominal place beside the support foot (m).
        max_dy, max_dtheta: lateral and yaw step bounds of PlaCo's naive footstep planner
            (:meth:`~pivot_ompl.wholebody.walker.PlacoWalker.plan_footsteps`, walks to a
            transfer's start) (m, rad).
        zmp_margin: ZMP margin inside the sole kept by the pattern generator (m).
        foot_offset: sole midpoint ahead of the robot pose centre (m).
        hand_position_weight, hand_orientation_weight: hand frame task weights.
        relative_weight: hand-to-hand relative task position weight.
        relative_orientation_weight: hand-to-hand relative task orientation weight.
        posture_weight: posture (joints) task weight.
        foot_dy_out: how far a foot may land outside its nominal place beside the support
            foot (m; :func:`~pivot_ompl.wholebody.footsteps.pivot_footsteps` and
            :func:`~pivot_ompl.wholebody.footsteps.path_footsteps`): the
            feet at most ``feet_spacing + foot_dy_out`` apart (0.38 m: 9 deg of hip roll per
            leg, of HRP-2's 35 deg outward).
        foot_dy_in: same, inside: the feet at least ``feet_spacing - foot_dy_in`` apart
            (and the soles at least :attr:`sole_gap` apart).
        foot_dtheta: largest yaw between the two feet (rad; 0.40 rad is split between the
            two hip yaw joints, each limited to 30 deg inward).
        sole_gap: least gap between the two sole rectangles (m).
        upper_accel: the largest acceleration of an arm, chest or head joint (these only
            follow the box): every change of their speed, braking before a position limit
            included, is bounded by it (rad/s²,
            :class:`~pivot_ompl.wholebody.joint_damper.JointDamper`).
        seed: seed of PlaCo's own pseudo-random generator (``placo.seed``), set when the
            robot is set up, so that a plan gives the same motion on every run.
        robot: the humanoid's profile name (:mod:`pivot_ompl.humanoids`); the other
            defaults are the default model's (:meth:`of` takes a profile's).
    """

    dt: float = 0.005
    substeps: int = 2
    single_support_duration: float = 0.7
    single_support_timesteps: int = 14
    double_support_ratio: float = 0.2
    startend_double_support_ratio: float = 1.0
    com_height: float = _DEFAULT.com_height
    foot_height: float = 0.04
    feet_spacing: float = _DEFAULT.feet_spacing
    max_dx_forward: float = _DEFAULT.step_forward
    max_dx_backward: float = _DEFAULT.step_backward
    max_dy: float = _DEFAULT.step_lateral
    max_dtheta: float = _DEFAULT.step_turn
    zmp_margin: float = 0.03
    foot_offset: float = 0.0
    hand_position_weight: float = 1000.0
    hand_orientation_weight: float = 0.01
    relative_weight: float = 0.1
    relative_orientation_weight: float = 0.0
    posture_weight: float = 1e-3
    foot_dy_out: float = FOOT_DY_OUT
    foot_dy_in: float = 0.03
    foot_dtheta: float = FOOT_DTHETA
    sole_gap: float = 0.02
    upper_accel: float = _DEFAULT.upper_accel
    seed: int = 1
    robot: str = DEFAULT_MODEL

    @property
    def profile(self) -> HumanoidProfile:
        """The humanoid's profile."""
        return profile_of(self.robot, field="settings.robot")

    @classmethod
    def of(cls, robot: HumanoidProfile, **overrides: Any) -> WalkSettings:
        """The settings of ``robot`` (its steps, legs, CoM height, feet spacing)."""
        fields: dict[str, Any] = {
            "robot": robot.name, "com_height": robot.com_height,
            "feet_spacing": robot.feet_spacing, "max_dx_forward": robot.step_forward,
            "max_dx_backward": robot.step_backward, "max_dy": robot.step_lateral,
            "max_dtheta": robot.step_turn, "foot_dy_out": robot.foot_dy_out,
            "foot_dtheta": robot.foot_dtheta, "upper_accel": robot.upper_accel}
        fields.update(overrides)
        return cls(**fields)

    @property
    def solver_dt(self) -> float:
        """Solver tick: ``substeps * dt`` (s)."""
        return self.substeps * self.dt

    @property
    def omega(self) -> float:
        """LIPM natural frequency sqrt(g / com_height) (1/s)."""
        return omega(self.com_height)

    @classmethod
    def from_walk(cls, walk: WalkParameters, *, robot: HumanoidProfile | None = None,
                  **overrides: Any) -> WalkSettings:
        """Settings whose footstep limits follow the scene's walk model ``walk``.

        A foot lands at most ``walk.step_forward`` ahead of and ``walk.step_backward``
        behind its nominal place beside the support foot (so the sole midpoint, which moves
        half the flying foot's displacement, advances at most that much per step on a
        straight walk); PlaCo's naive planner gets ``step_lateral`` and ``step_turn``; the
        legs' outward range :attr:`foot_dy_out` and yaw range :attr:`foot_dtheta` shrink in
        proportion to ``step_lateral`` and ``step_turn`` against the profile's and never
        exceed the legs' own (``foot_dy_out``, ``foot_dtheta`` of ``robot``, the default
        model's when ``None``). The profile's walk model gives its default settings.
        ``overrides`` set any other field.
        """
        robot = robot or _DEFAULT
        lateral = min(1.0, walk.step_lateral / robot.step_lateral)
        turn = min(1.0, walk.step_turn / robot.step_turn)
        limits: dict[str, Any] = {
            "max_dx_forward": walk.step_forward, "max_dx_backward": walk.step_backward,
            "max_dy": walk.step_lateral, "max_dtheta": walk.step_turn,
            "foot_dy_out": robot.foot_dy_out * lateral,
            "foot_dtheta": robot.foot_dtheta * turn}
        limits.update(overrides)
        return cls.of(robot, **limits)
