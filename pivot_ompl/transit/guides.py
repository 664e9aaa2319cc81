"""The walk search's guides, per query: the floor distances and the lattice's cost-to-go.

Both are fields of :class:`~pivot_ompl.transit.field.FloorField` to a query's goal states,
computed once and kept (a walk round the same resting box asks for them again and again):

* **floor distances** (:meth:`WalkGuides.floor_distances`): cheap, blind to the heading; a
  query asks only for the floor near its ends (a limit grown until the nearest start is
  exact), and the cache is bounded by :data:`DISTANCE_BYTES`;
* **lattice cost-to-go** (:meth:`WalkGuides.lattice_costs`): a Dijkstra over the lattice's
  states, asked only by the walks the floor distances could not guide cheaply.

The search they guide is :class:`~pivot_ompl.transit.planner.WalkPlanner`'s.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from pivot_ompl.cache import BoundedCache
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose
from pivot_ompl.transit.clearance import State
from pivot_ompl.transit.field import FloorField, FloorWindow
from pivot_ompl.transit.lattice import Primitive

#: Bytes the cached floor distances (a float per grid position each) may hold at most.
DISTANCE_BYTES = 256 * 2**20

Stop = Callable[[], bool] | None


class WalkGuides:
    """The floor distances and lattice cost-to-go of walk queries, cached (module docstring).

    Args:
        field: the floor's fields (in the lattice's frame).
        prims: the lattice's motion primitives per heading.
        resolution: lattice grid spacing (m).
        floor_inflation: weight of the floor-distance heuristic (the limits scale with it).
        positions: grid positions of the floor (the byte budget's unit is one field).
        box_cache: resting-box poses whose lattice clearances are kept (the floor distances
            keep four times as many queries, within :data:`DISTANCE_BYTES`).
    """

    def __init__(self, field: FloorField, prims: tuple[tuple[Primitive, ...], ...], *,
                 resolution: float, floor_inflation: float, positions: int,
                 box_cache: int) -> None:
        """Empty caches."""
        self.field, self.prims = field, prims
        self.resolution, self.floor_inflation = resolution, floor_inflation
        self._distances: BoundedCache[tuple, tuple[float, np.ndarray | FloorWindow]] = \
            BoundedCache(max(2, min(4 * box_cache, DISTANCE_BYTES // (8 * positions))))
        #: a float per lattice state each, rarely asked again
        self._lattice: BoundedCache[tuple, np.ndarray] = BoundedCache(4)

    def cached_fields(self) -> tuple[int, int]:
        """Floor-distance fields and lattice cost-to-go fields held in the caches."""
        return len(self._distances), len(self._lattice)

    def floor_distances(self, obj: Pose, goals: dict[State, float], *,
                        starts: dict[State, float] | None = None,
                        should_stop: Stop = None) -> np.ndarray | FloorWindow:
        """:meth:`FloorField.distances` to the goal states' positions (cached).

        Without ``starts``: over the whole floor (exact everywhere, ``inf`` where no walk
        exists). With them: within a limit that grows until it is at least
        ``floor_inflation`` times the nearest start's distance (exact there), first
        ``floor_inflation`` times the straight distance between the ends plus half a circle
        round the box (:meth:`FloorField.box_reach`), then doubled while no start is
        settled: a walk round the box pays for the floor near it, not for the whole floor.
        Farther positions hold the limit, a lower bound; ``inf`` still means no walk. A
        window whose Dijkstra settled every position its goals reach is kept as the whole
        floor's (limit ``inf``: :meth:`cached_limit`).
        """
        cells = tuple(sorted({(s[0], s[1]) for s in goals}))
        key = (obj, cells)
        hit = self._distances.get(key)
        limit = math.inf if starts is None else self.first_limit(starts, goals)
        if hit is not None:
            limit = max(limit, hit[0])
        while True:
            if hit is None or hit[0] < limit:
                if should_stop is not None and should_stop():  # tens of ms in C
                    raise Interrupted("walk planning")
                dist = self.field.distances(obj, list(cells), should_stop, limit=limit)
                # a window whose Dijkstra settled every position it reaches: the whole
                # floor's distances, exact at any limit (no query again with a larger one)
                done = isinstance(dist, FloorWindow) and math.isinf(dist.outside)
                hit = self._distances.put(key, (math.inf if done else limit, dist))
            limit, dist = hit
            if starts is None or math.isinf(limit):
                return dist
            near = min(float(dist[s[0], s[1]]) for s in starts)
            if math.isinf(near) or self.floor_inflation * near <= limit:
                return dist
            limit = self.floor_inflation * near if near < limit else 2.0 * limit

    def cached_limit(self, obj: Pose, goals: dict[State, float]) -> float | None:
        """The limit of the cached :meth:`floor_distances` to ``goals``' positions, if any.

        The box resting at ``obj``; ``None`` when none is cached, ``inf`` when the whole
        floor's are.
        """
        hit = self._distances.get((obj, tuple(sorted({(s[0], s[1]) for s in goals}))))
        return None if hit is None else hit[0]

    def first_limit(self, starts: dict[State, float], goals: dict[State, float]) -> float:
        """``floor_inflation`` times (the straight distance + half a circle round the box)."""
        res = self.resolution
        straight = min(math.hypot(a[0] - b[0], a[1] - b[1]) for a in starts for b in goals)
        return self.floor_inflation * (res * straight + math.pi * self.field.box_reach())

    def lattice_costs(self, obj: Pose, goals: dict[State, float], *,
                      should_stop: Stop = None) -> np.ndarray:
        """:meth:`FloorField.lattice_costs` to the goal states (cached)."""
        def compute() -> np.ndarray:
            if should_stop is not None and should_stop():
                raise Interrupted("walk planning")
            return self.field.lattice_costs(obj, list(goals), self.prims, should_stop)

        return self._lattice.get_or_compute((obj, tuple(sorted(goals))), compute)
