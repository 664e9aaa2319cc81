"""A lower bound on regrasps from the held assembly's poses, refined in yaw along its chain.

The held poses' relaxation (:mod:`~pivot_ompl.analysis.pose_proof`) joins the free parts of
every (yaw bin, grasp) by motions (neighbouring bins, one grasp) and by regrasps (one bin, two
grasps, the box standing still). A plan is a path through those parts whose grasp changes
only at a regrasp, so the fewest grasp changes on a chain of joined parts from a part holding
the start to one holding the goal is at most the regrasps of any plan (a regrasp back to the
grasp held before counts none: fewer, still a lower bound). Every round's least count is such
a bound, whatever its bins; the largest over the rounds is given.

The parts are taken at the checkers' full clearance, joined across the sweep's jumps
(:class:`~pivot_ompl.analysis.pose_jumps.JumpParts`), and a regrasp link only where the
walking robot may get round the resting box from one grasp to the other
(:class:`~pivot_ompl.analysis.pose_walk.RegraspWalks`, asked lazily of the chains found,
:func:`~pivot_ompl.analysis.pose_chain.walked_chain`: a link it refuses is cut and the chain
sought again; refusals are kept for the bins the next rounds keep).

The count is a shortest path with motions costing 0 and grasp changes 1; among chains of the
least count the one through the narrowest bins is taken, and the bins of its regrasps (else
its widest bins) are halved for the next round: a count held down by a coarse bin's loose
parts rises once the bin is fine enough, one that fine bins keep is the relaxation's answer
at that scale. Rounds end when the count reaches ``target`` (the plan's regrasps: nothing
more to prove), when the chain's bins are all at
:data:`~pivot_ompl.analysis.pose_proof.FINEST`, at
:data:`~pivot_ompl.analysis.pose_proof.MAX_BINS` bins, after :data:`MOST_ROUNDS` rounds or
:data:`MOST_SEARCHES` searches, or before a round that would compute more than
:data:`MOST_BINS` bins in all (counts, not a clock: the same on any load). ``should_stop``
is polled before every bin's parts and every chain search; stopped, the rounds done stand.

What it cannot see: the pivoting kinematics, and of the walk only its disk's way round the
box (not the walking body's heading). Where the held assembly fits a passage at the full
clearance in some yaw of a bin, its chain takes it.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass
from functools import partial

import numpy as np

from pivot_ompl.analysis.pose_chain import Node, Searches, walked_chain
from pivot_ompl.analysis.pose_graph import PoseGraph
from pivot_ompl.analysis.pose_jumps import JumpParts
from pivot_ompl.analysis.pose_proof import (
    ESTIMATED_BINS,
    FINEST,
    MAX_BINS,
    MOTION_CLEARANCE,
    HeldParts,
    halve,
    proof_estimate,
    widest_bins,
)
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)

#: Yaw bins of the first round (the corridor rows' count leaves 0 from 64 bins, not from 32).
FIRST_BINS = 64
#: Bins' worth of parts computed at most over all rounds (the first round's and the halves;
#: a bin and its opposite cost one bin's worth,
#: :func:`~pivot_ompl.analysis.pose_proof.with_opposites`): the time bound.
#: The corridor rows' count reaches its 2 in the first round and stays there however far
#: the chain is refined (up to 394 bins and 30 s on a 16-room row; on the 32-room row 96
#: bins' worth took 10.3 s against 7.1 s for 64, both 2, on a loaded machine); fig10's 2
#: needs 62.
MOST_BINS = 64
#: Rounds at most (a count, not a clock). With the walks and the full clearance the
#: corridor rows' first round gives most of their count (16 rooms, seed 1: 5 of the 6 that
#: eleven rounds reach, in a fifth of their time).
MOST_ROUNDS = 4
#: Shortest-path searches at most over all rounds (each after the walks refused a link of
#: the chain before; a count, not a clock): the 32-room row with a 0.89 m corridor asked 228
#: in four rounds, three quarters of its 19 s; the 4-room rows need 1-9.
MOST_SEARCHES = 48


@dataclass(frozen=True)
class PoseRegrasps:
    """The held poses' lower bound on regrasps (:func:`pose_regrasp_bound`).

    Attributes:
        regrasps: fewest grasp changes of any chain joining start and goal (the largest over
            the rounds), a lower bound on every plan's regrasps; ``None`` when no round ended,
            or when ``apart``.
        apart: no chain joins start and goal (no plan exists).
        complete: the rounds ended by themselves (the count reached ``target``, or the
            chain's bins could not be halved); ``False``: stopped, or start or goal in no
            part (then ``regrasps`` is what the rounds done proved).
        bins: yaw bins of the last round.
        finest: the narrowest bin (rad).
        rounds: rounds run.
        seconds: time taken (s).
    """

    regrasps: int | None
    apart: bool
    complete: bool
    bins: int
    finest: float
    rounds: int
    seconds: float


def pose_estimate(scene: Scene, *, most_bins: int = MOST_BINS) -> float:
    """Estimated time (s) of :func:`pose_regrasp_bound` (``most_bins`` bins' worth)."""
    return proof_estimate(scene) * most_bins / ESTIMATED_BINS


#: A grasp change's price against the bins' widths (rad) in
#: :func:`~pivot_ompl.analysis.pose_chain.cheapest`: above any chain's summed widths (a chain
#: enters each part once; parts are far fewer than 1e6 / 2pi).
CHANGE = 1e6


def least_changes(graph: PoseGraph, starts: list[Node], goals: list[Node],
                  widths: list[float], *, may_regrasp: Callable[[Node, Node], bool] | None = None,
                  searches: Searches | None = None,
                  should_stop: Callable[[], bool] | None = None
                  ) -> tuple[int, list[Node]] | None:
    """Fewest grasp changes from a start to a goal part, and a chain of that many.

    Among chains of the fewest changes, the one of least summed bin widths (``widths[i]``,
    rad, per part entered). ``None`` when no chain joins them. ``may_regrasp(u, v)``: whether
    the regrasp link from part ``u`` to part ``v`` may be taken
    (:func:`~pivot_ompl.analysis.pose_chain.walked_chain`: asked of the chains found, a link
    refused cut from ``graph.links``); with no search left the last chain is given unasked:
    its count is still a lower bound, the links it was not asked of being more than the
    relaxation's. ``should_stop`` is polled before every search
    (:class:`~pivot_ompl.errors.Interrupted` when true).
    """
    found = walked_chain(graph.links, starts, goals, widths, may_regrasp=may_regrasp,
                         change=CHANGE, searches=searches, should_stop=should_stop)
    return None if found.price is None else (int(found.price // CHANGE), found.nodes)


def cut_refused(graph: PoseGraph, parts: HeldParts, edges: list[float]) -> None:
    """Cut from ``graph`` the regrasp links refused in earlier rounds (of the bins kept)."""
    for i in range(len(edges) - 1):
        for (g, k, h, q), may in parts.walked.get((edges[i], edges[i + 1]), {}).items():
            if not may and (i, h, q) in graph.links.get((i, g, k), ()):
                graph.links[(i, g, k)].remove((i, h, q))
                graph.links[(i, h, q)].remove((i, g, k))


def regrasp_bins(edges: list[float], path: list[Node], finest: float
                 ) -> tuple[list[int], float]:
    """The bins of a chain to halve, with those opposite them, and the widest of them (rad).

    The bins of the chain's regrasps first (where the walk round the resting box is judged,
    at the bin's loosest: :mod:`~pivot_ompl.analysis.pose_walk`), the widest of them (within
    1 %), none of ``finest`` or finer; when those are all that fine, the chain's widest bins
    (:func:`~pivot_ompl.analysis.pose_proof.widest_bins`).
    """
    at = [u for u, v in zip(path, path[1:], strict=False) if u[1] != v[1]]
    split, widest = widest_bins(edges, at, finest) if at else ([], 0.0)
    return (split, widest) if split else widest_bins(edges, path, finest)


def pose_regrasp_bound(scene: Scene, *, target: int | None = None,
                       clearance: float = MOTION_CLEARANCE, first_bins: int = FIRST_BINS,
                       max_bins: int = MAX_BINS, finest: float = FINEST,
                       most_bins: int = MOST_BINS, most_rounds: int = MOST_ROUNDS,
                       most_searches: int = MOST_SEARCHES,
                       walk: bool = True, jumps: bool = True,
                       should_stop: Callable[[], bool] | None = None) -> PoseRegrasps:
    """The held poses' lower bound on the regrasps of any plan of ``scene`` (module docstring).

    Args:
        scene: the scene.
        target: the regrasps of the plan to judge (rounds end once the count reaches it);
            ``None``: refine until the chain's bins cannot be halved.
        clearance: kept from the obstacles by every held pose (m).
        first_bins: yaw bins of the first round.
        max_bins: most yaw bins.
        finest: narrowest bin halved again (rad).
        most_bins: bins' worth of parts computed at most over all rounds (a round that would
            pass it is not run: the rounds done stand, and the result is complete).
        jumps: parts at the checkers' full clearance joined across the sweep's jumps
            (:class:`~pivot_ompl.analysis.pose_jumps.JumpParts`; ``clearance`` then unused).
        most_rounds: rounds at most (then the rounds done stand, and the result is complete).
        most_searches: shortest-path searches at most over all rounds (:func:`least_changes`;
            then the last count stands, and the result is complete).
        walk: take a regrasp link only where the walking robot may get round the resting box
            (:meth:`~pivot_ompl.analysis.pose_proof.HeldParts.may_regrasp`).
        should_stop: polled before every bin's parts and every chain search; stopped, the
            rounds done stand.

    Never raises on a stop.
    """
    t0 = time.perf_counter()
    edges = [2.0 * math.pi * i / first_bins for i in range(first_bins + 1)]
    rounds, best, computed = 0, None, first_bins // 2  # opposite bins share parts

    def result(complete: bool, apart: bool = False) -> PoseRegrasps:
        return PoseRegrasps(None if apart else best, apart, complete, len(edges) - 1,
                            float(np.diff(edges).min()), rounds, time.perf_counter() - t0)

    try:
        parts = JumpParts(scene, should_stop) if jumps else HeldParts(scene, clearance,
                                                                       should_stop)
        if parts.room is None:
            return result(False)
        searches = Searches(most_searches)
        while True:
            graph = PoseGraph(parts, edges, should_stop)
            rounds += 1
            starts, goals = graph.nodes_at(edges, scene.start), graph.nodes_at(edges, scene.goal)
            if not starts or not goals:
                return result(False)
            if walk:
                cut_refused(graph, parts, edges)
            found = least_changes(
                graph, starts, goals, np.diff(edges).tolist(),
                may_regrasp=partial(parts.may_regrasp, edges) if walk else None,
                searches=searches, should_stop=should_stop)
            if found is None:
                return result(True, apart=True)
            count, path = found
            best = count if best is None else max(best, count)
            if (target is not None and best >= target) or searches.left < 0:
                return result(True)
            split, widest = regrasp_bins(edges, path, finest)
            log.debug("held poses' regrasps, round %d: %d bins, at least %d (chain of %d "
                      "parts); %d halved (%.2f degrees)", rounds, len(edges) - 1, best,
                      len(path), len(split), math.degrees(widest))
            computed += len(split)  # two halves each, an opposite pair's for one bin's
            if (not split or len(edges) - 1 + len(split) > max_bins or computed > most_bins
                    or rounds >= most_rounds):
                return result(True)
            halve(parts, edges, split)
    except Interrupted:
        return result(False)
