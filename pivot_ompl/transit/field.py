"""The walk planner's heuristics over the floor grid, in three layers.

- **grid** (:mod:`pivot_ompl.transit.floor_grid`): where the walking body fits at each yaw,
  what the resting box closes;
- **components** (:mod:`pivot_ompl.transit.floor_graph`): the open grid's graph and its
  connected components;
- **distances** (this module, :class:`FloorField`): the open positions, the floor distances
  to a goal, and the lattice costs-to-go (:mod:`pivot_ompl.transit.lattice_field`).

**Floor distances** (:meth:`FloorField.distances`, the heuristic of larger floors): a
relaxation of the lattice (:mod:`pivot_ompl.transit.lattice`): a grid position is *open*
when the walking body, there, is clear of the obstacles and inside the bounds at one of
:data:`~pivot_ompl.transit.floor_grid.OPEN_YAWS` at least (the 16 headings and the 16 yaws
half-way between neighbours), and the disk inscribed in the body round the robot pose is
``box_margin`` away from the resting box. Every lattice state's body is free at its heading,
one of those yaws, and contains that disk; every lattice motion's translation is a sum of the
16 heading vectors between open positions: a motion twice a unit vector passes the position in
between with its yaw half-way (turning while walking) or unchanged, and the body is free there
too. So the shortest path over open positions with those moves (Dijkstra, scipy) is a lower
bound of the length of any lattice walk: an admissible heuristic that knows the obstacles, and
a proof that no walk exists when it is infinite. Testing the body itself, not only its
inscribed disk, closes the gaps the robot cannot pass at any heading (a slot only the box fits
through): without that, a walk whose only way lies through such a gap is refused only after
the lattice search has expanded every state it can reach (seconds). The Dijkstra runs over the
connected component of the goals in the open grid's graph (the components computed once per
scene) and, given a ``limit``, settles only the positions within it: complete (exact) within
the limit, a lower bound (the limit) beyond it, ``inf`` only where no walk exists.

The obstacles' part is built once per scene (:meth:`FloorField.static_open`), a block of
yaws (on a floor of ``window_from`` positions or more: a tile, reusing those the windowed
queries built), then a block of grid rows of the graph, between polls of the termination
condition; the work done is kept when it is interrupted, and the next call resumes there.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose
from pivot_ompl.transit.floor_graph import GRAPH_CHUNK, OpenGraph, closed_entries, closing
from pivot_ompl.transit.floor_grid import OPEN_YAWS, FloorGrid
from pivot_ompl.transit.floor_window import FloorTiles, FloorWindow, flood_distances, goal_window
from pivot_ompl.transit.lattice import HEADING_VECTORS, Primitive
from pivot_ompl.transit.lattice_field import LatticeField
from pivot_ompl.validity.collision import CollisionWorld

__all__ = ["GRAPH_CHUNK", "OPEN_YAWS", "YAW_CHUNK", "FieldStats", "FloorField",
           "FloorWindow"]

#: Yaws of :data:`~pivot_ompl.transit.floor_grid.OPEN_YAWS` rasterised together between two
#: polls of the termination condition.
YAW_CHUNK = 8



@dataclass
class FieldStats:
    """What the last floor-distance query of a :class:`FloorField` ran over.

    Attributes:
        searched_positions: open positions of the graph its Dijkstra ran over (those of the
            goals' components; 0 when no goal was open).
        windowed: whether it ran in a window round its goals (:mod:`.floor_window`).
    """

    searched_positions: int = 0
    windowed: bool = False


class FloorField:
    """Open grid positions and floor distances to a goal (see the module docstring).

    Args:
        model: box and robot geometry.
        world: the static obstacles.
        resolution: grid spacing (m), the lattice's.
        box_margin: clearance kept from the resting box (m).
        window_from: grid positions from which a query within a limit runs in a window
            round its goals (:meth:`distances`); smaller floors run over the whole floor.

    Attributes:
        grid: the grid layer (:class:`~pivot_ompl.transit.floor_grid.FloorGrid`).
        graph: the components layer (:class:`~pivot_ompl.transit.floor_graph.OpenGraph`),
            ``None`` until :meth:`static_open` has summed every yaw.
        lattice: the lattice costs-to-go over the grid
            (:class:`~pivot_ompl.transit.lattice_field.LatticeField`).
        yaws_done, rows_done: yaws, then grid rows of the graph, of :meth:`static_open` done
            so far (it resumes there when interrupted).
        stats: what the last :meth:`distances` query ran over (:class:`FieldStats`).
        tiles: the open positions by tiles (:class:`~.floor_window.FloorTiles`), for the
            queries run in a window.
    """

    graph: OpenGraph | None

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, resolution: float,
                 box_margin: float, *, window_from: int = 62_500) -> None:
        """The grid layer; the graph is built by :meth:`static_open`."""
        self.grid = FloorGrid(model, world, resolution, box_margin)
        self.window_from = window_from
        self.lattice = LatticeField(self.grid)
        self.tiles = FloorTiles(self.grid)
        self.graph = None
        self.stats = FieldStats()
        self._open: np.ndarray | None = None
        self._partial: np.ndarray | None = None
        self.yaws_done = 0

    @property
    def rows_done(self) -> int:
        """Grid rows of the graph built so far."""
        return 0 if self.graph is None else self.graph.rows_done

    def static_open(self, should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions ignoring the resting box, ``(nx, ny)`` booleans (built once).

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per block of
                :data:`YAW_CHUNK` yaws, or per tile on a floor of ``window_from`` positions
                or more, then once per block of grid rows of the graph); the
                work done is kept (:attr:`yaws_done`, :attr:`rows_done`) and the next call
                resumes there.
        """
        if self._open is None:
            grid = self.grid
            if self._partial is None:
                self._partial = np.zeros((grid.nx, grid.ny), dtype=bool)
            ok = self._partial
            if grid.nx * grid.ny >= self.window_from and self.yaws_done < len(OPEN_YAWS):
                # a large floor: from its tiles (those the windowed queries built are kept)
                ok[:] = self.tiles.window(slice(0, grid.nx), slice(0, grid.ny), should_stop)
                self.yaws_done = len(OPEN_YAWS)
            for k0 in range(self.yaws_done, len(OPEN_YAWS), YAW_CHUNK):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking floor field")
                k1 = min(len(OPEN_YAWS), k0 + YAW_CHUNK)
                for fits in grid.fits_range(k0, k1, should_stop):
                    ok |= fits
                self.yaws_done = k1
            chunk = max(1, GRAPH_CHUNK // grid.ny)  # grid rows per poll
            for i0 in range(self.rows_done, grid.nx, chunk):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking floor field")
                if self.graph is None:
                    self.graph = OpenGraph(ok, grid.resolution)
                self.graph.add_rows(i0, min(grid.nx, i0 + chunk))
            self._open, self._partial = ok, None
        return self._open

    def open_with_box(self, obj: Pose,
                      should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions with the box resting at ``obj``."""
        return self.static_open(should_stop) & ~self.grid.box_closes(obj)

    def distances(self, obj: Pose, goals: list[tuple[int, int]],
                  should_stop: Callable[[], bool] | None = None, *,
                  limit: float = math.inf) -> np.ndarray | FloorWindow:
        """Shortest open-grid distance (m) of every position to the nearest of ``goals``.

        With the box resting at ``obj``; shape ``(nx, ny)``. Exact at every position whose
        distance is at most ``limit``: the Dijkstra settles only those (its cost follows
        the floor within ``limit`` of the goals, not the whole floor). The others hold
        ``inf`` when they are unreachable for certain (``limit`` is ``inf``, or the
        Dijkstra settled every position it could reach before the limit), else ``limit``:
        a lower bound of their distance (larger, or unreachable).

        On a floor of ``window_from`` grid positions or more, a finite ``limit`` whose window
        round the goals is not the whole grid (or any finite limit, until the whole floor's
        open positions are built) runs over the tiles round the goals that its
        Dijkstra reaches (:mod:`.floor_window`: nothing over the whole floor): the same
        distances wherever a walk from the goals can reach (an open position of another
        component may hold the limit instead of ``inf``), returned as a
        :class:`~.floor_window.FloorWindow` (indexed by ``[ix, iy]`` as the array).

        Raises:
            Interrupted: ``should_stop()`` became true while the open positions were built.
        """
        n = self.grid.nx * self.grid.ny
        if math.isfinite(limit) and goals and n >= self.window_from:
            wx, wy = goal_window(self.grid, goals, limit)
            if (wx.stop - wx.start) * (wy.stop - wy.start) < n or self._open is None:
                return self._window_distances(obj, goals, limit, should_stop)
        self.stats.windowed = False
        self.static_open(should_stop)
        graph, grid = self.graph, self.grid
        assert graph is not None
        ny = grid.ny
        flat = np.asarray([ix * ny + iy for ix, iy in goals], dtype=np.int64)
        out = np.full(grid.nx * ny, np.inf)
        open_goals = graph.node[flat][graph.node[flat] >= 0]
        self.stats.searched_positions = 0
        if len(open_goals):
            cells, component = graph.component_graph(open_goals)
            self.stats.searched_positions = len(cells)
            cut = closed_entries(cells, grid.box_closed(obj), ny, grid.nx)
            if should_stop is not None and should_stop():
                raise Interrupted("walking floor field")
            sources = np.searchsorted(cells, flat[graph.node[flat] >= 0])
            with closing(component, cut):
                dist = np.asarray(dijkstra(component, directed=True, min_only=True,
                                           limit=limit, indices=sources))
                if math.isfinite(limit) and _has_frontier(component, dist,
                                                          len(HEADING_VECTORS)):
                    dist[np.isinf(dist)] = limit
            out[cells] = dist
        out[flat] = 0.0  # a goal that is not open is its own distance 0 away
        return out.reshape(grid.nx, grid.ny)

    def _window_distances(self, obj: Pose, goals: list[tuple[int, int]], limit: float,
                          should_stop: Callable[[], bool] | None) -> FloorWindow:
        """:meth:`distances` over the tiles round the goals that the Dijkstra reaches."""
        grid = self.grid

        def closes(wx: slice, wy: slice) -> np.ndarray:
            closed = np.zeros((wx.stop - wx.start, wy.stop - wy.start), dtype=bool)
            cx, cy = np.divmod(grid.box_closed(obj), grid.ny)
            inside = (cx >= wx.start) & (cx < wx.stop) & (cy >= wy.start) & (cy < wy.stop)
            closed[cx[inside] - wx.start, cy[inside] - wy.start] = True
            return closed

        out, searched = flood_distances(self.tiles, closes, goals, limit, should_stop)
        self.stats.searched_positions, self.stats.windowed = searched, True
        return out

    def lattice_costs(self, obj: Pose, goals: list[tuple[int, int, int]],
                      prims: tuple[tuple[Primitive, ...], ...],
                      should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """:meth:`LatticeField.costs <pivot_ompl.transit.lattice_field.LatticeField.costs>`."""
        return self.lattice.costs(obj, goals, prims, should_stop)

    def box_reach(self) -> float:
        """:meth:`FloorGrid.box_reach <pivot_ompl.transit.floor_grid.FloorGrid.box_reach>`."""
        return self.grid.box_reach()


def _has_frontier(graph: csr_matrix, dist: np.ndarray, slots: int) -> bool:
    """Whether an open edge of ``graph`` leads from a settled node to one not settled.

    ``graph`` has ``slots`` entries a row (the floor grid's); ``dist``: a Dijkstra's
    distances, ``inf`` where it settled nothing. Without such an edge the settled nodes are
    every node the sources reach.
    """
    settled = np.flatnonzero(np.isfinite(dist))
    entries = (settled[:, None] * slots + np.arange(slots)[None, :]).ravel()
    open_ = np.isfinite(graph.data[entries])
    return bool(np.isinf(dist[graph.indices[entries[open_]]]).any())
