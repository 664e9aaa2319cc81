"""Rooms and passages first: the band of the floor round the box's cheapest coarse routes.

On a large floor (an office's SLAM map: thousands of wall pieces and specks) the scene holds
thousands of slots and doors (:mod:`.slots`); seeding them all, and multiplexing the tens of
thousands of roadmap nodes they give, takes longer than the planning limit, though a plan
visits only the few on its way. :class:`FloorBand` finds that way coarsely first: the floor
rasterised (cells whose centre lies inside an obstacle are blocked), the clearance of every
cell (a distance transform, scipy), and over the cells where the box alone fits (its narrow
half side plus the kept clearance) the cheapest routes from the start and from the goal (one
Dijkstra each): a step into a cell too narrow for the held assembly costs ``penalty`` metres
more (a place where the robot must let go of the box, which a plan pays for in regrasps).
The *band* at ``slack`` is the cells on a route at most ``slack`` times dearer than the
cheapest (rooms at both ends, alternative corridors of nearly equal cost), grown by
``margin``; :meth:`FloorBand.region` gives it as a :class:`BandRegion` that keeps a passage's
centre and skips the obstacles far from it. The passages are then found, and seeded, with
their exact geometry inside the band only; a wider slack widens it when the search fails.

The raster only chooses where to look: it never widens or narrows a passage (the passages'
widths and the planner's checks stay exact), and when start and goal are not joined on the
raster the band is the whole floor.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.sparse import coo_matrix, csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.errors import Interrupted
from pivot_ompl.planners.objects.slots import Passage, assembly_extent
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.footprints import obstacle_footprints
from pivot_ompl.validity.rasters import grid_inside

Stop = Callable[[], bool]

#: The 8-neighbourhood's moves, each taken both ways.
_MOVES = ((1, 0), (0, 1), (1, 1), (1, -1))


class BandRegion:
    """A set of raster cells: which points and boxes of the floor it holds or meets.

    Args:
        mask: the cells (``True`` inside), indexed ``[ix, iy]``.
        origin: the floor's lower corner (m).
        cell: the cells' side (m).

    Attributes:
        cells: how many cells it holds.
    """

    def __init__(self, mask: np.ndarray, origin: tuple[float, float], cell: float) -> None:
        """The region of ``mask``'s cells."""
        self.mask = mask
        self.origin = origin
        self.cell = cell
        self.cells = int(mask.sum())
        self._flat = np.flatnonzero(mask)
        self._sums = np.pad(np.cumsum(np.cumsum(mask, axis=0, dtype=np.int64), axis=1),
                            ((1, 0), (1, 0)))

    def _index(self, x: float, y: float) -> tuple[int, int]:
        nx, ny = self.mask.shape
        return (min(nx - 1, max(0, int((x - self.origin[0]) // self.cell))),
                min(ny - 1, max(0, int((y - self.origin[1]) // self.cell))))

    def holds(self, x: float, y: float) -> bool:
        """Whether the cell of ``(x, y)`` is in the region (a point off the floor: its nearest)."""
        return bool(self.mask[self._index(x, y)])

    @property
    def area(self) -> float:
        """Its area (m^2)."""
        return self.cells * self.cell * self.cell

    def sample(self, rng: np.random.Generator) -> tuple[float, float]:
        """A uniform point of the region (a uniform cell, then a uniform point in it)."""
        if not len(self._flat):
            raise ValueError("an empty region has no point")
        i, j = np.divmod(int(self._flat[int(rng.integers(len(self._flat)))]), self.mask.shape[1])
        return (self.origin[0] + (i + float(rng.uniform())) * self.cell,
                self.origin[1] + (j + float(rng.uniform())) * self.cell)

    def meets(self, bounds: tuple[float, float, float, float]) -> bool:
        """Whether a cell of the region lies in the box ``(x0, y0, x1, y1)`` (its cells)."""
        i0, j0 = self._index(bounds[0], bounds[1])
        i1, j1 = self._index(bounds[2], bounds[3])
        s = self._sums
        return bool(s[i1 + 1, j1 + 1] - s[i0, j1 + 1] - s[i1 + 1, j0] + s[i0, j0] > 0)


@dataclass(frozen=True)
class BandStats:
    """What the coarse routes found.

    Attributes:
        cell: the raster's cell side (m).
        free_cells: cells where the box alone fits.
        cost: the cheapest route's cost (m, narrow crossings' penalties included; ``inf``
            when start and goal are not joined on the raster).
        seconds: the raster and both searches.
    """

    cell: float
    free_cells: int
    cost: float
    seconds: float


class FloorBand:
    """The box's coarse routes from start to goal over a raster of the floor (module docstring).

    Args:
        checker: the scene (obstacles, bounds, clearance) and the box and held assembly.
        start, goal: the box's poses (only their positions are used).
        cell: the least cell side (m).
        max_cells: most cells of the raster (a larger floor gets larger cells).
        penalty: extra cost (m) of a step from a cell where the held assembly fits into one
            where it does not.
        margin: how far (m) the band reaches beyond the routes' cells.
        should_stop: polled between the steps.

    Raises:
        Interrupted: ``should_stop()`` became true.
    """

    def __init__(self, checker: PivotChecker, start: Pose, goal: Pose, *, cell: float,
                 max_cells: int, penalty: float, margin: float, should_stop: Stop) -> None:
        """Rasterise the floor and search the routes from both ends."""
        t0 = time.perf_counter()
        x0, y0, x1, y1 = checker.world.bounds
        h = max(cell, math.sqrt((x1 - x0) * (y1 - y0) / max_cells))
        self.cell, self.origin, self.margin = h, (x0, y0), margin
        nx, ny = max(1, math.ceil((x1 - x0) / h)), max(1, math.ceil((y1 - y0) / h))
        xs, ys = x0 + (np.arange(nx) + 0.5) * h, y0 + (np.arange(ny) + 0.5) * h
        blocked = np.zeros((nx, ny), dtype=bool)
        for k, shape in enumerate(obstacle_footprints(checker.world.obstacles)):
            if k % 512 == 0 and should_stop():
                raise Interrupted("floor band")
            cols, rows, inside = grid_inside(shape, xs, ys)
            blocked[cols, rows] |= inside
        # distance from each cell centre to the nearest blocked centre or the floor's edge
        clearance = ndimage.distance_transform_edt(
            np.pad(~blocked, 1, constant_values=False))[1:-1, 1:-1] * h + 0.5 * h
        clear = checker.world.clearance
        box = clearance >= 0.5 * min(checker.model.object_size[:2]) + clear
        wide = clearance >= 0.5 * assembly_extent(checker).width + clear
        if should_stop():
            raise Interrupted("floor band")
        self._wide, self._box = wide, box
        graph, self._ids = _cell_graph(box, wide, h, penalty)
        ends = [self._nearest_cell(box, p) for p in (start, goal)]
        self._cost = np.full(box.shape, np.inf)
        best = math.inf
        if graph.shape[0] and min(ends) >= 0:
            to_start = dijkstra(graph, directed=True, indices=[ends[0]])[0]
            if should_stop():
                raise Interrupted("floor band")
            to_goal = dijkstra(graph.T.tocsr(), directed=True, indices=[ends[1]])[0]
            total = to_start + to_goal
            best = float(total[ends[1]] if np.isfinite(total[ends[1]]) else math.inf)
            self._cost[box] = total
        self.best = best
        self.stats = BandStats(h, int(box.sum()), best, time.perf_counter() - t0)

    def _nearest_cell(self, box: np.ndarray, pose: Pose) -> int:
        """The graph id of the box-free cell nearest ``pose``'s position (within a metre)."""
        nx, ny = box.shape
        h, (x0, y0) = self.cell, self.origin
        i = min(nx - 1, max(0, int((pose[0] - x0) // h)))
        j = min(ny - 1, max(0, int((pose[1] - y0) // h)))
        r = max(1, math.ceil(1.0 / h))
        win = box[max(0, i - r):i + r + 1, max(0, j - r):j + r + 1]
        if not win.any():
            return -1
        wi, wj = np.nonzero(win)
        ci, cj = wi + max(0, i - r), wj + max(0, j - r)
        k = int(np.argmin((ci - i) ** 2 + (cj - j) ** 2))
        return int(self._ids[ci[k], cj[k]])

    def joined(self) -> bool:
        """Whether start and goal are joined on the raster (else every band is the floor)."""
        return math.isfinite(self.best)

    def region(self, slack: float) -> BandRegion:
        """The cells on routes at most ``slack`` times dearer than the cheapest, and the margin.

        The band is grown by the margin; the whole floor when start and goal are not joined,
        or for an infinite ``slack``.
        """
        if not self.joined() or not math.isfinite(slack):
            return BandRegion(np.ones(self._cost.shape, dtype=bool), self.origin, self.cell)
        core = self._cost <= self.best * (1.0 + slack) + 1e-9
        grown = ndimage.distance_transform_edt(~core) * self.cell <= self.margin
        return BandRegion(grown, self.origin, self.cell)

    def route_cost(self, x: float, y: float) -> float:
        """The cheapest route's cost (m) through the cell of ``(x, y)`` (``inf``: none there)."""
        nx, ny = self._cost.shape
        i = min(nx - 1, max(0, int((x - self.origin[0]) // self.cell)))
        j = min(ny - 1, max(0, int((y - self.origin[1]) // self.cell)))
        return float(self._cost[i, j])


    def bypassed(self, passage: Passage, *, reach: float) -> bool:
        """Whether ``passage`` leads nowhere, or the held assembly goes round it nearby.

        On the raster, within ``reach`` (m) of the passage's ends: the cells before and after
        the gap (the shortest segment between its two obstacles, two cells thick) along the
        passage's axis. Bypassed when one side has no cell where the box fits (a gap along a
        wall cut into pieces, whose one side is the wall), or when the cells where the
        assembly fits, less the gap's, join the two sides (a gap between two specks in an
        open room). A gap the raster closes is kept.
        """
        h, (x0, y0) = self.cell, self.origin
        cx, cy = passage.center
        nx, ny = self._wide.shape
        r = reach + 0.5 * max(passage.width, passage.length)
        i0, i1 = max(0, int((cx - r - x0) // h)), min(nx, int((cx + r - x0) // h) + 1)
        j0, j1 = max(0, int((cy - r - y0) // h)), min(ny, int((cy + r - y0) // h) + 1)
        if i1 <= i0 or j1 <= j0:
            return False
        gx = x0 + (np.arange(i0, i1) + 0.5) * h - cx
        gy = y0 + (np.arange(j0, j1) + 0.5) * h - cy
        c, s = math.cos(passage.axis), math.sin(passage.axis)
        along = c * gx[:, None] + s * gy[None, :]
        across = np.abs(-s * gx[:, None] + c * gy[None, :])
        on_gap = across <= 0.5 * passage.width
        half = 0.5 * passage.length
        cut = on_gap & (np.abs(along) <= half + h)
        ends = on_gap & (np.abs(along) > half + h) & (np.abs(along) <= half + 6.0 * h)
        box = self._box[i0:i1, j0:j1]
        if not (box & ends & (along < 0)).any() or not (box & ends & (along > 0)).any():
            return True
        free = self._wide[i0:i1, j0:j1] & ~cut & (np.maximum(np.abs(along) - half, across) <= r)
        labels, _ = ndimage.label(free, structure=np.ones((3, 3), dtype=bool))
        before = set(np.unique(labels[ends & (along < 0)]).tolist()) - {0}
        after = set(np.unique(labels[ends & (along > 0)]).tolist()) - {0}
        return bool(before & after)


def _cell_graph(box: np.ndarray, wide: np.ndarray, h: float,
                penalty: float) -> tuple[csr_matrix, np.ndarray]:
    """The 8-connected graph of the ``box`` cells (directed: the penalty is on entering).

    Returns the sparse matrix and the cells' ids (``-1`` off the graph), ``[ix, iy]``.
    """
    nx, ny = box.shape
    ids = np.full(box.shape, -1, dtype=np.int64)
    ix, iy = np.nonzero(box)
    n = len(ix)
    ids[ix, iy] = np.arange(n)
    rows, cols, weights = [], [], []
    for vx, vy in _MOVES:
        jx, jy = ix + vx, iy + vy
        inside = (jx >= 0) & (jx < nx) & (jy >= 0) & (jy < ny)
        there = np.full(n, -1, dtype=np.int64)
        there[inside] = ids[jx[inside], jy[inside]]
        a = np.flatnonzero(there >= 0)
        b = there[a]
        step = math.hypot(vx, vy) * h
        wa, wb = wide[ix[a], iy[a]], wide[ix[b], iy[b]]
        rows += [a, b]
        cols += [b, a]
        weights += [step + penalty * (wa & ~wb), step + penalty * (wb & ~wa)]
    if n == 0:
        return coo_matrix((0, 0)).tocsr(), ids
    return coo_matrix((np.concatenate(weights), (np.concatenate(rows), np.concatenate(cols))),
                      shape=(n, n)).tocsr(), ids
