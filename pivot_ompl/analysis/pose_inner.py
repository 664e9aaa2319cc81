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
the search reaches it), asking the walks of the chain's regrasps as the proof does (the
proof's loop, :func:`~pivot_ompl.analysis.pose_chain.walked_chain`, with this search).

It decides only whether the proof is worth its time
(:class:`~pivot_ompl.analysis.late_proof.LateProof`); it never proves anything, so a wrong
answer costs time, never a wrong plan or proof.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from functools import partial

import numpy as np
import shapely

from pivot_ompl.analysis.pose_bins import SAME_YAW, BinRegions
from pivot_ompl.analysis.pose_chain import Node, Searches, walked_chain
from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_proof import FIRST_BINS, MOTION_CLEARANCE, HeldParts, PoseGraph
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


#: Coordinates smaller than this (m) are zero in :func:`swept_hull` (far below any check).
TINY = 1e-100


def swept_hull(body: np.ndarray, half: float, steps: int = SWEEP_STEPS) -> np.ndarray:
    """A convex polygon (counter-clockwise) holding ``body`` turned by all of ``[-half, half]``.

    ``half`` in rad, the turns about the origin. The body's vertices turned by ``steps``
    angles, and between two neighbours the point where the arc's tangents at both meet (the
    arc lies in that triangle). Coordinates under :data:`TINY` m are taken as zero: GEOS's
    orientation products of such numbers underflow and make a wrong hull.
    """
    body = np.where(np.abs(body) < TINY, 0.0, body)
    angles = np.linspace(-half, half, max(steps, 2))
    step = float(angles[1] - angles[0])
    points = [_turned(body, t) for t in angles]
    points += [_turned(body, t) / math.cos(0.5 * step) for t in 0.5 * (angles[:-1] + angles[1:])]
    hull = shapely.orient_polygons(shapely.MultiPoint(np.concatenate(points)).convex_hull)
    return np.asarray(shapely.get_exterior_ring(hull).coords)[:-1]


class EveryYawRegions(BinRegions):
    """Per yaw bin and grasp, the box positions valid at every yaw of the bin (kept).

    :class:`~pivot_ompl.analysis.pose_bins.BinRegions`' regions (the box's sums joined once
    per bin for every grasp, only the sums near a region summed and joined, a bin half a turn
    from a known one taken with the grasps swapped), but from the bodies' :func:`swept_hull`
    instead of their rotation cores, and never from a parent bin (a half's positions valid at
    every yaw are more than its parent's), and from the floor's coarse pieces
    (:func:`~pivot_ompl.analysis.pose_coarse.coarse_pieces`: obstacles that only grow, so the
    positions found are still valid at every yaw).
    """

    from_parents = False
    coarse = True

    def _cores(self, which: int, bodies: list[np.ndarray], half: float) -> list[np.ndarray]:
        """The bodies' swept hulls for bins ``2 half`` wide (kept: bins share widths)."""
        key = (which, round(half / SAME_YAW))
        if key not in self.cores:
            self.cores[key] = [swept_hull(body, half) for body in bodies]
        return self.cores[key]


def _towards(graph: PoseGraph, goal: shapely.Point, links: dict[Node, list[Node]],
             starts: list[Node], goals: list[Node]) -> tuple[float | None, list[Node], set[Node]]:
    """A chain from a start to a goal, the parts nearest ``goal`` tried first.

    A :data:`~pivot_ompl.analysis.pose_chain.Search`: priced by its parts (``None``: none
    joins them), the chain, the parts reached.
    """
    ends = set(goals)
    before: dict[Node, Node | None] = dict.fromkeys(starts)
    todo = [(0.0, u) for u in starts]
    while todo:
        u = heapq.heappop(todo)[1]
        if u in ends:
            out = [u]
            while (p := before[out[-1]]) is not None:
                out.append(p)
            return float(len(out)), out[::-1], set(before)
        for v in links[u]:
            if v not in before:
                before[v] = u
                heapq.heappush(todo, (graph.bin(v[0])[v[1]][v[2]].distance(goal), v))
    return None, [], set(before)


def joined_at_every_yaw(scene: Scene, *, bins: int = FIRST_BINS,
                        should_stop: Callable[[], bool] | None = None,
                        floor: HeldFloor | None = None) -> bool | None:
    """Whether a chain of held poses valid at every yaw of its bins joins start and goal.

    ``True``: the held poses' proof cannot end apart (the module docstring); ``False``: no
    such chain at ``bins`` bins (the proof may prove); ``None``: stopped, or
    :data:`MOST_SEARCHES` searches found only chains the walks refuse and one more found a
    chain still. The poses keep the checkers' clearance; the box centre's room is the
    proof's (:data:`~pivot_ompl.analysis.pose_proof.MOTION_CLEARANCE`), read from ``floor``
    when given (the proof's, built once for both).
    """
    try:
        parts = HeldParts(scene, MOTION_CLEARANCE, should_stop, parts_clearance=KEEP_CLEARANCE,
                          regions=EveryYawRegions, floor=floor)
        if parts.room is None:
            return False
        edges = [2.0 * math.pi * i / bins for i in range(bins + 1)]
        graph = PoseGraph(parts, edges, should_stop, lazy=True)
        starts, goals = graph.nodes_at(edges, scene.start), graph.nodes_at(edges, scene.goal)
        if not starts or not goals:
            return False
        goal = shapely.Point(scene.goal[0], scene.goal[1])
        searches = Searches(MOST_SEARCHES)
        found = walked_chain(graph.links, starts, goals, [], search=partial(_towards, graph, goal),
                             may_regrasp=partial(parts.may_regrasp, edges), searches=searches,
                             should_stop=should_stop)
        if found.price is None:
            return False
        return True if searches.left >= 0 else None
    except Interrupted:
        return None
