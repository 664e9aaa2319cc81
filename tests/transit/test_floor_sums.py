"""The walking body's sums with the obstacle pieces, kept per (piece, yaw).

A sum must be the same floats whichever other pairs it was computed with, so that rasters of
sums computed tile by tile are those of the sums all computed at once; and each pair is
summed once.
"""

from __future__ import annotations

import numpy as np
import pytest
import shapely
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.transit.floor_grid import OPEN_YAWS, OPPOSITE_YAWS
from pivot_ompl.transit.floor_sums import PieceSums
from pivot_ompl.validity.minkowski import meeting_edges


@pytest.fixture(scope="module")
def grid():
    """The floor grid of a small generated building (its pieces and the walking body)."""
    scene = generate("building", 1, params=GeneratorParams(rooms=3)).scene
    return PivotChecker(scene).walker.field.grid


def _used_edges(edges, i):
    used = edges.used[i]
    return edges.start[i][used], edges.end[i][used], edges.bounds[i]


@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_sums_filled_in_any_groups_are_those_summed_at_once(grid, data):
    n, k = len(grid.pieces), len(OPEN_YAWS)
    sums = PieceSums(grid.pieces, grid.sums.bodies)
    calls = []

    def summing(pieces, bodies, **kw):  # noqa: ANN001, ANN003, ANN202
        calls.append(len(pieces))
        return meeting_edges(pieces, bodies, **kw)

    for _ in range(data.draw(st.integers(1, 4))):
        pieces = np.array(sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1,
                                                   max_size=12))))
        yaws = sorted(data.draw(st.sets(st.integers(0, k - 1), min_size=1, max_size=5)))
        before = int(sums.done.sum())
        assert sums.fill(pieces, yaws, summing) == int(sums.done.sum()) - before
    pieces = np.flatnonzero(sums.done.any(axis=1))
    yaws = np.flatnonzero(sums.done.any(axis=0)).tolist()
    sums.fill(pieces, yaws, summing)
    got, groups = sums.edges(pieces, yaws)
    want = meeting_edges([grid.pieces[i] for i in pieces for _ in yaws],
                         [sums.bodies[j] for _ in pieces for j in yaws])
    assert np.array_equal(groups, np.tile(np.arange(len(yaws)), len(pieces)))
    for row in range(len(got.used)):
        for a, b in zip(_used_edges(got, row), _used_edges(want, row), strict=True):
            assert np.array_equal(a, b)
    assert sum(calls) == len(pieces) * len(yaws)  # each pair summed once


def test_a_tile_sums_only_the_pieces_near_it():
    # regression: a tile's first build summed every piece at every yaw (3 s on the Willow
    # Garage office, whose regrasp walks enter a few tiles)
    scene = generate("building", 1, params=GeneratorParams(rooms=3)).scene
    g = PivotChecker(scene).walker.field.grid
    g.open_block(slice(0, 16), slice(0, 16))
    n, k = len(g.pieces), len(OPEN_YAWS)
    assert 0 < g.stats.pairs_summed < n * k
    assert g.stats.pairs_summed % k == 0  # a piece near it at every yaw
    assert g.stats.yaws_summed == 0  # no yaw summed with every piece
    whole = np.logical_or.reduce([g.fits_index(j) for j in range(k)], axis=0)
    assert g.stats.pairs_summed == n * k and g.stats.yaws_summed == k
    assert np.array_equal(g.open_block(slice(0, 16), slice(0, 16)), whole[:16, :16])


def test_kept_sums_give_back_every_end_whatever_the_slot_order(grid):
    # the sums keep each edge's start and the slot its end starts (not the end's floats):
    # edge sets whose slots run backwards (as a clockwise ring turned round) or are padded
    # with zeros must come back bit for bit
    from pivot_ompl.validity.minkowski import EdgeSet

    def reversed_padded(pieces, bodies, **kw):  # noqa: ANN001, ANN003, ANN202
        e = meeting_edges(pieces, bodies, **kw)
        pad = np.zeros((len(pieces), 3, 2))
        return EdgeSet(np.concatenate([e.end[:, ::-1], pad], axis=1),
                       np.concatenate([e.start[:, ::-1], pad], axis=1),
                       np.concatenate([e.used[:, ::-1], np.zeros((len(pieces), 3), bool)],
                                      axis=1), e.bounds)

    sums = PieceSums(grid.pieces, grid.sums.bodies)
    pieces, yaws = np.arange(min(6, len(grid.pieces))), [0, 3, 7, 20]
    sums.fill(pieces, yaws, reversed_padded)
    got, _ = sums.edges(pieces, yaws)
    want = reversed_padded([grid.pieces[i] for i in pieces for _ in yaws],
                           [sums.bodies[j] for _ in pieces for j in yaws])
    w = want.start.shape[1]
    assert np.array_equal(got.start[:, :w], want.start)
    assert np.array_equal(got.end[:, :w], want.end)
    assert np.array_equal(got.used[:, :w], want.used)


def _region(edges, row):
    start, _, _ = _used_edges(edges, row)
    return shapely.Polygon(start)


@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_a_wall_box_turned_by_pi_is_its_opposite_sum_reflected(grid, data):
    # the floor's sums at a yaw pi from an earlier one are reflected, not summed; each
    # must be the region summed directly (to rounding), whatever pairs were asked together
    n, k = len(grid.pieces), len(OPEN_YAWS)
    sums = PieceSums(grid.pieces, grid.sums.bodies, opposite=list(OPPOSITE_YAWS))
    for _ in range(data.draw(st.integers(1, 3))):
        pieces = np.array(sorted(data.draw(st.sets(st.integers(0, n - 1), min_size=1,
                                                   max_size=8))))
        yaws = sorted(data.draw(st.sets(st.integers(0, k - 1), min_size=1, max_size=4)))
        sums.fill(pieces, yaws, meeting_edges)
        assert sums.done[np.ix_(pieces, yaws)].all()
    pieces = np.flatnonzero(sums.done.any(axis=1))
    high = [j for j in range(k // 2, k) if sums.done[pieces, j].all()]
    if not high:
        return
    got, _ = sums.edges(pieces, high)
    want = meeting_edges([grid.pieces[i] for i in pieces for _ in high],
                         [sums.bodies[j] for _ in pieces for j in high])
    assert sums.reflected > 0
    for row in range(len(got.used)):
        a, b = _region(got, row), _region(want, row)
        # the region, not the slots' order (the kept slots need not run round the ring: what
        # reads them is the raster, held equal below)
        assert a.is_valid
        assert a.symmetric_difference(b).area <= 1e-9 * max(b.area, 1.0)
        assert np.allclose(got.bounds[row], want.bounds[row], atol=1e-9)
    again = PieceSums(grid.pieces, grid.sums.bodies, opposite=list(OPPOSITE_YAWS))
    again.fill(pieces, high, meeting_edges)  # all at once: the same floats
    once, _ = again.edges(pieces, high)
    for row in range(len(got.used)):
        for x, y in zip(_used_edges(got, row), _used_edges(once, row), strict=True):
            assert np.array_equal(x, y)


def test_the_open_floor_is_that_of_the_sums_all_summed():
    # the reflected sums rasterise to the open positions of the sums all summed
    scene = generate("building", 2, params=GeneratorParams(rooms=4)).scene
    g = PivotChecker(scene).walker.field.grid
    reflected = g.open_block(slice(0, g.nx), slice(0, g.ny))
    assert g.sums.reflected > 0
    g.sums = PieceSums(g.pieces, g.sums.bodies)  # no opposite yaws: every pair summed
    summed = g.open_block(slice(0, g.nx), slice(0, g.ny))
    assert g.sums.reflected == 0
    assert np.array_equal(reflected, summed)
