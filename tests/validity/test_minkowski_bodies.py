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
    _each_as_alone(got, pieces, bodies, pairs, certify)


def _box(rng: np.random.Generator) -> np.ndarray:
    """A wall box of random size and place: axis-aligned mostly, its corners from any one."""
    w, d = rng.uniform(0.05, 3.0, 2)
    c = rng.uniform(-20, 20, 2)
    corners = c + np.array([[-w, -d], [w, -d], [w, d], [-w, d]]) / 2
    if rng.uniform() < 0.2:  # turned
        a = rng.uniform(0, np.pi)
        rot = np.array([[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]])
        corners = c + (corners - c) @ rot.T
    corners = np.roll(corners, int(rng.integers(4)), axis=0)
    return corners if rng.uniform() < 0.8 else corners[::-1].copy()


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), certify=st.booleans())
def test_wall_boxes_sharing_their_normals_are_each_summed_as_alone(seed, certify):
    # wall boxes of any size and place have equal edge normals: their sums' vertex slots
    # are computed once per class of equal normals and gathered; each must be its own
    rng = np.random.default_rng(seed)
    pieces = [_box(rng) for _ in range(40)]
    bodies = [_convex(rng, int(rng.integers(3, 12)), 0.5) for _ in range(3)]
    pairs = [(i, int(rng.integers(len(bodies)))) for i in range(len(pieces))
             for _ in range(2)]
    got = meeting_edges([pieces[i] for i, _ in pairs], [bodies[j] for _, j in pairs],
                        certify=certify)
    _each_as_alone(got, pieces, bodies, pairs, certify)


def _each_as_alone(got, pieces, bodies, pairs, certify) -> None:  # noqa: ANN001
    """Each row of ``got`` (the sums of ``pairs`` together) is the pair's sum made alone."""
    for row, (i, j) in enumerate(pairs):
        alone = meeting_edges([pieces[i]], [bodies[j]], certify=certify)
        used = got.used[row]
        assert np.array_equal(got.start[row][used], alone.start[0][alone.used[0]])
        assert np.array_equal(got.end[row][used], alone.end[0][alone.used[0]])
        assert np.array_equal(got.bounds[row], alone.bounds[0])
