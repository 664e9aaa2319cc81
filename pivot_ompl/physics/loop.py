"""The simulation loop: the hands follow a motion's drive, the box moves through its contacts.

Per motion sample: the hands' welds are switched on when the motion starts holding the box
(anchored where the box really is: the hands grip the box where they find it, its planar
offset from the plan kept) and off when it lets go; the mocap hands are set to the sample's
frames; MuJoCo steps ``substeps`` times; the box pose, the hands' forces, the pivot corner's
force and slip, and any obstacle contact are recorded (:class:`RunTrace`).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.physics.backend import mujoco
from pivot_ompl.physics.contacts import PivotMeasure, box_contacts, corner_force, weld_forces
from pivot_ompl.physics.drive import DriveSignals, rotations_xyzw, yaw_of
from pivot_ompl.physics.model import PhysicsModel
from pivot_ompl.physics.perturb import Perturbations, Slip

log = logging.getLogger(__name__)

#: Samples between two polls of ``should_stop``.
POLL_SAMPLES = 200
#: Contacts with one obstacle less than this apart (s) are one touch.
TOUCH_GAP = 0.5
#: Share of the box's weight below which a corner's force ratio is not counted.
MIN_NORMAL_SHARE = 0.05


def rot_z(a: float) -> np.ndarray:
    """3x3 rotation about z by ``a`` (rad)."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass
class PivotRecord:
    """One simulated pivot rotation (see :class:`~pivot_ompl.physics.contacts.PivotMeasure`).

    Attributes:
        index: rotation number in the run (0 first); phase, step: in its plan.
        time: when it started (s, run time).
        pivot: the planned pivot corner (x, y).
        friction: the floor's friction coefficient at the corner.
        friction_median, friction_peak: median and largest horizontal/vertical force ratio
            at the corner (loaded samples; the peak cannot exceed ``friction``).
        at_limit: share of the loaded samples at the friction limit (the corner sliding).
        normal_max: largest normal force at the corner (N).
        corner_slip: how far the corner moved on the floor during the rotation (m).
        slip: the slip applied there, if any.
    """

    index: int
    phase: int
    step: int
    time: float
    pivot: tuple[float, float]
    friction: float
    friction_median: float
    friction_peak: float
    at_limit: float
    normal_max: float
    corner_slip: float
    slip: Slip | None = None


@dataclass
class RunTrace:
    """What a run recorded, sample by sample (lists of per-motion arrays, concatenated later).

    Attributes:
        t: run time of each sample (s).
        sim_pos, sim_yaw: the simulated box centre and heading.
        plan_pos, plan_yaw: the planned ones (of the motion being followed).
        sim_quat: the simulated box orientation (w x y z).
        hand_force_max: the largest weld force per hand (N).
        pivots: the rotations done.
        obstacle_contacts: the box's touches of obstacles: ``[start, end, obstacle index,
            deepest penetration m]`` (contacts less than :data:`TOUCH_GAP` s apart are one).
    """

    t: list[np.ndarray] = field(default_factory=list)
    sim_pos: list[np.ndarray] = field(default_factory=list)
    sim_quat: list[np.ndarray] = field(default_factory=list)
    plan_pos: list[np.ndarray] = field(default_factory=list)
    plan_yaw: list[np.ndarray] = field(default_factory=list)
    hand_force_max: list[float] = field(default_factory=lambda: [0.0, 0.0])
    pivots: list[PivotRecord] = field(default_factory=list)
    obstacle_contacts: list[list[float]] = field(default_factory=list)

    def touch(self, t: float, obstacle: int, depth: float) -> None:
        """Count a contact with ``obstacle`` at ``t``: a new touch, or the last one going on."""
        for c in reversed(self.obstacle_contacts):
            if int(c[2]) == obstacle and t - c[1] <= TOUCH_GAP:
                c[1], c[3] = t, max(c[3], depth)
                return
        self.obstacle_contacts.append([t, t, float(obstacle), max(depth, 0.0)])

    def arrays(self) -> dict[str, np.ndarray]:
        """The per-sample arrays concatenated: t, sim_pos, sim_yaw, sim_quat, plan_pos, plan_yaw."""
        if not self.t:
            z = np.zeros((0, 3))
            return dict(t=np.zeros(0), sim_pos=z, sim_yaw=np.zeros(0), sim_quat=np.zeros((0, 4)),
                        plan_pos=z, plan_yaw=np.zeros(0))
        q = np.concatenate(self.sim_quat)
        R = rotations_xyzw(np.column_stack([q[:, 1:], q[:, 0]]))
        return dict(t=np.concatenate(self.t), sim_pos=np.concatenate(self.sim_pos),
                    sim_yaw=yaw_of(R), sim_quat=q, plan_pos=np.concatenate(self.plan_pos),
                    plan_yaw=np.concatenate(self.plan_yaw))


class Simulator:
    """The box, the floor and the hands of one run (the model persists across motions).

    Args:
        pm: the compiled model.
        perturbations: friction patches and slips (the mass offset is in the model).
    """

    def __init__(self, pm: PhysicsModel, *, perturbations: Perturbations | None = None) -> None:
        self.pm = pm
        self.mj = mujoco()
        self.perturb = perturbations or Perturbations()
        self.time = 0.0
        self.pivot_count = 0
        self.held = False
        self._mu = pm.friction
        self._min_normal = MIN_NORMAL_SHARE * pm.mass * 9.81

    def place_box(self, pos: np.ndarray, quat_wxyz: np.ndarray) -> None:
        """Put the box at a pose, at rest."""
        d = self.pm.data
        d.qpos[:3] = pos
        d.qpos[3:7] = quat_wxyz
        d.qpos[7:] = 0.0
        d.qvel[:] = 0.0
        self.mj.mj_forward(self.pm.model, d)

    def box_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """The box's centre (3,) and rotation (3, 3) now."""
        d = self.pm.data
        b = self.pm.box_body
        return d.xpos[b].copy(), d.xmat[b].reshape(3, 3).copy()

    def planar_pose(self) -> tuple[float, float, float]:
        """The box's (x, y, yaw) now."""
        p, R = self.box_pose()
        return float(p[0]), float(p[1]), float(yaw_of(R))

    def _anchor(self, hand_pos: np.ndarray, hand_R: np.ndarray, target_pos: np.ndarray,
                target_R: np.ndarray) -> None:
        """Set both welds so that they hold the box at ``target`` from the hands' frames."""
        m = self.pm.model
        rel_R = hand_R.T @ target_R
        quat = np.zeros(4)
        self.mj.mju_mat2Quat(quat, rel_R.reshape(-1))
        for h, w in enumerate(self.pm.welds):
            m.eq_data[w, 0:3] = 0.0
            m.eq_data[w, 3:6] = hand_R.T @ (target_pos - hand_pos[h])
            m.eq_data[w, 6:10] = quat

    def _grip(self, drive: DriveSignals, i: int, slip: Slip | None = None,
              about: np.ndarray | None = None) -> None:
        """Grip the box where it is (its planar offset from the plan at sample ``i`` kept)."""
        p, R = self.box_pose()
        dyaw = float(yaw_of(R) - drive.box_yaw[i])
        target_R = rot_z(dyaw) @ drive.box_rot[i]
        target_p = drive.box_pos[i].copy()
        target_p[:2] = p[:2]
        if slip is not None and about is not None:
            Rs = rot_z(slip.dyaw)
            target_p[:2] = (Rs[:2, :2] @ (target_p[:2] - about[:2]) + about[:2]
                            + (slip.dx, slip.dy))
            target_R = Rs @ target_R
        d = self.pm.data
        d.qpos[7:9] = 0.0  # the hands' slides back to their mocap bodies
        d.qvel[6:8] = 0.0
        self._anchor(drive.hand_pos[i], drive.box_rot[i], target_p, target_R)
        self.pm.data.eq_active[list(self.pm.welds)] = 1
        self.held = True

    def _release(self) -> None:
        self.pm.data.eq_active[list(self.pm.welds)] = 0
        self.held = False

    def follow(self, drive: DriveSignals, trace: RunTrace, *, start: int = 0,
               end: int | None = None,
               should_stop: Callable[[], bool] | None = None) -> int:
        """Simulate samples ``start..end`` (inclusive) of ``drive``; return the last one done.

        Stops early (returning the sample reached) when ``should_stop()`` says so.
        """
        pm, mj = self.pm, self.mj
        m, d = pm.model, pm.data
        end = drive.n - 1 if end is None else end
        dt = float(np.median(np.diff(drive.t))) if drive.n > 1 else m.opt.timestep
        sub = max(1, int(math.ceil(dt / m.opt.timestep - 1e-9)))
        m.opt.timestep = dt / sub
        pivot_of = {s.start: s for s in drive.pivots}
        n = end - start + 1
        t0 = self.time - drive.t[start]
        sim_pos, sim_quat = np.zeros((n, 3)), np.zeros((n, 4))
        seg, meas, rec_slip = None, None, None
        obstacles = np.array(sorted(pm.obstacle_geoms), dtype=int)
        b = pm.box_body
        done = start - 1
        for j, i in enumerate(range(start, end + 1)):
            if should_stop is not None and j % POLL_SAMPLES == 0 and j and should_stop():
                break
            if drive.holding[i] and not self.held:
                self._grip(drive, i)
            elif not drive.holding[i] and self.held:
                self._release()
            if i in pivot_of:
                seg = pivot_of[i]
                meas = PivotMeasure(self._min_normal)
                rec_slip = self.perturb.slip_at(self.pivot_count)
                if rec_slip is not None and self.held:
                    self._grip(drive, i, rec_slip, about=np.array([*seg.pivot, 0.0]))
            if self.perturb.patches and j % 10 == 0:
                x, y = d.xpos[b, 0], d.xpos[b, 1]
                mu = self.perturb.friction_at(float(x), float(y), pm.friction)
                if mu != self._mu:
                    m.geom_friction[pm.box_geom, 0] = self._mu = mu
            d.mocap_pos[:] = drive.hand_pos[i]
            d.mocap_quat[:] = drive.hand_quat[i]
            mj.mj_step(m, d, sub)
            sim_pos[j] = d.xpos[b]
            sim_quat[j] = d.xquat[b]
            if self.held:
                fl, fr = weld_forces(pm, mj)
                trace.hand_force_max[0] = max(trace.hand_force_max[0], fl)
                trace.hand_force_max[1] = max(trace.hand_force_max[1], fr)
            if seg is not None or len(obstacles):
                con = box_contacts(pm)
                if len(obstacles):
                    for g, depth in zip(con.other, con.depth, strict=True):
                        if int(g) in pm.obstacle_geoms:
                            trace.touch(float(t0 + drive.t[i]), pm.obstacle_geoms[int(g)],
                                        float(depth))
                if seg is not None and meas is not None:
                    R = d.xmat[b].reshape(3, 3)
                    corner = R @ seg.corner + d.xpos[b]
                    meas.add(corner, corner_force(con.pos, con.force, corner))
                    if i == seg.end:
                        trace.pivots.append(PivotRecord(
                            self.pivot_count, seg.phase, seg.step,
                            float(t0 + drive.t[seg.start]), seg.pivot, self._mu,
                            *meas.friction(self._mu), meas.normal_max, meas.corner_slip,
                            rec_slip))
                        self.pivot_count += 1
                        seg, meas = None, None
            done = i
        k = done - start + 1
        trace.t.append(t0 + drive.t[start:done + 1])
        trace.sim_pos.append(sim_pos[:k])
        trace.sim_quat.append(sim_quat[:k])
        trace.plan_pos.append(drive.box_pos[start:done + 1])
        trace.plan_yaw.append(drive.box_yaw[start:done + 1])
        if done >= start:
            self.time = float(t0 + drive.t[done] + dt)
        return done
