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
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.minkowski import meeting_edges
from pivot_ompl.validity.rasters import grid_union

#: The field's yaws: the 16 headings and the 16 half-way yaws, in that order interleaved
#: (index ``2 h`` is heading ``h``, ``2 h + 1`` half-way to heading ``h + 1``).
FIELD_YAWS: tuple[float, ...] = tuple(
    y for a, b in zip(HEADING_YAWS, HEADING_YAWS[1:] + HEADING_YAWS[:1], strict=True)
    for y in (a, a + 0.5 * ((b - a + math.pi) % (2 * math.pi) - math.pi)))


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


class AssemblyField:
    """The car positions where the held assembly fits (see the module docstring).

    Args:
        model: box and robot geometry.
        world: obstacles, bounds and the kept clearance.
        resolution: grid spacing (m).

    Attributes:
        nx, ny: grid size; grid position ``(ix, iy)`` is the point
            ``(x0 + ix * resolution, y0 + iy * resolution)``.
    """

    nx: int
    ny: int

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, resolution: float) -> None:
        """Nothing rasterised yet."""
        self.model, self.world, self.resolution = model, world, resolution
        b = world.bounds
        self.nx = int(math.floor((b[2] - b[0]) / resolution)) + 1
        self.ny = int(math.floor((b[3] - b[1]) / resolution)) + 1
        self._xs = b[0] + resolution * np.arange(self.nx)
        self._ys = b[1] + resolution * np.arange(self.ny)
        self._pieces = obstacle_pieces(world.obstacles)
        self._bodies = {p: assembly_bodies(model, p, world.clearance) for p in (0, 1)}
        self._corners = {p: np.concatenate(assembly_bodies(model, p, 0.0)) for p in (0, 1)}
        self._fits: dict[tuple[int, int], np.ndarray] = {}

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
            todo = [j for j in range(len(FIELD_YAWS)) if (key[0], j) not in self._fits]
            for j, grid in zip(todo, self._compute(key[0], todo, should_stop), strict=True):
                self._fits[(key[0], j)] = grid
            v = self._fits[key]
        return v

    def _compute(self, parity: int, ks: list[int], should_stop: Callable[[], bool] | None
                 ) -> list[np.ndarray]:
        """The grids of yaws ``ks`` at ``parity``, every yaw's sums and raster in one batch.

        The same grids as one yaw at a time (each polygon's arithmetic is its own), for a
        thirtieth of the calls: a scene's 64 grids took 0.04-0.1 s one by one.
        """
        xs, ys = self._xs, self._ys
        b = self.world.bounds
        n = len(self._pieces)
        out, pieces, bodies = [], [], []
        for k in ks:
            yaw = FIELD_YAWS[k]
            c, s = math.cos(yaw), math.sin(yaw)
            rot = np.array([[c, -s], [s, c]]).T
            corners = self._corners[parity] @ rot
            out.append(
                ((xs + corners[:, 0].min() > b[0]) & (xs + corners[:, 0].max() < b[2]))[:, None]
                & ((ys + corners[:, 1].min() > b[1]) & (ys + corners[:, 1].max() < b[3]))[None, :])
            for body in self._bodies[parity]:
                pieces += self._pieces
                bodies += [body @ rot] * n
        if n and ks:
            edges = meeting_edges(pieces, bodies, should_stop=should_stop, certify=False)
            per_yaw = len(self._bodies[parity]) * n
            hit = grid_union(edges, xs, ys, groups=np.arange(len(pieces)) // per_yaw,
                             n_groups=len(ks))
            for ok, h in zip(out, hit, strict=True):
                ok &= ~h
        return out

    def state_fits(self, ix: int, iy: int, k: int, parity: int) -> bool:
        """Whether grid state ``(ix, iy)`` at field yaw ``k`` is free for ``parity``."""
        if not (0 <= ix < self.nx and 0 <= iy < self.ny):
            return False
        return bool(self.fits(parity, k)[ix, iy])

    def pose_fits(self, car: Pose, parity: int) -> bool:
        """Whether the nearest grid state of a car pose is free (a quick guess)."""
        fx, fy = self.cell(car[0], car[1])
        k = int(round((car[2] % (2 * math.pi)) / (2 * math.pi) * len(FIELD_YAWS)))
        return self.state_fits(int(round(fx)), int(round(fy)), k, parity)
