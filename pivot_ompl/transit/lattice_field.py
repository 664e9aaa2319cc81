"""The walk planner's lattice costs-to-go: the lattice relaxed to its free states.

The heuristic of floors up to ``WalkPlanner.max_field_states`` lattice states: the lattice
itself (:mod:`pivot_ompl.transit.lattice`) with its motions and their costs, relaxed to its
states: a state is free when the walking body at its heading is inside the bounds, clear of
the obstacles grown by the kept clearance (:meth:`~pivot_ompl.transit.floor_grid.FloorGrid.
fits_index`) and of the resting box grown by the walk's box margin
(:meth:`~pivot_ompl.transit.floor_grid.FloorGrid.meets_box`; both for polygons inside the true
grown shapes); a motion is kept when both its ends are free, its sweep is not checked. The
planner's search only takes motions whose ends are free by the exact checks, so every walk it
can find is a walk of this graph: its cost-to-go (one Dijkstra from the goal states over the
reversed motions) is admissible, knows at which heading the robot fits where, and is infinite
only where no walk exists. The obstacles' graph is built once per scene, in CSR form
directly; a query closes the states the box blocks (in place, restored after).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose
from pivot_ompl.transit.floor_graph import closing
from pivot_ompl.transit.floor_grid import OPEN_YAWS, FloorGrid
from pivot_ompl.transit.lattice import HEADING_YAWS, N_HEADINGS, Primitive


class LatticeField:
    """Lattice costs-to-go over a :class:`~pivot_ompl.transit.floor_grid.FloorGrid`.

    Args:
        grid: the floor grid (its yaw layers of the 16 headings are built on first use).
    """

    def __init__(self, grid: FloorGrid) -> None:
        """No graph yet: built on the first query."""
        self.grid = grid
        self._lattice: csr_matrix | None = None

    def costs(self, obj: Pose, goals: list[tuple[int, int, int]],
              prims: tuple[tuple[Primitive, ...], ...],
              should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Cost-to-go of every lattice state to the nearest of ``goals``, relaxed.

        The lattice with its motions ``prims`` and their costs, where a state
        ``(ix, iy, h)`` is free when the walking body at heading ``h`` fits there
        (obstacles grown by the kept clearance, bounds: the yaw's layer of the grid) and
        does not meet the resting box grown by ``box_margin`` (chords inside the rounded
        corners); a motion is kept when both its ends are free, its sweep is not checked.
        Every lattice walk the search may take is a walk of this graph: the cost-to-go is an
        admissible heuristic that knows where the body can stand at which heading (where it
        must turn, and where it cannot), and ``inf`` proves that no lattice walk reaches the
        goals. Shape ``(nx, ny, N_HEADINGS)``; Dijkstra (scipy) over the reversed motions.

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per heading while the
                graph is built, then once before the Dijkstra).
        """
        rows = self._graph(prims, should_stop)
        nx, ny, nh = self.grid.nx, self.grid.ny, N_HEADINGS
        node = np.arange(nx * ny * nh).reshape(nx, ny, nh)
        # the states where the body meets the box relay nothing: their rows (the motions
        # into them, reversed) closed in place for this query, restored after
        blocked = np.concatenate([node[:, :, h][meets]
                                  for h, meets in enumerate(self.grid.meets_box(obj))])
        first, count = rows.indptr[blocked], np.diff(rows.indptr)[blocked]
        cut = np.repeat(first - np.cumsum(count) + count, count) + np.arange(count.sum())
        if should_stop is not None and should_stop():
            raise Interrupted("walking lattice field")
        with closing(rows, cut):
            dist = dijkstra(rows, directed=True, indices=[node[s] for s in goals],
                            min_only=True, limit=math.inf)
        return np.asarray(dist).reshape(nx, ny, nh)

    def _graph(self, prims: tuple[tuple[Primitive, ...], ...],
               should_stop: Callable[[], bool] | None = None) -> csr_matrix:
        """The lattice's motions between states free of the obstacles and bounds, reversed.

        Built once (the primitives are the walk planner's, the same for every query),
        directly in CSR form (no sort): row ``v`` holds, per primitive that can end at
        ``v``'s heading, the motion from its start state when both states are free (its
        cost). Polls ``should_stop`` once per heading; the headings' layers already built
        are kept.
        """
        if self._lattice is None:
            nx, ny, nh = self.grid.nx, self.grid.ny, N_HEADINGS
            free = np.empty((nx, ny, nh), dtype=bool)
            for h in range(nh):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking lattice field")
                free[:, :, h] = self.grid.fits_index(OPEN_YAWS.index(HEADING_YAWS[h]))
            into: list[list[tuple[int, Primitive]]] = [[] for _ in range(nh)]
            for h in range(nh):
                for pr in prims[h]:
                    into[(h + pr.dh) % nh].append((h, pr))
            k = max(len(x) for x in into)
            n = nx * ny * nh
            indices = np.zeros((nx, ny, nh, k), dtype=np.int32)
            weights = np.full((nx, ny, nh, k), np.inf)
            node = np.arange(n, dtype=np.int32).reshape(nx, ny, nh)
            ix, iy = np.arange(nx)[:, None], np.arange(ny)[None, :]
            for h2 in range(nh):
                for slot in range(k):
                    if slot >= len(into[h2]):
                        continue
                    h, pr = into[h2][slot]
                    sx, sy = ix - pr.dix, iy - pr.diy
                    inside = (sx >= 0) & (sx < nx) & (sy >= 0) & (sy < ny)
                    sx, sy = np.where(inside, sx, ix), np.where(inside, sy, iy)
                    ok = inside & free[:, :, h2] & free[sx, sy, h]
                    indices[:, :, h2, slot] = node[sx, sy, h]
                    weights[:, :, h2, slot][ok] = pr.cost
            # only the motions that exist (Dijkstra scans every entry of a row)
            keep = np.isfinite(weights.reshape(n, k))
            indptr = np.zeros(n + 1, dtype=np.int32)
            np.cumsum(keep.sum(axis=1), out=indptr[1:])
            self._lattice = csr_matrix(
                (weights.reshape(n, k)[keep], indices.reshape(n, k)[keep], indptr),
                shape=(n, n), copy=False)
        return self._lattice
