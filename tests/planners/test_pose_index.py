"""PoseIndex: exact nearest nodes by the roadmap's pose metric, wherever the query is."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.planners.objects.roadmap import PoseIndex, Roadmap


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
