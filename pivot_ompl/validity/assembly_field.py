"""Where the held assembly fits: grid positions of the car, per heading and grasp parity.

The assembly is the box and the robot holding it (the two convex bodies the checkers test:
the box's footprint and the convex hull of
:meth:`~pivot_ompl.grasp.BoxGraspModel.held_outline`), placed by the Reeds-Shepp car of the
grasp (the supporting edge's centre and the robot's heading). Relative to its car the
assembly of grasp ``k`` is that of grasp ``k + 2``: one shape per grasp *parity*.

For each parity and each yaw of :data:`FIELD_YAWS` (the 16 lattice headings of
:data:`~pivot_ompl.se2.GRID_HEADING_YAWS` and the 16 yaws half-way between them), a
boolean grid says where the car may stand: both bodies inside the bounds and clear of the
obstacles grown by the kept clearance (the clearance's rounded corners by chords, a
cylinder by its inscribed polygon: the shapes are *inside* the true grown ones, so a
position the exact checks accept is never closed). The positions where a body meets an
obstacle piece are convex hulls of vertex differences
(:func:`~pivot_ompl.validity.minkowski.meeting_edges`), rasterised together
(:func:`~pivot_ompl.validity.rasters.grid_union`), the sums without their certificate
(:func:`~pivot_ompl.validity.minkowski.meeting_edges`, ``certify=False``: the same regions
to rounding). A guide for route planning, not a certificate: motions are certified by the
pivot checker.

**Half the sums.** The yaws come in opposite pairs (``FIELD_YAWS[k + 16]`` is
``FIELD_YAWS[k] + pi``): turned by pi, a body is its point reflection, and the sum of a
centrally symmetric piece (a wall box) with the reflected body is the point reflection of
its sum with the body about the piece's centre (:func:`reflected`). The yaws of a parity are
computed in one batch: the second yaw of each pair reflects the first's sums of the
symmetric pieces (an affine map of the edges, the same regions to rounding: a grid point
exactly on an edge, e.g. of an axis-aligned wall at yaw pi, whose sine is 1e-16 and not 0,
may fall either side) and sums only the others.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
import shapely

from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import GRID_HEADING_YAWS as HEADING_YAWS
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.cell_stencil import CellDilation, cell_dilation
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_pieces, piece_bounds
from pivot_ompl.validity.footprints import symmetric_centres as symmetric_centres
from pivot_ompl.validity.minkowski import EdgeSet, meeting_edges, reflected_bounds
from pivot_ompl.validity.rasters import grid_union

#: The field's yaws: the 16 headings and the 16 half-way yaws, in that order interleaved
#: (index ``2 h`` is heading ``h``, ``2 h + 1`` half-way to heading ``h + 1``).
FIELD_YAWS: tuple[float, ...] = tuple(
    y for a, b in zip(HEADING_YAWS, HEADING_YAWS[1:] + HEADING_YAWS[:1], strict=True)
    for y in (a, a + 0.5 * ((b - a + math.pi) % (2 * math.pi) - math.pi)))

#: Most (piece, body) sums computed and rasterised in one batch (a few MB of edges).
BATCH_POLYGONS = 16384
#: Fewest boxes on the grid's lines met by their cells' dilation (the ``cells`` argument):
#: a stencil per yaw and body costs about as much as summing 130 pieces (door, 2 of them:
#: its field's 64 grids 0.03 s summed, 0.11 s dilated; the Willow Garage office, 5049:
#: 3.7 s summed, 0.6 s dilated, the same grids).
CELL_BOXES = 128
#: Most grid positions rasterised in one call (yaws times positions): a 200 m floor's 32 yaws
#: at 0.4 m in one call took 0.34 s without a look at the stop (and 130 MB of counts).
RASTER_CELLS = 1 << 21


def reflected(edges: EdgeSet, centres: np.ndarray) -> EdgeSet:
    """Each polygon of ``edges`` reflected through its point of ``centres`` (``(n, 2)``).

    A point reflection is a rotation by pi: counter-clockwise edges stay counter-clockwise.
    """
    c = 2.0 * centres[:, None, :]
    return EdgeSet(np.where(edges.used[..., None], c - edges.start, 0.0),
                   np.where(edges.used[..., None], c - edges.end, 0.0), edges.used,
                   reflected_bounds(edges.bounds, centres))


def assembly_bodies(model: BoxGraspModel, grasp: int, clearance: float) -> list[np.ndarray]:
    """The assembly's two convex bodies (vertex arrays, CCW) relative to its car at yaw 0.

    Grown by ``clearance`` (rounded corners by chords: inside the true grown shapes).
    """
    car = (0.0, 0.0, 0.0)
    box = model.object_corners(model.object_from_car(car, grasp))
    held = model.held_corners(model.robot_from_car(car, grasp), grasp)
    out = []
    for pts in (box, held):
        hull = shapely.MultiPoint(pts).convex_hull
        if clearance > 0:
            hull = hull.buffer(clearance, quad_segs=2)
        out.append(np.asarray(shapely.orient_polygons(hull).exterior.coords)[:-1])
    return out


def least_boxes(stride: int) -> int:
    """Fewest boxes on a map's grid met by a stencil where the field's spacing is ``stride`` cells.

    ``stride ** 2`` times :data:`CELL_BOXES`: a stencil's runs and the cells it reads grow
    with the stride (the hospital's 330 boxes at 0.1 m on a 0.05 m map: 0.56 s dilated
    against 0.52 s summed; the bookstore's 521: 0.20 s against 0.45 s).
    """
    return stride * stride * CELL_BOXES


class AssemblyField:
    """The car positions where the held assembly fits (see the module docstring).

    Args:
        model: box and robot geometry.
        world: obstacles, bounds and the kept clearance.
        resolution: grid spacing (m).
        reflect: the second yaw of an opposite pair reflects the first's sums for the
            centrally symmetric pieces (module docstring); ``False`` sums every one.
        cells: where :data:`CELL_BOXES` pieces or more are axis-aligned boxes on the lines
            of a map's grid whose cell divides ``resolution`` (a floor imported from an
            occupancy map at the field's resolution or a whole fraction of it), those are
            met by a stencil's dilation of their cells
            (:mod:`~pivot_ompl.validity.cell_stencil`: the same grids), the others summed;
            ``False`` sums every one.

    Attributes:
        nx, ny: grid size; grid position ``(ix, iy)`` is the point
            ``(x0 + ix * resolution, y0 + iy * resolution)``.
    """

    nx: int
    ny: int

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, resolution: float, *,
                 reflect: bool = True, cells: bool = True) -> None:
        """Nothing rasterised yet."""
        self.model, self.world, self.resolution = model, world, resolution
        self.reflect = reflect
        b = world.bounds
        self.nx = int(math.floor((b[2] - b[0]) / resolution)) + 1
        self.ny = int(math.floor((b[3] - b[1]) / resolution)) + 1
        self._xs = b[0] + resolution * np.arange(self.nx)
        self._ys = b[1] + resolution * np.arange(self.ny)
        self._pieces = obstacle_pieces(world.obstacles)
        self._bodies = {p: assembly_bodies(model, p, world.clearance) for p in (0, 1)}
        self._corners = {p: np.concatenate(assembly_bodies(model, p, 0.0)) for p in (0, 1)}
        self._fits: dict[tuple[int, int], np.ndarray] = {}
        self._cells: CellDilation | None = None  # the boxes met by a stencil (cell_stencil)
        if cells:
            self._dilate_cells()
        self._centres, self._symmetric = symmetric_centres(self._pieces)
        self.sums_reflected = 0  #: pieces' sums reflected rather than summed (a figure)
        self._area: np.ndarray | None = None

    @property
    def pieces(self) -> list[np.ndarray]:
        """The obstacle pieces the sums cover (all, or those near :meth:`restrict`'s area).

        Not the boxes met by their cells' dilation (the ``cells`` argument).
        """
        return self._pieces

    def _dilate_cells(self) -> None:
        """Take the boxes on the map's grid out of the sums, into a stencil's dilation.

        The map's grid: :func:`~.cell_stencil.cell_dilation`, this grid's spacing a whole
        multiple ``k`` of its cell; at least :func:`least_boxes` boxes on it.
        """
        reach = max(float(np.hypot(*np.concatenate(self._bodies[p]).T).max()) for p in (0, 1))
        self._cells = cell_dilation(self._pieces, self.world.bounds, self.resolution,
                                    (self.nx, self.ny), reach=reach, least=least_boxes)
        if self._cells is not None:
            self._pieces = [q for q, a in zip(self._pieces, self._cells.aligned, strict=True)
                            if not a]

    def restrict(self, area: np.ndarray) -> None:
        """Answer only within ``area`` (``(nx, ny)`` booleans): elsewhere nothing fits.

        The obstacle pieces farther from every position of ``area`` than the assembly's
        bodies reach (at any yaw) cannot meet an assembly there: they are left out of the
        sums and rasters (a route planner whose states lie in the region the box can reach
        pays for the pieces round that region, not for the whole floor's). The rasters are
        then exactly those of the whole floor within ``area``. Forgets the rasters made so far.
        """
        reach = max(float(np.hypot(*np.concatenate(self._bodies[p]).T).max()) for p in (0, 1))
        boxes = piece_bounds(self._pieces)
        b, res = self.world.bounds, self.resolution
        i0 = np.clip(np.ceil((boxes[:, 0] - reach - b[0]) / res), 0, self.nx).astype(int)
        i1 = np.clip(np.floor((boxes[:, 2] + reach - b[0]) / res) + 1, 0, self.nx).astype(int)
        j0 = np.clip(np.ceil((boxes[:, 1] - reach - b[1]) / res), 0, self.ny).astype(int)
        j1 = np.clip(np.floor((boxes[:, 3] + reach - b[1]) / res) + 1, 0, self.ny).astype(int)
        total = np.zeros((self.nx + 1, self.ny + 1), dtype=np.int64)  # summed-area table
        total[1:, 1:] = np.cumsum(np.cumsum(area, axis=0), axis=1)
        near = (total[i1, j1] - total[i0, j1] - total[i1, j0] + total[i0, j0]) > 0
        near &= (i0 < i1) & (j0 < j1)
        keep = np.flatnonzero(near)
        self._pieces = [self._pieces[i] for i in keep]
        self._centres, self._symmetric = self._centres[keep], self._symmetric[keep]
        self._area = np.asarray(area, dtype=bool)
        self._fits.clear()

    def _within(self) -> tuple[slice, slice]:
        """The grid rows and columns of :meth:`restrict`'s area's positions (all without)."""
        if self._area is None:
            return slice(0, self.nx), slice(0, self.ny)
        ix, iy = np.flatnonzero(self._area.any(axis=1)), np.flatnonzero(self._area.any(axis=0))
        if not len(ix):
            return slice(0, 0), slice(0, 0)
        return slice(int(ix[0]), int(ix[-1]) + 1), slice(int(iy[0]), int(iy[-1]) + 1)

    def position(self, ix: int, iy: int) -> tuple[float, float]:
        """The floor point of grid position ``(ix, iy)`` (m)."""
        b = self.world.bounds
        return b[0] + ix * self.resolution, b[1] + iy * self.resolution

    def cell(self, x: float, y: float) -> tuple[float, float]:
        """Fractional grid coordinates of a floor point."""
        b = self.world.bounds
        return (x - b[0]) / self.resolution, (y - b[1]) / self.resolution

    def fits(self, parity: int, k: int, *,
             should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Car positions where the assembly fits: ``(nx, ny)`` booleans, kept.

        At grasp parity ``parity`` and yaw ``FIELD_YAWS[k]``.

        Raises:
            Interrupted: ``should_stop()`` said stop before or while it was computed.
        """
        key = (parity % 2, k % len(FIELD_YAWS))
        v = self._fits.get(key)
        if v is None:
            if should_stop is not None and should_stop():
                raise Interrupted("assembly field")
            for batch in self._batches(key[0]):
                for j, grid in zip(batch, self._compute(key[0], batch, should_stop),
                                   strict=True):
                    self._fits[(key[0], j)] = grid
            v = self._fits[key]
        return v

    def _batches(self, parity: int) -> list[list[int]]:
        """The yaws of ``parity`` not yet rasterised, in batches of opposite pairs.

        A batch holds at most :data:`BATCH_POLYGONS` sums (one pair at least), so the
        memory a batch takes does not grow with the floor's pieces.
        """
        half = len(FIELD_YAWS) // 2
        per_pair = max(1, 2 * len(self._bodies[parity]) * len(self._pieces))
        pairs_per_batch = max(1, BATCH_POLYGONS // per_pair)
        pairs = [[j for j in (k, k + half) if (parity, j) not in self._fits]
                 for k in range(half)]
        pairs = [p for p in pairs if p]
        return [[j for p in pairs[i:i + pairs_per_batch] for j in p]
                for i in range(0, len(pairs), pairs_per_batch)]

    def _compute(self, parity: int, ks: list[int], should_stop: Callable[[], bool] | None
                 ) -> list[np.ndarray]:
        """The grids of yaws ``ks`` at ``parity``, every yaw's sums and raster in one batch.

        The same grids as one yaw at a time (each polygon's arithmetic is its own), for a
        thirtieth of the calls: a scene's 64 grids took 0.04-0.1 s one by one.
        """
        xs, ys = self._xs, self._ys
        b = self.world.bounds
        out, rots = [], []
        rows, cols = self._within()
        for k in ks:
            yaw = FIELD_YAWS[k]
            c, s = math.cos(yaw), math.sin(yaw)
            rot = np.array([[c, -s], [s, c]]).T
            rots.append(rot)
            corners = self._corners[parity] @ rot
            ok = ((xs + corners[:, 0].min() > b[0]) & (xs + corners[:, 0].max() < b[2]))[:, None] \
                & ((ys + corners[:, 1].min() > b[1]) & (ys + corners[:, 1].max() < b[3]))[None, :]
            if self._area is not None:
                ok &= self._area
            if self._cells is not None:
                if should_stop is not None and should_stop():
                    raise Interrupted("assembly field")
                inner = ok[rows, cols]  # a view: the positions outside the area fit nowhere
                for body in self._bodies[parity] if inner.size else ():
                    inner &= ~self._cells.hits(self._cells.stencil(body @ rot), inner.shape,
                                               at=(rows.start, cols.start))
            out.append(ok)
        n = len(self._pieces)
        if n and ks:
            edges = self._sums(parity, ks, rots, should_stop)
            if should_stop is not None and should_stop():  # before the batch's raster
                raise Interrupted("assembly field")
            per_yaw = len(self._bodies[parity]) * n
            step = max(1, RASTER_CELLS // (len(xs) * len(ys)))  # yaws a raster call
            for y0 in range(0, len(ks), step):
                if y0 and should_stop is not None and should_stop():
                    raise Interrupted("assembly field")
                y1 = min(len(ks), y0 + step)
                part = slice(y0 * per_yaw, y1 * per_yaw)
                hit = grid_union(EdgeSet(edges.start[part], edges.end[part], edges.used[part],
                                         edges.bounds[part]), xs, ys,
                                 groups=np.arange(part.stop - part.start) // per_yaw,
                                 n_groups=y1 - y0)
                for ok, h in zip(out[y0:y1], hit, strict=True):
                    ok &= ~h
        return out

    def _sums(self, parity: int, ks: list[int], rots: list[np.ndarray],
              should_stop: Callable[[], bool] | None) -> EdgeSet:
        """Every (piece, body) sum at the yaws ``ks`` (rotations ``rots``).

        Polygon ``(y * m + j) * n + i`` is yaw ``ks[y]``, body ``j`` (of ``m``), piece ``i``
        (of ``n``). A yaw whose opposite is also asked reflects that one's sums for the
        symmetric pieces (module docstring; when ``reflect``) and sums only the others.
        """
        n, half = len(self._pieces), len(FIELD_YAWS) // 2
        bodies = [[body @ rot for body in self._bodies[parity]] for rot in rots]
        m = len(bodies[0])
        index = {k: y for y, k in enumerate(ks)}
        mirrored = {y: index[k - half] for y, k in enumerate(ks)
                    if self.reflect and k >= half and k - half in index}
        direct = [y for y in range(len(ks)) if y not in mirrored]
        summed = meeting_edges(self._pieces * (m * len(direct)),
                               [bd for y in direct for bd in bodies[y] for _ in range(n)],
                               should_stop=should_stop, certify=False)
        rows = np.tile(self._symmetric, m)
        todo = np.flatnonzero(~rows)
        own = meeting_edges([self._pieces[i % n] for _ in mirrored for i in todo],
                            [bodies[y][i // n] for y in mirrored for i in todo],
                            should_stop=should_stop, certify=False) if len(todo) else None
        # every yaw's block written in place into one edge set (no block copied twice)
        w = max(summed.start.shape[1], 0 if own is None else own.start.shape[1])
        per = m * n
        out = EdgeSet(np.zeros((len(ks) * per, w, 2)), np.zeros((len(ks) * per, w, 2)),
                      np.zeros((len(ks) * per, w), dtype=bool), np.empty((len(ks) * per, 4)))
        at = {y: slice(y * per, (y + 1) * per) for y in range(len(ks))}
        for u, y in enumerate(direct):
            _put(out, at[y], _rows(summed, slice(u * per, (u + 1) * per)))
        centres = np.tile(self._centres, (m, 1))
        for u, (y, first) in enumerate(mirrored.items()):
            _put(out, at[y], reflected(_rows(summed, slice(direct.index(first) * per,
                                                           (direct.index(first) + 1) * per)),
                                       centres))
            self.sums_reflected += int(rows.sum())
            if own is not None:  # the pieces that are not their own reflection: summed
                part = _rows(own, slice(u * len(todo), (u + 1) * len(todo)))
                _put(out, y * per + todo, part)
        return out

    def state_fits(self, ix: int, iy: int, k: int, parity: int,
                   should_stop: Callable[[], bool] | None = None) -> bool:
        """Whether grid state ``(ix, iy)`` at field yaw ``k`` is free for ``parity``.

        Raises:
            Interrupted: ``should_stop()`` said stop while the yaw's grid was computed.
        """
        if not (0 <= ix < self.nx and 0 <= iy < self.ny):
            return False
        return bool(self.fits(parity, k, should_stop=should_stop)[ix, iy])

    def pose_fits(self, car: Pose, parity: int) -> bool:
        """Whether the nearest grid state of a car pose is free (a quick guess)."""
        fx, fy = self.cell(car[0], car[1])
        k = int(round((car[2] % (2 * math.pi)) / (2 * math.pi) * len(FIELD_YAWS)))
        return self.state_fits(int(round(fx)), int(round(fy)), k, parity)


def _rows(edges: EdgeSet, rows: slice) -> EdgeSet:
    """Polygons ``rows`` of ``edges``."""
    return EdgeSet(edges.start[rows], edges.end[rows], edges.used[rows], edges.bounds[rows])


def _put(edges: EdgeSet, rows: slice | np.ndarray, part: EdgeSet) -> None:
    """Polygons ``rows`` of ``edges`` set to ``part``'s (as wide or narrower: padded)."""
    w = part.start.shape[1]
    if isinstance(rows, slice):
        edges.start[rows, :w], edges.end[rows, :w] = part.start, part.end
        edges.used[rows, :w] = part.used
        edges.start[rows, w:], edges.end[rows, w:], edges.used[rows, w:] = 0.0, 0.0, False
    else:
        pad = edges.start.shape[1] - w
        edges.start[rows] = np.pad(part.start, [(0, 0), (0, pad), (0, 0)])
        edges.end[rows] = np.pad(part.end, [(0, 0), (0, pad), (0, 0)])
        edges.used[rows] = np.pad(part.used, [(0, 0), (0, pad)])
    edges.bounds[rows] = part.bounds
