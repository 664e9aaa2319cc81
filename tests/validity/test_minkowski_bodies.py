"""Sums of many (piece, body) pairs whose bodies repeat: each body's own terms computed once.

A body passed many times (one array per yaw, repeated for every piece) has its reflection,
edge normals and short-edge test computed once; every pair's sum must be the one it has
alone, whatever the other pairs, whether bodies are one object repeated or equal copies.
"""

from __future__ import annotations

import numpy as np
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.validity.minkowski import meeting_edges


def _convex(rng: np.random.Generator, sides: int, size: float) -> np.ndarray:
    """A random convex polygon's vertices (counter-clockwise or clockwise)."""
    pts = rng.uniform(-size, size, (sides + 3, 2))
    ring = np.asarray(shapely.MultiPoint(pts).convex_hull.exterior.coords)[:-1]
    return ring if rng.uniform() < 0.5 else ring[::-1].copy()


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), certify=st.booleans())
def test_each_pair_is_summed_as_alone_whatever_the_bodies_repeated(seed, certify):
    rng = np.random.default_rng(seed)
    pieces = [_convex(rng, int(rng.integers(1, 6)), 1.0) + rng.uniform(-5, 5, 2)
              for _ in range(12)]
    bodies = [_convex(rng, int(rng.integers(1, 8)), 0.5) for _ in range(4)]
    pairs = [(int(rng.integers(len(pieces))), int(rng.integers(len(bodies))))
             for _ in range(60)]
    copies = rng.uniform(size=len(pairs)) < 0.3  # some bodies an equal copy, not the object
    got = meeting_edges([pieces[i] for i, _ in pairs],
                        [bodies[j].copy() if c else bodies[j]
                         for (_, j), c in zip(pairs, copies, strict=True)], certify=certify)
    for row, (i, j) in enumerate(pairs):
        alone = meeting_edges([pieces[i]], [bodies[j]], certify=certify)
        used = got.used[row]
        assert np.array_equal(got.start[row][used], alone.start[0][alone.used[0]])
        assert np.array_equal(got.end[row][used], alone.end[0][alone.used[0]])
        assert np.array_equal(got.bounds[row], alone.bounds[0])
