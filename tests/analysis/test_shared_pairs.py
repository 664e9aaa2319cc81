"""The pieces two raster layers share: every pair of labels met at a cell, kept while the
layers' label arrays stay the same."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.raster_bound import shared_pairs


def _layers(rng: np.random.Generator, count_a: int, count_b: int, cells: int) -> dict:
    dtype = np.uint8 if max(count_a, count_b) <= 255 else np.int16
    a = rng.integers(0, count_a + 1, cells).astype(dtype)
    b = rng.integers(0, count_b + 1, cells).astype(dtype)
    return {(0, 0): (a, count_a), (1, 0): (b, count_b)}


@settings(max_examples=120, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), count_a=st.integers(0, 600),
       count_b=st.integers(0, 600), cells=st.integers(0, 3000))
def test_the_shared_pieces_are_the_label_pairs_of_the_cells(seed, count_a, count_b, cells):
    """Both ways of counting (a table of every pair, or the cells' pairs sorted where the
    table would be larger than the cells) give every pair met at a cell, sorted."""
    layers = _layers(np.random.default_rng(seed), count_a, count_b, cells)
    a, b = layers[(0, 0)][0], layers[(1, 0)][0]
    ia, ib = shared_pairs({}, layers, (0, 0), (1, 0), lambda: (a, b))
    expected = sorted({(int(i), int(j)) for i, j in zip(a, b, strict=True) if i and j})
    assert list(zip(ia.tolist(), ib.tolist(), strict=True)) == expected


def test_the_pairs_are_read_again_only_when_a_layer_changed():
    """Kept while both label arrays are the layers' own; a layer labelled again (a new array,
    even of the same labels) is read again."""
    rng = np.random.default_rng(3)
    layers = _layers(rng, 40, 30, 500)
    a, b = layers[(0, 0)][0], layers[(1, 0)][0]
    kept: dict = {}
    first = shared_pairs(kept, layers, (0, 0), (1, 0), lambda: (a, b))

    def unread() -> tuple[np.ndarray, np.ndarray]:
        raise AssertionError("read again")

    again = shared_pairs(kept, layers, (0, 0), (1, 0), unread)
    assert all(np.array_equal(x, y) for x, y in zip(first, again, strict=True))
    cut = b.copy()
    cut[b == b.max()] = 0
    layers[(1, 0)] = (cut, 30)
    with pytest.raises(AssertionError, match="read again"):
        shared_pairs(kept, layers, (0, 0), (1, 0), unread)
    ia, ib = shared_pairs(kept, layers, (0, 0), (1, 0), lambda: (a, cut))
    assert int(b.max()) not in ib.tolist()
