"""The raster layers' labels in their smallest type, and a regrasp's shared cells read at the
cells free in some layer: the same pieces and the same cells as the full-size computation."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage

from pivot_ompl.analysis.raster_bound import shared_cells
from pivot_ompl.analysis.raster_cover import piece_labels

_EIGHT = np.ones((3, 3), dtype=bool)


def random_mask(seed: int, nx: int, ny: int, rate: float) -> np.ndarray:
    return np.random.default_rng(seed).random((nx, ny)) < rate


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**16), nx=st.integers(1, 90), ny=st.integers(1, 90),
       rate=st.floats(0.05, 0.95))
def test_piece_labels_are_scipys_labels_in_a_type_that_holds_them(seed, nx, ny, rate):
    free = random_mask(seed, nx, ny, rate)
    labels, count = piece_labels(free)
    expected, n = ndimage.label(free, structure=_EIGHT, output=np.int64)
    assert count == n
    assert np.array_equal(labels.astype(np.int64), expected)
    assert np.iinfo(labels.dtype).max >= count
    if count <= 255:
        assert labels.dtype == np.uint8


def test_more_pieces_than_a_byte_holds_keep_every_label():
    free = np.zeros((64, 64), dtype=bool)
    free[::2, ::2] = True  # 1024 single-cell pieces
    labels, count = piece_labels(free)
    assert count == 1024
    assert labels.max() == 1024
    assert len(np.unique(labels[free])) == 1024


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**16), nx=st.integers(2, 60), ny=st.integers(2, 60),
       rates=st.tuples(st.floats(0.2, 0.9), st.floats(0.2, 0.9)))
def test_shared_cells_are_the_cells_both_pieces_hold_in_raster_order(seed, nx, ny, rates):
    rng = np.random.default_rng(seed)
    a, _ = piece_labels(rng.random((nx, ny)) < rates[0])
    b, _ = piece_labels(rng.random((nx, ny)) < rates[1])
    extra, _ = piece_labels(rng.random((nx, ny)) < 0.5)  # a third layer free elsewhere
    cells = np.flatnonzero((a > 0) | (b > 0) | (extra > 0))
    ra, rb = a.ravel()[cells], b.ravel()[cells]
    pairs = {(int(i), int(c)) for i, c in zip(ra.tolist(), rb.tolist(), strict=True) if i and c}
    for i, c in sorted(pairs)[:20]:
        ii, jj = shared_cells(cells, ra, i, rb, c, (nx, ny))
        ei, ej = np.nonzero((a == i) & (b == c))
        assert np.array_equal(ii, ei) and np.array_equal(jj, ej)
        assert ii.dtype == ei.dtype  # the walk relaxation's memo keys are these bytes
