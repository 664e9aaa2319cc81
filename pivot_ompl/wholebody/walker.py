"""PlaCo whole-body controller for HRP-2: walk pattern generator, kinematics solver and tasks.

Tasks (PlaCo ``KinematicsSolver``, one QP per tick of :attr:`WalkSettings.dt`):

* feet and CoM -- **hard** (``WalkTasks`` with ``scaled = False``), tracking the LIPM/ZMP walk
  pattern generator's trajectory, or fixed targets while standing;
* trunk orientation -- soft, from the walk trajectory (yaw between the feet);
* both hands -- soft frame tasks (position weight 1, low orientation weight) tracking targets
  given every tick, plus a soft hand-to-hand relative frame task;
* posture -- a weak joints task towards half-sitting with bent elbows; a small regularisation;
* joint position and velocity limits -- solver constraints.

Robot pose convention: the plan's robot pose (centre of the floor bounding box, heading) is the
midpoint of the two sole centres, shifted :attr:`WalkSettings.foot_offset` along the heading.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from pivot_ompl import hrp2
from pivot_ompl.hrp2 import HALF_SITTING, SOLE_SIZE, urdf_path
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.wholebody.box import rot_z, transform
from pivot_ompl.wholebody.lipm import omega

log = logging.getLogger(__name__)

#: The sole's corners in its own frame (homogeneous columns).
_SOLE_CORNERS = np.array([[x, y, 0.0, 1.0] for x in (0.5 * SOLE_SIZE[0], -0.5 * SOLE_SIZE[0])
                          for y in (0.5 * SOLE_SIZE[1], -0.5 * SOLE_SIZE[1])]).T


@dataclass(frozen=True)
class WalkSettings:
    """Walking and solver parameters (SI units).

    Attributes:
        dt: solver tick and motion sampling period (s).
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
            (:meth:`PlacoWalker.plan_footsteps`, walks to a transfer's start) (m, rad).
        zmp_margin: ZMP margin inside the sole kept by the pattern generator (m).
        foot_offset: sole midpoint ahead of the robot pose centre (m).
        hand_position_weight, hand_orientation_weight: hand frame task weights.
        relative_weight: hand-to-hand relative task position weight.
        relative_orientation_weight: hand-to-hand relative task orientation weight.
        posture_weight: posture (joints) task weight.
        foot_dy_out: how far a foot may land outside its nominal place beside the support
            foot (m; :meth:`PlacoWalker.pivot_footsteps` and :meth:`path_footsteps`): the
            feet at most ``feet_spacing + foot_dy_out`` apart (0.38 m: 9 deg of hip roll per
            leg, of HRP-2's 35 deg outward).
        foot_dy_in: same, inside: the feet at least ``feet_spacing - foot_dy_in`` apart
            (and the soles at least :attr:`sole_gap` apart).
        foot_dtheta: largest yaw between the two feet (rad; 0.40 rad is split between the
            two hip yaw joints, each limited to 30 deg inward).
        sole_gap: least gap between the two sole rectangles (m).
    """

    dt: float = 0.005
    single_support_duration: float = 0.7
    single_support_timesteps: int = 14
    double_support_ratio: float = 0.2
    startend_double_support_ratio: float = 1.0
    com_height: float = 0.79
    foot_height: float = 0.04
    feet_spacing: float = 0.20
    max_dx_forward: float = hrp2.STEP_FORWARD
    max_dx_backward: float = hrp2.STEP_BACKWARD
    max_dy: float = hrp2.STEP_LATERAL
    max_dtheta: float = hrp2.STEP_TURN
    zmp_margin: float = 0.03
    foot_offset: float = 0.0
    hand_position_weight: float = 1000.0
    hand_orientation_weight: float = 0.01
    relative_weight: float = 0.1
    relative_orientation_weight: float = 0.0
    posture_weight: float = 1e-3
    foot_dy_out: float = 0.18
    foot_dy_in: float = 0.03
    foot_dtheta: float = 0.40
    sole_gap: float = 0.02

    @property
    def omega(self) -> float:
        """LIPM natural frequency sqrt(g / com_height) (1/s)."""
        return omega(self.com_height)


def pose_matrix(x: float, y: float, yaw: float, z: float = 0.0) -> np.ndarray:
    """4x4 transform of a planar pose."""
    return transform(rot_z(yaw), (x, y, z))


def planar(T: np.ndarray) -> Pose:
    """Planar pose (x, y, yaw) of a 4x4 transform."""
    return (float(T[0, 3]), float(T[1, 3]), math.atan2(T[1, 0], T[0, 0]))


#: Posture targets of the upper body: chest and head upright, upper arms slightly inward
#: (shoulder roll 0.15 rad) and elbows bent 0.9 rad, so that the arms stay inside the 0.70 m
#: wide floor box while the trunk sways over the feet.
UPPER_POSTURE = {k: v for k, v in HALF_SITTING.items() if not k.startswith(("RLEG", "LLEG"))}
UPPER_POSTURE.update({"RARM_JOINT0": 0.15, "LARM_JOINT0": 0.15, "RARM_JOINT1": 0.15,
                      "LARM_JOINT1": -0.15, "RARM_JOINT3": -0.5, "LARM_JOINT3": -0.5})


class SolverFailure(RuntimeError):
    """The QP of one tick failed (infeasible or numerical failure)."""


class PlacoWalker:
    """HRP-2 in PlaCo, stepping one solver tick at a time (see the module docstring).

    Args:
        settings: walking and solver parameters.
        start: robot pose (x, y, heading) to stand at in half-sitting.
    """

    def __init__(self, settings: WalkSettings, start: Pose) -> None:
        import placo

        self._placo = placo
        self.settings = s = settings
        robot = placo.HumanoidRobot(str(urdf_path()), placo.Flags.ignore_collisions)
        self.robot = robot
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
        P.foot_length = SOLE_SIZE[0]
        P.foot_width = SOLE_SIZE[1]
        P.feet_spacing = s.feet_spacing
        P.zmp_margin = s.zmp_margin
        P.foot_zmp_target_x = 0.0
        P.foot_zmp_target_y = 0.0
        P.walk_max_dtheta = s.max_dtheta
        P.walk_max_dy = s.max_dy
        P.walk_max_dx_forward = s.max_dx_forward
        P.walk_max_dx_backward = s.max_dx_backward
        self.params = P

        solver = placo.KinematicsSolver(robot)
        solver.dt = s.dt
        self.solver = solver
        tasks = placo.WalkTasks()
        tasks.scaled = False
        tasks.initialize_tasks(solver, robot)
        self.tasks = tasks

        for name, value in HALF_SITTING.items():
            robot.set_joint(name, value)
        for name, value in UPPER_POSTURE.items():
            robot.set_joint(name, value)
        robot.update_kinematics()
        tasks.reach_initial_pose(np.eye(4), s.feet_spacing, s.com_height, 0.0)
        for name, task in (("left_foot", tasks.left_foot_task),
                           ("right_foot", tasks.right_foot_task)):
            task.configure(name, "hard", 1.0, 1.0)
        tasks.com_task.configure("com", "hard", 1.0)
        solver.enable_velocity_limits(True)
        solver.enable_joint_limits(True)

        posture = solver.add_joints_task()
        posture.set_joints(dict(UPPER_POSTURE))
        posture.configure("posture", "soft", s.posture_weight)
        legs = {k: v for k, v in HALF_SITTING.items() if k.startswith(("RLEG", "LLEG"))}
        leg_posture = solver.add_joints_task()
        leg_posture.set_joints(legs)
        leg_posture.configure("leg_posture", "soft", 1e-5)
        solver.add_regularization_task(1e-6)

        self._place(start)
        T_l = robot.get_T_world_frame("left_hand")
        T_r = robot.get_T_world_frame("right_hand")
        self.left_hand = solver.add_frame_task("left_hand", T_l)
        self.left_hand.configure("left_hand", "soft", s.hand_position_weight,
                                 s.hand_orientation_weight)
        self.right_hand = solver.add_frame_task("right_hand", T_r)
        self.right_hand.configure("right_hand", "soft", s.hand_position_weight,
                                  s.hand_orientation_weight)
        self.hands = solver.add_relative_frame_task("left_hand", "right_hand",
                                                    np.linalg.inv(T_l) @ T_r)
        self.hands.configure("hands", "soft", s.relative_weight, s.relative_orientation_weight)
        # settle: the limits and posture tasks move the initial posture a little; let that
        # happen before anything is recorded, then settle again with the rest hand targets
        # that the generator uses (trunk-relative), so the first recorded tick is at rest
        self.stand()
        n = int(round(self.PRESETTLE / s.dt))
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

    #: Unrecorded standing time after set-up (s).
    PRESETTLE = 0.5

    # -- placement ----------------------------------------------------------------------
    def feet_frames(self, pose: Pose) -> tuple[np.ndarray, np.ndarray]:
        """Sole frames (left, right) on the floor for the robot pose ``pose``."""
        s = self.settings
        c, sn = math.cos(pose[2]), math.sin(pose[2])
        mx, my = pose[0] + s.foot_offset * c, pose[1] + s.foot_offset * sn
        half = 0.5 * s.feet_spacing
        return (pose_matrix(mx - half * sn, my + half * c, pose[2]),
                pose_matrix(mx + half * sn, my - half * c, pose[2]))

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
        mid = 0.5 * (self.T_left + self.T_right)
        yaw = planar(self.T_left)[2]
        yaw2 = planar(self.T_right)[2]
        yaw = yaw + 0.5 * wrap_angle(yaw2 - yaw)
        off = self.settings.foot_offset
        return (mid[0, 3] - off * math.cos(yaw), mid[1, 3] - off * math.sin(yaw), yaw)

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
        footsteps: list = []
        last_side = None
        for pose in targets:
            want_l, want_r = self.feet_frames(pose)
            if (np.allclose(want_l, T_l, atol=1e-4) and np.allclose(want_r, T_r, atol=1e-4)):
                continue
            if last_side is None:
                cur = self._inv_pose(0.5 * (T_l + T_r), planar(T_l)[2])
                local = cur @ np.array([pose[0], pose[1], 0.0, 1.0])
                dyaw = wrap_angle(pose[2] - planar(T_l)[2])
                left_first = local[1] > 1e-3 or (abs(local[1]) <= 1e-3 and dyaw >= 0)
                side = placo.HumanoidRobot_Side.left if left_first else \
                    placo.HumanoidRobot_Side.right
            else:
                side = (placo.HumanoidRobot_Side.right if last_side == "left"
                        else placo.HumanoidRobot_Side.left)
            planner.configure(want_l, want_r)
            fs = list(planner.plan(side, T_l, T_r))
            if len(fs) <= 2:
                continue
            footsteps.extend(fs if not footsteps else fs[2:])
            for f in fs[2:]:
                if str(f.side) == "left":
                    T_l = np.array(f.frame)
                else:
                    T_r = np.array(f.frame)
            last_side = str(fs[-1].side)
        return footsteps if len(footsteps) > 2 else []

    def path_footsteps(self, path: list[Pose], *, resolution: float = 0.01,
                       path_tol: float = 0.015) -> list:
        """Footsteps that follow ``path`` (robot poses joined by straight lines, linear yaw).

        Each step lands the flying foot at its nominal place beside the furthest pose along
        the path that it reaches from the support foot: relative to its nominal place beside
        the support foot, in the ellipsoid of :attr:`WalkSettings.max_dx_forward` /
        ``max_dx_backward`` (along), ``foot_dy_out`` (outside) and ``foot_dtheta`` (yaw),
        at most ``foot_dy_in`` inside and the soles ``sole_gap`` apart, and the sole
        midpoint of the double support that follows within ``path_tol`` (m) of the path
        (corners are not cut). A last step brings the feet together at the path's end.
        The list starts with the two current feet, as PlaCo's ``make_supports`` expects; it
        is empty when no step is needed.
        """
        dense = _densify([self.robot_pose(), *path], resolution)
        cur = dense[0]
        T_l, T_r = self.T_left, self.T_right
        # first flying foot: the side the path leaves towards (or turns towards)
        fly_left = True
        for pose in dense[1:]:
            dx, dy, dth = _relative(cur, pose)
            if abs(dy) > 0.02 or abs(dth) > 0.05:
                fly_left = dy > 0 if abs(dy) > 0.02 else dth > 0
                break
            if abs(dx) > 0.05:
                break

        steps = [self._footstep(fly_left, T_l if fly_left else T_r),
                 self._footstep(not fly_left, T_r if fly_left else T_l)]
        feet = {True: np.array(T_l), False: np.array(T_r)}
        beside = {True: 0, False: 0}  # index of the dense pose each foot stands beside
        i = 0
        while i < len(dense) - 1:
            j = i
            while j + 1 < len(dense):
                cand = self.feet_frames(dense[j + 1])[0 if fly_left else 1]
                if not self._reachable(cand, feet[not fly_left], left=fly_left,
                                       ellipsoid=True):
                    break
                # the sole midpoint of the double support that follows stays on the path
                mid = 0.5 * (cand[:2, 3] + feet[not fly_left][:2, 3])
                near = dense[beside[not fly_left]:j + 2]
                if min(math.hypot(mid[0] - q[0], mid[1] - q[1]) for q in near) > path_tol:
                    break
                j += 1
            if j == i:  # resolution too coarse for the limits: force progress
                j = i + 1
            cur, i = dense[j], j
            want_l, want_r = self.feet_frames(cur)
            feet[fly_left], beside[fly_left] = (want_l if fly_left else want_r), j
            steps.append(self._footstep(fly_left, feet[fly_left]))
            fly_left = not fly_left
        if len(steps) == 2:
            return []
        want_l, want_r = self.feet_frames(cur)
        last = want_l if fly_left else want_r
        prev = T_l if fly_left else T_r
        for f in steps[2:]:
            if (str(f.side) == "left") == fly_left:
                prev = np.array(f.frame)
        if not np.allclose(prev, last, atol=1e-4):
            steps.append(self._footstep(fly_left, last))
        return steps

    def pivot_footsteps(self, path: list[Pose], *, feet: tuple[np.ndarray, np.ndarray],
                        fly_left: bool | None = None, resolution: float = 0.005) -> list:
        """Fewest footsteps from the sole frames ``feet`` (left, right) to ``path[-1]``.

        Each foot lands at its nominal place beside a pose along ``path``, which runs from
        the robot's pose to its pose after a pivot rotation (the arc its attached pose
        describes about the pivot). Each step lands the flying foot at its
        nominal place beside the furthest pose along the path that the support foot can
        reach: landing within :attr:`WalkSettings.max_dx_forward` / ``max_dx_backward``
        along and ``foot_dy_out`` / ``foot_dy_in`` across the foot's nominal place beside
        the support foot, turned at most ``foot_dtheta`` from it, the soles
        ``sole_gap`` apart. Unlike :meth:`path_footsteps` the robot need not stand at
        each intermediate pose, only both feet at the end's, so a pivot takes two or three
        steps. ``fly_left`` forces the first flying foot (a walk alternates its feet).

        Returns the footsteps led by the two given feet (flying foot first), as
        ``make_supports`` expects; empty when no step is needed or when no sequence of at
        most 8 steps reaches the end (the caller then walks with :meth:`path_footsteps`).
        """
        dense = _densify(list(path), resolution)
        nominal = [self.feet_frames(q) for q in dense]
        goal_l, goal_r = nominal[-1]
        T = {True: np.array(feet[0]), False: np.array(feet[1])}
        if (np.allclose(T[True], goal_l, atol=1e-4) and np.allclose(T[False], goal_r, atol=1e-4)):
            return []
        if fly_left is None:
            dx, dy, dth = _relative(dense[0], dense[-1])
            fly_left = dy > 0 if abs(dy) > 0.02 else dth >= 0

        steps = [self._footstep(fly_left, T[fly_left]),
                 self._footstep(not fly_left, T[not fly_left])]
        side = fly_left
        for _ in range(8):
            landing = None
            for k in range(len(dense) - 1, -1, -1):
                cand = nominal[k][0 if side else 1]
                if self._reachable(cand, T[not side], left=side):
                    landing = cand
                    break
            if landing is None:
                return []
            T[side] = landing
            steps.append(self._footstep(side, landing))
            side = not side
            if (np.allclose(T[True], goal_l, atol=1e-4)
                    and np.allclose(T[False], goal_r, atol=1e-4)):
                return steps
        return []

    def _footstep(self, left: bool, frame: np.ndarray):  # noqa: ANN202 - a placo.Footstep
        """A PlaCo footstep of the left (or right) foot at sole frame ``frame``."""
        placo = self._placo
        f = placo.Footstep(self.params.foot_width, self.params.foot_length)
        f.side = placo.HumanoidRobot_Side.left if left else placo.HumanoidRobot_Side.right
        f.frame = frame
        return f

    def _reachable(self, T_fly: np.ndarray, T_support: np.ndarray, *, left: bool,
                   ellipsoid: bool = False) -> bool:
        """Whether a foot can land at ``T_fly`` beside the support foot ``T_support``.

        Relative to the foot's nominal place beside the support foot: along within
        ``max_dx_forward`` / ``max_dx_backward``, outside within ``foot_dy_out``, yaw within
        ``foot_dtheta`` (each alone, or together in their ellipsoid with ``ellipsoid``);
        inside at most ``foot_dy_in``; the soles at least ``sole_gap`` apart.
        """
        s = self.settings
        sign = 1.0 if left else -1.0
        rel = np.linalg.inv(T_support) @ T_fly
        dx = float(rel[0, 3])
        dy = sign * (float(rel[1, 3]) - sign * s.feet_spacing)  # > 0: outside
        dth = abs(math.atan2(rel[1, 0], rel[0, 0]))
        if not (-s.max_dx_backward <= dx <= s.max_dx_forward):
            return False
        if not (-s.foot_dy_in <= dy <= s.foot_dy_out) or dth > s.foot_dtheta:
            return False
        if ellipsoid:
            dx_max = s.max_dx_forward if dx >= 0 else s.max_dx_backward
            if ((dx / dx_max) ** 2 + (max(dy, 0.0) / s.foot_dy_out) ** 2
                    + (dth / s.foot_dtheta) ** 2) > 1.0:
                return False
        # soles apart: the flying sole's corners beyond the support sole's inner side
        # and the support sole's corners beyond the flying sole's, by the gap
        hy = 0.5 * SOLE_SIZE[1]
        a = sign * (rel @ _SOLE_CORNERS)[1]
        b = -sign * (np.linalg.inv(rel) @ _SOLE_CORNERS)[1]
        return bool(a.min() >= hy + s.sole_gap and b.min() >= hy + s.sole_gap)

    @staticmethod
    def chunks(footsteps: list, max_steps: int) -> list[list]:
        """Split footsteps into walks of at most ``max_steps`` steps.

        Each walk is led by its two current feet and starts and ends at rest.
        """
        moves = len(footsteps) - 2
        out = []
        for a in range(0, moves, max_steps):
            b = min(moves, a + max_steps)
            out.append(footsteps[a:b + 2])
        return out

    def plan_walk(self, footsteps: list, t0: float):  # noqa: ANN201 - placo type
        """LIPM/ZMP trajectory of a walk (footsteps led by the two current feet) from ``t0``.

        The commanded feet become the walk's final feet.
        """
        placo = self._placo
        supports = placo.FootstepsPlanner.make_supports(footsteps, t0, True,
                                                        self.params.has_double_support(), True)
        wpg = placo.WalkPatternGenerator(self.robot, self.params)
        traj = wpg.plan(supports, self.com(), t0)
        for f in footsteps[-2:]:
            if str(f.side) == "left":
                self.T_left = np.array(f.frame)
            else:
                self.T_right = np.array(f.frame)
        return traj

    @staticmethod
    def _inv_pose(T: np.ndarray, yaw: float) -> np.ndarray:
        M = pose_matrix(T[0, 3], T[1, 3], yaw)
        return np.linalg.inv(M)

    # -- one tick -----------------------------------------------------------------------
    def tick(self, t: float, traj, T_left_hand: np.ndarray,  # noqa: ANN001
             T_right_hand: np.ndarray) -> tuple[int, np.ndarray]:
        """Solve one tick at time ``t``; return (support code, planned ZMP xy).

        Raises:
            SolverFailure: the QP failed.
        """
        self.left_hand.T_world_frame = T_left_hand
        self.right_hand.T_world_frame = T_right_hand
        self.hands.T_a_b = np.linalg.inv(T_left_hand) @ T_right_hand
        held = False
        if traj is not None:
            self.tasks.update_tasks_from_trajectory(traj, t)
            held = self._delay_lift_off(traj, t)
        self.robot.update_kinematics()
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

    def _delay_lift_off(self, traj, t: float) -> bool:  # noqa: ANN001
        """Hold the swing foot down for :attr:`lift_off_delay` after a single support starts.

        The swing trajectory is then played time-compressed into the rest of the support.
        The pattern generator constrains the ZMP only at its LIPM samples: it reaches the new
        support foot one sample after the double support ends. Holding the swing foot down
        meanwhile keeps that ZMP transfer inside a real double support polygon.
        Returns whether the swing foot is held (both feet in contact).
        """
        if traj.support_is_both(t):
            return False
        t0, t1 = traj.get_part_t_start(t), traj.get_part_t_end(t)
        delay = self.lift_off_delay
        if t1 - t0 <= 2 * delay:
            return False
        swing = "right" if str(traj.support_side(t)) == "left" else "left"
        if t - t0 < delay:
            tau, held = t0, True
        else:
            tau, held = t0 + (t - t0 - delay) * (t1 - t0) / (t1 - t0 - delay), False
        T = traj.get_T_world_right(tau) if swing == "right" else traj.get_T_world_left(tau)
        task = self.tasks.right_foot_task if swing == "right" else self.tasks.left_foot_task
        task.T_world_frame = T
        return held

    @property
    def lift_off_delay(self) -> float:
        """Time the swing foot stays down after a single support starts (s)."""
        s = self.settings
        return s.single_support_duration / s.single_support_timesteps + 2.5 * s.dt


def _relative(a: Pose, b: Pose) -> tuple[float, float, float]:
    """Pose ``b`` in the frame of pose ``a`` (dx, dy, dyaw)."""
    c, sn = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return (c * dx + sn * dy, -sn * dx + c * dy, wrap_angle(b[2] - a[2]))


def _densify(path: list[Pose], resolution: float) -> list[Pose]:
    """Poses along ``path`` (straight lines, yaw linear the shorter way).

    Consecutive poses are at most ``resolution`` m (or ``2 * resolution`` rad) apart.
    """
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:], strict=True):
        dth = wrap_angle(b[2] - a[2])
        n = max(1, math.ceil(max(math.hypot(b[0] - a[0], b[1] - a[1]),
                                 0.5 * abs(dth)) / resolution))
        for k in range(1, n + 1):
            u = k / n
            out.append((a[0] + u * (b[0] - a[0]), a[1] + u * (b[1] - a[1]), a[2] + u * dth))
    return out
