"""What the Minkowski sums compute of each polygon alone, once per distinct polygon.

:func:`~pivot_ompl.validity.minkowski.meeting_edges` sums many (piece, body) pairs in which
a piece or a body is usually one array passed many times (a body per yaw, a piece per yaw
and body). :class:`DistinctPolygons` finds the distinct arrays of such a list (by object),
stacks them by vertex count and computes their own terms (:class:`PolygonTerms`: the
orientation, the edge normals, the short-edge test) once; it numbers their *classes*, the
polygons whose orientation and normals are the same floats (wall boxes of any size and
place share one), whose sums' vertex slots are then computed once. The indexing is
vectorised (numpy over the objects' ids): a list of tens of thousands of pairs is indexed
in a few milliseconds, not a few Python loops over it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: Relative length below which an edge makes a sum without a certificate refuse a row (a
#: near-degenerate polygon, whose edge normals are not reliable).
SHORT_EDGE = 1e-9


@dataclass(frozen=True)
class PolygonTerms:
    """What a sum computes of one side's polygons alone, per row ``(g, ...)``.

    ``flipped``: whether making the polygon (a body: its reflection ``-body``)
    counter-clockwise reversed it; ``normals``: that counter-clockwise polygon's outward
    edge normal angles in ``[0, 2 pi)``; ``short``: whether the polygon has an edge shorter
    than :data:`SHORT_EDGE` times its extent.
    """

    flipped: np.ndarray
    normals: np.ndarray
    short: np.ndarray

    def rows(self, index: np.ndarray) -> PolygonTerms:
        """The terms of polygons ``index`` (rows gathered)."""
        return PolygonTerms(self.flipped[index], self.normals[index], self.short[index])


def counter_clockwise(poly: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Polygons ``(g, k, 2)`` with their vertices counter-clockwise, and which were reversed."""
    x, y = poly[..., 0], poly[..., 1]
    flip = np.sum(x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y, axis=1) < 0.0
    return np.where(flip[:, None, None], poly[:, ::-1], poly), flip


def _has_short_edge(polys: np.ndarray) -> np.ndarray:
    """Per row of ``(g, k, 2)`` polygons: an edge shorter than :data:`SHORT_EDGE` x extent."""
    e = np.linalg.norm(np.roll(polys, -1, axis=1) - polys, axis=2)
    extent = np.ptp(polys, axis=1).max(axis=1)
    return np.any(e <= SHORT_EDGE * np.maximum(extent, 1.0)[:, None], axis=1)


def _normal_angles(poly: np.ndarray) -> np.ndarray:
    """Outward normal angles ``[0, 2 pi)`` of counter-clockwise polygons' edges ``(g, k)``."""
    e = np.roll(poly, -1, axis=1) - poly
    return np.arctan2(-e[..., 0], e[..., 1]) % (2 * math.pi)


def own_terms(polys: np.ndarray, *, reflect: bool) -> PolygonTerms:
    """:class:`PolygonTerms` of polygons ``(g, k, 2)`` (of their reflections if ``reflect``)."""
    ccw, flipped = counter_clockwise(-polys if reflect else polys)
    return PolygonTerms(flipped, _normal_angles(ccw), _has_short_edge(polys))


class DistinctPolygons:
    """The distinct polygons of a list (by object: one array passed many times counts once).

    Stacked by vertex count, with their :class:`PolygonTerms` computed once, and each
    numbered by its class (polygons of one vertex count whose orientation and edge normals
    are the same bytes share one).

    Attributes:
        sizes: each listed polygon's vertex count ``(n,)``.
        n_classes: classes numbered (``0 .. n_classes - 1``, all sizes together).
    """

    def __init__(self, polys: list[np.ndarray], *, reflect: bool) -> None:
        """Index ``polys``."""
        n = len(polys)
        ids = np.fromiter(map(id, polys), dtype=np.uint64, count=n)
        _, first, which = np.unique(ids, return_index=True, return_inverse=True)
        which = which.reshape(-1)
        distinct = [polys[i] for i in first.tolist()]
        counts = np.fromiter(map(len, distinct), dtype=np.int64, count=len(distinct))
        self.sizes = counts[which]
        local = np.zeros(len(distinct), dtype=np.int64)  # each one's row in its size's stack
        self.stacked: dict[int, np.ndarray] = {}
        self.terms: dict[int, PolygonTerms] = {}
        self.classes: dict[int, np.ndarray] = {}
        self.n_classes = 0
        for size in np.unique(counts).tolist():
            members = np.flatnonzero(counts == size)
            local[members] = np.arange(len(members))
            stack = np.stack([distinct[i] for i in members.tolist()]).reshape(-1, size, 2)
            terms = own_terms(stack, reflect=reflect)
            keys = np.column_stack([terms.flipped, terms.normals])
            seen: dict[bytes, int] = {}  # a dict of the rows' bytes: no sort, few rows cheap
            inverse = np.fromiter((seen.setdefault(row.tobytes(), len(seen)) for row in keys),
                                  dtype=np.int64, count=len(keys))
            self.stacked[size], self.terms[size] = stack, terms
            self.classes[size] = self.n_classes + inverse
            self.n_classes += len(seen)
        self._row = local[which]

    def rows(self, idx: np.ndarray, size: int) -> tuple[np.ndarray, PolygonTerms, np.ndarray]:
        """Polygons ``idx`` of the list (each of ``size`` vertices), their terms and classes."""
        r = self._row[idx]
        return self.stacked[size][r], self.terms[size].rows(r), self.classes[size][r]
