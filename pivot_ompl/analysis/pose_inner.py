"""Held poses valid at every yaw of their bins: where they join start and goal, nothing to prove.

The held poses' proof (:mod:`~pivot_ompl.analysis.pose_proof`) over-approximates the held
poses: per yaw bin and grasp, the box positions valid at *some* yaw of the bin. This module
under-approximates them the same way: per bin and grasp, the positions where the assembly's
bodies turned through the *whole* bin (:func:`swept_hull`) keep the checkers' clearance
(:class:`EveryYawRegions`), their parts joined as the proof joins its own (a motion across
neighbouring bins, a regrasp at one bin where the walk round the resting box may be made).
Every finer bin's region of the proof holds such a part (valid at every yaw of a bin, so at
some yaw of any bin inside it), so a chain of them is a chain at every refinement: the proof
cannot end apart (up to its walks, asked again at every bin). :func:`joined_at_every_yaw`
looks for one at :data:`~pivot_ompl.analysis.pose_proof.FIRST_BINS` bins, towards the goal
first (a best-first search on the parts' distance to the goal, a bin's parts computed when
the search reaches it), asking the walks of the chain's regrasps as the proof does.

It decides only whether the proof is worth its time
(:class:`~pivot_ompl.analysis.late_proof.LateProof`); it never proves anything, so a wrong
answer costs time, never a wrong plan or proof.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_bins import SAME_YAW, BinRegions
from pivot_ompl.analysis.pose_cells import free_region
from pivot_ompl.analysis.pose_chain import Node
from pivot_ompl.analysis.pose_proof import FIRST_BINS, HeldParts, PoseGraph
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.validity.collision import KEEP_CLEARANCE

#: Turned copies of a body per bin in :func:`swept_hull` (the arcs between them covered).
SWEEP_STEPS = 5
#: Most searches of :func:`joined_at_every_yaw` (each after walks refused a chain's regrasps).
MOST_SEARCHES = 16


def _turned(points: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return points @ np.array([[c, s], [-s, c]])


def swept_hull(body: np.ndarray, half: float, steps: int = SWEEP_STEPS) -> np.ndarray:
    """A convex polygon (counter-clockwise) holding ``body`` turned by all of ``[-half, half]``.

    ``half`` in rad, the turns about the origin. The body's vertices turned by ``steps``
    angles, and between two neighbours the point where the arc's tangents at both meet (the
    arc lies in that triangle).
    """
    angles = np.linspace(-half, half, max(steps, 2))
    step = float(angles[1] - angles[0])
    points = [_turned(body, t) for t in angles]
    points += [_turned(body, t) / math.cos(0.5 * step) for t in 0.5 * (angles[:-1] + angles[1:])]
    hull = shapely.orient_polygons(shapely.MultiPoint(np.concatenate(points)).convex_hull)
    return np.asarray(shapely.get_exterior_ring(hull).coords)[:-1]


class EveryYawRegions(BinRegions):
    """Per yaw bin and grasp, the box positions valid at every yaw of the bin (kept).

    :meth:`regions` as :class:`~pivot_ompl.analysis.pose_bins.BinRegions` gives them, but
    from the bodies' :func:`swept_hull` instead of their rotation cores, and never from a
    parent bin (a half's positions valid at every yaw are more than its parent's). A bin half
    a turn from a known one takes its regions with the grasps swapped.
    """

    def __init__(self, grown: dict[int, np.ndarray], bodies: list[list[np.ndarray]],
                 area: BaseGeometry) -> None:
        """Nothing computed yet."""
        super().__init__(grown, bodies, area)
        self.bodies = bodies
        self.every: dict[tuple[int, int], list[BaseGeometry]] = {}

    def regions(self, a: float, b: float) -> list[BaseGeometry]:
        """Per grasp, the box centres valid at every yaw of ``[a, b]``."""
        key = (round(a / SAME_YAW), round(b / SAME_YAW))
        if key in self.every:
            return self.every[key]
        shift = -math.pi if a >= math.pi - SAME_YAW else math.pi
        twin = self.every.get((round((a + shift) / SAME_YAW), round((b + shift) / SAME_YAW)))
        if twin is not None and self.twins is not None:
            out = [twin[self.twins[g]] for g in range(len(twin))]
        else:
            half = 0.5 * (b - a)
            out = [free_region(self.grown, [swept_hull(body, half) for body in bodies],
                               0.5 * (a + b), self.area) for bodies in self.bodies]
            self.computed += 1
        self.every[key] = out
        return out


def _towards(graph: PoseGraph, starts: list[Node], goals: list[Node],
             goal: shapely.Point) -> list[Node] | None:
    """A chain from a start to a goal, the parts nearest the goal tried first (or ``None``)."""
    ends = set(goals)
    before: dict[Node, Node | None] = dict.fromkeys(starts)
    todo = [(0.0, u) for u in starts]
    while todo:
        u = heapq.heappop(todo)[1]
        if u in ends:
            out = [u]
            while (p := before[out[-1]]) is not None:
                out.append(p)
            return out[::-1]
        for v in graph.links[u]:
            if v not in before:
                before[v] = u
                heapq.heappush(todo, (graph.bin(v[0])[v[1]][v[2]].distance(goal), v))
    return None


def joined_at_every_yaw(scene: Scene, *, bins: int = FIRST_BINS,
                        should_stop: Callable[[], bool] | None = None) -> bool | None:
    """Whether a chain of held poses valid at every yaw of its bins joins start and goal.

    ``True``: the held poses' proof cannot end apart (the module docstring); ``False``: no
    such chain at ``bins`` bins (the proof may prove); ``None``: stopped, or
    :data:`MOST_SEARCHES` searches found only chains the walks refuse.
    """
    try:
        parts = HeldParts(scene, KEEP_CLEARANCE, should_stop)
        if parts.room is None:
            return False
        old = parts.bins
        parts.bins = EveryYawRegions(old.grown, parts.bodies, old.area)
        edges = [2.0 * math.pi * i / bins for i in range(bins + 1)]
        graph = PoseGraph(parts, edges, should_stop, lazy=True)
        starts, goals = graph.nodes_at(edges, scene.start), graph.nodes_at(edges, scene.goal)
        if not starts or not goals:
            return False
        goal = shapely.Point(scene.goal[0], scene.goal[1])
        for _ in range(MOST_SEARCHES):
            chain = _towards(graph, starts, goals, goal)
            if chain is None:
                return False
            cut = [(u, v) for u, v in zip(chain, chain[1:], strict=False)
                   if u[0] == v[0] and u[1] != v[1] and not parts.may_regrasp(edges, u, v)]
            if not cut:
                return True
            for u, v in cut:
                graph.links[u].remove(v)
                graph.links[v].remove(u)
        return None
    except Interrupted:
        return None
