"""The open grid's components (one labelling per scene) against the graph's definition.

Two open positions are joined when one of the 16 heading vectors leads from one to the other
(:mod:`pivot_ompl.transit.lattice`): the 8 unit moves and the 8 moves two cells long, which
step past a closed cell. The reference labels the graph by a breadth-first search.
"""

from __future__ import annotations

from collections import deque

import numpy as np
import pytest

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.transit.floor_graph import open_components
from pivot_ompl.transit.lattice import HEADING_VECTORS
from tests.factories import shipped


def _reference(mask: np.ndarray) -> np.ndarray:
    """Component of every open position (flat grid order), by breadth-first search."""
    nx, ny = mask.shape
    label = np.full(mask.shape, -1)
    k = 0
    for start in zip(*np.nonzero(mask), strict=True):
        if label[start] >= 0:
            continue
        label[start] = k
        todo = deque([start])
        while todo:
            x, y = todo.popleft()
            for vx, vy in HEADING_VECTORS:
                t = (x + vx, y + vy)
                if 0 <= t[0] < nx and 0 <= t[1] < ny and mask[t] and label[t] < 0:
                    label[t] = k
                    todo.append(t)
        k += 1
    return label.ravel()[np.flatnonzero(mask.ravel())]


def _same_partition(a: np.ndarray, b: np.ndarray) -> bool:
    pairs = set(zip(a.tolist(), b.tolist(), strict=True))
    return len(pairs) == len(set(a.tolist())) == len(set(b.tolist()))


@pytest.mark.parametrize("density", [0.2, 0.35, 0.5])
def test_components_are_those_of_the_heading_moves_on_random_floors(density):
    grid = PivotChecker(shipped("corridor")).walker.field.grid
    rng = np.random.default_rng(int(density * 100))
    mask = rng.uniform(size=(grid.nx, grid.ny)) < density  # many knight-move-only joins
    got = open_components(mask)
    want = _reference(mask)
    assert len(got) == len(want)
    assert _same_partition(got, want)


def test_components_of_a_shipped_floor_are_the_graphs():
    field = PivotChecker(shipped("fig10")).walker.field
    mask = field.static_open()
    assert field.graph is not None
    assert _same_partition(field.graph.labels(), _reference(mask))
