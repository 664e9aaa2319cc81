"""The walk planner's heuristics: lattice costs-to-go, and floor distances on the grid.

**Lattice costs** (:meth:`FloorField.lattice_costs`, the heuristic of floors up to
``WalkPlanner.max_field_states`` lattice states): the lattice itself with its motions and
their costs, relaxed to its states: a state is free when the walking body at its heading is
inside the bounds, clear of the obstacles grown by the kept clearance and of the resting box
grown by the walk's box margin (both for polygons inside the true grown shapes, see below);
a motion is kept when both its ends are free, its sweep is not checked. The planner's search
only takes motions whose ends are free by the exact checks, so every walk it can find is a
walk of this graph: its cost-to-go (one Dijkstra from the goal states over the reversed
motions) is admissible, knows at which heading the robot fits where, and is infinite only
where no walk exists. The obstacles' graph is built once per scene, in CSR form directly;
a query closes the states the box blocks (in place, restored after).

**Floor distances** (:meth:`FloorField.distances`, the heuristic of larger floors): a
relaxation of the lattice (:mod:`pivot_ompl.transit.lattice`): a grid position is *open*
when the walking body, there, is clear of the obstacles and inside the bounds at one of
:data:`OPEN_YAWS` at least (the 16 headings and the 16 yaws half-way between neighbours), and
the disk inscribed in the body round the robot pose is ``box_margin`` away from the resting
box. Every lattice state's body is free at its heading, one of those yaws, and contains that
disk; every lattice motion's translation is a sum of the 16 heading vectors between open
positions: a motion twice a unit vector passes the position in between with its yaw half-way
(turning while walking) or unchanged, and the body is free there too. So the shortest path over
open positions with those moves (Dijkstra, scipy) is a lower bound of the length of any lattice
walk: an admissible heuristic that knows the obstacles, and a proof that no walk exists when it
is infinite. Testing the body itself, not only its inscribed disk, closes the gaps the robot
cannot pass at any heading (a slot only the box fits through): without that, a walk whose only
way lies through such a gap is refused only after the lattice search has expanded every state
it can reach (seconds).

The obstacles' part is built once per scene, vectorised (numpy), a block of yaws at a time
between polls of the termination condition: at each yaw, the positions where the body (grown
by the kept clearance) meets an obstacle are the convex hulls of vertex differences
(:func:`~pivot_ompl.validity.footprints.meeting_edges`, the same hulls as shapely's
:func:`~pivot_ompl.validity.footprints.meeting_hulls`; rasterised together by
:func:`~pivot_ompl.validity.footprints.grid_union`), computed for polygons
*inside* the true shapes (a cylinder's inscribed polygon, the clearance's rounded corners by
chords), so a position is never closed where the exact checks would let the body stand. The
resting box's part is computed per query (vectorised): for the lattice costs, the same hulls
of the box grown by the margin (its rounded corners by chords) and the body at each heading.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose, rectangle_corners
from pivot_ompl.transit.lattice import HEADING_VECTORS, HEADING_YAWS, N_HEADINGS, Primitive
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import EdgeSet, grid_union, meeting_edges, obstacle_pieces

#: Grid positions whose graph edges are built between two polls of the termination condition.
GRAPH_CHUNK = 20_000

#: Yaws of :data:`OPEN_YAWS` rasterised together between two polls of the termination
#: condition.
YAW_CHUNK = 8

#: Yaws at which a grid position may hold the walking body: the 16 lattice headings and the
#: yaws half-way between neighbouring ones (a step that turns while walking passes a grid
#: position with its yaw half-way).
OPEN_YAWS: tuple[float, ...] = tuple(sorted(
    {*HEADING_YAWS, *(a + 0.5 * ((b - a + math.pi) % (2 * math.pi) - math.pi)
                      for a, b in zip(HEADING_YAWS, HEADING_YAWS[1:] + HEADING_YAWS[:1],
                                      strict=True))}))


class FloorField:
    """Open grid positions and floor distances to a goal (see the module docstring).

    Args:
        model: box and robot geometry.
        world: the static obstacles.
        resolution: grid spacing (m), the lattice's.
        box_margin: clearance kept from the resting box (m).

    Attributes:
        nx, ny: grid size.
        radius: the walking body's inscribed radius (m).
        pieces: the obstacles' convex pieces (:func:`~pivot_ompl.validity.footprints.
            obstacle_pieces`).
        grid_x, grid_y: the grid positions' coordinates (m), ``(nx, ny)`` arrays.
        outline: the walking body's corners relative to the robot pose at yaw 0 (m).
        grown_outline: that outline grown by the kept clearance (chords inside the rounded
            corners).
        yaws_done, rows_done: yaws, then grid rows of the graph, of :meth:`static_open` done
            so far (it resumes there when interrupted).
    """

    nx: int
    ny: int
    radius: float
    pieces: list[np.ndarray]
    yaws_done: int
    rows_done: int

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, resolution: float,
                 box_margin: float) -> None:
        """Grid size, the inscribed radius, the walking body's outlines, obstacle pieces."""
        self.model, self.world = model, world
        self.resolution, self.box_margin = resolution, box_margin
        self._open: np.ndarray | None = None
        #: per index into :data:`OPEN_YAWS` (as far as built), where the walking body fits
        self._fits: dict[int, np.ndarray] = {}
        self._lattice: csr_matrix | None = None
        self._partial: np.ndarray | None = None
        self.yaws_done = self.rows_done = 0
        b = world.bounds
        self.nx = int(math.floor((b[2] - b[0]) / resolution)) + 1
        self.ny = int(math.floor((b[3] - b[1]) / resolution)) + 1
        self.radius = model.robot_inradius()
        xs = b[0] + resolution * np.arange(self.nx)
        ys = b[1] + resolution * np.arange(self.ny)
        self.grid_x, self.grid_y = np.meshgrid(xs, ys, indexing="ij")
        #: the walking body's corners, and its outline grown by the kept clearance (chords
        #: inside the rounded corners), relative to the robot pose at yaw 0
        self.outline = np.array(model.walking_outline())
        grown = shapely.Polygon(self.outline).buffer(world.clearance, quad_segs=4) \
            if world.clearance > 0 else shapely.Polygon(self.outline)
        self.grown_outline = np.asarray(grown.exterior.coords)[:-1]
        self.pieces = obstacle_pieces(world.obstacles)

    def static_open(self, should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions ignoring the resting box, ``(nx, ny)`` booleans (built once).

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per block of
                :data:`YAW_CHUNK` yaws, then once per
                block of grid rows of the graph); the work done is kept (:attr:`yaws_done`,
                :attr:`rows_done`) and the next call resumes there.
        """
        if self._open is None:
            if self._partial is None:
                self._partial = np.zeros((self.nx, self.ny), dtype=bool)
            ok = self._partial
            for k0 in range(self.yaws_done, len(OPEN_YAWS), YAW_CHUNK):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking floor field")
                k1 = min(len(OPEN_YAWS), k0 + YAW_CHUNK)
                for fits in self.fits_range(k0, k1, should_stop):
                    ok |= fits
                self.yaws_done = k1
            chunk = max(1, GRAPH_CHUNK // self.ny)  # grid rows per poll
            for i0 in range(self.rows_done, self.nx, chunk):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking floor field")
                self._add_rows(ok, i0, min(self.nx, i0 + chunk))
                self.rows_done = min(self.nx, i0 + chunk)
            self._open, self._partial = ok, None
        return self._open

    def _add_rows(self, ok: np.ndarray, i0: int, i1: int) -> None:
        """The grid graph's edges from grid rows ``i0:i1``, into a CSR matrix built directly.

        Every position has one slot per heading vector (16, in :data:`HEADING_VECTORS`
        order): the edge to the position that vector away, of its length when both ends are
        open, ``inf`` otherwise (no edge; an outside target points back at the position
        itself). No COO-to-CSR conversion (a sort): a query only closes the resting box's
        positions (in place, restored after). Built a block of rows at a time, as the memory
        it fills costs time on a large floor.
        """
        nx, ny, nd = self.nx, self.ny, len(HEADING_VECTORS)
        if i0 == 0:
            self._indices = np.empty((nx * ny, nd), dtype=np.int32)
            self._weights = np.empty((nx * ny, nd))
            self._indptr = np.arange(0, nd * nx * ny + 1, nd, dtype=np.int64)
        ix, iy = np.arange(i0, i1)[:, None, None], np.arange(ny)[None, :, None]
        v = np.asarray(HEADING_VECTORS)
        tx, ty = ix + v[None, None, :, 0], iy + v[None, None, :, 1]
        inside = (tx >= 0) & (tx < nx) & (ty >= 0) & (ty < ny)
        target = np.where(inside, tx * ny + ty, ix * ny + iy).reshape(-1, nd)
        rows = slice(i0 * ny, i1 * ny)
        self._indices[rows] = target
        flat = ok.ravel()
        both = inside.reshape(-1, nd) & flat[rows, None] & flat[target]
        lengths = self.resolution * np.hypot(v[:, 0], v[:, 1])
        self._weights[rows] = np.where(both, lengths[None, :], np.inf)

    def fits_index(self, k: int) -> np.ndarray:
        """Grid positions where the walking body at yaw ``OPEN_YAWS[k]`` fits (kept).

        Inside the bounds and clear of the obstacles grown by the clearance.
        """
        return self.fits_range(k, k + 1)[0]

    def fits_range(self, k0: int, k1: int, should_stop: Callable[[], bool] | None = None
                   ) -> list[np.ndarray]:
        """:meth:`fits_index` of ``k0 .. k1 - 1``, those not kept yet computed together.

        Raises:
            Interrupted: ``should_stop()`` became true (polled while the obstacle pieces and
                the body are summed, :func:`~pivot_ompl.validity.footprints.meeting_edges`).
        """
        todo = [k for k in range(k0, k1) if k not in self._fits]
        if todo:
            xs, ys = self.grid_x[:, 0], self.grid_y[0, :]
            n = len(self.pieces)
            meets = grid_union(self._static_edges(todo, should_stop), xs, ys,
                               groups=np.repeat(np.arange(len(todo)), n), n_groups=len(todo)) \
                if n else np.zeros((len(todo), self.nx, self.ny), dtype=bool)
            b = self.world.bounds
            for k, hit in zip(todo, meets, strict=True):
                c, s = math.cos(OPEN_YAWS[k]), math.sin(OPEN_YAWS[k])
                corners = self.outline @ np.array([[c, -s], [s, c]]).T
                inside = ((xs + corners[:, 0].min() > b[0])
                          & (xs + corners[:, 0].max() < b[2]))[:, None] \
                    & ((ys + corners[:, 1].min() > b[1])
                       & (ys + corners[:, 1].max() < b[3]))[None, :]
                self._fits[k] = inside & ~hit
        return [self._fits[k] for k in range(k0, k1)]

    def _static_edges(self, yaws: list[int], should_stop: Callable[[], bool] | None = None
                      ) -> EdgeSet:
        """Where the grown body meets each obstacle piece, at the yaws ``OPEN_YAWS[k]``.

        Polygon ``j * len(pieces) + i``: piece ``i`` at yaw ``OPEN_YAWS[yaws[j]]`` (summed at
        once, vectorised). Only the yaws asked for: :meth:`static_open` asks a block at a
        time, polling the termination condition between blocks (all 32 yaws at once ran
        past a 0.5 s limit by 30 ms on fig10).
        """
        bodies = []
        for k in yaws:
            c, s = math.cos(OPEN_YAWS[k]), math.sin(OPEN_YAWS[k])
            body = self.grown_outline @ np.array([[c, -s], [s, c]]).T
            bodies.extend([body] * len(self.pieces))
        return meeting_edges(self.pieces * len(yaws), bodies, should_stop=should_stop)

    def open_with_box(self, obj: Pose,
                      should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions with the box resting at ``obj``."""
        ok = self.static_open(should_stop)
        c, s = math.cos(obj[2]), math.sin(obj[2])
        ex, ey = self.grid_x - obj[0], self.grid_y - obj[1]
        lx = np.abs(c * ex + s * ey) - 0.5 * self.model.object_size[0]
        ly = np.abs(-s * ex + c * ey) - 0.5 * self.model.object_size[1]
        d = np.hypot(np.maximum(lx, 0.0), np.maximum(ly, 0.0))
        return ok & (d > self.radius + self.box_margin)

    def distances(self, obj: Pose, goals: list[tuple[int, int]],
                  should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Shortest open-grid distance (m) of every position to the nearest of ``goals``.

        ``inf``: unreachable. With the box resting at ``obj``; shape ``(nx, ny)``.
        """
        static = self.static_open(should_stop)
        closed = np.nonzero((static & ~self.open_with_box(obj, should_stop)).ravel())[0]
        nd, ny = len(HEADING_VECTORS), self.ny
        slots = [(closed[:, None] * nd + np.arange(nd)[None, :]).ravel()]  # edges out
        cx, cy = closed // ny, closed % ny
        for d, (vx, vy) in enumerate(HEADING_VECTORS):  # edges in: from the position -v away
            sx, sy = cx - vx, cy - vy
            inside = (sx >= 0) & (sx < self.nx) & (sy >= 0) & (sy < ny)
            slots.append((sx[inside] * ny + sy[inside]) * nd + d)
        cut = np.concatenate(slots)
        if should_stop is not None and should_stop():
            raise Interrupted("walking floor field")
        n = self.nx * ny
        g = csr_matrix((self._weights.reshape(-1), self._indices.reshape(-1), self._indptr),
                       shape=(n, n), copy=False)
        dist = _dijkstra_closing(g, cut, [ix * ny + iy for ix, iy in goals])
        return dist.reshape(self.nx, self.ny)

    def lattice_costs(self, obj: Pose, goals: list[tuple[int, int, int]],
                      prims: tuple[tuple[Primitive, ...], ...],
                      should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Cost-to-go of every lattice state to the nearest of ``goals``, relaxed.

        The lattice (:mod:`~pivot_ompl.transit.lattice`) with its motions ``prims`` and
        their costs, where a state ``(ix, iy, h)`` is free when the walking body at heading
        ``h`` fits there (obstacles grown by the kept clearance, bounds: the yaw's
        :meth:`static_open` layer) and does not meet the resting box grown by ``box_margin``
        (chords inside the rounded corners); a motion is kept when both its ends are free,
        its sweep is not checked. Every lattice walk the search may take is a walk of this
        graph: the cost-to-go is an admissible heuristic that knows where the body can stand
        at which heading (where it must turn, and where it cannot), and ``inf`` proves that
        no lattice walk reaches the goals. Shape ``(nx, ny, N_HEADINGS)``; Dijkstra (scipy)
        over the reversed motions.
        """
        rows = self._lattice_graph(prims, should_stop)
        nx, ny, nh = self.nx, self.ny, N_HEADINGS
        node = np.arange(nx * ny * nh).reshape(nx, ny, nh)
        # the states where the body meets the box relay nothing: their rows (the motions
        # into them, reversed) closed in place for this query, restored after
        blocked = np.concatenate([node[:, :, h][meets]
                                  for h, meets in enumerate(self.meets_box(obj))])
        first, count = rows.indptr[blocked], np.diff(rows.indptr)[blocked]
        cut = np.repeat(first - np.cumsum(count) + count, count) + np.arange(count.sum())
        if should_stop is not None and should_stop():
            raise Interrupted("walking lattice field")
        return _dijkstra_closing(rows, cut, [node[s] for s in goals]).reshape(nx, ny, nh)

    def _lattice_graph(self, prims: tuple[tuple[Primitive, ...], ...],
                       should_stop: Callable[[], bool] | None = None) -> csr_matrix:
        """The lattice's motions between states free of the obstacles and bounds, reversed.

        Built once (the primitives are the walk planner's, the same for every query),
        directly in CSR form (no sort): row ``v`` holds, per primitive that can end at
        ``v``'s heading, the motion from its start state when both states are free (its
        cost). Polls ``should_stop`` once per heading; the headings' layers already built
        are kept.
        """
        if self._lattice is None:
            nx, ny, nh = self.nx, self.ny, N_HEADINGS
            free = np.empty((nx, ny, nh), dtype=bool)
            for h in range(nh):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking lattice field")
                free[:, :, h] = self.fits_index(OPEN_YAWS.index(HEADING_YAWS[h]))
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

    def meets_box(self, obj: Pose) -> list[np.ndarray]:
        """Per heading, the grid positions where the walking body meets the grown box.

        The box resting at ``obj`` grown by ``box_margin``: a polygon inside the rounded
        grown box; ``(nx, ny)`` booleans for each of the ``N_HEADINGS`` headings.
        """
        w, d = self.model.object_size[0], self.model.object_size[1]
        box = shapely.Polygon(rectangle_corners(obj, w, d))
        if self.box_margin > 0:
            box = box.buffer(self.box_margin, quad_segs=4)
        pts = np.asarray(box.exterior.coords)[:-1]
        bodies = []
        for yaw in HEADING_YAWS:  # the Minkowski sums of the box and the turned body
            c, s = math.cos(yaw), math.sin(yaw)
            bodies.append(self.outline @ np.array([[c, -s], [s, c]]).T)
        edges = meeting_edges([pts] * len(bodies), bodies)
        meets = grid_union(edges, self.grid_x[:, 0], self.grid_y[0, :],
                           groups=np.arange(len(bodies)), n_groups=len(bodies))
        return list(meets)


def _dijkstra_closing(graph: csr_matrix, cut: np.ndarray, sources: list) -> np.ndarray:
    """Distances from the nearest of ``sources`` over ``graph``, its entries ``cut`` closed.

    The entries (the resting box's part of a query) are closed in place in the graph built
    once per scene, and restored after.
    """
    saved = graph.data[cut]
    graph.data[cut] = np.inf
    try:
        return np.asarray(dijkstra(graph, directed=True, indices=sources, min_only=True))
    finally:
        graph.data[cut] = saved
