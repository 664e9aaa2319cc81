"""A lower bound on regrasps from the held assembly's poses, refined in yaw along its chain.

The held poses' relaxation (:mod:`~pivot_ompl.analysis.pose_proof`) joins the free parts of
every (yaw bin, grasp) by motions (neighbouring bins, one grasp) and by regrasps (one bin, two
grasps, the box standing still). A plan is a path through those parts whose grasp changes
only at a regrasp, so the fewest grasp changes on a chain of joined parts from a part holding
the start to one holding the goal is at most the regrasps of any plan (a regrasp back to the
grasp held before counts none: fewer, still a lower bound). Every round's least count is such
a bound, whatever its bins; the largest over the rounds is given.

The count is a shortest path with motions costing 0 and grasp changes 1; among chains of the
least count the one through the narrowest bins is taken (costs compared as pairs: grasp
changes, then the summed widths of the bins of the parts entered), and its widest bins are
halved for the next round: a count held down by a coarse bin's loose parts rises once the
bin is fine enough, one that fine bins keep is the relaxation's answer at that scale. Rounds
end when the count reaches ``target`` (the plan's regrasps: nothing more to prove), when the
chain's bins are all at :data:`~pivot_ompl.analysis.pose_proof.FINEST`, at
:data:`~pivot_ompl.analysis.pose_proof.MAX_BINS` bins, or before a round that would compute
more than :data:`MOST_BINS` bins in all (a count, not a clock: the same on any load).
``should_stop`` is polled before every bin's parts; stopped, the rounds done stand.

What it cannot see: the walk round the resting box (a regrasp is allowed wherever both
grasps' parts meet) and the pivoting kinematics. Where the held assembly fits a passage at the
relaxation's clearance (:data:`~pivot_ompl.analysis.pose_proof.MOTION_CLEARANCE`), its chain
takes it.
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pivot_ompl.analysis.pose_proof import (
    ESTIMATED_BINS,
    FINEST,
    MAX_BINS,
    MOTION_CLEARANCE,
    HeldParts,
    Node,
    PoseGraph,
    cheapest,
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


def least_changes(graph: PoseGraph, starts: list[Node], goals: list[Node],
                  widths: list[float]) -> tuple[int, list[Node]] | None:
    """Fewest grasp changes from a start to a goal part, and a chain of that many.

    Among chains of the fewest changes, the one of least summed bin widths (``widths[i]``,
    rad, per part entered). ``None`` when no chain joins them.
    """
    price, out, _ = cheapest(
        graph.links, starts, goals,
        lambda u, v: (float(u is not None and v[1] != u[1]), widths[v[0]]))
    return None if price is None else (int(price[0]), out[::-1])


def pose_regrasp_bound(scene: Scene, *, target: int | None = None,
                       clearance: float = MOTION_CLEARANCE, first_bins: int = FIRST_BINS,
                       max_bins: int = MAX_BINS, finest: float = FINEST,
                       most_bins: int = MOST_BINS,
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
        should_stop: polled before every bin's parts; stopped, the rounds done stand.

    Never raises on a stop.
    """
    t0 = time.perf_counter()
    edges = [2.0 * math.pi * i / first_bins for i in range(first_bins + 1)]
    rounds, best, computed = 0, None, first_bins // 2  # opposite bins share parts

    def result(complete: bool, apart: bool = False) -> PoseRegrasps:
        return PoseRegrasps(None if apart else best, apart, complete, len(edges) - 1,
                            float(np.diff(edges).min()), rounds, time.perf_counter() - t0)

    try:
        parts = HeldParts(scene, clearance, should_stop)
        if parts.room is None:
            return result(False)
        while True:
            graph = PoseGraph(parts, edges, should_stop)
            rounds += 1
            starts, goals = graph.nodes_at(edges, scene.start), graph.nodes_at(edges, scene.goal)
            if not starts or not goals:
                return result(False)
            found = least_changes(graph, starts, goals, np.diff(edges).tolist())
            if found is None:
                return result(True, apart=True)
            count, path = found
            best = count if best is None else max(best, count)
            if target is not None and best >= target:
                return result(True)
            split, widest = widest_bins(edges, path, finest)
            log.debug("held poses' regrasps, round %d: %d bins, at least %d (chain of %d "
                      "parts); %d halved (%.2f degrees)", rounds, len(edges) - 1, best,
                      len(path), len(split), math.degrees(widest))
            computed += len(split)  # two halves each, an opposite pair's for one bin's
            if not split or len(edges) - 1 + len(split) > max_bins or computed > most_bins:
                return result(True)
            halve(parts, edges, split)
    except Interrupted:
        return result(False)
