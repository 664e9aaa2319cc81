"""Segment durations and tolerances of the whole-body timeline, and its smooth profiles."""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from pivot_ompl.wholebody.box import transform

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class Timing:
    """Durations of the non-walking segments (s) and tolerances.

    Attributes:
        reach: hands from rest to the grip points.
        tilt: inclining (and, at the end, setting down) the box.
        release: hands from the grip points back to rest.
        settle: standing still before the motion starts.
        rotate_margin: the rotation of a pivot step starts this long after its segment start
            and ends this long before its end.
        min_rotate: duration of a pivot step that needs no footstep.
        max_hand_error: a hand further than this from its grip point while holding fails (m).
        max_steps: a transit walk is planned (and comes to rest) every this many steps.
        follow_feet: a pivot's rotation progress is this share of how far the feet have
            turned and the rest a minimum-jerk profile over the pivot's time (1: with the
            feet, which the trunk and the shoulders follow, so that every link stays in the
            planner's held body; 0 (smoother) let shoulders out by 34 mm on fig10).
        pivot_walk_steps: pivot steps are walked continuously in walks of at most this
            many steps (each comes to rest; its CoM planned in windows of supports,
            :mod:`~pivot_ompl.wholebody.walk_windows`).
    """

    reach: float = 1.5
    tilt: float = 1.0
    release: float = 1.5
    settle: float = 0.3
    rotate_margin: float = 0.3
    min_rotate: float = 1.2
    max_hand_error: float = 0.01
    max_steps: int = 20
    pivot_walk_steps: int = 24
    follow_feet: float = 1.0


def min_jerk(s: float) -> float:
    """Minimum-jerk profile on [0, 1] (clipped)."""
    s = min(1.0, max(0.0, s))
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


class FramePath:
    """The frames from ``T0`` (s=0) to ``T1`` (s=1): linear position, geodesic rotation.

    The rotation's logarithm is taken once, so that each frame costs one exponential.
    """

    def __init__(self, T0: np.ndarray, T1: np.ndarray) -> None:
        import pinocchio as pin

        self._exp3 = pin.exp3
        self._R0, self._p0 = T0[:3, :3].copy(), T0[:3, 3].copy()
        self._w = pin.log3(T0[:3, :3].T @ T1[:3, :3])
        self._dp = T1[:3, 3] - T0[:3, 3]

    def at(self, s: float) -> np.ndarray:
        """The frame at progress ``s`` (not clipped)."""
        return transform(self._R0 @ self._exp3(s * self._w), self._p0 + s * self._dp)


def interpolate_frame(T0: np.ndarray, T1: np.ndarray, s: float) -> np.ndarray:
    """Frame between ``T0`` (s=0) and ``T1`` (s=1): linear position, geodesic rotation."""
    return FramePath(T0, T1).at(s)


class MinJerkSwing:
    """A swing foot's frames from lift-off ``T0`` to landing ``T1`` (:func:`min_jerk_swing`)."""

    def __init__(self, T0: np.ndarray, T1: np.ndarray, height: float) -> None:
        self._path, self._height = FramePath(T0, T1), height

    def at(self, s: float) -> np.ndarray:
        """The foot's frame at progress ``s`` in [0, 1] (clipped)."""
        s = min(1.0, max(0.0, s))
        T = self._path.at(min_jerk(s))
        T[2, 3] += self._height * 64.0 * (s * (1.0 - s)) ** 3
        return T


def min_jerk_swing(T0: np.ndarray, T1: np.ndarray, s: float, height: float) -> np.ndarray:
    """A swing foot's frame at progress ``s`` in [0, 1] from lift-off ``T0`` to landing ``T1``.

    Position and rotation follow :func:`min_jerk` (:func:`interpolate_frame`); the foot rises
    by ``height * 64 s³ (1 - s)³`` (``height`` at mid-swing). Speed and acceleration are zero
    at both ends, so the leg starts and ends its swing without a jump of acceleration.
    """
    return MinJerkSwing(T0, T1, height).at(s)
