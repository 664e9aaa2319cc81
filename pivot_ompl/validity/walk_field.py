"""The walk planner's heuristic: floor distances on the lattice grid, obstacles included.

A relaxation of the lattice (:mod:`pivot_ompl.validity.walk_lattice`): a grid position is
*open* when the disk inscribed in the robot's footprint (radius ``min(depth, width) / 2``),
centred there, is clear of the obstacles and the bounds, and ``box_margin`` away from the
resting box. A lattice state is collision-free only at an open position (the footprint
contains that disk), and every lattice motion's translation is a sum of the 16 heading vectors
between open positions (a motion twice a unit vector passes the position in between, where
the footprint is free too). So the shortest path over open positions with those moves
(Dijkstra, scipy) is a lower bound of the length of any lattice walk: an admissible
heuristic that knows the obstacles, and a proof that no walk exists when it is infinite.
The obstacles' part is built once per scene; the resting box's per query (vectorised).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.errors import Interrupted
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.walk_lattice import HEADING_VECTORS


@dataclass
class FloorField:
    """Open grid positions and floor distances to a goal (see the module docstring).

    Args:
        model: box and robot geometry.
        world: the static obstacles.
        resolution: grid spacing (m), the lattice's.
        box_margin: clearance kept from the resting box (m).
    """

    model: BoxGraspModel
    world: CollisionWorld
    resolution: float
    box_margin: float
    _open: np.ndarray | None = field(default=None, init=False, repr=False)
    _partial: np.ndarray | None = field(default=None, init=False, repr=False)
    #: Grid rows of :meth:`static_open` done so far (it resumes there when interrupted).
    rows_done: int = field(default=0, init=False)

    def __post_init__(self) -> None:
        """Grid size and the inscribed radius."""
        b = self.world.bounds
        self.nx = int(math.floor((b[2] - b[0]) / self.resolution)) + 1
        self.ny = int(math.floor((b[3] - b[1]) / self.resolution)) + 1
        self.radius = self.model.robot_inradius()
        xs = b[0] + self.resolution * np.arange(self.nx)
        ys = b[1] + self.resolution * np.arange(self.ny)
        self._x, self._y = np.meshgrid(xs, ys, indexing="ij")

    def static_open(self, should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions ignoring the resting box, ``(nx, ny)`` booleans (built once).

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per grid row); the rows
                done are kept (:attr:`rows_done`) and the next call resumes there.
        """
        if self._open is None:
            b, r = self.world.bounds, self.radius
            x, y = self._x, self._y
            if self._partial is None:
                self._partial = (x - b[0] >= r) & (b[2] - x >= r) & (y - b[1] >= r) \
                    & (b[3] - y >= r)
            ok = self._partial
            if self.world.has_obstacles:
                for ix in range(self.rows_done, self.nx):
                    if should_stop is not None and should_stop():
                        raise Interrupted("walking floor field")
                    for iy in np.nonzero(ok[ix])[0]:
                        ok[ix, iy] = self.world.disk_distance(float(x[ix, iy]),
                                                              float(y[ix, iy]), r) > 0.0
                    self.rows_done = ix + 1
            self.rows_done = self.nx
            self._open, self._partial = ok, None
            sx, sy = np.nonzero(ok)
            n = self.nx * self.ny
            rows, cols, lens = [], [], []
            for vx, vy in HEADING_VECTORS[:8]:  # the other 8 are their opposites
                tx, ty = sx + vx, sy + vy
                inside = (tx >= 0) & (tx < self.nx) & (ty >= 0) & (ty < self.ny)
                a = sx[inside] * self.ny + sy[inside]
                t = tx[inside] * self.ny + ty[inside]
                keep = ok.ravel()[t]
                rows.append(a[keep])
                cols.append(t[keep])
                lens.append(np.full(int(keep.sum()), self.resolution * math.hypot(vx, vy)))
            self._rows = np.concatenate(rows)
            self._cols = np.concatenate(cols)
            self._lens = np.concatenate(lens)
            self._n = n
        return self._open

    def open_with_box(self, obj: Pose,
                      should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Open positions with the box resting at ``obj``."""
        ok = self.static_open(should_stop)
        c, s = math.cos(obj[2]), math.sin(obj[2])
        ex, ey = self._x - obj[0], self._y - obj[1]
        lx = np.abs(c * ex + s * ey) - 0.5 * self.model.object_size[0]
        ly = np.abs(-s * ex + c * ey) - 0.5 * self.model.object_size[1]
        d = np.hypot(np.maximum(lx, 0.0), np.maximum(ly, 0.0))
        return ok & (d > self.radius + self.box_margin)

    def distances(self, obj: Pose, goals: list[tuple[int, int]],
                  should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """Shortest open-grid distance (m) of every position to the nearest of ``goals``.

        ``inf``: unreachable. With the box resting at ``obj``; shape ``(nx, ny)``.
        """
        ok = self.open_with_box(obj, should_stop).ravel()
        keep = ok[self._rows] & ok[self._cols]
        g = csr_matrix((self._lens[keep], (self._rows[keep], self._cols[keep])),
                       shape=(self._n, self._n))
        idx = [ix * self.ny + iy for ix, iy in goals]
        d = dijkstra(g, directed=False, indices=idx, min_only=True)
        return np.asarray(d).reshape(self.nx, self.ny)
