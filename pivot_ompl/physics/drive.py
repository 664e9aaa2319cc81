"""What the motion drives: the hands' frames at every sample and the pivot rotations.

A motion ``.npz`` holds the planned box pose at each sample (``box``), whether the hands hold
it (``holding``), with which grasp (``grasp``) and the grip points in the box frame per grasp
(``grip_box``). The hands' frames are the planned box pose carried to each grip point (their
orientation the box's): the frames the whole-body motion puts the hands on (its ``hands``
check bounds the difference by 1 cm). ``phase`` and ``step`` mark the pivot rotations: the
samples of one rotation and the corner it turns about (the planned box corner that stays put).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion


def rotations_xyzw(q: np.ndarray) -> np.ndarray:
    """Rotation matrices (N x 3 x 3) of unit quaternions (N x 4, x y z w)."""
    q = np.asarray(q, dtype=float).reshape(-1, 4)
    q = q / np.linalg.norm(q, axis=1, keepdims=True)
    x, y, z, w = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], axis=1)


def yaw_of(R: np.ndarray) -> np.ndarray:
    """Heading (rad) of the box's x axis of each rotation (the held box tilts about x or y)."""
    R = np.asarray(R)
    return np.arctan2(R[..., 1, 0], R[..., 0, 0])


@dataclass(frozen=True)
class PivotSegment:
    """The samples ``[start, end]`` of one pivot rotation.

    Attributes:
        start, end: first and last sample.
        phase, step: the plan's phase and step indices.
        corner: the box-frame corner the rotation turns about (3,).
        pivot: its planned world position (x, y).
    """

    start: int
    end: int
    phase: int
    step: int
    corner: np.ndarray
    pivot: tuple[float, float]


@dataclass(frozen=True)
class DriveSignals:
    """A motion's drive: times, planned box, hand frames and pivots (see the module doc).

    Attributes:
        t: sample times (N,), from 0.
        box_pos, box_rot: planned box centre (N, 3) and rotation (N, 3, 3).
        box_yaw: planned heading (N,).
        holding: hands on the grip points (N,).
        hand_pos: the left and right hand's position (N, 2, 3).
        hand_quat: their orientation, MuJoCo's w x y z (N, 4): the box's.
        pivots: the rotations in order.
        size: the box size (m).
    """

    t: np.ndarray
    box_pos: np.ndarray
    box_rot: np.ndarray
    box_yaw: np.ndarray
    holding: np.ndarray
    hand_pos: np.ndarray
    hand_quat: np.ndarray
    pivots: tuple[PivotSegment, ...]
    size: tuple[float, float, float]

    @property
    def n(self) -> int:
        """Number of samples."""
        return len(self.t)

    def releases(self) -> list[int]:
        """The samples where the hands let go of the box (holding turns false), then the last."""
        h = self.holding.astype(int)
        out = [int(i) + 1 for i in np.flatnonzero(np.diff(h) < 0)]
        return out + ([self.n - 1] if not out or out[-1] != self.n - 1 else [])


def corners(size: tuple[float, float, float]) -> np.ndarray:
    """The box's 8 corners in its frame (8 x 3)."""
    s = 0.5 * np.asarray(size)
    return np.array([[a, b, c] for a in (-1, 1) for b in (-1, 1) for c in (-1, 1)]) * s


def drive_signals(motion: Motion) -> DriveSignals:
    """The drive of ``motion``.

    Raises:
        InputError: the motion lacks the box size, or holds the box with no grip points.
    """
    if motion.box_size is None:
        raise InputError("motion.box_size", None, "is required to simulate the box",
                         source=motion.source)
    assert motion.holding is not None and motion.grasp is not None  # noqa: S101 - defaults
    assert motion.step is not None  # noqa: S101 - filled by Motion
    holding = motion.holding.astype(bool) & (motion.grasp >= 0)
    if holding.any() and not np.any(motion.grip_box):
        raise InputError("motion.grip_box", 0, "must give the grip points of a held box",
                         source=motion.source)
    pos = np.asarray(motion.box[:, :3], dtype=float)
    rot = rotations_xyzw(motion.box[:, 3:7])
    quat = np.column_stack([motion.box[:, 6], motion.box[:, 3:6]])  # w x y z
    grasp = np.maximum.accumulate(np.where(motion.grasp >= 0, np.arange(len(pos)), 0))
    k = np.clip(motion.grasp[grasp], 0, 3)
    grips = motion.grip_box[k]  # N x 2 x 3, the last grasp held (the hands' rest values)
    hands = np.einsum("nij,nhj->nhi", rot, grips) + pos[:, None, :]
    pivots = _pivots(motion, pos, rot)
    return DriveSignals(motion.t - motion.t[0], pos, rot, yaw_of(rot), holding, hands, quat,
                        pivots, motion.box_size)


def _pivots(motion: Motion, pos: np.ndarray, rot: np.ndarray) -> tuple[PivotSegment, ...]:
    assert motion.step is not None  # noqa: S101 - filled by Motion
    assert motion.box_size is not None  # noqa: S101 - checked by the caller
    phase = motion.phase if motion.phase is not None else np.zeros(len(pos), dtype=int)
    key = np.where(motion.step >= 0, phase * 100_000 + motion.step, -1)
    edges = np.flatnonzero(np.diff(key)) + 1
    bounds = np.concatenate([[0], edges, [len(key)]])
    c = corners(motion.box_size)
    out = []
    for a, b in zip(bounds[:-1], bounds[1:], strict=True):
        if key[a] < 0 or b - a < 2:
            continue
        w0 = c @ rot[a].T + pos[a]
        w1 = c @ rot[b - 1].T + pos[b - 1]
        j = int(np.argmin(np.linalg.norm(w1 - w0, axis=1) + 10.0 * np.abs(w0[:, 2])))
        out.append(PivotSegment(int(a), int(b - 1), int(phase[a]), int(motion.step[a]), c[j],
                                (float(w0[j, 0]), float(w0[j, 1]))))
    return tuple(out)


def wrap(a: float | np.ndarray) -> float | np.ndarray:
    """Angle(s) wrapped to [-pi, pi)."""
    return (np.asarray(a) + math.pi) % (2 * math.pi) - math.pi
