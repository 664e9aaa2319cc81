"""A floor raster for the relaxations: square cells, and which of them meet a region.

A cell *meets* a region when its centre lies within half a cell diagonal of it, so a
continuous path through the region crosses only cells that meet it, one after another
8-adjacent: connectivity and path lengths on the raster stay on the safe side of the
continuous ones (the lower bounds' use).
"""

from __future__ import annotations

import math

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry


class FloorRaster:
    """Cells of side ``cell`` over ``bounds``, at least ``min_cell``, at most ``max_cells``.

    Attributes:
        cell: the cell side (m).
        origin: the floor's lower corner.
        shape: cells along x and y.
        gx, gy: the cell centres (``shape`` arrays, indexed ``[i, j]``).
        half_diag: half a cell diagonal (m).
    """

    def __init__(self, bounds: tuple[float, float, float, float], *, min_cell: float,
                 max_cells: int) -> None:
        """The raster of ``bounds``."""
        x0, y0, x1, y1 = bounds
        self.cell = h = max(min_cell, math.sqrt((x1 - x0) * (y1 - y0) / max_cells))
        self.origin = (x0, y0)
        self.shape = (max(1, math.ceil((x1 - x0) / h)), max(1, math.ceil((y1 - y0) / h)))
        self.half_diag = h * math.sqrt(0.5)
        xs = x0 + (np.arange(self.shape[0]) + 0.5) * h
        ys = y0 + (np.arange(self.shape[1]) + 0.5) * h
        self.gx, self.gy = np.meshgrid(xs, ys, indexing="ij")

    def meeting(self, region: BaseGeometry) -> np.ndarray:
        """The cells that meet ``region`` (a boolean ``shape`` array).

        An exact distance test of every centre (GEOS): a buffer of the region would be a
        polygon of chords inside the round one and miss cells near its corners.
        """
        shapely.prepare(region)
        centres = shapely.points(self.gx.ravel(), self.gy.ravel())
        return shapely.dwithin(region, centres, self.half_diag).reshape(self.shape)

    def index(self, x: float, y: float) -> tuple[int, int]:
        """The cell holding ``(x, y)`` (the nearest one for a point off the floor)."""
        (x0, y0), h = self.origin, self.cell
        return (min(self.shape[0] - 1, max(0, int((x - x0) // h))),
                min(self.shape[1] - 1, max(0, int((y - y0) // h))))

    def window(self, geom: BaseGeometry) -> tuple[slice, slice]:
        """The block of cells round ``geom``'s bounding box (one cell of margin)."""
        return self.window_box(*geom.bounds)

    def window_box(self, gx0: float, gy0: float, gx1: float, gy1: float
                   ) -> tuple[slice, slice]:
        """The block of cells round the box ``gx0, gy0, gx1, gy1`` (one cell of margin)."""
        (x0, y0), h = self.origin, self.cell
        i0 = max(0, int((gx0 - x0) / h) - 1)
        j0 = max(0, int((gy0 - y0) / h) - 1)
        i1 = min(self.shape[0], int((gx1 - x0) / h) + 2)
        j1 = min(self.shape[1], int((gy1 - y0) / h) + 2)
        return slice(i0, max(i0, i1)), slice(j0, max(j0, j1))
