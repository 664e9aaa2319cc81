"""Exact nearest box poses by the roadmap's pose metric, on a k-d tree that grows in batches.

The metric (:func:`~.roadmap.pose_metric`) is the floor distance plus ``YAW_WEIGHT`` times the
yaw difference modulo pi: not a norm, so no tree searches it directly. Each pose is embedded
as ``(x, y, r cos 2 yaw, r sin 2 yaw)`` with ``r = YAW_WEIGHT / 2``; two poses' Euclidean
distance there is ``sqrt(d^2 + (2 r sin dyaw)^2) <= d + YAW_WEIGHT dyaw``, at most their
metric. A query therefore takes the ``k`` tree neighbours in the embedding, measures their
metric, and gathers every pose within the ``k``-th of those values in the embedding (a ball
query): a superset of the true ``k`` nearest, which are then picked exactly. The answer is
the brute-force scan's (ties by insertion order).

scipy's ``cKDTree`` is static: nodes added since the last build (the *tail*) are scanned with
numpy, and the tree is built again once the tail reaches ``1 / REBUILD`` of the nodes (at least
:data:`SCAN`): about ``REBUILD n`` points built in all over ``n`` insertions (a build of 40 000
takes about 0.02 s), while a query scans at most that share of the nodes. OMPL's
``NearestNeighborsGNAT`` (exact too: the pose metric is a metric) would call the metric in
Python once per node it visits (its distance is a callback, ~1 us a call before any work).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from pivot_ompl.se2 import Pose

if TYPE_CHECKING:
    from scipy.spatial import cKDTree

#: Below this many poses a query scans them all.
SCAN = 256
#: The tree is built again once the nodes added since its last build reach this fraction
#: (1 / REBUILD) of it: about ``REBUILD n`` points built in all, a query scans ``n / REBUILD``.
REBUILD = 32
#: Relative slack of the ball query's radius (round-off of the embedding's distances).
SLACK = 1e-9


class PoseTree:
    """A growing set of poses (by caller's index) with exact ``k``-nearest queries.

    Args:
        metric: ``(poses N x 3, pose) -> N`` distances, at least the embedding's distance
            (module docstring).
        yaw_weight: the metric's metres per radian of yaw (modulo pi).
    """

    def __init__(self, metric: Callable[[np.ndarray, Pose], np.ndarray], *,
                 yaw_weight: float) -> None:
        """An empty set."""
        self.metric = metric
        self.radius = 0.5 * yaw_weight
        self._ids = np.zeros(64, dtype=np.int64)
        self._poses = np.zeros((64, 3))
        self._n = 0
        self._built = 0
        self._tree: cKDTree | None = None
        self.rebuilds = 0

    def __len__(self) -> int:
        """Number of poses held."""
        return self._n

    def add(self, i: int, pose: Pose) -> None:
        """Hold ``pose`` under index ``i``."""
        n = self._n
        if n >= len(self._ids):
            self._ids = np.concatenate([self._ids, np.zeros_like(self._ids)])
            self._poses = np.concatenate([self._poses, np.zeros_like(self._poses)])
        self._ids[n] = i
        self._poses[n] = pose
        self._n = n + 1
        if n + 1 - self._built >= max(SCAN, self._built // REBUILD):
            self._build()

    def _embed(self, poses: np.ndarray) -> np.ndarray:
        r, a = self.radius, 2.0 * poses[:, 2]
        return np.column_stack([poses[:, 0], poses[:, 1], r * np.cos(a), r * np.sin(a)])

    def _build(self) -> None:
        # scipy.spatial costs a process ~0.05 s to import: only a roadmap past SCAN poses needs it
        from scipy.spatial import cKDTree

        self._built = self._n
        self._tree = cKDTree(self._embed(self._poses[:self._n]))
        self.rebuilds += 1

    def nearest(self, pose: Pose, k: int) -> list[int]:
        """The indices of the ``k`` poses nearest to ``pose``, nearest first."""
        n = self._n
        if n == 0 or k <= 0:
            return []
        tree, built = self._tree, self._built
        if tree is None or n <= SCAN:
            return self._ids[smallest(self.metric(self._poses[:n], pose), k)].tolist()
        tail = np.arange(built, n)
        r, a = self.radius, 2.0 * pose[2]
        e = (pose[0], pose[1], r * math.cos(a), r * math.sin(a))
        _, near = tree.query(e, k=min(k, built))
        near = np.atleast_1d(near)
        first = np.concatenate([near, tail])
        d = self.metric(self._poses[first], pose)
        bound = float(np.partition(d, min(k, len(d)) - 1)[min(k, len(d)) - 1])
        ball = tree.query_ball_point(e, bound * (1.0 + SLACK) + SLACK, return_sorted=True)
        cand = np.concatenate([np.asarray(ball, dtype=np.int64), tail])
        return self._best(cand, pose, k)

    def any_within(self, pose: Pose, radius: float) -> bool:
        """Whether a held pose lies nearer than ``radius`` to ``pose`` (by the metric).

        One ball query of that radius in the embedding (a superset: the embedding's
        distance is at most the metric) and the tail, measured exactly: the answer of
        :meth:`nearest`'s first pose compared with ``radius``, without its k-nearest query.
        """
        n = self._n
        if n == 0:
            return False
        tree, built = self._tree, self._built
        if tree is None or n <= SCAN:
            rows = np.arange(n)
        else:
            r, a = self.radius, 2.0 * pose[2]
            e = (pose[0], pose[1], r * math.cos(a), r * math.sin(a))
            ball = tree.query_ball_point(e, radius * (1.0 + SLACK) + SLACK)
            rows = np.concatenate([np.asarray(ball, dtype=np.int64), np.arange(built, n)])
        return bool(len(rows)) and bool(np.any(self.metric(self._poses[rows], pose) < radius))

    def _best(self, rows: np.ndarray, pose: Pose, k: int) -> list[int]:
        """The ``k`` of ``rows`` (ascending) nearest to ``pose``: ties by insertion order."""
        d = self.metric(self._poses[rows], pose)
        return self._ids[rows[smallest(d, k)]].tolist()


def smallest(d: np.ndarray, k: int) -> np.ndarray:
    """Indices of the ``k`` smallest values of ``d``, increasing, ties by position."""
    if k >= len(d) or len(d) <= 4 * SCAN:  # a sort is cheapest on few values
        return np.argsort(d, kind="stable")[:k]
    kth = np.partition(d, k - 1)[k - 1]
    below = np.flatnonzero(d < kth)
    tied = np.flatnonzero(d == kth)[:k - len(below)]
    part = np.concatenate([below, tied])
    return part[np.argsort(d[part], kind="stable")]
