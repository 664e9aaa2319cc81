"""The obstacle pieces' sums with the walking body, per piece and yaw, each computed once.

Where the grown walking body at a yaw meets an obstacle piece is the convex hull of their
vertex differences (the caller's summing, :func:`~pivot_ompl.validity.minkowski.meeting_edges`
or its uncertified form). The
floor grid rasterises them two ways: every piece at a block of yaws (the whole floor's
layers) and, for a tile, the pieces near it at every yaw. :class:`PieceSums` keeps each
(piece, yaw) sum once computed, so either way asks only for the pairs it has not summed yet:
a walk round a box on an office floor of 5000 wall pieces sums the few hundred pieces near
its tiles, not every piece at every yaw (3 s on the Willow Garage office).

Each pair's sum is its own arithmetic (a row of the vectorised sums), so a sum is the same
floats whichever other pairs it was computed with: the rasters are those of the sums all
computed at once.

An edge's end is the start of another edge of its polygon (the same floats): a sum keeps its
starts and, per edge, which slot its end starts (two bytes), and the ends are gathered back
when asked, bit for bit (on the Willow Garage office the kept sums took 127 MB, now 75 MB).

**Opposite yaws.** Where ``opposite[k]`` names a yaw whose body is the point reflection of
yaw ``k``'s (turned by pi), the sum of a centrally symmetric piece (a wall box) at ``k`` is
the point reflection of its sum at ``opposite[k]`` about the piece's centre (as the assembly
field's, :func:`~pivot_ompl.validity.assembly_field.reflected`): an affine map of the kept
floats, the same region to rounding, and not summed. It is always made so (its source summed
first when not kept), whatever pairs are asked together: a sum is still the same floats
however the pairs were grouped. On the Willow Garage office, whose 5049 pieces are all wall
boxes, the whole floor's 32 yaws take half the sums.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pivot_ompl.errors import PivotError
from pivot_ompl.validity.footprints import symmetric_centres
from pivot_ompl.validity.minkowski import EdgeSet, reflected_bounds

Stop = Callable[[], bool] | None


class PieceSums:
    """Sums of ``pieces`` with ``bodies[k]`` (one body per yaw), kept per (piece, yaw).

    Args:
        pieces: convex obstacle pieces (vertex arrays).
        bodies: the body's vertices at each yaw (relative to its reference point).
        opposite: per yaw, the yaw whose body is its point reflection, from which the
            symmetric pieces' sums are reflected (module docstring), or ``None``; by
            default none (every pair summed). A yaw's source must have no source itself.

    Attributes:
        done: ``(pieces, yaws)`` booleans, which sums are kept.
        reflected: pairs kept by reflection rather than summed (a figure).
    """

    def __init__(self, pieces: list[np.ndarray], bodies: list[np.ndarray], *,
                 opposite: list[int | None] | None = None) -> None:
        """Nothing summed yet (the arrays are allocated untouched: no memory until filled)."""
        self.pieces, self.bodies = pieces, bodies
        n, k = len(pieces), len(bodies)
        self.opposite = [None] * k if opposite is None else list(opposite)
        if len(self.opposite) != k or any(
                j is not None and self.opposite[j] is not None for j in self.opposite):
            raise PivotError(f"a reflected yaw's source must be summed itself: {self.opposite}")
        self._centres: np.ndarray = np.zeros((0, 2))
        self._symmetric: np.ndarray = np.zeros(0, dtype=bool)
        if n:
            self._centres, self._symmetric = symmetric_centres(pieces)
        self.reflected = 0
        self.done = np.zeros((n, k), dtype=bool)
        width = max([1, *(len(p) for p in pieces)]) + max(len(b) for b in bodies)
        self._start = np.zeros((n, k, width, 2))
        self._next = np.zeros((n, k, width), dtype=np.int16)  # the slot an end starts
        self._used = np.zeros((n, k, width), dtype=bool)
        self._bounds = np.zeros((n, k, 4))

    def yaws_complete(self) -> int:
        """Yaws whose sums with every piece are kept."""
        return int(self.done.all(axis=0).sum()) if len(self.pieces) else 0

    def fill(self, pieces: np.ndarray, yaws: list[int], summing: Callable[..., EdgeSet],
             should_stop: Stop = None) -> int:
        """Keep the pairs of ``pieces`` (indices) x ``yaws`` not kept yet, summed in one call.

        ``summing``: sums pairs as :func:`~pivot_ompl.validity.minkowski.meeting_edges`
        does (its signature). A symmetric piece at a yaw with an opposite is reflected from
        its sum there (summed too when not kept). Returns the pairs kept by this call (its
        sources included). Nothing is kept from an interrupted call.

        Raises:
            Interrupted: ``should_stop()`` became true (polled by ``summing``).
        """
        sym = self._symmetric[pieces]
        direct: dict[int, np.ndarray] = {}
        mirror: dict[int, np.ndarray] = {}
        for k in yaws:
            j = self.opposite[k]
            todo = pieces[~self.done[pieces, k] & (~sym if j is not None else True)]
            direct[k] = np.union1d(direct.get(k, todo), todo)
            if j is not None:
                mine = pieces[sym & ~self.done[pieces, k]]
                mirror[k] = mine
                need = mine[~self.done[mine, j]]
                direct[j] = np.union1d(direct.get(j, need), need)
        summed = self._sum(direct, summing, should_stop)
        for k, mine in mirror.items():
            self._reflect(mine, k, self.opposite[k])  # type: ignore[arg-type]
        self.reflected += sum(len(m) for m in mirror.values())
        return summed + sum(len(m) for m in mirror.values())

    def _sum(self, direct: dict[int, np.ndarray], summing: Callable[..., EdgeSet],
             should_stop: Stop) -> int:
        """Sum and keep the pairs ``direct`` (per yaw, piece indices), in one call."""
        ii = np.concatenate([np.zeros(0, dtype=np.int64),
                             *(v.astype(np.int64) for v in direct.values())])
        kk = np.concatenate([np.zeros(0, dtype=np.int64),
                             *(np.full(len(v), k, dtype=np.int64) for k, v in direct.items())])
        if not len(ii):
            return 0
        edges = summing([self.pieces[i] for i in ii.tolist()],
                        [self.bodies[k] for k in kk.tolist()], should_stop=should_stop)
        w = edges.start.shape[1]
        if w > self._start.shape[2]:  # never for convex hulls of differences; kept general
            self._widen(w)
        self._start[ii, kk, :w], self._next[ii, kk, :w] = edges.start, _next_slots(edges)
        self._used[ii, kk, :w], self._bounds[ii, kk] = edges.used, edges.bounds
        self.done[ii, kk] = True
        return len(ii)

    def _reflect(self, pieces: np.ndarray, k: int, source: int) -> None:
        """Keep ``pieces``' sums at yaw ``k``: their kept sums at ``source``, point-reflected.

        About each piece's centre; a point reflection is a rotation by pi, so the edges
        stay counter-clockwise in the same slots (every slot reflected, padding too: an
        end gathered from a padding slot that repeats a vertex is still that vertex's).
        """
        if not len(pieces):
            return
        centres = self._centres[pieces]
        self._start[pieces, k] = 2.0 * centres[:, None, :] - self._start[pieces, source]
        self._next[pieces, k] = self._next[pieces, source]
        self._used[pieces, k] = self._used[pieces, source]
        self._bounds[pieces, k] = reflected_bounds(self._bounds[pieces, source], centres)
        self.done[pieces, k] = True

    def _widen(self, width: int) -> None:
        """Room for ``width`` edges a polygon."""
        pad = width - self._start.shape[2]
        self._start = np.pad(self._start, [(0, 0), (0, 0), (0, pad), (0, 0)])
        self._next = np.pad(self._next, [(0, 0), (0, 0), (0, pad)])
        self._used = np.pad(self._used, [(0, 0), (0, 0), (0, pad)])

    def edges(self, pieces: np.ndarray, yaws: list[int]) -> tuple[EdgeSet, np.ndarray]:
        """The kept sums of ``pieces`` x ``yaws`` and each polygon's yaw's position in ``yaws``.

        Piece-major: polygon ``i * len(yaws) + j`` is ``pieces[i]`` at ``yaws[j]``.
        """
        sel = np.ix_(pieces, np.asarray(yaws, dtype=np.int64))
        m = len(pieces) * len(yaws)
        w = self._start.shape[2]
        start = self._start[sel].reshape(m, w, 2)
        end = np.take_along_axis(start, self._next[sel].reshape(m, w, 1).astype(np.intp),
                                 axis=1)
        edges = EdgeSet(start, end, self._used[sel].reshape(m, w), self._bounds[sel].reshape(m, 4))
        return edges, np.tile(np.arange(len(yaws)), len(pieces))


def _next_slots(edges: EdgeSet) -> np.ndarray:
    """Per polygon and edge slot, a slot whose start is that edge's end (the same floats).

    Every end is one of its polygon's starts (the sums' edges join their vertices in turn,
    a padding slot repeats a vertex or is zero at both ends): usually the next slot's, so
    that one is tried first and the polygon's slots searched only where it is not.

    Raises:
        PivotError: an end that is no start of its polygon (never for the sums' edge sets:
            a broken invariant, not a bad input).
    """
    start, end = edges.start, edges.end
    w = start.shape[1]
    out = np.broadcast_to((np.arange(w) + 1) % w, start.shape[:2]).astype(np.int16)
    rows, slots = np.nonzero(~(end == start[:, (np.arange(w) + 1) % w]).all(axis=2))
    if len(rows):
        same = (start[rows] == end[rows, slots][:, None, :]).all(axis=2)
        if not same.any(axis=1).all():
            raise PivotError("a Minkowski sum's edge ends at no vertex of its polygon")
        out[rows, slots] = same.argmax(axis=1)
    return out
