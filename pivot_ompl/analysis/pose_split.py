"""Which bins of a chain of held-pose parts to halve first: those whose part spans more.

A chain of the held poses' relaxation (:mod:`~pivot_ompl.analysis.pose_proof`) moves from a
part of one yaw bin to a part of a neighbouring bin, or regrasps within a bin. Where the box
truly turns (say in the middle of a room), neighbouring bins' parts cover about the same
floor and halving their bins changes little. A part that covers markedly more floor than
the parts before and after it on the chain is where a coarse bin joins places its
neighbours keep apart (a door the held assembly passes only at that bin's coarse yaws): the
likeliest false step, so its bin is the one to halve. Halving any bins keeps the
relaxation sound; the choice only orders the work.
"""

from __future__ import annotations

from collections.abc import Sequence

from pivot_ompl.analysis.pose_chain import Node

#: A part spans more than its chain neighbours when its area exceeds both by this factor.
SPANS = 1.1


def spanning_bins(path: Sequence[Node], areas: Sequence[float], widths: Sequence[float],
                  finest: float) -> set[int]:
    """The bins of ``path``'s inner parts larger than both chain neighbours (:data:`SPANS`).

    ``areas``: each node's part area (m²); ``widths``: every bin's width (rad). Bins of
    ``finest`` width or narrower are never returned (they are not halved again).
    """
    out = set()
    for n in range(1, len(path) - 1):
        i = path[n][0]
        if widths[i] > finest and areas[n] > SPANS * max(areas[n - 1], areas[n + 1]):
            out.add(i)
    return out
