"""Planar convex hulls (GEOS, through shapely) as counter-clockwise vertex arrays."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry.polygon import orient


def convex_hull(points: np.ndarray) -> np.ndarray:
    """Counter-clockwise vertices (M x 2, not closed) of the convex hull of 2-D ``points``.

    The hull must have an area (at least three points not on one line).
    """
    hull = shapely.MultiPoint(np.asarray(points, dtype=float)[:, :2]).convex_hull
    if not isinstance(hull, shapely.Polygon):
        raise ValueError(f"the points' convex hull has no area ({hull.geom_type})")
    return np.asarray(orient(hull, 1.0).exterior.coords)[:-1]
