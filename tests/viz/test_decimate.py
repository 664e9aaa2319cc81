"""Mesh decimation for replays: within budget, inside the bounding box, no degenerate face."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.viz.decimate import decimate


def grid_mesh(n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A bumpy n x n height field: 2 (n - 1)² triangles."""
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 2, n))
    z = 0.1 * rng.standard_normal(x.shape)
    v = np.column_stack([x.ravel(), y.ravel(), z.ravel()])
    i = np.arange(n * n).reshape(n, n)
    a, b, c, d = i[:-1, :-1].ravel(), i[:-1, 1:].ravel(), i[1:, :-1].ravel(), i[1:, 1:].ravel()
    return v, np.vstack([np.column_stack([a, b, d]), np.column_stack([a, d, c])])


@settings(max_examples=30, deadline=None)
@given(n=st.integers(3, 60), budget=st.integers(1, 3000), seed=st.integers(0, 2**16))
def test_decimated_meshes_keep_the_budget_and_the_box(n, budget, seed):
    v, f = grid_mesh(n, np.random.default_rng(seed))
    dv, df = decimate(v, f, budget)
    assert 1 <= len(df) <= budget
    assert df.min() >= 0 and df.max() < len(dv)
    assert np.all(dv.min(axis=0) >= v.min(axis=0) - 1e-12)
    assert np.all(dv.max(axis=0) <= v.max(axis=0) + 1e-12)
    assert np.all(  # no face with two corners merged
        (df[:, 0] != df[:, 1]) & (df[:, 1] != df[:, 2]) & (df[:, 0] != df[:, 2]))
    if len(f) <= budget:
        assert np.array_equal(df, f) and np.array_equal(dv, v)


def test_a_large_mesh_keeps_its_shape():
    v, f = grid_mesh(120, np.random.default_rng(0))
    dv, df = decimate(v, f, 2000)
    assert 500 <= len(df) <= 2000  # fewer, but not collapsed to nothing
    assert np.ptp(dv[:, 1]) > 0.95 * np.ptp(v[:, 1])
