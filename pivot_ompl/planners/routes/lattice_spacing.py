"""The held assembly's lattice spacing: sized by the floor, snapped onto an occupancy map's grid.

A lattice over a large floor gets a coarser grid, so that its positions stay within
:data:`MAX_CELLS` (its field's grids and components within a few hundred MB). On a floor
imported from an occupancy map (boxes of merged map cells, every side on the map's grid:
:func:`~pivot_ompl.validity.cell_stencil.map_cell`), a spacing off the map's lines makes the
assembly field sum one Minkowski sum per box; a spacing that is a whole multiple of the map's
cell meets the boxes by a stencil's dilation of their cells
(:mod:`~pivot_ompl.validity.cell_stencil`), several times cheaper. :func:`lattice_spacing`
takes the largest whole multiple of the map's cell not above the sized spacing (a finer
lattice: every passage the sized one has at its own spacing is still there to within a
cell), where the positions stay within :data:`SNAP_CELLS`.
"""

from __future__ import annotations

import math

from pivot_ompl.validity.assembly_field import CELL_BOXES, least_boxes
from pivot_ompl.validity.cell_stencil import ALIGN_TOL, map_cell
from pivot_ompl.validity.collision import CollisionWorld
from pivot_ompl.validity.footprints import obstacle_pieces

__all__ = ["MAX_CELLS", "SNAP_CELLS", "lattice_spacing"]

#: Most grid positions of the lattice (over the bounds' rectangle, as its field): a larger floor
#: gets a coarser grid, so the field's grids and the components stay within a few hundred MB
#: (a 200 x 200 m hall at 0.1 m took 9 GB).
MAX_CELLS = 250_000
#: Most grid positions of a lattice snapped down onto a map's grid (:func:`lattice_spacing`):
#: twice :data:`MAX_CELLS` (the Willow Garage office, 3 400 m^2 of bounds: 342 000 positions
#: at its map's 0.1 m instead of 250 000 at 0.117 m).
SNAP_CELLS = 2 * MAX_CELLS


def lattice_spacing(world: CollisionWorld, resolution: float) -> float:
    """The lattice's grid spacing (m) over ``world``'s bounds, asked at ``resolution``.

    ``resolution``, or coarser on floors of more than :data:`MAX_CELLS` grid positions (the
    spacing that gives that many); then, where the floor is a map grid whose cell is at most
    that spacing (at least :data:`~pivot_ompl.validity.assembly_field.CELL_BOXES` boxes on
    it, as the field's stencil needs), the largest whole multiple of the cell not above it
    and not below ``resolution``, if its positions are at most :data:`SNAP_CELLS`.
    """
    x0, y0, x1, y1 = world.bounds
    area = (x1 - x0) * (y1 - y0)
    sized = max(resolution, math.sqrt(area / MAX_CELLS))
    if sized <= resolution:
        return resolution
    pieces = obstacle_pieces(world.obstacles)
    cell = map_cell(pieces, world.bounds, least=CELL_BOXES)
    if cell is None:
        return sized
    k = int(math.floor(sized / cell * (1.0 + ALIGN_TOL)))
    if k < 1 or k * cell < resolution or area > SNAP_CELLS * (k * cell) ** 2:
        return sized
    if k > 1 and map_cell(pieces, world.bounds, least=least_boxes(k)) is None:
        return sized
    return k * cell
