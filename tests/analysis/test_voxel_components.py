"""The fine voxels' components: a labelling grown by new voxels is the labelling of them all,
and both are the components of the joins the refined cover defines."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.voxel_components import grown_components, voxel_components


def reference(keys: np.ndarray, nx: int, ny: int, bins: int) -> list[frozenset[int]]:
    """The components by a plain search over the joins (8-adjacent in a bin; yaw crossings)."""
    cells = nx * ny
    have = set(keys.tolist())
    seen: set[int] = set()
    out = []
    for s in keys.tolist():
        if s in seen:
            continue
        part, stack = set(), [s]
        seen.add(s)
        while stack:
            k = stack.pop()
            part.add(k)
            f, rest = divmod(k, cells)
            a, b = divmod(rest, ny)
            near = [((f + df) % bins) * cells + a * ny + b for df in (-1, 1)]
            near += [f * cells + (a + da) * ny + b + db for da in (-1, 0, 1) for db in (-1, 0, 1)
                     if (da or db) and 0 <= a + da < nx and 0 <= b + db < ny]
            for v in near:
                if v in have and v not in seen:
                    seen.add(v)
                    stack.append(v)
        out.append(frozenset(part))
    return sorted(out, key=min)


def partition(keys: np.ndarray, labels: np.ndarray) -> list[frozenset[int]]:
    groups: dict[int, set[int]] = {}
    for k, c in zip(keys.tolist(), labels.tolist(), strict=True):
        groups.setdefault(c, set()).add(k)
    return sorted((frozenset(g) for g in groups.values()), key=min)


@st.composite
def windows(draw):
    """A coarse grid, an old window and new cells beside it, voxels free at random."""
    cx, cy, bins = draw(st.integers(1, 4)), draw(st.integers(1, 4)), draw(st.integers(1, 5))
    state = draw(st.lists(st.integers(0, 2), min_size=cx * cy, max_size=cx * cy))
    window = np.array(state).reshape(cx, cy)  # 0 outside, 1 old window, 2 new cells
    rate = draw(st.floats(0.2, 1.0))
    seed = draw(st.integers(0, 2**16))
    return window, bins, rate, seed


def voxels_of(cells: np.ndarray, bins: int, rate: float, rng: np.random.Generator) -> np.ndarray:
    nx, ny = 2 * cells.shape[0], 2 * cells.shape[1]
    f, a, b = np.meshgrid(np.arange(bins), np.arange(nx), np.arange(ny), indexing="ij")
    inside = cells[a // 2, b // 2] & (rng.random(a.shape) < rate)
    return np.sort((f * nx * ny + a * ny + b)[inside].astype(np.int64))


@given(windows())
@settings(max_examples=150, deadline=None)
def test_grown_components_are_the_components_of_every_voxel(case):
    window, bins, rate, seed = case
    rng = np.random.default_rng(seed)
    nx, ny = 2 * window.shape[0], 2 * window.shape[1]
    old = voxels_of(window == 1, bins, rate, rng)
    new = voxels_of(window == 2, bins, rate, rng)
    count, labels = voxel_components(old, nx, ny, bins)
    assert partition(old, labels) == reference(old, nx, ny, bins)
    assert count == len(reference(old, nx, ny, bins))
    grown = grown_components(old, labels, count, rng.permutation(new), window == 1, nx, ny,
                             bins)
    every = np.sort(np.concatenate([old, new]))
    assert np.array_equal(grown.keys, every)
    want = reference(every, nx, ny, bins)
    assert partition(grown.keys, grown.labels) == want and grown.count == len(want)
    assert set(grown.labels.tolist()) == set(range(grown.count))
    # the new voxels' labels, and the earlier components' labels now, read alike
    at = np.searchsorted(grown.keys, grown.new)
    assert np.array_equal(grown.new, new) and np.array_equal(grown.labels[at], grown.new_labels)
    if len(old):
        assert np.array_equal(grown.labels[np.searchsorted(grown.keys, old)],
                              grown.merged[labels])


@given(windows())
@settings(max_examples=100, deadline=None)
def test_components_are_numbered_by_their_first_voxel(case):
    """Labels in order of each component's smallest voxel: the refined graph's node order
    (and with it the guided path's ties) does not depend on how the components are found."""
    window, bins, rate, seed = case
    rng = np.random.default_rng(seed)
    nx, ny = 2 * window.shape[0], 2 * window.shape[1]
    keys = voxels_of(window > 0, bins, rate, rng)
    count, labels = voxel_components(keys, nx, ny, bins)
    _, first = np.unique(labels, return_index=True)
    assert np.array_equal(labels[np.sort(first)], np.arange(count))
    old = voxels_of(window == 1, bins, rate, rng)
    c0, l0 = voxel_components(old, nx, ny, bins)
    grown = grown_components(old, l0, c0, voxels_of(window == 2, bins, rate, rng),
                             window == 1, nx, ny, bins)
    nodes = np.concatenate([grown.merged, grown.new_labels])  # old components, then new voxels
    _, first = np.unique(nodes, return_index=True)
    assert np.array_equal(nodes[np.sort(first)], np.arange(grown.count))
