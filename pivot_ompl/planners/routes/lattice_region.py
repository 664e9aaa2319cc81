"""The grid positions a lattice over a region holds: those within reach of the region."""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

__all__ = ["within_distance"]


def within_distance(region: BaseGeometry, xs: np.ndarray, ys: np.ndarray,
                    distance: float) -> np.ndarray:
    """Grid points ``(xs[i], ys[j])`` within ``distance`` of ``region`` (``(nx, ny)`` booleans).

    Those inside it, and those within ``distance`` of one of its boundary's segments (a
    tree of the segments): exact, where buffering a region of thousands of vertices took
    seconds on an office's floor and its chords left out points within the distance.
    """
    result = np.zeros((len(xs), len(ys)), dtype=bool)
    if region.is_empty:
        return result
    x0, y0, x1, y1 = region.bounds  # only the points within its box grown by the distance
    i = slice(int(np.searchsorted(xs, x0 - distance)), int(np.searchsorted(xs, x1 + distance,
                                                                           side="right")))
    j = slice(int(np.searchsorted(ys, y0 - distance)), int(np.searchsorted(ys, y1 + distance,
                                                                           side="right")))
    xs, ys = xs[i], ys[j]
    inside = shapely.contains_xy(region, xs[:, None], ys[None, :])
    lines = shapely.get_parts(shapely.boundary(region))
    segments = [np.stack([c[:-1], c[1:]], axis=1) for c in map(shapely.get_coordinates, lines)
                if len(c) > 1]
    if segments:
        tree = shapely.STRtree(shapely.linestrings(np.concatenate(segments)))
        out = np.flatnonzero(~inside.ravel())
        px, py = np.divmod(out, len(ys))
        hit, _ = tree.query(shapely.points(xs[px], ys[py]), predicate="dwithin",
                            distance=distance)
        flat = inside.ravel()
        flat[out[np.unique(hit)]] = True
    result[i, j] = inside
    return result
