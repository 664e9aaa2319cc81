"""PlaCo whole-body controller of a humanoid: walk pattern generator, kinematics solver, tasks.

The humanoid is the settings' profile (:mod:`pivot_ompl.humanoids`): its model and postures.

Tasks (PlaCo ``KinematicsSolver``, one QP per tick of :attr:`WalkSettings.solver_dt`):

* feet and CoM -- **hard** (``WalkTasks`` with ``scaled = False``), tracking the LIPM/ZMP walk
  pattern generator's trajectory, or fixed targets while standing; the swing foot's target
  is :class:`~pivot_ompl.wholebody.swing.SwingFoot`'s (held down, then a minimum-jerk swing);
* trunk orientation -- soft, from the walk trajectory (yaw between the feet);
* both hands -- soft frame tasks (position weight 1, low orientation weight) tracking targets
  given every tick, plus a soft hand-to-hand relative frame task;
* posture -- a weak joints task towards half-sitting with bent elbows; a small regularisation;
* joint position and velocity limits -- one pair of bounds per joint on the QP's step
  (:class:`~pivot_ompl.wholebody.joint_damper.JointDamper`: position limits narrowed to
  the velocity limit times the tick, and to braking and acceleration bounds).

Robot pose convention: the plan's robot pose (centre of the floor bounding box, heading) is the
midpoint of the two sole centres, shifted :attr:`WalkSettings.foot_offset` along the heading.
"""

from __future__ import annotations

import logging

import numpy as np

from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.wholebody import footsteps
from pivot_ompl.wholebody.box import rot_z
from pivot_ompl.wholebody.footsteps import planar, pose_matrix
from pivot_ompl.wholebody.joint_damper import JointDamper
from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.swing import SwingFoot
from pivot_ompl.wholebody.walk_windows import WindowedWalk

__all__ = ["PlacoWalker", "SolverFailure", "WalkSettings", "planar", "pose_matrix"]

log = logging.getLogger(__name__)


class SolverFailure(RuntimeError):
    """The QP of one tick failed (infeasible or numerical failure)."""


class PlacoWalker:
    """A humanoid in PlaCo, stepping one solver tick at a time (see the module docstring).

    The robot is ``settings.robot``'s profile: its URDF, half-sitting and upper-body posture.

    Args:
        settings: walking and solver parameters.
        start: robot pose (x, y, heading) to stand at in half-sitting.
    """

    def __init__(self, settings: WalkSettings, start: Pose) -> None:
        import placo

        self._placo = placo
        self.settings = s = settings
        self.swing = SwingFoot(s)
        placo.seed(s.seed)  # PlaCo's own pseudo-random generator: the same motion every run
        profile = s.profile
        robot = placo.HumanoidRobot(str(profile.solver_urdf_path()),
                                    placo.Flags.ignore_collisions)
        self.robot = robot
        self.params = humanoid_parameters(settings)

        solver = placo.KinematicsSolver(robot)
        solver.dt = s.solver_dt
        self.solver = solver
        tasks = placo.WalkTasks()
        tasks.scaled = False
        tasks.initialize_tasks(solver, robot)
        self.tasks = tasks

        for name, value in profile.half_sitting.items():
            robot.set_joint(name, value)
        for name, value in {**profile.upper_posture, **profile.fixed_joints}.items():
            robot.set_joint(name, value)
        robot.update_kinematics()
        tasks.reach_initial_pose(np.eye(4), s.feet_spacing, s.com_height, 0.0)
        # PlaCo's initial pose moves every joint: put back those held still (and the upper
        # posture, where the profile asks)
        repose = dict(profile.upper_posture) if profile.repose_upper else {}
        repose.update(profile.fixed_joints)
        for name, value in repose.items():
            robot.set_joint(name, value)
        if repose:
            robot.update_kinematics()
        for name, task in (("left_foot", tasks.left_foot_task),
                           ("right_foot", tasks.right_foot_task)):
            task.configure(name, "hard", 1.0, 1.0)
        tasks.com_task.configure("com", "hard", 1.0)
        # the velocity limits are in the damper's per-tick position bounds (the same
        # feasible steps, half the QP's inequality rows)
        solver.enable_velocity_limits(False)
        solver.enable_joint_limits(True)
        for name in profile.fixed_joints:
            solver.mask_dof(name)

        posture = solver.add_joints_task()
        posture.set_joints(dict(profile.upper_posture))
        posture.configure("posture", "soft", s.posture_weight)
        legs = profile.leg_posture()
        leg_posture = solver.add_joints_task()
        leg_posture.set_joints(legs)
        leg_posture.configure("leg_posture", "soft", 1e-5)
        solver.add_regularization_task(1e-6)
        #: the arms, chest and head, which only follow the box, brake before their limits
        #: and change their speed by at most ``upper_accel`` a second at any time
        upper = [j for j in profile.upper_posture if j in robot.joint_names()]
        self.damper = JointDamper(robot, list(robot.joint_names()), accel=s.upper_accel,
                                  dt=s.solver_dt, smooth=upper, damped=upper)

        self._place(start)
        self._add_hand_tasks()
        self._settle()

    #: Unrecorded standing time after set-up, twice (s). The head and arms, whose speed
    #: changes are bounded, take about 0.9 s to come to rest after the hand targets are set
    #: (at 0.5 s the first recorded second still had them swinging at up to 1.2 rad/s).
    PRESETTLE = 1.0

    def _add_hand_tasks(self) -> None:
        """Soft frame tasks of both hands (at their current frames) and between them."""
        s = self.settings
        T_l = self.robot.get_T_world_frame("left_hand")
        T_r = self.robot.get_T_world_frame("right_hand")
        self.left_hand = self.solver.add_frame_task("left_hand", T_l)
        self.left_hand.configure("left_hand", "soft", s.hand_position_weight,
                                 s.hand_orientation_weight)
        self.right_hand = self.solver.add_frame_task("right_hand", T_r)
        self.right_hand.configure("right_hand", "soft", s.hand_position_weight,
                                  s.hand_orientation_weight)
        rel = np.linalg.inv(T_l) @ T_r
        #: the hand-to-hand task: position only when its orientation weight is 0 (a task of
        #: weight 0 changes nothing in the QP but costs its rows every tick)
        self._relative_frame = s.relative_orientation_weight > 0.0
        if self._relative_frame:
            self.hands = self.solver.add_relative_frame_task("left_hand", "right_hand", rel)
            self.hands.configure("hands", "soft", s.relative_weight,
                                 s.relative_orientation_weight)
        else:
            self.hands = self.solver.add_relative_position_task("left_hand", "right_hand",
                                                                rel[:3, 3])
            self.hands.configure("hands", "soft", s.relative_weight)

    def _settle(self) -> None:
        """Stand still, unrecorded, until the posture is at rest (see :attr:`PRESETTLE`).

        Also measures :attr:`rest_hands`, the rest hand frames relative to the trunk.
        """
        s = self.settings
        T_l, T_r = self.hand_frames()
        # the limits and posture tasks move the initial posture a little; let that
        # happen before anything is recorded, then settle again with the rest hand targets
        # that the generator uses (trunk-relative), so the first recorded tick is at rest
        self.stand()
        n = int(round(max(self.PRESETTLE, s.profile.settle_time) / s.solver_dt))
        for _ in range(n):
            self.tick(0.0, None, T_l, T_r)
        T_trunk_inv = np.linalg.inv(self.trunk_frame())
        T_l, T_r = self.hand_frames()
        #: Rest hand frames relative to the (yaw-only) trunk frame.
        self.rest_hands = (T_trunk_inv @ T_l, T_trunk_inv @ T_r)
        for _ in range(n):
            T = self.trunk_frame()
            self.tick(0.0, None, T @ self.rest_hands[0], T @ self.rest_hands[1])
        self.stand()

    # -- placement ----------------------------------------------------------------------
    def feet_frames(self, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
        """Sole frames (left, right) on the floor for the robot pose ``pose``."""
        return footsteps.feet_frames(pose, self.settings)

    def _place(self, pose: Pose) -> None:
        robot = self.robot
        robot.update_kinematics()
        T_l, T_r = robot.get_T_world_left(), robot.get_T_world_right()
        mid = pose_matrix(*planar(0.5 * (T_l + T_r)))
        mid[:3, :3] = pose_matrix(0, 0, planar(T_l)[2])[:3, :3]
        want_l, want_r = self.feet_frames(pose)
        want = 0.5 * (want_l + want_r)
        want[:3, :3] = want_l[:3, :3]
        robot.set_T_world_fbase(want @ np.linalg.inv(mid) @ robot.get_T_world_fbase())
        robot.update_kinematics()
        # the support frame used by ensure_on_floor() must follow the relocation
        side = str(robot.get_support_side())
        robot.set_T_world_support(want_l if side == "left" else want_r)
        self.T_left, self.T_right = want_l, want_r

    def robot_pose(self) -> Pose:
        """Commanded robot pose: from the commanded sole frames."""
        return footsteps.stance_pose(self.T_left, self.T_right, self.settings)

    def trunk_frame(self) -> np.ndarray:
        """Current trunk frame reduced to its position and yaw."""
        T = self.robot.get_T_world_frame("trunk")
        x, y, yaw = planar(T)
        return pose_matrix(x, y, yaw, T[2, 3])

    def com(self) -> np.ndarray:
        """Current centre of mass (world)."""
        return np.array(self.robot.com_world())

    def q(self) -> np.ndarray:
        """Current pinocchio configuration."""
        return np.array(self.robot.state.q)

    def hand_frames(self) -> tuple[np.ndarray, np.ndarray]:
        """Current hand frames (left, right)."""
        return (np.array(self.robot.get_T_world_frame("left_hand")),
                np.array(self.robot.get_T_world_frame("right_hand")))

    # -- modes --------------------------------------------------------------------------
    def stand(self) -> np.ndarray:
        """Hold the feet at the commanded sole frames and the CoM where it is; return the CoM."""
        t = self.tasks
        t.left_foot_task.T_world_frame = self.T_left
        t.right_foot_task.T_world_frame = self.T_right
        com = self.com()
        mid = 0.5 * (self.T_left[:3, 3] + self.T_right[:3, 3])
        target = np.array([mid[0], mid[1], self.settings.com_height])
        if np.linalg.norm(com[:2] - target[:2]) > 0.01:
            target[:2] = com[:2]
        t.com_task.target_world = target
        yaw = planar(self.T_left)[2]
        yaw += 0.5 * wrap_angle(planar(self.T_right)[2] - yaw)
        t.trunk_orientation_task.R_world_frame = rot_z(yaw)
        self._stand_com = target
        return target

    def plan_footsteps(self, targets: list[Pose]) -> list:
        """Footsteps (PlaCo naive planner) from the commanded feet through robot poses ``targets``.

        The list starts with the two current feet (flying foot first), as PlaCo's
        ``make_supports`` expects; it is empty when no step is needed.
        """
        placo = self._placo
        planner = placo.FootstepsPlannerNaive(self.params)
        T_l, T_r = self.T_left, self.T_right
        steps: list = []
        last_side = None
        for pose in targets:
            want_l, want_r = self.feet_frames(pose)
            if (np.allclose(want_l, T_l, atol=1e-4) and np.allclose(want_r, T_r, atol=1e-4)):
                continue
            left = (footsteps.left_flies_first(T_l, T_r, pose) if last_side is None
                    else last_side != "left")
            side = placo.HumanoidRobot_Side.left if left else placo.HumanoidRobot_Side.right
            planner.configure(want_l, want_r)
            fs = list(planner.plan(side, T_l, T_r))
            if len(fs) <= 2:
                continue
            steps.extend(fs if not steps else fs[2:])
            for f in fs[2:]:
                if str(f.side) == "left":
                    T_l = np.array(f.frame)
                else:
                    T_r = np.array(f.frame)
            last_side = str(fs[-1].side)
        return steps if len(steps) > 2 else []

    def path_footsteps(self, path: list[Pose], *, resolution: float = 0.01,
                       path_tol: float = 0.015) -> list:
        """PlaCo footsteps from the commanded feet along ``path``.

        See :func:`pivot_ompl.wholebody.footsteps.path_footsteps`.
        """
        return self._placo_footsteps(footsteps.path_footsteps(
            path, feet=(self.T_left, self.T_right), settings=self.settings,
            resolution=resolution, path_tol=path_tol))

    def pivot_footsteps(self, path: list[Pose], *, feet: tuple[np.ndarray, np.ndarray],
                        fly_left: bool | None = None, resolution: float = 0.005) -> list:
        """PlaCo footsteps from the sole frames ``feet`` (left, right) to ``path[-1]``.

        See :func:`pivot_ompl.wholebody.footsteps.pivot_footsteps`.
        """
        return self._placo_footsteps(footsteps.pivot_footsteps(
            path, feet=feet, settings=self.settings, fly_left=fly_left,
            resolution=resolution))

    def _placo_footsteps(self, steps: list[footsteps.Footstep]) -> list:
        return [self._footstep(f.left, f.frame) for f in steps]

    def _footstep(self, left: bool, frame: np.ndarray):  # noqa: ANN202 - a placo.Footstep
        """A PlaCo footstep of the left (or right) foot at sole frame ``frame``."""
        placo = self._placo
        f = placo.Footstep(self.params.foot_width, self.params.foot_length)
        f.side = placo.HumanoidRobot_Side.left if left else placo.HumanoidRobot_Side.right
        f.frame = frame
        return f

    def plan_walk(self, footsteps: list, t0: float) -> WindowedWalk:
        """LIPM/ZMP trajectory of a walk (footsteps led by the two current feet) from ``t0``.

        The commanded feet become the walk's final feet.
        """
        placo = self._placo
        supports = placo.FootstepsPlanner.make_supports(footsteps, t0, True,
                                                        self.params.has_double_support(), True)
        wpg = placo.WalkPatternGenerator(self.robot, self.params)
        traj = WindowedWalk(wpg, supports, self.com(), t0)
        for f in footsteps[-2:]:
            if str(f.side) == "left":
                self.T_left = np.array(f.frame)
            else:
                self.T_right = np.array(f.frame)
        return traj

    # -- one tick -----------------------------------------------------------------------
    def tick(self, t: float, walk: WindowedWalk | None, T_left_hand: np.ndarray,
             T_right_hand: np.ndarray) -> tuple[int, np.ndarray]:
        """Solve one tick at time ``t``; return (support code, planned ZMP xy).

        Raises:
            SolverFailure: the QP failed.
        """
        self.left_hand.T_world_frame = T_left_hand
        self.right_hand.T_world_frame = T_right_hand
        R, p = T_left_hand[:3, :3], T_left_hand[:3, 3]
        if self._relative_frame:
            rel = np.eye(4)  # inverse of the rigid left frame, times the right one
            rel[:3, :3] = R.T @ T_right_hand[:3, :3]
            rel[:3, 3] = R.T @ (T_right_hand[:3, 3] - p)
            self.hands.T_a_b = rel
        else:
            self.hands.target = R.T @ (T_right_hand[:3, 3] - p)
        held = False
        traj = walk.at(t) if walk is not None else None
        if traj is not None:
            self.tasks.update_tasks_from_trajectory(traj, t)
            held = self.swing.update(traj, t, self.tasks)
        # the kinematics are up to date: set-up and every tick end with update_kinematics
        self.damper.apply()
        try:
            self.solver.solve(True)
        except Exception as e:  # placo raises QPError / RuntimeError from C++
            raise SolverFailure(str(e) or type(e).__name__) from e
        if traj is None:
            self.robot.update_kinematics()
            return 0, self._stand_com[:2].copy()
        zmp = np.array(traj.get_p_world_ZMP(t, self.settings.omega))[:2]
        if traj.support_is_both(t):
            self.robot.update_kinematics()
            return 0, zmp
        side = str(traj.support_side(t))
        self.robot.update_support_side(side)
        self.robot.ensure_on_floor()
        self.robot.update_kinematics()
        if held:
            return 0, zmp
        return (1 if side == "left" else 2), zmp


def humanoid_parameters(settings: WalkSettings):  # noqa: ANN201 - a placo.HumanoidParameters
    """PlaCo's walk parameters from ``settings`` (the profile's sole, no trunk pitch)."""
    import placo

    s = settings
    P = placo.HumanoidParameters()
    P.single_support_duration = s.single_support_duration
    P.single_support_timesteps = s.single_support_timesteps
    P.double_support_ratio = s.double_support_ratio
    P.startend_double_support_ratio = s.startend_double_support_ratio
    P.planned_timesteps = 10_000
    P.walk_com_height = s.com_height
    P.walk_foot_height = s.foot_height
    P.walk_trunk_pitch = 0.0
    P.walk_foot_rise_ratio = 0.2
    P.foot_length, P.foot_width = s.profile.sole_size
    P.feet_spacing = s.feet_spacing
    P.zmp_margin = s.zmp_margin
    P.foot_zmp_target_x = 0.0
    P.foot_zmp_target_y = 0.0
    P.walk_max_dtheta = s.max_dtheta
    P.walk_max_dy = s.max_dy
    P.walk_max_dx_forward = s.max_dx_forward
    P.walk_max_dx_backward = s.max_dx_backward
    return P
