"""The floor field's grid layer: where the walking body fits, and what the resting box closes.

The grid is the walk lattice's (:mod:`pivot_ompl.transit.lattice`): positions ``resolution``
apart over the scene's bounds. At each of :data:`OPEN_YAWS` (the 16 headings and the 16 yaws
half-way between neighbours) a position *fits* the walking body when the body there is inside
the bounds and clear of the obstacles grown by the kept clearance.

The obstacles' part is vectorised (numpy), a block of yaws at a time: at each yaw, the
positions where the body (grown by the kept clearance) meets an obstacle are the convex hulls
of vertex differences (:func:`~pivot_ompl.validity.minkowski.meeting_edges` without its
certificate: the regions of shapely's :func:`~pivot_ompl.validity.footprints.meeting_hulls`
to rounding, for a floor that guides the walk search; rasterised together by
:func:`~pivot_ompl.validity.rasters.grid_union`), computed for polygons *inside* the true
shapes (a cylinder's inscribed polygon, the clearance's rounded corners by chords), so a
position is never closed where the exact checks would let the body stand. A centrally
symmetric piece's sum at a yaw pi from an earlier one is that sum point-reflected
(:data:`OPPOSITE_YAWS`; the same region to rounding). On a floor imported from an
occupancy map whose grid the walk grid's lines follow, the boxes on the map's lines are met
instead by a stencil's dilation of their cells, per yaw
(:func:`~pivot_ompl.validity.cell_stencil.cell_dilation`: the same positions as their sums
rasterised, several times cheaper on thousands of boxes); the other pieces are summed.

The resting box's part is computed per query, in the window it can close: the positions whose
inscribed disk comes within ``box_margin`` of the box (:meth:`FloorGrid.box_closes`, the floor
distances'), and per heading the positions where the body meets the box grown by the margin
(:meth:`FloorGrid.meets_box`, the lattice costs', its rounded corners by chords).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import shapely

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose, rectangle_corners
from pivot_ompl.transit.floor_sums import PieceSums
from pivot_ompl.transit.lattice import HEADING_YAWS
from pivot_ompl.validity.assembly_field import least_boxes
from pivot_ompl.validity.cell_stencil import cell_dilation
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_pieces, piece_bounds
from pivot_ompl.validity.minkowski import EdgeSet, meeting_edges
from pivot_ompl.validity.rasters import grid_union

#: Yaws at which a grid position may hold the walking body: the 16 lattice headings and the
#: yaws half-way between neighbouring ones (a step that turns while walking passes a grid
#: position with its yaw half-way).
OPEN_YAWS: tuple[float, ...] = tuple(sorted(
    {*HEADING_YAWS, *(a + 0.5 * ((b - a + math.pi) % (2 * math.pi) - math.pi)
                      for a, b in zip(HEADING_YAWS, HEADING_YAWS[1:] + HEADING_YAWS[:1],
                                      strict=True))}))


#: Per yaw of :data:`OPEN_YAWS`, the earlier one opposite it (pi apart), or ``None``: a body
#: turned by pi is its point reflection, so a wall box's sum there is reflected, not summed
#: (:class:`~.floor_sums.PieceSums`).
OPPOSITE_YAWS: tuple[int | None, ...] = tuple(
    next((j for j in range(k) if abs(math.remainder(OPEN_YAWS[k] - OPEN_YAWS[j] - math.pi,
                                                    2 * math.pi)) < 1e-9), None)
    for k in range(len(OPEN_YAWS)))


#: Yaws whose obstacle sums are computed together (all 32 at once ran slower on a floor of
#: 5000 pieces: arrays too large for the caches).
YAW_BLOCK = 8


@dataclass
class GridStats:
    """What a :class:`FloorGrid` has computed so far.

    Attributes:
        yaws_summed: yaw layers whose obstacle footprints were summed with every piece (each
            sum at most once: a sum is kept once computed).
        pairs_summed: (piece, yaw) sums computed (the tiles sum only the pieces near them).
    """

    yaws_summed: int = 0
    pairs_summed: int = 0


def _guide_sums(pieces: list[np.ndarray], bodies: list[np.ndarray], *,
                should_stop: Callable[[], bool] | None = None) -> EdgeSet:
    """:func:`~pivot_ompl.validity.minkowski.meeting_edges` without the certificate.

    The same regions to rounding, about four times cheaper: the floor guides the walk
    search (its heuristic), every walk is certified by the clearance checks.
    """
    return meeting_edges(pieces, bodies, should_stop=should_stop, certify=False)


def _turned(points: np.ndarray, yaw: float) -> np.ndarray:
    """``points`` (rows of x, y) turned by ``yaw`` about the origin."""
    c, s = math.cos(yaw), math.sin(yaw)
    return points @ np.array([[c, -s], [s, c]]).T


class FloorGrid:
    """Grid positions, where the walking body fits at each yaw, what the resting box closes.

    Args:
        model: box and robot geometry.
        world: the static obstacles.
        resolution: grid spacing (m), the lattice's.
        box_margin: clearance kept from the resting box (m).
        cells: where enough obstacle pieces are boxes on the lines of a map's grid whose
            cell divides ``resolution`` (:func:`~pivot_ompl.validity.cell_stencil.
            cell_dilation`), those are met by a stencil's dilation of their cells (the same
            positions), the others summed; ``False`` sums every one.

    Attributes:
        nx, ny: grid size.
        radius: the walking body's inscribed radius (m).
        pieces: the obstacles' convex pieces (:func:`~pivot_ompl.validity.footprints.
            obstacle_pieces`).
        xs, ys: the grid's columns' and rows' coordinates (m), ``nx`` and ``ny`` long
            (:attr:`grid_x`, :attr:`grid_y`: whole-floor arrays, built only when asked).
        outline: the walking body's corners relative to the robot pose at yaw 0 (m).
        grown_outline: that outline grown by the kept clearance (chords inside the rounded
            corners).
        stats: what was computed so far (:class:`GridStats`).
    """

    nx: int
    ny: int
    radius: float
    pieces: list[np.ndarray]

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, resolution: float,
                 box_margin: float, *, cells: bool = True) -> None:
        """Grid size, the inscribed radius, the walking body's outlines, obstacle pieces."""
        self.model, self.world = model, world
        self.resolution, self.box_margin = resolution, box_margin
        self.stats = GridStats()
        #: per index into :data:`OPEN_YAWS` (as far as built), where the walking body fits
        self._fits: dict[int, np.ndarray] = {}
        b = world.bounds
        self.nx = int(math.floor((b[2] - b[0]) / resolution)) + 1
        self.ny = int(math.floor((b[3] - b[1]) / resolution)) + 1
        self.radius = model.robot_inradius()
        self.xs = b[0] + resolution * np.arange(self.nx)
        self.ys = b[1] + resolution * np.arange(self.ny)
        self.outline = np.array(model.walking_outline())
        grown = shapely.Polygon(self.outline).buffer(world.clearance, quad_segs=4) \
            if world.clearance > 0 else shapely.Polygon(self.outline)
        self.grown_outline = np.asarray(grown.exterior.coords)[:-1]
        self.pieces = obstacle_pieces(world.obstacles)
        #: farthest a point of the grown body lies from the robot pose (m)
        self._body_reach = float(np.hypot(self.grown_outline[:, 0],
                                          self.grown_outline[:, 1]).max())
        bodies = [_turned(self.grown_outline, yaw) for yaw in OPEN_YAWS]
        #: the boxes on a map's grid, met by a stencil's dilation of their cells (the same
        #: positions as their sums rasterised); the other pieces summed
        self._cells = cell_dilation(self.pieces, b, resolution, (self.nx, self.ny),
                                    reach=self._body_reach, least=least_boxes) \
            if cells else None
        summed = self.pieces if self._cells is None else \
            [q for q, a in zip(self.pieces, self._cells.aligned, strict=True) if not a]
        self._runs = [] if self._cells is None else [self._cells.stencil(d) for d in bodies]
        self._piece_boxes = piece_bounds(summed)
        #: every (summed piece, yaw) sum with the grown body, summed once when first asked
        #: (shared by :meth:`fits_range` and :meth:`open_block`)
        self.sums = PieceSums(summed, bodies, opposite=list(OPPOSITE_YAWS))

    @property
    def grid_x(self) -> np.ndarray:
        """The grid positions' x (m), ``(nx, ny)`` (a whole-floor array, built per call)."""
        return np.broadcast_to(self.xs[:, None], (self.nx, self.ny))

    @property
    def grid_y(self) -> np.ndarray:
        """The grid positions' y (m), ``(nx, ny)`` (a whole-floor array, built per call)."""
        return np.broadcast_to(self.ys[None, :], (self.nx, self.ny))

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
                the body are summed, :func:`~pivot_ompl.validity.minkowski.meeting_edges`).
        """
        todo = [k for k in range(k0, k1) if k not in self._fits]
        if todo:
            every = np.arange(len(self._piece_boxes))
            for b0 in range(0, len(todo), YAW_BLOCK):  # the stop polled between blocks
                self._summed(every, todo[b0:b0 + YAW_BLOCK], should_stop)
            edges, groups = self.sums.edges(every, todo)
            meets = grid_union(edges, self.xs, self.ys, groups=groups, n_groups=len(todo)) \
                if len(every) else np.zeros((len(todo), self.nx, self.ny), dtype=bool)
            self._cell_hits(todo, meets, (0, 0))
            self._fits.update(zip(todo, self._inside(todo, self.xs, self.ys, meets),
                                  strict=True))
        return [self._fits[k] for k in range(k0, k1)]

    def open_block(self, wx: slice, wy: slice,
                   should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Grid positions ``[wx, wy]`` where the body fits at one of :data:`OPEN_YAWS` at least.

        The same positions as :meth:`fits_index` of every yaw or-ed, there (the same float
        expressions on the same coordinates), rasterised over the block alone from the
        obstacle pieces that can reach it (nothing over the whole floor; the pieces' sums
        with the body at every yaw are computed once, on first use).

        Raises:
            Interrupted: ``should_stop()`` became true (polled while the pieces are summed).
        """
        xs, ys = self.xs[wx], self.ys[wy]
        r = self._body_reach + self.resolution
        pb = self._piece_boxes
        near = np.flatnonzero((pb[:, 0] <= xs[-1] + r) & (pb[:, 2] >= xs[0] - r)
                              & (pb[:, 1] <= ys[-1] + r) & (pb[:, 3] >= ys[0] - r))
        k = len(OPEN_YAWS)
        self._summed(near, list(range(k)), should_stop)
        edges, groups = self.sums.edges(near, list(range(k)))
        meets = grid_union(edges, xs, ys, groups=groups, n_groups=k) \
            if len(near) else np.zeros((k, len(xs), len(ys)), dtype=bool)
        self._cell_hits(list(range(k)), meets, (wx.start, wy.start))
        return np.logical_or.reduce(self._inside(list(range(k)), xs, ys, meets), axis=0)

    def _cell_hits(self, yaws: list[int], meets: np.ndarray, at: tuple[int, int]) -> None:
        """Add to ``meets`` (per yaw, a block from grid position ``at``) the map's boxes hit.

        Those met by a stencil's dilation of their cells (none where the floor is not a
        map's grid at this spacing); in place.
        """
        if self._cells is None:
            return
        for k, hit in zip(yaws, meets, strict=True):
            hit |= self._cells.hits(self._runs[k], hit.shape, at=at)

    def _inside(self, yaws: list[int], xs: np.ndarray, ys: np.ndarray, meets: np.ndarray
                ) -> np.ndarray:
        """``meets`` (per yaw, where the body meets an obstacle) made where the body fits.

        Inside the bounds and meeting no obstacle; in place.
        """
        b = self.world.bounds
        for k, hit in zip(yaws, meets, strict=True):
            corners = _turned(self.outline, OPEN_YAWS[k])
            inside = ((xs + corners[:, 0].min() > b[0])
                      & (xs + corners[:, 0].max() < b[2]))[:, None] \
                & ((ys + corners[:, 1].min() > b[1])
                   & (ys + corners[:, 1].max() < b[3]))[None, :]
            np.logical_and(inside, ~hit, out=hit)
        return meets

    def _summed(self, pieces: np.ndarray, yaws: list[int],
                should_stop: Callable[[], bool] | None) -> None:
        """Sum the pieces ``pieces`` (indices) with the grown body at ``yaws``, those not yet.

        In one call of :func:`~pivot_ompl.validity.minkowski.meeting_edges` (which polls the
        stop); the sums are kept (:class:`~.floor_sums.PieceSums`).
        """
        self.stats.pairs_summed += self.sums.fill(pieces, yaws, _guide_sums, should_stop)
        self.stats.yaws_summed = self.sums.yaws_complete()

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
        out[self.box_closed(obj)] = True
        return out.reshape(self.nx, self.ny)

    def box_closed(self, obj: Pose) -> np.ndarray:
        """Flat grid indices of :meth:`box_closes` (from its window alone)."""
        wx, wy = self._box_window(obj)
        c, s = math.cos(obj[2]), math.sin(obj[2])
        ex, ey = self.xs[wx][:, None] - obj[0], self.ys[wy][None, :] - obj[1]
        lx = np.abs(c * ex + s * ey) - 0.5 * self.model.object_size[0]
        ly = np.abs(-s * ex + c * ey) - 0.5 * self.model.object_size[1]
        d = np.hypot(np.maximum(lx, 0.0), np.maximum(ly, 0.0))
        ix, iy = np.nonzero(d <= self.radius + self.box_margin)
        return (ix + wx.start) * self.ny + iy + wy.start

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
        # the Minkowski sums of the box and the turned body
        bodies = [_turned(self.outline, yaw) for yaw in HEADING_YAWS]
        edges = meeting_edges([pts] * len(bodies), bodies)
        meets = grid_union(edges, self.xs, self.ys,
                           groups=np.arange(len(bodies)), n_groups=len(bodies))
        return list(meets)
