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
it can reach (seconds). The Dijkstra runs over the connected component of the goals in the
open grid's graph (the components computed once per scene; the open floor outside a turned
building, say, costs a query nothing) and, given a ``limit``, settles only the positions
within it: complete (exact) within the limit, a lower bound (the limit) beyond it, ``inf``
only where no walk exists. The resting box's part is computed in the window it can close.

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
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import connected_components, dijkstra

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
        self._components: np.ndarray | None = None
        self._graphs: dict[tuple[int, ...], tuple[np.ndarray, csr_matrix]] = {}
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
        """The grid graph's edges from the open positions of grid rows ``i0:i1`` (CSR).

        The graph follows the open floor, not the bounds' rectangle (a turned row of rooms
        fills a small part of it, and the rectangle grows with the square of its length):
        its nodes are the open positions in grid order (:attr:`_cells`: their flat grid
        indices). Every node has one slot per heading vector (16, in
        :data:`HEADING_VECTORS` order): the edge to the position that vector away, of its
        length when that position is open too, ``inf`` otherwise (no edge; it then points
        back at the node itself). Built directly in CSR form (no sort), a block of rows at a
        time; a query only closes the resting box's positions (in place, restored after).
        """
        ny, nd = self.ny, len(HEADING_VECTORS)
        if i0 == 0:
            self._cells = np.flatnonzero(ok.ravel())
            self._node = np.full(self.nx * ny, -1, dtype=np.int64)
            self._node[self._cells] = np.arange(len(self._cells))
            m = len(self._cells)
            self._indices = np.empty((m, nd), dtype=np.int32)
            self._weights = np.empty((m, nd))
            kind = np.int32 if nd * m < 2 ** 31 else np.int64
            self._indptr = np.arange(0, nd * m + 1, nd, dtype=kind)
        lo, hi = np.searchsorted(self._cells, [i0 * ny, i1 * ny])
        ix, iy = np.divmod(self._cells[lo:hi], ny)
        v = np.asarray(HEADING_VECTORS)
        tx, ty = ix[:, None] + v[None, :, 0], iy[:, None] + v[None, :, 1]
        inside = (tx >= 0) & (tx < self.nx) & (ty >= 0) & (ty < ny)
        there = np.where(inside, self._node[np.where(inside, tx * ny + ty, 0)], -1)
        both = there >= 0
        here = np.arange(lo, hi)[:, None]
        self._indices[lo:hi] = np.where(both, there, here)
        lengths = self.resolution * np.hypot(v[:, 0], v[:, 1])
        self._weights[lo:hi] = np.where(both, lengths[None, :], np.inf)

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

    def box_reach(self) -> float:
        """Farthest (m) from the resting box's centre a position the box closes can lie.

        The box's half diagonal plus the inscribed radius and the box margin: a position
        farther than that from the centre is at least ``radius + box_margin`` from the box.
        """
        w, d = self.model.object_size[0], self.model.object_size[1]
        return 0.5 * math.hypot(w, d) + self.radius + self.box_margin

    def _box_window(self, obj: Pose) -> tuple[slice, slice]:
        """The grid rows and columns within :meth:`box_reach` of ``obj``'s centre."""
        b, res, r = self.world.bounds, self.resolution, self.box_reach()
        i0 = max(0, math.floor((obj[0] - r - b[0]) / res))
        i1 = min(self.nx, math.ceil((obj[0] + r - b[0]) / res) + 1)
        j0 = max(0, math.floor((obj[1] - r - b[1]) / res))
        j1 = min(self.ny, math.ceil((obj[1] + r - b[1]) / res) + 1)
        return slice(i0, max(i0, i1)), slice(j0, max(j0, j1))

    def box_closes(self, obj: Pose) -> np.ndarray:
        """Grid positions the box resting at ``obj`` closes, ``(nx, ny)`` booleans.

        Those whose inscribed disk comes within ``box_margin`` of the box; computed only in
        the window within :meth:`box_reach` of its centre (nothing farther is closed).
        """
        out = np.zeros(self.nx * self.ny, dtype=bool)
        out[self._box_closed(obj)] = True
        return out.reshape(self.nx, self.ny)

    def _box_closed(self, obj: Pose) -> np.ndarray:
        """Flat grid indices of :meth:`box_closes` (from its window alone)."""
        wx, wy = self._box_window(obj)
        c, s = math.cos(obj[2]), math.sin(obj[2])
        ex, ey = self.grid_x[wx, wy] - obj[0], self.grid_y[wx, wy] - obj[1]
        lx = np.abs(c * ex + s * ey) - 0.5 * self.model.object_size[0]
        ly = np.abs(-s * ex + c * ey) - 0.5 * self.model.object_size[1]
        d = np.hypot(np.maximum(lx, 0.0), np.maximum(ly, 0.0))
        ix, iy = np.nonzero(d <= self.radius + self.box_margin)
        return (ix + wx.start) * self.ny + iy + wy.start

    def open_with_box(self, obj: Pose,
                      should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions with the box resting at ``obj``."""
        return self.static_open(should_stop) & ~self.box_closes(obj)

    def distances(self, obj: Pose, goals: list[tuple[int, int]],
                  should_stop: Callable[[], bool] | None = None, *,
                  limit: float = math.inf) -> np.ndarray:
        """Shortest open-grid distance (m) of every position to the nearest of ``goals``.

        With the box resting at ``obj``; shape ``(nx, ny)``. Exact at every position whose
        distance is at most ``limit``: the Dijkstra settles only those (its cost follows
        the floor within ``limit`` of the goals, not the whole floor). The others hold
        ``inf`` when they are unreachable for certain (``limit`` is ``inf``, or the
        Dijkstra settled every position it could reach before the limit), else ``limit``:
        a lower bound of their distance (larger, or unreachable).
        """
        self.static_open(should_stop)
        ny, nd = self.ny, len(HEADING_VECTORS)
        flat = np.asarray([ix * ny + iy for ix, iy in goals], dtype=np.int64)
        out = np.full(self.nx * ny, np.inf)
        open_goals = self._node[flat][self._node[flat] >= 0]
        if len(open_goals):
            cells, graph = self._component_graph(open_goals)
            cut = self._box_cut(obj, cells)
            if should_stop is not None and should_stop():
                raise Interrupted("walking floor field")
            sources = np.searchsorted(cells, flat[self._node[flat] >= 0])
            saved = graph.data[cut]
            graph.data[cut] = np.inf
            try:
                dist = np.asarray(dijkstra(graph, directed=True, min_only=True, limit=limit,
                                           indices=sources))
                if math.isfinite(limit) and _has_frontier(graph, dist, nd):
                    dist[np.isinf(dist)] = limit
            finally:
                graph.data[cut] = saved
            out[cells] = dist
        out[flat] = 0.0  # a goal that is not open is its own distance 0 away
        return out.reshape(self.nx, self.ny)

    def _box_cut(self, obj: Pose, cells: np.ndarray) -> np.ndarray:
        """The entries of a component's graph (over ``cells``) the box at ``obj`` closes.

        The edges out of and into the open positions of ``cells`` the box closes.
        """
        ny, nd = self.ny, len(HEADING_VECTORS)
        closed = self._box_closed(obj)
        local = np.searchsorted(cells, closed)
        hit = (local < len(cells)) & (cells[np.minimum(local, len(cells) - 1)] == closed)
        closed, local = closed[hit], local[hit]
        slots = [(local[:, None] * nd + np.arange(nd)[None, :]).ravel()]  # edges out
        cx, cy = np.divmod(closed, ny)
        for d, (vx, vy) in enumerate(HEADING_VECTORS):  # edges in: from the position -v away
            sx, sy = cx - vx, cy - vy
            inside = (sx >= 0) & (sx < self.nx) & (sy >= 0) & (sy < ny)
            src = sx[inside] * ny + sy[inside]
            k = np.searchsorted(cells, src)
            ok = (k < len(cells)) & (cells[np.minimum(k, len(cells) - 1)] == src)
            slots.append(k[ok] * nd + d)
        return np.concatenate(slots)

    def _component_graph(self, nodes: np.ndarray) -> tuple[np.ndarray, csr_matrix]:
        """The grid graph restricted to the components of ``nodes`` (open-graph nodes).

        Returns the components' positions (flat grid indices, sorted) and their graph, its
        node ``k`` the position ``cells[k]`` (kept per set of components). A walk never
        leaves the component it starts in: the floor outside it costs a query nothing
        (outside a turned building, say, the bounds' rectangle is open floor too).
        """
        labels = self._labels()
        key = tuple(sorted({int(v) for v in labels[nodes]}))
        hit = self._graphs.get(key)
        if hit is None:
            nd = len(HEADING_VECTORS)
            members = np.flatnonzero(np.isin(labels, key))
            local = np.full(len(self._cells), -1, dtype=np.int64)
            local[members] = np.arange(len(members))
            idx = self._indices[members]
            sub = np.where(local[idx] >= 0, local[idx], np.arange(len(members))[:, None])
            graph = csr_matrix((self._weights[members].reshape(-1),
                                sub.reshape(-1).astype(np.int32),
                                np.arange(0, nd * len(members) + 1, nd, dtype=np.int64)),
                               shape=(len(members), len(members)))
            hit = self._graphs[key] = (self._cells[members], graph)
        return hit

    def _labels(self) -> np.ndarray:
        """Connected component of every node of the open grid's graph (computed once).

        The components of the open positions joined by the 8 unit moves (image labelling),
        merged where a move of :data:`HEADING_VECTORS` two cells long joins two of them: the
        graph's edges are exactly those moves between open positions.
        """
        if self._components is None:
            assert self._open is not None
            image, _ = ndimage.label(self._open, structure=np.ones((3, 3), dtype=bool))
            pairs = []
            for vx, vy in HEADING_VECTORS:
                if abs(vx) + abs(vy) != 3 or vx < 0:  # the knight moves, one way each
                    continue
                a = image[:self.nx - vx, max(0, -vy):self.ny - max(0, vy)]  # p
                b = image[vx:, max(0, vy):self.ny + min(0, vy)]  # p + (vx, vy)
                join = (a > 0) & (b > 0) & (a != b)
                pairs.append(np.stack([a[join], b[join]]))
            n = int(image.max()) + 1
            ab = np.concatenate(pairs, axis=1) if pairs else np.zeros((2, 0), dtype=np.int64)
            merged = connected_components(
                csr_matrix((np.ones(ab.shape[1], dtype=np.int8), (ab[0], ab[1])), shape=(n, n)),
                directed=False)[1]
            self._components = merged[image.ravel()[self._cells]]
        return self._components

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


def _dijkstra_closing(graph: csr_matrix, cut: np.ndarray, sources: list, *,
                      limit: float = math.inf) -> np.ndarray:
    """Distances from the nearest of ``sources`` over ``graph``, its entries ``cut`` closed.

    The entries (the resting box's part of a query) are closed in place in the graph built
    once per scene, and restored after. Nodes farther than ``limit`` are not settled
    (``inf``).
    """
    saved = graph.data[cut]
    graph.data[cut] = np.inf
    try:
        return np.asarray(dijkstra(graph, directed=True, indices=sources, min_only=True,
                                   limit=limit))
    finally:
        graph.data[cut] = saved
