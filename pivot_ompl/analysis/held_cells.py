"""Floor cells no held pose of the box can occupy: a conservative test, cell by cell.

The box moves only while the robot holds it, so every position its centre takes on any plan
is the centre of a *held pose*: the box at some yaw, held at some grasp, with both floor
bodies the checkers test (:func:`~pivot_ompl.analysis.regrasp_bound.held_bodies`: the box's
footprint and the holding robot's convex hull) kept the clearance ``c`` from the obstacles
(less the swept checks' tolerance ``tol``) and inside the bounds (less ``tol``), as in the
regrasp relaxation (:mod:`~pivot_ompl.analysis.regrasp_bound`). :class:`HeldCells` proves,
for a square cell, that *no* point of it is such a centre, at any yaw and any grasp.

**A voxel's test.** A voxel is a square of centre ``p`` and half-diagonal ``rho`` times a yaw
interval of centre ``t`` and half-width ``d``. A body ``B`` (convex, box frame) of a pose
``(q, phi)`` of the voxel is ``q + R(phi) B``; the map sending ``p + R(t) x`` to
``q + R(phi) x`` moves no point of ``B`` by more than ``e = rho + 2 r sin(d / 2)`` (``r``: the
body's farthest point from the box's centre), so (Brouwer's argument, as in
:mod:`~pivot_ompl.analysis.regrasp_bound`) ``p + R(t) B`` eroded by ``e`` lies inside
``q + R(phi) B``. The same holds for ``B`` grown by ``c - tol``. So if that grown body,
eroded by ``e`` (a net offset) and placed at ``(p, t)``, meets an obstacle piece (pieces are
subsets of the obstacles: :func:`~pivot_ompl.validity.footprints.obstacle_pieces`), the body
of every pose of the voxel comes closer than ``c - tol`` to an obstacle; and if ``B`` eroded
by ``e + tol`` at ``(p, t)`` reaches outside the bounds, so does every pose's body: no pose
of the voxel is held. Growth by the offset's chords and the exact inward offset are subsets
of the true offsets, so the test stays on the safe side; the bodies are offset once at yaw 0
and then turned (offsets commute with rotations), and :data:`ROUND_OFF` is added to every
erosion.

**Refinement.** A cell is first tried at :data:`FIRST_YAWS` yaw intervals per grasp parity
(grasp ``k + 2`` is grasp ``k`` a half turn on, so two parities over every yaw are all four
grasps); a voxel not closed is split, its square in four or its yaw interval in two,
whichever term of ``e`` is larger, until ``e`` is at most :data:`FINEST` m. The cell is
closed when every voxel is. It is given up (left open: never wrong) when a voxel at the
finest ``e`` is not closed, or when the pose at a voxel's centre has its grown bodies clear
of every obstacle and inside the bounds (every finer voxel holding that pose tests a subset
of those bodies, so none would close), which ends most cells of open floor at once.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely

from pivot_ompl.analysis.regrasp_bound import ROUND_OFF, Body, held_bodies
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.merge import merge_boxes

__all__ = ["FINEST", "FIRST_YAWS", "HeldCells"]

#: Yaw intervals per grasp parity a cell is first tried at.
FIRST_YAWS = 32
#: Largest erosion (m) of a voxel's test at the finest split (square and yaw together).
FINEST = 0.005
#: Cells tested together (the stop is polled between batches and between levels).
BATCH = 256
#: Bounds' round-off margin (m): a body's point beyond the bounds by less is taken inside.
EPS = 1e-9


class HeldCells:
    """The conservative held-pose test of floor cells of ``scene`` (module docstring).

    Args:
        scene: the scene.
        tolerance: the swept checks' tolerance (m).
        clearance: distance (m) the checkers keep every body from the obstacles.
        finest: largest erosion (m) of the finest voxels (:data:`FINEST`).

    Attributes:
        reach: the farthest point (m) of any held body from the box's centre.
        voxels: voxels tested so far (a figure of the work done).
    """

    def __init__(self, scene: Scene, *, tolerance: float = SWEEP_TOLERANCE,
                 clearance: float = KEEP_CLEARANCE, finest: float | None = None,
                 should_stop: Callable[[], bool] | None = None) -> None:
        """The bodies and the obstacle pieces (touching boxes merged) of ``scene``.

        Raises:
            Interrupted: ``should_stop()`` said stop while the boxes were merged.
        """
        self.bounds = scene.bounds
        self.tolerance, self.clearance = tolerance, clearance
        self.finest = FINEST if finest is None else finest
        self.bodies: dict[int, list[Body]] = {g: held_bodies(scene, g) for g in (0, 1)}
        self.reach = max(b.reach for parts in self.bodies.values() for b in parts)
        pieces = obstacle_pieces(merge_boxes(scene.obstacles, should_stop=should_stop))
        self._tree = shapely.STRtree(_polygons(pieces)) if pieces else None
        self._shapes: dict[tuple[int, int, float], np.ndarray | None] = {}
        self.voxels = 0

    def closed(self, x: np.ndarray, y: np.ndarray, half: float, *,
               should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Whether each square cell is proven to hold no held pose's centre.

        ``(x, y)``: the cells' centres (m); ``half``: their half side (m). A boolean array
        (``False``: not proven).

        Raises:
            Interrupted: ``should_stop()`` said stop (polled between batches and levels).
        """
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        out = np.zeros(len(x), dtype=bool)
        for a in range(0, len(x), BATCH):
            out[a:a + BATCH] = self._batch(x[a:a + BATCH], y[a:a + BATCH], half, should_stop)
        return out

    def _batch(self, cx: np.ndarray, cy: np.ndarray, half: float,
               should_stop: Callable[[], bool] | None) -> np.ndarray:
        """:meth:`closed` of a batch of cells, all voxels of a level tested together."""
        n = len(cx)
        alive = np.ones(n, dtype=bool)  # not yet found open
        yaws = -math.pi + (np.arange(FIRST_YAWS) + 0.5) * (2.0 * math.pi / FIRST_YAWS)
        k = np.repeat(np.arange(n), 2 * FIRST_YAWS)
        g = np.tile(np.repeat(np.array([0, 1]), FIRST_YAWS), n)
        t = np.tile(np.concatenate([yaws, yaws]), n)
        x, y = cx[k], cy[k]
        s, d = half, math.pi / FIRST_YAWS
        # the first level's centres probed first, every fourth yaw then the rest: most cells
        # tried are open floor, ended here
        some = (np.arange(len(k)) % FIRST_YAWS) % 4 == 0
        for which in (some, ~some):
            which = which & alive[k]
            alive[np.unique(k[self._clear(g, x, y, t, which)])] = False
        keep = alive[k]
        k, g, x, y, t = k[keep], g[keep], x[keep], y[keep], t[keep]
        first = True
        while len(k):
            if should_stop is not None and should_stop():
                raise Interrupted("the held cells' test")
            self.voxels += len(k)
            rho, turn = s * math.sqrt(2.0), 2.0 * self.reach * math.sin(0.5 * d)
            shut = self._shut(g, x, y, t, rho, d)
            left = ~shut
            if not first:
                alive[np.unique(k[left & self._clear(g, x, y, t, left)])] = False
            first = False
            if rho + turn <= self.finest:
                alive[np.unique(k[left])] = False
                break
            keep = left & alive[k]
            k, g, x, y, t = k[keep], g[keep], x[keep], y[keep], t[keep]
            if rho >= turn:  # split the square in four
                s *= 0.5
                ox, oy = np.array([-s, -s, s, s]), np.array([-s, s, -s, s])
                x = (x[:, None] + ox).ravel()
                y = (y[:, None] + oy).ravel()
                k, g, t = np.repeat(k, 4), np.repeat(g, 4), np.repeat(t, 4)
            else:  # split the yaw interval in two
                d *= 0.5
                t = (t[:, None] + np.array([-d, d])).ravel()
                k, g, x, y = np.repeat(k, 2), np.repeat(g, 2), np.repeat(x, 2), np.repeat(y, 2)
        return alive

    def _shut(self, g: np.ndarray, x: np.ndarray, y: np.ndarray, t: np.ndarray, rho: float,
              d: float) -> np.ndarray:
        """Whether each voxel holds no held pose (module docstring).

        Voxels of centre ``(x, y, t)``, half-diagonal ``rho`` (m) and yaw half-width ``d``.
        """
        shut = np.zeros(len(g), dtype=bool)
        for gg in (0, 1):
            for part, body in reversed(list(enumerate(self.bodies[gg]))):  # the robot first
                idx = np.flatnonzero((g == gg) & ~shut)
                if not len(idx):
                    break
                e = rho + 2.0 * body.reach * math.sin(0.5 * d) + ROUND_OFF
                hit = self._meets(gg, part, e + self.tolerance - self.clearance,
                                  x[idx], y[idx], t[idx])
                hit |= self._outside(gg, part, e + self.tolerance, x[idx], y[idx], t[idx])
                shut[idx[hit]] = True
        return shut

    def _clear(self, g: np.ndarray, x: np.ndarray, y: np.ndarray, t: np.ndarray,
               which: np.ndarray) -> np.ndarray:
        """Whether the pose at each voxel's centre (where ``which``) is clear.

        Its bodies grown by the clearance less the tolerance clear of the obstacles, and
        inside the bounds.
        """
        clear = which.copy()
        for gg in (0, 1):
            for part in range(len(self.bodies[gg])):
                idx = np.flatnonzero((g == gg) & clear)
                if not len(idx):
                    break
                hit = self._meets(gg, part, self.tolerance - self.clearance, x[idx], y[idx],
                                  t[idx])
                hit |= self._outside(gg, part, self.tolerance, x[idx], y[idx], t[idx])
                clear[idx[hit]] = False
        return clear

    def _shape(self, g: int, part: int, d: float) -> np.ndarray | None:
        """Part ``part`` of parity ``g`` at yaw 0 offset by ``d`` (> 0 erodes; ``None``: empty)."""
        key = (g, part, d)
        if key not in self._shapes:
            self._shapes[key] = self.bodies[g][part].offset_points(0.0, d)
        return self._shapes[key]

    def _placed(self, g: int, part: int, d: float, x: np.ndarray, y: np.ndarray,
                t: np.ndarray) -> np.ndarray | None:
        """The offset part's vertices at each pose (``(len(x), m, 2)``; ``None``: empty)."""
        e = self._shape(g, part, d)
        if e is None:
            return None
        c, s = np.cos(t)[:, None], np.sin(t)[:, None]
        return np.stack([x[:, None] + c * e[:, 0] - s * e[:, 1],
                         y[:, None] + s * e[:, 0] + c * e[:, 1]], axis=2)

    def _meets(self, g: int, part: int, d: float, x: np.ndarray, y: np.ndarray,
               t: np.ndarray) -> np.ndarray:
        """Whether the offset part at each pose meets an obstacle piece."""
        out = np.zeros(len(x), dtype=bool)
        pts = self._placed(g, part, d, x, y, t)
        if pts is None or self._tree is None:
            return out
        out[self._tree.query(shapely.polygons(pts), predicate="intersects")[0]] = True
        return out

    def _outside(self, g: int, part: int, d: float, x: np.ndarray, y: np.ndarray,
                 t: np.ndarray) -> np.ndarray:
        """Whether the part eroded by ``d`` at each pose has a point beyond the bounds."""
        pts = self._placed(g, part, d, x, y, t)
        if pts is None:
            return np.zeros(len(x), dtype=bool)
        x0, y0, x1, y1 = self.bounds
        return ((pts[..., 0].min(axis=1) < x0 - EPS) | (pts[..., 0].max(axis=1) > x1 + EPS)
                | (pts[..., 1].min(axis=1) < y0 - EPS) | (pts[..., 1].max(axis=1) > y1 + EPS))


def _polygons(pieces: list[np.ndarray]) -> np.ndarray:
    """The pieces as shapely polygons, made together per vertex count (thousands of boxes)."""
    out = np.empty(len(pieces), dtype=object)
    sizes = np.array([len(p) for p in pieces])
    for m in np.unique(sizes):
        idx = np.flatnonzero(sizes == m)
        out[idx] = shapely.polygons(np.stack([pieces[i] for i in idx]))
    return out
