"""PoseIndex: exact nearest nodes by the roadmap's pose metric, wherever the query is."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.planners.objects.nearest import PoseTree
from pivot_ompl.planners.objects.roadmap import YAW_WEIGHT, PoseIndex, Roadmap, pose_metric


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 1500), k=st.integers(1, 12),
       spread=st.sampled_from([0.5, 5.0, 80.0]))
def test_nearest_equals_a_scan_of_every_node(seed: int, n: int, k: int, spread: float) -> None:
    rng = np.random.default_rng(seed)
    rm = Roadmap()
    index = PoseIndex(rm)
    held: list[int] = []
    for _ in range(n):
        # clustered poses, some on exactly the same spot (ties), far queries included
        xy = rng.normal(0.0, spread, 2) if rng.random() < 0.8 else rng.integers(-3, 3, 2) * 1.0
        i = rm.add((float(xy[0]), float(xy[1]), float(rng.uniform(-math.pi, math.pi))), "x")
        if rng.random() < 0.7:  # a subset of the roadmap's nodes
            index.append(i)
            held.append(i)
    for _ in range(20):
        q = rng.normal(0.0, 3 * spread, 2)
        pose = (float(q[0]), float(q[1]), float(rng.uniform(-math.pi, math.pi)))
        assert index.nearest(pose, k) == rm.nearest(pose, k, among=held)


def _scan(poses: np.ndarray, pose: tuple[float, float, float], k: int) -> list[int]:
    """The reference: every node's metric, sorted by (distance, index)."""
    d = pose_metric(poses, pose)
    return [int(i) for i in np.lexsort((np.arange(len(d)), d))[:k]]


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(1, 3000), k=st.integers(1, 12),
       spread=st.sampled_from([0.2, 5.0, 80.0]), dup=st.floats(0.0, 0.5))
def test_roadmap_nearest_is_the_brute_force_scan(seed: int, n: int, k: int, spread: float,
                                                 dup: float) -> None:
    # the k-d tree over every node, queried while it grows (tail scanned, rebuilt in
    # batches): the same nodes in the same order as a scan of all of them, ties included
    rng = np.random.default_rng(seed)
    rm = Roadmap()
    for step in range(n):
        if step and rng.random() < dup:  # the same pose again, or its half turn
            x, y, t = rm.poses[int(rng.integers(step))]
            t = t if rng.random() < 0.5 else math.remainder(t + math.pi, 2 * math.pi)
        else:
            x, y = (float(v) for v in rng.normal(0.0, spread, 2))
            t = float(rng.uniform(-math.pi, math.pi))
        rm.add((x, y, t), "x")
        if step % 97 == 0 or step == n - 1:
            arr = np.array(rm.poses)
            for _ in range(4):
                if rng.random() < 0.5:
                    q = rm.poses[int(rng.integers(len(rm)))]  # on a node: exact ties
                else:
                    xy = rng.normal(0.0, 2 * spread, 2)
                    q = (float(xy[0]), float(xy[1]), float(rng.uniform(-math.pi, math.pi)))
                assert rm.nearest(q, k) == _scan(arr, q, k)


def test_a_query_measures_a_small_part_of_a_large_roadmap() -> None:
    # the point of the tree: at 20 000 nodes a query measures the metric on a few hundred
    # (the tail since the last build and the ball round the query), not on every node
    rng = np.random.default_rng(7)
    rows: list[int] = []

    def counted(a: np.ndarray, b: tuple[float, float, float]) -> np.ndarray:
        rows.append(len(a))
        return pose_metric(a, b)

    tree = PoseTree(counted, yaw_weight=YAW_WEIGHT)
    poses = np.column_stack([rng.uniform(0, 20, 20_000), rng.uniform(0, 20, 20_000),
                             rng.uniform(-math.pi, math.pi, 20_000)])
    for i, p in enumerate(poses):
        tree.add(i, (float(p[0]), float(p[1]), float(p[2])))
    rows.clear()
    for q in poses[:50]:
        pose = (float(q[0]) + 0.01, float(q[1]), float(q[2]))
        assert tree.nearest(pose, 10) == _scan(poses, pose, 10)
    assert sum(rows) / 50 < 0.05 * len(poses)


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), n=st.integers(0, 1200),
       radius=st.sampled_from([0.01, 0.1, 0.5, 3.0]))
def test_any_within_is_the_nearest_node_compared_with_the_radius(seed: int, n: int,
                                                                 radius: float) -> None:
    # the seeding's duplicate test: a held node nearer than the radius, by the pose metric,
    # wherever it lies (the k-d tree's built part or the tail added since)
    rng = np.random.default_rng(seed)
    rm = Roadmap()
    index = PoseIndex(rm)
    for _ in range(n):
        xy = rng.normal(0.0, 2.0, 2)
        index.append(rm.add((float(xy[0]), float(xy[1]),
                             float(rng.uniform(-math.pi, math.pi))), "x"))
    for _ in range(40):
        q = rng.normal(0.0, 2.0, 2)
        pose = (float(q[0]), float(q[1]), float(rng.uniform(-math.pi, math.pi)))
        near = index.nearest(pose, 1)
        truth = bool(near) and float(rm.distances(near, pose)[0]) < radius
        assert index.any_within(pose, radius) == truth
