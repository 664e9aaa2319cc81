"""Camera placements of a replay: three-quarter overview, top-down, robot and box followed.

The same geometry as the page's controls (:mod:`pivot_ompl.viz.overlay`), for notebooks:
:func:`frame_scene`, :func:`top_view` and :func:`follow_view` compute a :class:`CameraPose`
and send it to meshcat's default camera (:func:`look_at`). meshcat's camera has a 75 deg
vertical field of view; the framing assumes a 16:10 pane unless told otherwise.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import meshcat
import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.viz.overlay import CAMERA_FOV, THREE_QUARTER

Bounds = tuple[float, float, float, float]


@dataclass(frozen=True)
class CameraPose:
    """Where the camera is and what it looks at (world frame, m, z up).

    Attributes:
        target: the point looked at (the orbit centre).
        eye: the camera position.
    """

    target: tuple[float, float, float]
    eye: tuple[float, float, float]

    @property
    def distance(self) -> float:
        """Eye-to-target distance (m)."""
        return math.dist(self.target, self.eye)


def _check_bounds(bounds: Sequence[float]) -> Bounds:
    if len(bounds) != 4:
        raise InputError("bounds", list(bounds), "must be (xmin, ymin, xmax, ymax)")
    x0, y0, x1, y1 = (float(b) for b in bounds)
    if not all(map(math.isfinite, (x0, y0, x1, y1))) or x1 <= x0 or y1 <= y0:
        raise InputError("bounds", [x0, y0, x1, y1], "must be finite with xmin < xmax, "
                         "ymin < ymax")
    return x0, y0, x1, y1


def fit_pose(lo: Sequence[float], hi: Sequence[float], direction: Sequence[float], *,
             margin: float = 0.95, aspect: float = 1.6, fov: float = CAMERA_FOV) -> CameraPose:
    """The closest view along ``direction`` holding the box ``lo``..``hi`` (m) in the pane.

    The camera looks at the box's centre from ``direction`` (target to eye); every corner
    projects within ``margin`` of the pane's edges (pinhole camera, vertical field of view
    ``fov`` deg, ``aspect`` width/height), with at least 0.3 m in front of the camera.
    """
    lo_, hi_ = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
    c = 0.5 * (lo_ + hi_)
    d = np.asarray(direction, dtype=float)
    d = d / np.linalg.norm(d)
    f = -d
    r = np.cross(f, [0.0, 0.0, 1.0])
    r = r / np.linalg.norm(r) if np.linalg.norm(r) > 1e-9 else np.array([1.0, 0.0, 0.0])
    u = np.cross(r, f)
    tv = math.tan(math.radians(fov) / 2)
    corners = np.array([[x, y, z] for x in (lo_[0], hi_[0]) for y in (lo_[1], hi_[1])
                        for z in (lo_[2], hi_[2])]) - c
    z0 = corners @ f
    dist = max(0.5, float(np.max(np.maximum.reduce([
        np.abs(corners @ r) / (margin * tv * aspect) - z0,
        np.abs(corners @ u) / (margin * tv) - z0, 0.3 - z0]))))
    eye = c + dist * d
    return CameraPose((float(c[0]), float(c[1]), float(c[2])),
                      (float(eye[0]), float(eye[1]), float(eye[2])))


def overview_pose(bounds: Sequence[float], *, height: float = 1.5,
                  aspect: float = 1.6) -> CameraPose:
    """The scene's bounds (up to ``height``, m) framed from a three-quarter view."""
    x0, y0, x1, y1 = _check_bounds(bounds)
    return fit_pose((x0, y0, 0.0), (x1, y1, height), THREE_QUARTER, aspect=aspect)


def top_pose(bounds: Sequence[float], *, height: float = 1.5,
             aspect: float = 1.6) -> CameraPose:
    """The whole floor seen from straight above."""
    x0, y0, x1, y1 = _check_bounds(bounds)
    d = 0.55 * max(y1 - y0, (x1 - x0) / aspect) / math.tan(math.radians(CAMERA_FOV) / 2) \
        + height
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return CameraPose((cx, cy, 0.0), (cx, cy - 1e-3 * d, d))


def _points(points: object) -> np.ndarray:
    """``points`` as a finite ``(N, 3)`` array (N >= 1), else :class:`InputError`."""
    try:
        p = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError("points", type(points).__name__, "must be an (N, 3) array of numbers") \
            from None
    if p.size == 0 or p.size % 3:
        raise InputError("points", list(p.shape), "must be an (N, 3) array, N >= 1")
    p = p.reshape(-1, 3)
    if not np.all(np.isfinite(p)):
        raise InputError("points", "NaN or infinity", "must be finite (m)")
    return p


def follow_pose(points: np.ndarray, *, aspect: float = 1.6) -> CameraPose:
    """Robot and box framed from a three-quarter view, with 0.6 m of context around.

    ``points`` ``(N, 3)``: points of both (e.g. corners of their bounding boxes, m).
    """
    p = _points(points)
    lo, hi = p.min(axis=0), p.max(axis=0)
    c = 0.5 * (lo + hi)
    ctx = np.array([0.6, 0.6, 0.4])
    return fit_pose(np.minimum(lo, c - ctx), np.maximum(hi, c + ctx), THREE_QUARTER,
                    margin=0.9, aspect=aspect)


def look_at(vis: meshcat.Visualizer, pose: CameraPose) -> None:
    """Put meshcat's default camera (``/Cameras/default``) at ``pose.eye``.

    meshcat's own page orbits about the scene origin and offers no command to move that
    centre, so a bare meshcat viewer looks towards the origin from ``pose.eye``; the replay
    pages (:func:`~pivot_ompl.viz.html.write_html`, :func:`~pivot_ompl.viz.serve.serve`)
    place eye and target exactly. ``vis`` must share the root of the scene.
    """
    root = meshcat.Visualizer.view_into(vis.window, vis.path.append("/Cameras/default"))
    root.set_transform(np.eye(4))
    x, y, z = pose.eye
    # The camera's "rotated" frame is y-up: world (x, y, z) is (x, z, -y) there.
    root["rotated/<object>"].set_property("position", [x, z, -y])


def frame_scene(vis: meshcat.Visualizer, bounds: Sequence[float], *,
                height: float = 1.5) -> CameraPose:
    """Look at the whole scene from a three-quarter view (the view a replay opens with)."""
    pose = overview_pose(bounds, height=height)
    look_at(vis, pose)
    return pose


def top_view(vis: meshcat.Visualizer, bounds: Sequence[float], *,
             height: float = 1.5) -> CameraPose:
    """Look at the whole floor from above."""
    pose = top_pose(bounds, height=height)
    look_at(vis, pose)
    return pose


def follow_view(vis: meshcat.Visualizer, points: np.ndarray) -> CameraPose:
    """Frame robot and box given by ``points`` ``(N, 3)`` (one view; the page follows live)."""
    pose = follow_pose(points)
    look_at(vis, pose)
    return pose
