"""The object roadmap: box poses with a label, nearest-neighbour queries and components.

The box is symmetric under a half turn: object yaw ``t`` with grasp ``k`` and yaw ``t + pi``
with grasp ``k + 2`` are the same car, robot pose and pivots (:func:`half_turn`,
:func:`canonical`). Neighbours are therefore found with yaw modulo pi (:func:`pose_metric`).
"""

from __future__ import annotations

import math

import numpy as np

from pivot_ompl.graph import UnionFind, astar
from pivot_ompl.planners.objects.nearest import PoseTree, smallest
from pivot_ompl.se2 import Pose

#: Weight of yaw in the nearest-neighbour metric (m per rad).
YAW_WEIGHT = 0.5


def canonical_yaw(yaw: float) -> tuple[float, int]:
    """The box's yaw modulo pi, in ``[-pi/2, pi/2)``, and the grasp shift (0 or 2) it implies."""
    c = (yaw + 0.5 * math.pi) % math.pi - 0.5 * math.pi
    return c, (0 if abs(math.remainder(c - yaw, 2 * math.pi)) < 1.0 else 2)


def half_turn(pose: Pose) -> Pose:
    """The same box turned by pi (with grasp ``k + 2`` it is the same physical state)."""
    return (pose[0], pose[1], math.remainder(pose[2] + math.pi, 2 * math.pi))


def canonical(pose: Pose) -> Pose:
    """``pose`` with its yaw taken modulo pi (see :func:`canonical_yaw`)."""
    return (pose[0], pose[1], canonical_yaw(pose[2])[0])


def pose_metric(a: np.ndarray, b: Pose) -> np.ndarray:
    """Cheap metric between an array of poses ``a`` (N x 3) and pose ``b`` (m).

    Yaw differences are taken modulo pi (the box's half-turn symmetry: the grasps cover the
    rest).
    """
    dyaw = np.abs((a[:, 2] - b[2] + 0.5 * math.pi) % math.pi - 0.5 * math.pi)
    return np.hypot(a[:, 0] - b[0], a[:, 1] - b[1]) + YAW_WEIGHT * dyaw


class Roadmap:
    """Object poses with a label (``"guard"``, ``"slot"``, ...), edges and components.

    Attributes:
        poses: the nodes' object poses, by index.
        kinds: each node's label.
        edges: the visibility edges ``(i, j)``.
    """

    poses: list[Pose]
    kinds: list[str]
    edges: list[tuple[int, int]]
    _arr: np.ndarray
    _components: UnionFind[int]
    _tree: PoseTree

    def __init__(self) -> None:
        """An empty roadmap."""
        self.poses = []
        self.kinds = []
        self.edges = []
        self._arr = np.zeros((64, 3))
        self._components = UnionFind()
        self._tree = PoseTree(pose_metric, yaw_weight=YAW_WEIGHT)

    def __len__(self) -> int:
        """Number of nodes."""
        return len(self.poses)

    def __getitem__(self, i: int) -> Pose:
        """The pose of node ``i``."""
        return self.poses[i]

    def add(self, pose: Pose, kind: str) -> int:
        """Add a node; return its index."""
        i = len(self.poses)
        if i >= len(self._arr):
            self._arr = np.concatenate([self._arr, np.zeros_like(self._arr)])
        self._arr[i] = pose
        self.poses.append(pose)
        self.kinds.append(kind)
        self._components.add(i)
        self._tree.add(i, pose)
        return i

    def connect(self, i: int, j: int) -> None:
        """Add edge ``i - j`` and merge their components."""
        self.edges.append((i, j))
        self._components.union(i, j)

    def component(self, i: int) -> int:
        """Representative of ``i``'s connected component."""
        return self._components.find(i)

    def path(self, i: int, j: int) -> list[int]:
        """Fewest edges from node ``i`` to node ``j`` (``[]`` if not connected)."""
        if self.component(i) != self.component(j):
            return []
        adjacent: dict[int, list[int]] = {}
        for a, b in self.edges:
            adjacent.setdefault(a, []).append(b)
            adjacent.setdefault(b, []).append(a)
        return astar([i], {j}, lambda n: ((m, 1.0) for m in adjacent.get(n, ())),
                     lambda n: 0.0)

    def of_kind(self, kind: str) -> list[int]:
        """Indices of the nodes labelled ``kind``."""
        return [i for i, k in enumerate(self.kinds) if k == kind]

    def nearest(self, pose: Pose, k: int, *,
                among: list[int] | PoseIndex | None = None) -> list[int]:
        """Indices of the ``k`` nodes nearest to ``pose`` (optionally among a subset).

        Nearest first by :func:`pose_metric`, ties by index; over every node or a
        :class:`PoseIndex`, a k-d tree query (:mod:`.nearest`), over a list a scan of it.
        """
        if not self.poses:
            return []
        if isinstance(among, PoseIndex):
            return among.nearest(pose, k)
        if among is None:
            return self._tree.nearest(pose, k)
        if not among:
            return []
        idx = np.sort(np.asarray(among))
        return [int(idx[i]) for i in smallest(pose_metric(self._arr[idx], pose), k)]

    def distances(self, indices: list[int], pose: Pose) -> np.ndarray:
        """:func:`pose_metric` from the nodes ``indices`` to ``pose``."""
        return pose_metric(self._arr[np.asarray(indices, dtype=int)], pose)


class PoseIndex:
    """A growing subset of a roadmap's nodes with exact nearest queries (:mod:`.nearest`).

    Args:
        roadmap: the roadmap whose node indices it holds.
    """

    def __init__(self, roadmap: Roadmap) -> None:
        """An empty subset."""
        self.roadmap = roadmap
        self.items: list[int] = []
        self._tree = PoseTree(pose_metric, yaw_weight=YAW_WEIGHT)

    def __len__(self) -> int:
        """Number of nodes held."""
        return len(self.items)

    def append(self, i: int) -> None:
        """Add node ``i``."""
        self.items.append(i)
        self._tree.add(i, self.roadmap.poses[i])

    def nearest(self, pose: Pose, k: int) -> list[int]:
        """The ``k`` held nodes nearest to ``pose`` by :func:`pose_metric`, nearest first.

        Ties by the order the nodes were appended.
        """
        return self._tree.nearest(pose, k)

    def any_within(self, pose: Pose, radius: float) -> bool:
        """Whether a held node lies nearer than ``radius`` to ``pose`` (:func:`pose_metric`)."""
        return self._tree.any_within(pose, radius)
