"""What every motion check reads: the motion, its plan and scene, kinematics recomputed once."""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, cast

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan
from pivot_ompl.scene import Scene
from pivot_ompl.wholebody.box import BoxHold, matrix_from_quat, transform
from pivot_ompl.wholebody.clearance import ClearanceReport
from pivot_ompl.wholebody.urdf_model import UrdfModel

if TYPE_CHECKING:
    from pivot_ompl.wholebody.joint_peaks import JointPeaks

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class CheckResult:
    """One check: its worst value against its limit.

    Attributes:
        name: check name.
        passed: whether the motion satisfies it.
        value: the worst measured value (unit in ``unit``).
        limit: the threshold.
        unit: unit of value and limit.
        detail: where the worst value occurs.
        index: sample index of the worst value (-1 if not tied to a sample).
    """

    name: str
    passed: bool
    value: float
    limit: float
    unit: str
    detail: str = ""
    index: int = -1


@dataclass(frozen=True)
class Tolerances:
    """Limits of the checks (see :func:`~pivot_ompl.wholebody.motion_checks.check_motion`)."""

    zmp: float = 0.0
    foot: float = 1e-3
    hand: float = 0.01
    corner: float = 1e-3
    #: acceleration limits (rad/s²): arm, chest and head joints, other joints, held box
    upper_accel: float = 30.0
    accel: float = 50.0
    box_accel: float = 5.0
    obstacle: float = 0.01


@dataclass
class Kinematics:
    """Frames of a motion recomputed from its ``q``, and the URDF's joint limits.

    Attributes:
        com: centre of mass per sample (N x 3).
        feet: sole frames per sample (``left_foot``/``right_foot`` -> N x 4 x 4).
        hands: hand positions per sample (``left_hand``/``right_hand`` -> N x 3).
        lower, upper: joint position limits (actuated joints).
        velocity: joint velocity limits (actuated joints).
    """

    com: np.ndarray
    feet: dict[str, np.ndarray]
    hands: dict[str, np.ndarray]
    lower: np.ndarray
    upper: np.ndarray
    velocity: np.ndarray


def kinematics(motion: Motion, robot: UrdfModel) -> Kinematics:
    """CoM, sole and hand frames of every sample of ``motion`` (pinocchio).

    Raises:
        InputError: the motion's joints or ``q`` columns do not match the URDF.
    """
    import pinocchio as pin

    model = robot.model
    names = [str(n) for n in model.names[2:]]
    if names != list(motion.joint_names):
        raise InputError("motion.joint_names", motion.joint_names[:3],
                         f"do not match the joints of {motion.urdf}")
    if motion.q.shape[1] != model.nq:
        raise InputError("motion.q", motion.q.shape, f"must have {model.nq} columns")
    data = model.createData()
    fids = {n: model.getFrameId(n) for n in ("left_foot", "right_foot", "left_hand",
                                             "right_hand")}
    n = len(motion.t)
    com = np.empty((n, 3))
    feet = {k: np.empty((n, 4, 4)) for k in ("left_foot", "right_foot")}
    hands = {k: np.empty((n, 3)) for k in ("left_hand", "right_hand")}
    for i, q in enumerate(motion.q):
        com[i] = pin.centerOfMass(model, data, q)
        pin.updateFramePlacements(model, data)
        for k in feet:
            feet[k][i] = data.oMf[fids[k]].homogeneous
        for k in hands:
            hands[k][i] = data.oMf[fids[k]].translation
    return Kinematics(com, feet, hands, model.lowerPositionLimit[7:],
                      model.upperPositionLimit[7:], model.velocityLimit[6:])


def runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges [a, b) where ``mask`` is true."""
    out, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        elif not m and start is not None:
            out.append((start, i))
            start = None
    if start is not None:
        out.append((start, len(mask)))
    return out


def box_T(row: np.ndarray) -> np.ndarray:
    """4x4 box frame of a motion's ``box`` row (position, quaternion xyzw)."""
    return transform(matrix_from_quat(row[3:]), row[:3])


@dataclass
class CheckContext:
    """A motion under check with what its checks share.

    The motion's dynamics arrays (``com``, ``support``, ``phase``, ``step``, ``holding``,
    ``grasp``, ``box_size``) are present (:func:`check_motion` requires them).

    Attributes:
        motion: the motion.
        plan: its plan, or ``None`` (the plan checks are skipped).
        scene: its scene, or ``None`` (the obstacle check is skipped).
        robot: the pinocchio model of the motion's URDF.
        kin: the motion's kinematics.
        tol: the checks' limits.
        clearance: obstacle clearance per link, once the obstacle check has run.
        peaks: every joint's largest speed and acceleration, once a peak check has run.
    """

    motion: Motion
    plan: Plan | None
    scene: Scene | None
    robot: UrdfModel
    kin: Kinematics
    tol: Tolerances = field(default_factory=Tolerances)
    clearance: ClearanceReport | None = None
    peaks: JointPeaks | None = None

    def array(self, name: str) -> np.ndarray:
        """A required per-sample array of the motion (``support``, ``phase``, ...)."""
        a = getattr(self.motion, name)
        assert a is not None  # required by check_motion
        return cast(np.ndarray, a)

    @cached_property
    def hold(self) -> BoxHold:
        """The box's kinematics (its size from the motion)."""
        size = self.motion.box_size
        assert size is not None  # required by check_motion
        return BoxHold(cast("tuple[float, float, float]", tuple(float(x) for x in size)))

    @cached_property
    def box_corners(self) -> np.ndarray:
        """The box's eight corners per sample (N x 8 x 3)."""
        return np.array([self.hold.box_corners(box_T(row)) for row in self.motion.box])
