"""The samples a whole-body generation records, and what the generation cost."""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.humanoids import DEFAULT_MODEL, profile_of
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan
from pivot_ompl.wholebody.blend import blend, blend_quaternions, sample_labels, sample_support
from pivot_ompl.wholebody.box import BoxHold, quats_xyzw

log = logging.getLogger(__name__)


@dataclass
class GenerationStats:
    """What a generation cost.

    Attributes:
        duration: seconds of motion produced.
        compute: wall-clock seconds spent.
        ticks: solver ticks.
        samples: motion samples (``substeps`` per tick, see :mod:`.blend`).
        max_hand_error: largest hand-to-grip distance while holding (m).
        max_hand_angle: largest angle between a hand's approach axis and its grip frame's
            while holding (rad; the hand orientation is a low-weight task).
    """

    duration: float = 0.0
    compute: float = 0.0
    ticks: int = 0
    samples: int = 0
    max_hand_error: float = 0.0
    max_hand_angle: float = 0.0

    def note_hands(self, frames: tuple[np.ndarray, np.ndarray],
                   targets: tuple[np.ndarray, np.ndarray]) -> float:
        """Count the hand frames (left, right) against their grip targets; return the error.

        The error is the larger hand-to-grip distance (m); the approach axes (hand -z) give
        the angle.
        """
        (Tl, Tr), (gl, gr) = frames, targets
        err = math.sqrt(max(float(d @ d) for d in (Tl[:3, 3] - gl[:3, 3], Tr[:3, 3] - gr[:3, 3])))
        self.max_hand_error = max(self.max_hand_error, err)
        c = min(float(Tl[:3, 2] @ gl[:3, 2]), float(Tr[:3, 2] @ gr[:3, 2]))
        self.max_hand_angle = max(self.max_hand_angle, math.acos(max(-1.0, min(1.0, c))))
        return err

    @property
    def real_time_factor(self) -> float:
        """Seconds of motion per second of compute."""
        return self.duration / self.compute if self.compute > 0 else math.inf


@dataclass(frozen=True)
class Sample:
    """What one solver tick records besides the robot's state.

    Attributes:
        support: support code (0 double, 1 left, 2 right).
        zmp: planned ZMP (x, y).
        phase: plan phase index.
        step: pivot step index while holding (else -1).
        holding: the hands hold the box.
        grasp: grasp index while holding (else -1).
        tilt: box inclination (rad).
    """

    support: int
    zmp: np.ndarray
    phase: int
    step: int
    holding: bool
    grasp: int
    tilt: float


@dataclass
class Recorder:
    """Per-tick lists of a motion being generated (the solver's ticks, the blend's knots)."""

    t: list[float] = field(default_factory=list)
    q: list[np.ndarray] = field(default_factory=list)
    box: list[np.ndarray] = field(default_factory=list)
    com: list[np.ndarray] = field(default_factory=list)
    samples: list[Sample] = field(default_factory=list)

    def record(self, t: float, q: np.ndarray, box_T: np.ndarray, com: np.ndarray,
               sample: Sample) -> None:
        """Append one tick: time, configuration, box frame (4x4), CoM and the rest."""
        self.t.append(t)
        self.q.append(q)
        self.box.append(box_T[:3, :].copy())
        self.com.append(com)
        self.samples.append(sample)

    def motion(self, plan: Plan, hold: BoxHold, joint_names: tuple[str, ...], *,
               substeps: int = 1) -> Motion:
        """The recorded motion of ``plan`` (box and grips of ``hold``), ``substeps`` samples a tick.

        Configurations, box poses, CoM, planned ZMP and tilt are blended between the ticks
        (:func:`~pivot_ompl.wholebody.blend.blend`); labels and support codes follow
        :func:`~pivot_ompl.wholebody.blend.sample_labels` and
        :func:`~pivot_ompl.wholebody.blend.sample_support`.
        """
        grip = np.zeros((4, 2, 3))
        for k in range(4):
            left, right = hold.T_box_hands(k)
            grip[k, 0], grip[k, 1] = left[:3, 3], right[:3, 3]
        ss, m = self.samples, max(1, substeps)
        t = np.array(self.t)
        if m > 1 and len(t) > 1:
            t = np.append((t[:-1, None] + np.diff(t)[:, None] * (np.arange(m) / m)).ravel(),
                          t[-1])
        q = np.array(self.q)
        q = np.hstack((blend(q[:, :3], m), blend_quaternions(q[:, 3:7], m),
                       blend(q[:, 7:], m)))
        frames = np.array(self.box)
        box = np.hstack((blend(frames[:, :, 3], m),
                         blend_quaternions(quats_xyzw(frames[:, :, :3]), m, positive_w=True)))

        def labels(values: list, dtype: type) -> np.ndarray:
            return sample_labels(np.array(values, dtype=dtype), m)

        robot = profile_of(plan.robot_model)
        return Motion(
            t=t, q=q, joint_names=joint_names,
            robot_model="" if robot.name == DEFAULT_MODEL else robot.name,
            urdf=robot.urdf_name, box=box, com=blend(np.array(self.com), m),
            zmp=blend(np.array([s.zmp for s in ss]), m),
            support=sample_support(np.array([s.support for s in ss], dtype=int), m),
            phase=labels([s.phase for s in ss], int),
            step=labels([s.step for s in ss], int),
            holding=labels([s.holding for s in ss], bool),
            grasp=labels([s.grasp for s in ss], int),
            tilt=blend(np.array([s.tilt for s in ss]), m),
            box_size=tuple(float(x) for x in plan.object_size),  # type: ignore[arg-type]
            grip_box=grip, sole_size=robot.sole_size, scene=plan.scene,
            scene_path=_text(plan.extra.get("scene_path")),
            scene_sha256=_text(plan.extra.get("scene_sha256")))


def _text(value: object) -> str:
    """A plan's text field, ``""`` when absent or not text."""
    return value if isinstance(value, str) else ""
