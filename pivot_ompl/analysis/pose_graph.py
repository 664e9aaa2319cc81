"""The held poses' parts joined: the graph the proof, the every-yaw test and the count search.

A node is a part ``(bin, grasp, part)`` of :class:`~pivot_ompl.analysis.pose_proof.HeldParts`
for one set of bin edges. A part is linked to the parts it meets at its grasp in the two
neighbouring bins (a motion crossing the bins' common yaw) and to the parts it meets at the
other grasps in its own bin (a regrasp: one pose, two grasps). Which parts meet is asked of
the parts (:meth:`~pivot_ompl.analysis.pose_proof.HeldParts.meet`, kept per pair of bins and
grasps, indexed by part), so a node's links cost what it has.

The links are computed one way, per node: the lazy graph computes a node's when a chain
search reaches it, the eager one every node's at once. The chain searches over them
(:mod:`~pivot_ompl.analysis.pose_chain`) do not depend on the links' order.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial
from typing import TYPE_CHECKING

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_chain import Chain, LazyLinks, Node, walked_chain
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose

if TYPE_CHECKING:
    from pivot_ompl.analysis.pose_proof import HeldParts

__all__ = ["PoseGraph"]

def _holding(parts: list[list[BaseGeometry]], pose: Pose) -> list[tuple[int, int]]:
    point = shapely.Point(pose[0], pose[1])
    return [(g, k) for g, ps in enumerate(parts) for k, p in enumerate(ps) if p.covers(point)]


def _bins_of(edges: list[float], yaw: float) -> list[int]:
    """The bins (one, or two on a common edge) holding ``yaw``."""
    t = yaw % (2.0 * math.pi)
    n = len(edges) - 1
    return [i for i in range(n) if edges[i] - 1e-12 <= t <= edges[i + 1] + 1e-12] or [n - 1]


class PoseGraph:
    """The parts joined (see the module docstring) for one set of bins.

    Eager (the default): every bin's parts and every node's links at once. ``lazy``: a bin's
    parts are computed the first time a chain search reaches a part of it or of a
    neighbouring bin (:class:`~pivot_ompl.analysis.pose_chain.LazyLinks`), and a node's links
    when the search asks for them: the same links wherever the search goes, so the same
    chains, reaches and answers, without the bins no search reaches.
    """

    def __init__(self, parts: HeldParts, edges: list[float],
                 should_stop: Callable[[], bool] | None, *, lazy: bool = False) -> None:
        self.parts, self.edges, self.should_stop = parts, edges, should_stop
        self._table: dict[int, list[list[BaseGeometry]]] = {}
        self.refused: list[BaseGeometry] = []  # the regrasps dropped (:meth:`walked`)
        if lazy:
            self.links: dict[Node, list[Node]] = LazyLinks(self._links_of)
            return
        n = len(edges) - 1
        for i in range(n):
            self.bin(i)
        self.links = {(i, g, k): self._links_of((i, g, k)) for i in range(n)
                      for g, here in enumerate(self.bin(i)) for k in range(len(here))}

    def bin(self, i: int) -> list[list[BaseGeometry]]:
        """Per grasp, the free parts of bin ``i`` (computed once; the stop polled before)."""
        if i not in self._table:
            if self.should_stop is not None and self.should_stop():
                raise Interrupted("the held poses' relaxation")
            self._table[i] = self.parts.of(self.edges[i], self.edges[i + 1])
        return self._table[i]

    def _links_of(self, u: Node) -> list[Node]:
        """The links of part ``u``: the next bin's parts, the bin before's, then regrasps.

        Empty for a part that is not one (``u``'s grasp or part out of its bin's range).
        """
        i, g, k = u
        edges, n = self.edges, len(self.edges) - 1
        here = self.bin(i)
        if g >= len(here) or k >= len(here[g]):
            return []
        j = (i + 1) % n  # the next bin, then the one before: motions at grasp g
        ahead = self.parts.meet((edges[i], edges[i + 1], edges[j + 1], g), here[g],
                                self.bin(j)[g])[0]
        out = [(j, g, q) for q in ahead.get(k, ())]
        j = (i - 1) % n
        behind = self.parts.meet((edges[j], edges[j + 1], edges[i + 1], g),
                                 self.bin(j)[g], here[g])[1]
        out += [(j, g, p) for p in behind.get(k, ())]
        for h in range(len(here)):  # regrasps: one pose, two grasps
            if h < g:
                low = self.parts.meet((edges[i], edges[i + 1], h, g), here[h], here[g])[1]
                out += [(i, h, p) for p in low.get(k, ())]
            elif h > g:
                high = self.parts.meet((edges[i], edges[i + 1], g, h), here[g], here[h])[0]
                out += [(i, h, q) for q in high.get(k, ())]
        return out

    def walked(self, parts: HeldParts, edges: list[float], starts: list[Node],
               goals: list[Node], *, should_stop: Callable[[], bool] | None = None) -> Chain:
        """The cheapest chain whose regrasps the walks allow (priced by bin widths, rad).

        :func:`~pivot_ompl.analysis.pose_chain.walked_chain` over this graph's links, asking
        :meth:`~pivot_ompl.analysis.pose_proof.HeldParts.may_regrasp`; the regrasps refused
        are cut from the links and their box positions kept in :attr:`refused`. Through fine
        bins where it can, so the coarse bins it still needs are the ones to halve.
        ``should_stop`` is polled before every search
        (:class:`~pivot_ompl.errors.Interrupted` when true).
        """
        found = walked_chain(self.links, starts, goals, np.diff(edges).tolist(),
                             may_regrasp=partial(parts.may_regrasp, edges),
                             should_stop=should_stop)
        for u, v in found.refused:
            here = self.bin(u[0])
            self.refused.append(here[u[1]][u[2]].intersection(here[v[1]][v[2]]))
        return found

    def nodes_at(self, edges: list[float], pose: Pose) -> list[Node]:
        """The parts holding ``pose`` (any grasp)."""
        return [(i, g, k) for i in _bins_of(edges, pose[2])
                for g, k in _holding(self.bin(i), pose)]
