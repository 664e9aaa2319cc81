"""Sampled valid states against a relaxation's cover (the bounds' soundness tests)."""

from __future__ import annotations

import math

import numpy as np

from pivot_ompl.checking.pivot_checker import PivotChecker


def near_contact_states_covered(scene, cover, *, samples: int, seed: int) -> int:
    """Assert every sampled valid state at every grasp lies in ``cover``; the count of those
    within 3 cm of contact (where a too small erosion would show)."""
    ck = PivotChecker(scene, seed=0)
    rng = np.random.default_rng(seed)
    x0, y0, x1, y1 = scene.bounds
    near = 0
    for _ in range(samples):
        q = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
             float(rng.uniform(-math.pi, math.pi)))
        for g in range(4):
            c = ck.clearance(q, g)
            if c > 0:
                near += c < 0.03
                assert cover.covers(q, g), (q, g, c)
    return near
