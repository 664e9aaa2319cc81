"""The transfer lattice's integer A* expands what the generic A* expands, and returns its route.

Pushes into a state without room to swing (the turns to both neighbouring headings not free)
cost ``tight`` times their price in both.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar
from pivot_ompl.planners.routes.lattice_search import lattice_astar, route_cost
from pivot_ompl.transit.lattice import HEADING_VECTORS, N_HEADINGS

START, GOAL = (-1, -1, -1), (-2, -2, -2)


def _problem(seed: int, nx: int = 14, ny: int = 11):
    rng = np.random.default_rng(seed)
    free = rng.random((2 * N_HEADINGS, nx * ny)) < 0.8
    grids = [bytes(row.astype(np.uint8)) for row in free]
    states = [(ix, iy, h) for ix in range(nx) for iy in range(ny) for h in range(N_HEADINGS)
              if free[2 * h, ix * ny + iy]]
    pick = rng.choice(len(states), size=6, replace=False)
    starts = {states[k]: float(rng.uniform(0.0, 2.0)) for k in pick[:3]}
    goals = {states[k]: float(rng.uniform(0.0, 2.0)) for k in pick[3:]}
    push = [float(x) for x in rng.uniform(0.5, 1.5, N_HEADINGS)]
    turn = [float(x) for x in rng.uniform(0.2, 1.0, N_HEADINGS)]
    gx, gy = rng.uniform(0, nx), rng.uniform(0, ny)
    walls = rng.random((nx, ny)) < 0.05  # cells no goal is reached from: inf heuristic

    def cell_part(ix: int, iy: int) -> float:
        return math.inf if walls[ix, iy] else 0.5 * math.hypot(ix - gx, iy - gy)

    turning = [float(x) for x in rng.uniform(0.0, 0.3, N_HEADINGS)]
    return grids, (nx, ny), starts, goals, push, turn, cell_part, turning


def _reference(grids, shape, starts, goals, push, turn, cell_part, turning, weight, cap,
               tight=1.0):
    """The same search through the generic A*, over tuples (the lattice's former form)."""
    nx, ny = shape
    count = [0]

    def neighbours(u):
        if u == START:
            yield from starts.items()
            return
        count[0] += 1
        if count[0] > cap:
            return
        ix, iy, h = u
        vx, vy = HEADING_VECTORS[h]
        for sgn in (1, -1):
            jx, jy = ix + sgn * vx, iy + sgn * vy
            j = jx * ny + jy
            if 0 <= jx < nx and 0 <= jy < ny and grids[2 * h][j]:
                room = grids[2 * h + 1][j] and grids[2 * ((h - 1) % N_HEADINGS) + 1][j]
                yield (jx, jy, h), push[h] if room else tight * push[h]
        at, ha, hb = ix * ny + iy, (h + 1) % N_HEADINGS, (h - 1) % N_HEADINGS
        if grids[2 * h + 1][at] and grids[2 * ha][at]:
            yield (ix, iy, ha), turn[h]
        if grids[2 * hb + 1][at] and grids[2 * hb][at]:
            yield (ix, iy, hb), turn[hb]
        if u in goals:
            yield GOAL, goals[u]

    def heuristic(u):
        return 0.0 if u[0] < 0 else weight * (cell_part(u[0], u[1]) + turning[u[2]])

    return astar([START], {GOAL}, neighbours, heuristic), count[0]


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize(("weight", "cap", "tight"),
                         [(1.0, 10**6, 1.0), (1.2, 10**6, 1.0), (1.5, 300, 1.0),
                          (1.0, 10**6, 2.0), (1.2, 10**6, 3.0)])
def test_the_integer_search_returns_the_generic_searchs_route(seed, weight, cap, tight):
    grids, shape, starts, goals, push, turn, cell_part, turning = _problem(seed)
    want, want_n = _reference(grids, shape, starts, goals, push, turn, cell_part, turning,
                              weight, cap, tight)
    got, n = lattice_astar(starts, goals, grids=grids, shape=shape, push=push, turn=turn,
                           cell_part=cell_part, turning=turning, weight=weight,
                           max_expansions=cap, should_stop=None, tight=tight)
    assert got == want
    assert n == want_n
    if got:
        assert got[0] == START and got[-1] == GOAL
        assert got[1] in starts and got[-2] in goals


def test_the_integer_search_stops_when_told():
    grids, shape, starts, goals, push, turn, cell_part, turning = _problem(0, 60, 60)
    with pytest.raises(Interrupted):
        lattice_astar(starts, {(59, 59, 0): 0.0}, grids=grids, shape=shape, push=push,
                      turn=turn, cell_part=lambda ix, iy: 0.0, turning=[0.0] * N_HEADINGS,
                      weight=1.0, max_expansions=10**6, should_stop=lambda: True)



def _costs(route, grids, shape, starts, goals, push, turn):
    """A route's price and the part of it pushed into states without room to swing."""
    ny = shape[1]
    inner = route[1:-1]
    price, tight = starts[inner[0]] + goals[inner[-1]], 0.0
    for u, v in zip(inner, inner[1:], strict=False):
        if u[2] == v[2]:
            j, h = v[0] * ny + v[1], v[2]
            price += push[h]
            if not (grids[2 * h + 1][j] and grids[2 * ((h - 1) % N_HEADINGS) + 1][j]):
                tight += push[h]
        else:
            price += turn[u[2] if (u[2] + 1) % N_HEADINGS == v[2] else v[2]]
    return price, tight


@pytest.mark.parametrize("seed", range(12))
def test_the_tight_factor_trades_pushes_beside_walls_for_a_bounded_detour(seed):
    """The cheapest route at ``tight = t`` pushes no more beside walls than the cheapest at
    ``t = 1``, and costs at most ``(t - 1)`` times the pushes it saved there more."""
    grids, shape, starts, goals, push, turn, _, turning = _problem(seed, 9, 8)
    kw = dict(grids=grids, shape=shape, push=push, turn=turn, cell_part=lambda ix, iy: 0.0,
              turning=[0.0] * N_HEADINGS, weight=1.0, max_expansions=10**6,
              should_stop=None)
    base, _ = lattice_astar(starts, goals, tight=1.0, **kw)
    if not base:
        return
    t = 2.0
    off, _ = lattice_astar(starts, goals, tight=t, **kw)
    p1, t1 = _costs(base, grids, shape, starts, goals, push, turn)
    p2, t2 = _costs(off, grids, shape, starts, goals, push, turn)
    assert t2 <= t1 + 1e-9
    assert p1 - 1e-9 <= p2 <= p1 + (t - 1.0) * (t1 - t2) + 1e-9
    # the route's cost is what the search summed: the pushes beside walls at t times
    ny = shape[1]
    assert route_cost(base, starts, goals, grids=grids, ny=ny, push=push, turn=turn,
                      tight=1.0) == pytest.approx(p1, rel=1e-12)
    assert route_cost(off, starts, goals, grids=grids, ny=ny, push=push, turn=turn,
                      tight=t) == pytest.approx(p2 + (t - 1.0) * t2, rel=1e-12)
