"""The whole-body motion file (``.npz``, a contract read by outside tools): one reader, one writer.

Required arrays (N samples)::

    t            (N,)      time (s), N >= 2, increasing by at least 1e-6 s a sample
    q            (N, nq)   pinocchio configuration of the URDF with a free-flyer root
                           ([x, y, z, qx, qy, qz, qw, joints...]; unit quaternion)
    joint_names  (nq - 7,) names of the joint entries of q, in order
    urdf         ()        the robot's URDF: a shipped file relative to the data folder
                           (robots/hrp2/hrp2.urdf), or the name a humanoid profile gives it
    box          (N, 7)    box centre xyz + unit quaternion xyzw (T_world_box)

Positions are within +-1e4 m; the box's sides within [0.05, 20] m and the soles' within
[1e-3, 1] m; codes (``support``, ``grasp``, ...) within their ranges (:data:`CODES`). A
value out of range is an :class:`~pivot_ompl.errors.InputError` naming the array, the sample
and the value, so that the checks never meet one.

Written by the generator and required by ``check-motion`` (optional for a replay)::

    com (N, 3) centre of mass; zmp (N, 2) planned ZMP; support (N,) 0 double support,
    1 left foot, 2 right foot; phase (N,) index into the plan's phases

Optional: ``format`` = ``"pivot-motion/1"``; ``step`` (N, index of the pivot step being rotated
in its phase, -1 otherwise); ``holding`` (N bool, both hands on the grip points); ``grasp``
(N, -1 when not holding); ``tilt`` (N, rad); ``box_size`` (or ``object_size``) (3,) box size
(w, d, h); ``grip_box`` (4 x 2 x 3: grip points in the box frame per grasp, left then right);
``sole_size`` (2,) sole length and width (m); ``robot_model`` () the humanoid profile's name
(written for every model but the default, HRP-2; a motion without it is the model whose
profile names its ``urdf``, else HRP-2's: :attr:`Motion.model`); ``scene`` () scene name
(``check-motion``
loads it to check the obstacles, unless given ``--scene``); ``scene_path`` () the scene file,
relative to the motion file's folder, and ``scene_sha256`` () its
:func:`~pivot_ompl.scene.scene_digest` (both copied from the plan by ``animate``; in memory
:attr:`Motion.scene_path` is absolute). Other keys are ignored.
"""

from __future__ import annotations

import os
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.fileio import atomic_output, regular_file
from pivot_ompl.humanoids import DEFAULT_MODEL, PROFILES, model_of_urdf

FORMAT = "pivot-motion/1"
REQUIRED = ("t", "q", "joint_names", "urdf", "box")
#: Arrays the motion checks need beyond :data:`REQUIRED`.
DYNAMICS = ("com", "zmp", "support", "phase")
SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT = 0, 1, 2
_ROOT_NAMES = ("universe", "root_joint")


@dataclass
class Motion:
    """A whole-body motion in memory (see the module docstring for each array).

    ``com``, ``zmp``, ``support`` and ``phase`` are ``None`` when the file has none; the other
    optional arrays hold their defaults (``step``/``grasp`` -1, ``holding`` False, ``tilt`` 0).
    """

    t: np.ndarray
    q: np.ndarray
    joint_names: tuple[str, ...]
    urdf: str
    box: np.ndarray
    com: np.ndarray | None = None
    zmp: np.ndarray | None = None
    support: np.ndarray | None = None
    phase: np.ndarray | None = None
    step: np.ndarray | None = None
    holding: np.ndarray | None = None
    grasp: np.ndarray | None = None
    tilt: np.ndarray | None = None
    box_size: tuple[float, float, float] | None = None
    grip_box: np.ndarray = field(default_factory=lambda: np.zeros((4, 2, 3)))
    sole_size: tuple[float, float] | None = None
    scene: str = ""
    scene_path: str = ""
    scene_sha256: str = ""
    source: str = field(default="", compare=False)
    robot_model: str = ""

    def __post_init__(self) -> None:
        """Fill the per-sample defaults (``step``, ``holding``, ``grasp``, ``tilt``)."""
        n = len(self.t)
        self.joint_names = tuple(str(s) for s in self.joint_names)
        if self.step is None:
            self.step = np.full(n, -1, dtype=int)
        if self.holding is None:
            self.holding = np.zeros(n, dtype=bool)
        if self.grasp is None:
            self.grasp = np.full(n, -1, dtype=int)
        if self.tilt is None:
            self.tilt = np.zeros(n)

    @property
    def object_size(self) -> tuple[float, float, float] | None:
        """The box size (w, d, h) in m, or ``None`` when the file does not give it."""
        return self.box_size

    @property
    def model(self) -> str:
        """The humanoid's profile name.

        ``robot_model``, else the profile naming ``urdf``, else the default model's.
        """
        return self.robot_model or model_of_urdf(self.urdf) or DEFAULT_MODEL

    @property
    def duration(self) -> float:
        """Length of the motion (s)."""
        return float(self.t[-1] - self.t[0]) if len(self.t) else 0.0

    @property
    def dt(self) -> float:
        """Sampling period (s)."""
        return float(self.t[1] - self.t[0]) if len(self.t) > 1 else 0.0

    def require(self, *keys: str) -> None:
        """Raise :class:`InputError` naming the first of ``keys`` the motion lacks."""
        for key in keys:
            if getattr(self, key) is None:
                raise InputError(f"motion.{key}", None, "is required", source=self.source)

    def save(self, path: str | Path) -> Path:
        """Write the motion as a compressed ``.npz``; return the path.

        The file is replaced only once completely written (a temporary file moved into place).
        """
        self.require(*DYNAMICS)
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        assert self.support is not None and self.phase is not None  # noqa: S101 - for mypy
        assert self.step is not None and self.holding is not None and self.grasp is not None
        arrays: dict[str, Any] = dict(
            format=np.array(FORMAT), t=self.t, q=self.q,
            joint_names=np.array(self.joint_names), urdf=np.array(self.urdf),
            box=self.box, com=self.com, zmp=self.zmp,
            support=self.support.astype(np.int8), phase=self.phase.astype(np.int32),
            step=self.step.astype(np.int32), holding=self.holding.astype(bool),
            grasp=self.grasp.astype(np.int8), tilt=self.tilt,
            box_size=np.array(self.box_size or (0.0, 0.0, 0.0)), grip_box=self.grip_box)
        if self.sole_size is not None:
            arrays["sole_size"] = np.array(self.sole_size)
        if self.scene:
            arrays["scene"] = np.array(self.scene)
        if self.model != DEFAULT_MODEL:
            arrays["robot_model"] = np.array(self.model)
        if self.scene_path:
            arrays["scene_path"] = np.array(_relative(self.scene_path, path.parent))
        if self.scene_sha256:
            arrays["scene_sha256"] = np.array(self.scene_sha256)
        with atomic_output(path) as tmp, tmp.open("wb") as fh:
            np.savez_compressed(fh, **arrays)
        return path


def _relative(path: str, folder: Path) -> str:
    """``path`` relative to ``folder`` (absolute when it cannot be, another drive)."""
    try:
        return Path(os.path.relpath(Path(path).resolve(), folder.resolve())).as_posix()
    except ValueError:
        return path


def _str(v: np.ndarray) -> str:
    return str(v.item() if hasattr(v, "item") and np.ndim(v) == 0 else v)


def load_motion(path: str | Path) -> Motion:
    """Read and check a motion ``.npz`` file (each array read once).

    Raises:
        InputError: not a path to a regular file, unreadable file, missing key or inconsistent
            shapes (naming the key).
    """
    path = regular_file(path, field="motion")
    src = str(path)
    try:
        data = np.load(path, allow_pickle=False)
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, MemoryError) as e:
        raise InputError("motion", src, f"is not a readable .npz motion file ({e!s:.120})") from e
    if not isinstance(data, np.lib.npyio.NpzFile):
        raise InputError("motion", src, "is a single array, not a .npz motion file")
    try:
        with data:
            for key in REQUIRED:
                if key not in data.files:
                    raise InputError(f"motion.{key}", None, "is required", source=src)
            arrays = {k: data[k] for k in data.files}
    except InputError:
        raise
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError, MemoryError) as e:
        raise InputError("motion", src, f"is not a readable .npz motion file ({e!s:.120})") from e
    try:
        return _motion_from_arrays(arrays, src)
    except (TypeError, ValueError, OverflowError) as e:  # e.g. text where numbers belong
        if isinstance(e, InputError):
            raise
        raise InputError("motion", src, f"has an array of the wrong kind ({e!s:.120})") from e


def _finite(a: np.ndarray, key: str, src: str) -> np.ndarray:
    if not a.size:
        return a
    bad = np.nonzero(~np.isfinite(a).reshape(len(a), -1).all(axis=1))[0]
    if len(bad):
        raise InputError(f"motion.{key}", f"sample {int(bad[0])}",
                         f"must be finite (NaN or inf in {len(bad)} samples)", source=src)
    return a


def _motion_from_arrays(arrays: dict[str, np.ndarray], src: str) -> Motion:
    t = np.asarray(arrays["t"], dtype=float).reshape(-1)
    q = np.asarray(arrays["q"], dtype=float)
    box = np.asarray(arrays["box"], dtype=float)
    names = [str(n) for n in np.asarray(arrays["joint_names"]).reshape(-1)]
    names = [n for n in names if n not in _ROOT_NAMES]
    n = len(t)
    _times(t, src)
    if q.ndim != 2 or q.shape[0] != n or q.shape[1] < 7:
        raise InputError("motion.q", list(q.shape), f"must have shape ({n}, 7 + joints)",
                         source=src)
    if q.shape[1] - 7 != len(names):
        raise InputError("motion.joint_names", len(names),
                         f"must name the {q.shape[1] - 7} joint values of q", source=src)
    if box.shape != (n, 7):
        raise InputError("motion.box", list(box.shape), f"must have shape ({n}, 7)", source=src)
    _finite(q, "q", src)
    _finite(box, "box", src)
    _pose_range(q, "q", src)
    _pose_range(box, "box", src)
    extra: dict[str, Any] = {}
    for key, shape in (("com", (n, 3)), ("zmp", (n, 2))):
        if key in arrays:
            a = np.asarray(arrays[key], dtype=float)
            if a.shape != shape:
                raise InputError(f"motion.{key}", list(a.shape), f"must have shape {shape}",
                                 source=src)
            extra[key] = _finite(a, key, src)
    for key in ("support", "phase", "step", "holding", "grasp", "tilt"):
        if key in arrays:
            a = np.asarray(arrays[key]).reshape(-1)
            if a.shape != (n,):
                raise InputError(f"motion.{key}", list(a.shape), f"must have shape ({n},)",
                                 source=src)
            if a.dtype.kind not in "biuf":
                raise InputError(f"motion.{key}", str(a.dtype), "must hold numbers", source=src)
            if a.dtype.kind == "f":
                _finite(a, key, src)
            if key in CODES:
                _codes(a, key, src)
            extra[key] = a.astype(bool if key == "holding" else float if key == "tilt" else int)
    if "grip_box" in arrays:
        g = np.asarray(arrays["grip_box"], dtype=float)
        if g.shape != (4, 2, 3):
            raise InputError("motion.grip_box", list(g.shape), "must have shape (4, 2, 3)",
                             source=src)
        extra["grip_box"] = g
    size = _lengths(arrays, ("box_size", "object_size"), 3, src)
    sole = _lengths(arrays, ("sole_size",), 2, src)
    if "com" in extra:
        _coordinates(extra["com"], "com", src)
    if "zmp" in extra:
        _coordinates(extra["zmp"], "zmp", src)
    scene = _str(arrays["scene"]) if "scene" in arrays else ""
    scene_path = _str(arrays["scene_path"]) if "scene_path" in arrays else ""
    if scene_path:
        scene_path = os.path.normpath(Path(src).resolve().parent / scene_path)
    digest = _str(arrays["scene_sha256"]) if "scene_sha256" in arrays else ""
    robot_model = _str(arrays["robot_model"]) if "robot_model" in arrays else ""
    if robot_model and robot_model not in PROFILES:
        raise InputError("motion.robot_model", robot_model,
                         f"unknown robot model (known: {sorted(PROFILES)})", source=src)
    return Motion(t, q, tuple(names), _str(arrays["urdf"]), box,
                  box_size=size, sole_size=sole, scene=scene,  # type: ignore[arg-type]
                  scene_path=scene_path, scene_sha256=digest,
                  source=src, robot_model=robot_model, **extra)


#: Largest ``|coordinate|`` of a position in a motion (m), the scene files' limit.
MAX_COORD = 1.0e4
#: Smallest time step between two samples (s): the checks differentiate twice.
MIN_STEP = 1e-6
#: Largest ``|deviation|`` of a quaternion's norm from 1.
QUATERNION_TOLERANCE = 1e-3
#: Lengths of the box and the soles (m): the scene files' box limits, soles 1 mm to 1 m.
LENGTH_RANGE = {"box_size": (0.05, 20.0), "object_size": (0.05, 20.0), "sole_size": (1e-3, 1.0)}


def _times(t: np.ndarray, src: str) -> None:
    """Refuse times that are not at least two finite, increasing samples."""
    if len(t) < 2:
        raise InputError("motion.t", t.tolist(), "must hold at least two samples", source=src)
    _finite(t, "t", src)
    if t[-1] <= t[0]:
        raise InputError("motion.t", [float(t[0]), float(t[-1])],
                         "must span a positive duration", source=src)
    bad = np.flatnonzero(np.diff(t) < MIN_STEP)
    if len(bad):
        k = int(bad[0]) + 1
        raise InputError(f"motion.t[{k}]", float(t[k]), f"must be at least {MIN_STEP:g} s after "
                         f"the sample before ({float(t[k - 1])!r} s): times increase",
                         source=src)


def _coordinates(a: np.ndarray, key: str, src: str) -> None:
    """Refuse a position beyond +-:data:`MAX_COORD` m."""
    bad = np.flatnonzero((np.abs(a) > MAX_COORD).any(axis=1))
    if len(bad):
        k = int(bad[0])
        raise InputError(f"motion.{key}[{k}]", a[k].tolist(),
                         f"coordinates must be within +-{MAX_COORD:g} m", source=src)


def _pose_range(a: np.ndarray, key: str, src: str) -> None:
    """Refuse poses (position, quaternion xyzw first) far away or with a non-unit quaternion."""
    _coordinates(a[:, :3], key, src)
    norm = np.linalg.norm(a[:, 3:7], axis=1)
    bad = np.flatnonzero(np.abs(norm - 1.0) > QUATERNION_TOLERANCE)
    if len(bad):
        k = int(bad[0])
        raise InputError(f"motion.{key}[{k}]", a[k, 3:7].tolist(),
                         f"columns 3..6 must be a unit quaternion (norm {float(norm[k]):.6g})",
                         source=src)


#: Per-sample code arrays and their ranges ``(lowest, highest)``; ``None``: no upper end.
CODES: dict[str, tuple[int, int | None]] = {"support": (0, 2), "phase": (0, None),
                                            "step": (-1, None), "grasp": (-1, 3),
                                            "holding": (0, 1)}


def _codes(a: np.ndarray, key: str, src: str) -> None:
    """Refuse a code array with a value that is not a whole number in its range."""
    lo, hi = CODES[key]
    v = a.astype(float)
    bad = np.flatnonzero((v != np.round(v)) | (v < lo) | ((v > hi) if hi is not None else False))
    if len(bad):
        k = int(bad[0])
        where = f"{lo}..{hi}" if hi is not None else f">= {lo}"
        raise InputError(f"motion.{key}[{k}]", float(v[k]), f"must be a whole number {where}",
                         source=src)


def _lengths(arrays: dict[str, np.ndarray], keys: tuple[str, ...], n: int,
             src: str) -> tuple[float, ...] | None:
    """The first of ``keys`` present as ``n`` lengths; all-zero means "not given"."""
    for key in keys:
        if key in arrays:
            s = np.asarray(arrays[key], dtype=float).reshape(-1)
            if s.shape == (n,) and np.all(s == 0):
                continue
            lo, hi = LENGTH_RANGE[key]
            if s.shape != (n,) or not np.all((s >= lo) & (s <= hi)):
                raise InputError(f"motion.{key}", s.tolist(),
                                 f"must be {n} lengths in [{lo:g}, {hi:g}] m", source=src)
            return tuple(float(x) for x in s)
    return None
