"""Whole-body motion files (``.npz`` written by ``pivot_ompl.wholebody``): loading and checks.

Contract (keys of the archive)::

    t            (N,)      time (s), non-decreasing
    q            (N, nq)   pinocchio configuration: free-flyer root xyz + quaternion xyzw,
                           then one value per actuated 1-dof joint
    joint_names  (nq - 7,) names of those joints in q order ("universe"/"root_joint" ignored)
    urdf         ()        URDF path relative to the repository root (robots/hrp2/hrp2.urdf)
    box          (N, 7)    box centre xyz + quaternion xyzw (T_world_box)
    com          (N, 3)    centre of mass
    zmp          (N, 2)    zero-moment point on the floor
    support      (N,)      support state per sample
    phase        (N,)      plan phase index per sample

Optional: ``box_size`` (or ``object_size``) (3,) box size (w, d, h); ``sole_size`` (2,)
sole length and width for footstep marks; ``scene`` () scene name. Other keys are ignored.
"""

from __future__ import annotations

import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError

REQUIRED = ("t", "q", "joint_names", "urdf", "box")
OPTIONAL = ("com", "zmp", "support", "phase", "box_size", "object_size", "sole_size", "scene")
_ROOT_NAMES = ("universe", "root_joint")


@dataclass
class Motion:
    """A loaded whole-body motion (see the module docstring for each field)."""

    t: np.ndarray
    q: np.ndarray
    joint_names: tuple[str, ...]
    urdf: str
    box: np.ndarray
    com: np.ndarray | None = None
    zmp: np.ndarray | None = None
    support: np.ndarray | None = None
    phase: np.ndarray | None = None
    object_size: tuple[float, float, float] | None = None
    sole_size: tuple[float, float] | None = None
    scene: str = ""
    source: str = ""

    @property
    def duration(self) -> float:
        """Length of the motion (s)."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0


def _str(v: np.ndarray) -> str:
    return str(v.item() if hasattr(v, "item") and np.ndim(v) == 0 else v)


def load_motion(path: str | Path) -> Motion:
    """Read and check a motion ``.npz`` file.

    Raises:
        InputError: unreadable file, missing key or inconsistent shapes (naming the key).
    """
    path = Path(path)
    src = str(path)
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError, zipfile.BadZipFile) as e:
        raise InputError("path", src, f"is not a readable .npz motion file ({e})") from e
    with data:
        for key in REQUIRED:
            if key not in data.files:
                raise InputError(key, None, "is required in a motion file", source=src)
        t = np.asarray(data["t"], dtype=float).reshape(-1)
        q = np.asarray(data["q"], dtype=float)
        box = np.asarray(data["box"], dtype=float)
        names = [str(n) for n in np.asarray(data["joint_names"]).reshape(-1)]
        names = [n for n in names if n not in _ROOT_NAMES]
        n = len(t)
        if n == 0:
            raise InputError("t", [], "must hold at least one sample", source=src)
        if np.any(np.diff(t) < 0) or not np.all(np.isfinite(t)):
            raise InputError("t", "...", "must be finite and non-decreasing", source=src)
        if q.ndim != 2 or q.shape[0] != n or q.shape[1] < 7:
            raise InputError("q", list(q.shape), f"must have shape ({n}, 7 + joints)", source=src)
        if q.shape[1] - 7 != len(names):
            raise InputError("joint_names", len(names),
                             f"must name the {q.shape[1] - 7} joint values of q", source=src)
        if box.shape != (n, 7):
            raise InputError("box", list(box.shape), f"must have shape ({n}, 7)", source=src)
        extra: dict = {}
        for key, shape in (("com", (n, 3)), ("zmp", (n, 2))):
            if key in data.files:
                a = np.asarray(data[key], dtype=float)
                if a.shape != shape:
                    raise InputError(key, list(a.shape), f"must have shape {shape}", source=src)
                extra[key] = a
        for key in ("support", "phase"):
            if key in data.files:
                extra[key] = np.asarray(data[key]).reshape(-1)
        size = _lengths(data, ("box_size", "object_size"), 3, src)
        sole = _lengths(data, ("sole_size",), 2, src)
        scene = _str(data["scene"]) if "scene" in data.files else ""
        return Motion(t, q, tuple(names), _str(data["urdf"]), box, object_size=size,
                      sole_size=sole, scene=scene, source=src, **extra)


def _lengths(data, keys: tuple[str, ...], n: int, src: str) -> tuple[float, ...] | None:
    """The first of ``keys`` present as ``n`` lengths; all-zero means "not given"."""
    for key in keys:
        if key in data.files:
            s = np.asarray(data[key], dtype=float).reshape(-1)
            if s.shape == (n,) and np.all(s == 0):
                continue
            if s.shape != (n,) or not np.all(s > 0):
                raise InputError(key, s.tolist(), f"must be {n} positive lengths (m)",
                                 source=src)
            return tuple(float(x) for x in s)
    return None
