"""Pivot steps walked continuously: footsteps chained over pivots, rotation timing, checks."""

from __future__ import annotations

import logging

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.planfile import TransferPhase, TransferStep
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.wholebody.box import BoxHold, rotation_about_vertical
from pivot_ompl.wholebody.footsteps import planar
from pivot_ompl.wholebody.timeline import min_jerk
from pivot_ompl.wholebody.walker import PlacoWalker

log = logging.getLogger(__name__)


def check_pivot_steps(hold: BoxHold, phase: TransferPhase, i: int) -> None:
    """Raise InputError unless each step of phase ``i`` turns the box about a pivot corner.

    The pivot is an end corner of the supporting edge and the step's object pose is the
    previous one rotated about it by the step's angle.
    """
    k, obj = phase.grasp, phase.object_start
    for j, step in enumerate(phase.steps):
        corners = hold.pivot_corners(obj, k)
        piv = np.array([step.pivot[0], step.pivot[1], 0.0])
        if min(np.linalg.norm(c - piv) for c in corners) > 1e-4:
            raise InputError(f"phases[{i}].steps[{j}].pivot", step.pivot,
                             "is not an end corner of the supporting edge")
        R = rotation_about_vertical(step.pivot, step.angle)
        if np.abs(R @ hold.T_world_G(obj, k) - hold.T_world_G(step.object, k)).max() > 1e-4:
            raise InputError(f"phases[{i}].steps[{j}].object", step.object,
                             "is not the previous pose rotated about the pivot")
        obj = step.object


def pivot_arc(before: Pose, step: TransferStep, n: int = 8) -> list[Pose]:
    """The robot's attached pose turning about the pivot with the box (``n`` pieces)."""
    return [rotate_about(before, step.pivot, step.angle * u / n) for u in range(n + 1)]


def rotation_windows(traj, last: list[int], t0: float,  # noqa: ANN001 - a placo trajectory
                      dt: float) -> tuple[list[int], list[int]]:
    """Tick windows (starts, ends) of each pivot's rotation in a walk from ``t0``.

    Pivot ``p`` turns until the middle of the double support after landing its last
    footstep ``last[p]`` (support ``2 (n - 1)``), from the end of the previous one; the
    first waits for the walk's first step (the body does not follow the box while the CoM
    shifts in the starting double support).
    """
    supports = traj.get_supports()
    ends = []
    for n in last:
        a = 2 * (n - 1)
        t_a = supports[a].t_start
        t_b = supports[a + 1].t_start if a + 1 < len(supports) else traj.t_end
        ends.append(int(round((0.5 * (t_a + t_b) - t0) / dt)))
    first = int(round((supports[1].t_start - t0) / dt))
    return [min(first, ends[0] - 1), *ends[:-1]], ends


def turn_progress(traj, t: float, before: Pose, step: TransferStep,  # noqa: ANN001
                   s: float, *, follow_feet: float) -> float:
    """How far (0..1) the box has turned at time ``t`` of a pivot step.

    A share ``follow_feet`` (:attr:`Timing.follow_feet`) follows the planned feet: their
    mean yaw (which the trunk, and so the shoulders, follow) measured from ``before``
    towards the step's end; the rest is a minimum-jerk profile over the pivot's time ``s``.
    A step of (almost) no angle turns in time only.
    """
    if abs(step.angle) < 1e-3:
        return min_jerk(s)
    left = planar(np.array(traj.get_T_world_left(t)))[2]
    right = planar(np.array(traj.get_T_world_right(t)))[2]
    yaw = left + 0.5 * wrap_angle(right - left)
    feet = min(1.0, max(0.0, wrap_angle(yaw - before[2]) / step.angle))
    return follow_feet * feet + (1.0 - follow_feet) * min_jerk(s)


def object_before(phase: TransferPhase, j: int) -> Pose:
    """Object pose before pivot step ``j`` of ``phase``."""
    return phase.object_start if j == 0 else phase.steps[j - 1].object



def chain_pivot_footsteps(walker: PlacoWalker, phase: TransferPhase, j0: int,
                      robots: list[Pose], *, max_steps: int) -> tuple[list, list[int]]:
    """Footsteps of pivots ``j0, j0 + 1, ...`` chained in one walk, feet alternating.

    Returns the footsteps (led by the two current feet) and, per pivot, the index of
    its last landing; at most ``max_steps`` steps (:attr:`Timing.pivot_walk_steps`), up to the first
    pivot that needs no step or cannot be stepped so.
    """
    feet = (walker.T_left, walker.T_right)
    fly: bool | None = None
    footsteps: list = []
    last: list[int] = []  # index in footsteps of each pivot's last landing
    j = j0
    while j < len(phase.steps):
        fs = walker.pivot_footsteps(pivot_arc(robots[j], phase.steps[j]),
                                    feet=feet, fly_left=fly)
        if not fs or (footsteps and len(footsteps) + len(fs) - 4 > max_steps):
            break
        footsteps = fs if not footsteps else footsteps + fs[2:]
        last.append(len(footsteps) - 1)
        left = [np.array(f.frame) for f in fs if str(f.side) == "left"]
        right = [np.array(f.frame) for f in fs if str(f.side) == "right"]
        feet = (left[-1], right[-1])
        fly = str(fs[-1].side) != "left"
        j += 1
    return footsteps, last
