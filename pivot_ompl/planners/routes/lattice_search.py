"""The transfer lattice's A*, over states numbered by integers: the lattice's inner loop.

:meth:`~.lattice.TransferLattice.route` searches lattice states ``(ix, iy, h)``; the generic
:func:`~pivot_ompl.graph.astar` would hold them as tuples and reach the moves through a
generator per state. :func:`lattice_astar` is the same search (the same queue entries pushed in
the same order with the same costs and heuristic values, so the same states expanded and the
same route returned, ties broken alike) with a state ``(ix, iy, h)`` numbered
``(ix * ny + iy) * N_HEADINGS + h``, and its moves (a push and a pull along the heading, a turn
in place either way, and the join to the goal) written out in the loop.

A push (or pull) into a state where the assembly has no room to swing costs
:data:`TIGHT_PUSH` times its price: the state is free at its heading but the turns to the
headings either side of it are not (the box cannot be rotated 11.25 degrees either way
there, a wall beside it). The pivot steering moves the box by rotations about its corners;
beside a wall they must be small, and a straight push along one costs several times its
price (the bug trap's lattice routes along its walls: chains made real at 1.2-1.9 times the
lattice's seconds, pushes of 4.6 m at 7 times). The factor only makes moves dearer, so the
heuristic stays admissible; it chooses, among routes of near cost, the one off the walls,
and the route's cost (:func:`route_cost`, what :meth:`~.lattice.TransferLattice.route`
answers) counts it too: an estimate nearer what the route costs once made real.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable, Sequence

from pivot_ompl.errors import Interrupted
from pivot_ompl.transit.lattice import HEADING_VECTORS, N_HEADINGS

State = tuple[int, int, int]
Stop = Callable[[], bool]

_START, _GOAL = -1, -2

#: The factor on a push into a state without room to swing (module docstring): a route may
#: still run along a wall where no other way is near as cheap, but a detour of up to twice
#: the pushes off it wins. Measured first plans (fresh process): the bug trap 409.98 s and
#: 158 pivots -> 335.72 s and 129 with the re-routing's CPU halved; cluttered_room 212.51 ->
#: 194.84 s; the hall 1009.14 -> 999.37 s; t_junction 823.13 -> 818.49 s; the other shipped
#: scenes alike (docs/quality.md).
TIGHT_PUSH = 2.0


def lattice_astar(starts: dict[State, float], goals: dict[State, float], *,
                  grids: Sequence[bytes], shape: tuple[int, int], push: Sequence[float],
                  turn: Sequence[float], cell_part: Callable[[int, int], float],
                  turning: Sequence[float], weight: float, max_expansions: int,
                  should_stop: Stop | None, tight: float = TIGHT_PUSH
                  ) -> tuple[list[State], int]:
    """The cheapest route from a start state to a goal state, and the states expanded.

    Args:
        starts: the states joined to the start, with the joins' costs.
        goals: the states joined to the goal, with the joins' costs.
        grids: per lattice heading ``h``, ``grids[2 h]`` (a state free at ``h``) and
            ``grids[2 h + 1]`` (the turn from ``h`` to ``h + 1`` free), one byte per grid
            position ``ix * ny + iy``.
        shape: ``(nx, ny)``, the grid's positions.
        push: a push's (or pull's) cost along each heading.
        turn: the cost of the turn from each heading ``h`` to ``h + 1`` (and back).
        cell_part: the heuristic's part of a grid position (kept per position once asked).
        turning: the heuristic's part of each heading.
        weight: the heuristic's inflation.
        max_expansions: states expanded before the search gives up (no more moves).
        should_stop: polled every 256 expansions.
        tight: the factor on a push or pull into a state whose turns to both neighbouring
            headings are not free (module docstring; 1: every push at its price).

    Returns:
        ``(states, expanded)``: the route as ``[(-1, -1, -1), s1, ..., sk, (-2, -2, -2)]``
        (the start and goal ends as those markers), ``[]`` when there is none.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """
    nx, ny = shape
    nh = N_HEADINGS
    goal_cost = {(s[0] * ny + s[1]) * nh + s[2]: c for s, c in goals.items()}
    start_moves = [((s[0] * ny + s[1]) * nh + s[2], c) for s, c in starts.items()]
    parts: dict[int, float] = {}
    dist: dict[int, float] = {_START: 0.0}
    done: set[int] = set()
    parent: dict[int, int] = {}
    heap: list[tuple[float, int, float, int, int | None]] = [(0.0, 0, 0.0, _START, None)]
    tie = 0
    expanded = 0
    pop, push_heap, inf = heapq.heappop, heapq.heappush, math.inf

    while heap:
        _, _, du, u, p = pop(heap)
        if u in done or du > dist[u]:
            continue
        done.add(u)
        if p is not None:
            parent[u] = p
        if u == _GOAL:
            return _states(parent, ny), expanded
        if u == _START:
            moves = start_moves
        else:
            expanded += 1
            if expanded > max_expansions:
                continue
            if expanded % 256 == 0 and should_stop is not None and should_stop():
                raise Interrupted("transfer lattice")
            cell, h = divmod(u, nh)
            ix, iy = divmod(cell, ny)
            vx, vy = HEADING_VECTORS[h]
            moves = []
            free, ccw, cw = grids[2 * h], grids[2 * h + 1], grids[2 * ((h - 1) % nh) + 1]
            for sgn in (1, -1):
                jx, jy = ix + sgn * vx, iy + sgn * vy
                j = jx * ny + jy
                if 0 <= jx < nx and 0 <= jy < ny and free[j]:
                    moves.append((j * nh + h, push[h] if ccw[j] and cw[j] else tight * push[h]))
            ha, hb = (h + 1) % nh, (h - 1) % nh
            if grids[2 * h + 1][cell] and grids[2 * ha][cell]:
                moves.append((cell * nh + ha, turn[h]))
            if grids[2 * hb + 1][cell] and grids[2 * hb][cell]:
                moves.append((cell * nh + hb, turn[hb]))
            c = goal_cost.get(u)
            if c is not None:
                moves.append((_GOAL, c))
        for v, c in moves:
            nd = du + c
            if v in done or nd >= dist.get(v, inf):
                continue
            if v < 0:
                hv = 0.0
            else:
                cell, h = divmod(v, nh)
                part = parts.get(cell)
                if part is None:
                    part = parts[cell] = cell_part(*divmod(cell, ny))
                hv = weight * (part + turning[h])
                if hv == inf:
                    continue
            dist[v] = nd
            tie += 1
            push_heap(heap, (nd + hv, tie, nd, v, u))
    return [], expanded


def _states(parent: dict[int, int], ny: int) -> list[State]:
    """The route to the goal marker as lattice states (the ends as their markers)."""
    path = [_GOAL]
    while path[-1] in parent:
        path.append(parent[path[-1]])
    out: list[State] = []
    for v in reversed(path):
        if v < 0:
            out.append((v, v, v))
        else:
            cell, h = divmod(v, N_HEADINGS)
            ix, iy = divmod(cell, ny)
            out.append((ix, iy, h))
    return out


def route_cost(states: list[State], starts: dict[State, float], goals: dict[State, float], *,
               grids: Sequence[bytes], ny: int, push: Sequence[float], turn: Sequence[float],
               tight: float = TIGHT_PUSH) -> float:
    """The cost of a route of :func:`lattice_astar` (its arguments), the ends' joins included.

    What the search summed along it: a push into a state without room to swing at ``tight``
    times its price.
    """
    inner = states[1:-1]
    total = starts[inner[0]] + goals[inner[-1]]
    nh = N_HEADINGS
    for u, v in zip(inner, inner[1:], strict=False):
        h = u[2]
        if h == v[2]:
            j = v[0] * ny + v[1]
            total += push[h] if grids[2 * h + 1][j] and grids[2 * ((h - 1) % nh) + 1][j] \
                else tight * push[h]
        else:
            total += turn[h if (h + 1) % nh == v[2] else v[2]]
    return total
