"""The walk planner's heuristic: floor distances on the lattice grid, obstacles included.

A relaxation of the lattice (:mod:`pivot_ompl.validity.walk_lattice`): a grid position is
*open* when the walking body, there, is clear of the obstacles and inside the bounds at one
of :data:`OPEN_YAWS` at least (the 16 headings and the 16 yaws half-way between neighbours),
and the disk inscribed in the body round the robot pose is ``box_margin`` away from the
resting box. Every lattice state's body is free at its heading, one of those yaws, and
contains that disk; every lattice motion's translation is a sum of the 16 heading vectors
between open positions: a motion twice a unit vector passes the position in between with its
yaw half-way (turning while walking) or unchanged, and the body is free there too. So the
shortest path over open positions with those moves (Dijkstra, scipy) is a lower bound of the
length of any lattice walk: an admissible heuristic that knows the obstacles, and a proof that
no walk exists when it is infinite. Testing the body itself, not only its inscribed disk,
closes the gaps the robot cannot pass at any heading (a slot only the box fits through):
without that, a walk whose only way lies through such a gap is refused only after the
lattice search has expanded every state it can reach (seconds). A position is tested at the
yaws only where the inscribed disk is clear and the disk the body sweeps turning in place is
not. The obstacles' part is built once per scene; the resting box's per query (vectorised).
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
from pivot_ompl.validity.walk_lattice import HEADING_VECTORS, HEADING_YAWS

#: Yaws at which a grid position may hold the walking body: the 16 lattice headings and the
#: yaws half-way between neighbouring ones (a step that turns while walking passes a grid
#: position with its yaw half-way).
OPEN_YAWS: tuple[float, ...] = tuple(sorted(
    {*HEADING_YAWS, *(a + 0.5 * ((b - a + math.pi) % (2 * math.pi) - math.pi)
                      for a, b in zip(HEADING_YAWS, HEADING_YAWS[1:] + HEADING_YAWS[:1],
                                      strict=True))}))


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
    _last_yaw: int = field(default=0, init=False, repr=False)

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
                        ok[ix, iy] = self._body_fits(float(x[ix, iy]), float(y[ix, iy]))
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

    def _body_fits(self, x: float, y: float) -> bool:
        """The walking body at ``(x, y)`` is free and inside the bounds at some open yaw."""
        w = self.world
        if w.disk_distance(x, y, self.radius) <= 0.0:
            return False
        b, rr = w.bounds, self.model.robot_radius()
        if min(x - b[0], b[2] - x, y - b[1], b[3] - y) > rr and \
                w.turning_disk_distance(x, y) > 0.0:
            return True
        m = self.model
        k0 = self._last_yaw  # neighbouring positions mostly fit at the same yaw: tried first
        n = len(OPEN_YAWS)
        for k in range(k0, k0 + n):
            yaw = OPEN_YAWS[k % n]
            if w.bounds_margin(m.robot_corners((x, y, yaw))) > 0.0 and \
                    w.robot_distance((x, y, yaw)) > 0.0:
                self._last_yaw = k % n
                return True
        return False

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
