"""The whole-body motion file (``.npz``, a contract read by outside tools).

Required arrays (N samples):

* ``t`` (N) time in s, uniformly sampled;
* ``q`` (N x nq) pinocchio configuration of ``robots/hrp2/hrp2.urdf`` with a free-flyer root
  (``[x, y, z, qx, qy, qz, qw, joints...]``);
* ``joint_names`` (nq - 7 strings, the order of the joint entries of ``q``);
* ``urdf`` (string) the URDF path relative to the repository root;
* ``box`` (N x 7) box centre ``xyz`` + quaternion ``xyzw``;
* ``com`` (N x 3) centre of mass; ``zmp`` (N x 2) planned ZMP;
* ``support`` (N) 0 double support, 1 left foot, 2 right foot;
* ``phase`` (N) index into the plan's phases.

Extra arrays (used by the checks): ``format`` = ``"pivot-motion/1"``, ``step`` (N, index of
the pivot step being rotated in its phase, -1 otherwise), ``holding`` (N bool, both hands on
the grip points), ``grasp`` (N, -1 when not holding), ``tilt`` (N, rad), ``box_size`` (3),
``grip_box`` (4 x 2 x 3: grip points in the box frame per grasp, left then right),
``sole_size`` (2: sole length and width, m).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError

FORMAT = "pivot-motion/1"
REQUIRED = ("t", "q", "joint_names", "urdf", "box", "com", "zmp", "support", "phase")
SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT = 0, 1, 2


@dataclass
class Motion:
    """A whole-body motion in memory (see the module docstring for each array)."""

    t: np.ndarray
    q: np.ndarray
    joint_names: list[str]
    urdf: str
    box: np.ndarray
    com: np.ndarray
    zmp: np.ndarray
    support: np.ndarray
    phase: np.ndarray
    step: np.ndarray
    holding: np.ndarray
    grasp: np.ndarray
    tilt: np.ndarray
    box_size: np.ndarray
    grip_box: np.ndarray
    sole_size: np.ndarray = field(default_factory=lambda: np.array([0.241, 0.138]))

    @property
    def duration(self) -> float:
        """Length of the motion (s)."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    @property
    def dt(self) -> float:
        """Sampling period (s)."""
        return float(self.t[1] - self.t[0]) if len(self.t) > 1 else 0.0

    def save(self, path: str | Path) -> Path:
        """Write the motion as a compressed ``.npz``; return the path."""
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("wb") as fh:
            np.savez_compressed(
                fh, format=np.array(FORMAT), t=self.t, q=self.q,
                joint_names=np.array(self.joint_names), urdf=np.array(self.urdf),
                box=self.box, com=self.com, zmp=self.zmp,
                support=self.support.astype(np.int8), phase=self.phase.astype(np.int32),
                step=self.step.astype(np.int32), holding=self.holding.astype(bool),
                grasp=self.grasp.astype(np.int8), tilt=self.tilt, box_size=self.box_size,
                grip_box=self.grip_box, sole_size=self.sole_size)
        return path


def load_motion(path: str | Path) -> Motion:
    """Read a motion file.

    Raises:
        InputError: unreadable file, missing array or inconsistent shapes.
    """
    path = Path(path)
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError) as e:
        raise InputError("motion", str(path), f"cannot be read as .npz ({e})") from e
    with data:
        for key in REQUIRED:
            if key not in data.files:
                raise InputError(f"motion.{key}", None, "is required", source=str(path))
        arrays = {k: data[k] for k in data.files}
    n = len(arrays["t"])
    shapes = {"q": (n, None), "box": (n, 7), "com": (n, 3), "zmp": (n, 2), "support": (n,),
              "phase": (n,)}
    for key, shape in shapes.items():
        a = arrays[key]
        cols_bad = len(shape) > 1 and shape[1] is not None and a.shape[1:] != shape[1:]
        if a.shape[0] != n or cols_bad:
            raise InputError(f"motion.{key}", a.shape, f"must have shape {shape}", source=str(path))
    if arrays["q"].shape[1] != len(arrays["joint_names"]) + 7:
        raise InputError("motion.q", arrays["q"].shape, "must have 7 + len(joint_names) columns",
                         source=str(path))
    if n < 3:
        raise InputError("motion.t", n, "needs at least 3 samples", source=str(path))

    def opt(key: str, default: np.ndarray) -> np.ndarray:
        return arrays[key] if key in arrays else default

    return Motion(
        t=arrays["t"], q=arrays["q"], joint_names=[str(s) for s in arrays["joint_names"]],
        urdf=str(arrays["urdf"]), box=arrays["box"], com=arrays["com"], zmp=arrays["zmp"],
        support=arrays["support"].astype(int), phase=arrays["phase"].astype(int),
        step=opt("step", np.full(n, -1)).astype(int),
        holding=opt("holding", np.zeros(n, bool)).astype(bool),
        grasp=opt("grasp", np.full(n, -1)).astype(int), tilt=opt("tilt", np.zeros(n)),
        box_size=opt("box_size", np.zeros(3)), grip_box=opt("grip_box", np.zeros((4, 2, 3))),
        sole_size=opt("sole_size", np.array([0.241, 0.138])))
