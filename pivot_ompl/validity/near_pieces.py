"""Distance queries answered among the obstacle pieces near the query: the whole floor's.

A floor of thousands of wall pieces in one broad-phase tree makes every distance query walk
a deep tree (on the Willow Garage office, 5049 pieces: 10-35 us a query). The queries of a
plan come in places (a transfer's rotations, a walk's bisections), so :class:`NearPieces`
cuts the floor into square cells of :data:`CELL` metres and gives each cell, when first
queried there, its own broad-phase tree of the pieces whose bounding boxes come within
:data:`MARGIN` of the cell (per axis). A query whose body has its centre in a
cell (the caller gives its centre and reach: reading coal's bounding box back costs more than
the query saves) is answered by that cell's tree; the answer is kept only when it is
certainly the whole floor's:

* every piece left out lies farther than ``MARGIN - overhang`` from the body along some axis
  (``overhang``: how far the body reaches beyond the cell), so a nearest
  distance below that is the whole floor's nearest (the same pair measured by the same GJK:
  on the office's 140 000 queries of a plan, equal or within 6e-10 m, far below GJK's
  micrometre that :data:`~pivot_ompl.checking.rotation_sweeps.BOUND_SLACK` allows for);
* otherwise (nothing that near) the whole floor's tree answers.

A body that meets a piece gets a distance ``<= 0`` either way (the depth of the first
overlapping pair each tree meets, as the whole floor's tree gives).
"""

from __future__ import annotations

import math

import coal
import numpy as np

#: Side (m) of the cells whose trees hold the pieces near them.
CELL = 3.0
#: How far (m, per axis) beyond its cell a piece's bounding box may lie and still be in
#: the cell's tree. With :data:`CELL`, on the Willow Garage office: 98 trees of 100 pieces
#: on average (2.3 MB), 0.3 % of the queries asked again of the whole floor's tree; 2 m
#: cells with 3 m margins took as long with three times the memory.
MARGIN = 1.5


class NearPieces:
    """Per-cell broad-phase trees over registered objects (see the module docstring).

    Args:
        objects: the static collision objects (their placements final).
        cell: the cells' side (m).
        margin: how far (m) beyond a cell its tree's pieces may lie (per axis).

    Attributes:
        local: queries answered by a cell's tree.
        fallback: queries a cell's tree could not answer for certain.
    """

    def __init__(self, objects: list[coal.CollisionObject], *, cell: float = CELL,
                 margin: float = MARGIN) -> None:
        """The objects' bounding boxes; no cell's tree yet."""
        self.objects, self.cell, self.margin = objects, cell, margin
        boxes = np.empty((len(objects), 4))
        for i, o in enumerate(objects):
            o.computeAABB()
            a = o.getAABB()
            lo, hi = a.min_, a.max_
            boxes[i] = (lo[0], lo[1], hi[0], hi[1])
        self._boxes = boxes
        self._trees: dict[tuple[int, int], coal.DynamicAABBTreeCollisionManager] = {}
        self._cb = coal.DistanceCallBackDefault()
        #: the callback's result (each ``cb.data.result`` builds a new wrapper of it: a
        #: microsecond, twice per query)
        self._result = self._cb.data.result
        self.local = 0
        self.fallback = 0

    def distance(self, obj: coal.CollisionObject, whole: coal.DynamicAABBTreeCollisionManager,
                 x: float, y: float, radius: float) -> float:
        """The least distance (m) from ``obj`` (AABB computed) to the objects (``whole``'s).

        ``obj`` lies within ``radius`` (m) of ``(x, y)`` along each axis (its footprint's
        reach from its placement); ``whole``: the tree of every object, asked when the
        cell's cannot answer for certain.
        """
        s = self.cell
        i, j = math.floor(x / s), math.floor(y / s)
        overhang = max(i * s - x, x - (i + 1) * s, j * s - y, y - (j + 1) * s, -s) + radius
        cb, result = self._cb, self._result
        if overhang < self.margin:
            tree = self._trees.get((i, j))
            if tree is None:
                tree = self._trees[(i, j)] = self._tree(i, j)
            result.clear()
            tree.distance(obj, cb)
            d = result.min_distance
            if d < self.margin - overhang:
                self.local += 1
                return d
        self.fallback += 1
        result.clear()
        whole.distance(obj, cb)
        return result.min_distance

    def _tree(self, i: int, j: int) -> coal.DynamicAABBTreeCollisionManager:
        """The tree of the objects whose boxes come within the margin of cell ``(i, j)``."""
        s, m, b = self.cell, self.margin, self._boxes
        near = np.flatnonzero((b[:, 0] <= (i + 1) * s + m) & (b[:, 2] >= i * s - m)
                              & (b[:, 1] <= (j + 1) * s + m) & (b[:, 3] >= j * s - m))
        tree = coal.DynamicAABBTreeCollisionManager()
        for k in near.tolist():
            tree.registerObject(self.objects[k])
        tree.setup()
        return tree
