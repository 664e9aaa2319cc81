"""Which bins of a chain of held-pose parts to halve first: its regrasps', then wide parts'.

A chain of the held poses' relaxation (:mod:`~pivot_ompl.analysis.pose_proof`) moves from a
part of one yaw bin to a part of a neighbouring bin, or regrasps within a bin. Where the box
truly turns (say in the middle of a room), neighbouring bins' parts cover about the same
floor and halving their bins changes little. A part that covers markedly more floor than
the parts before and after it on the chain is where a coarse bin joins places its
neighbours keep apart (a door the held assembly passes only at that bin's coarse yaws): the
likeliest false step, so its bin is the one to halve (:func:`spanning_bins`).

A regrasp on a chain is likelier still to be false while its bin is coarse: the two grasps'
parts hold the positions where each grasp is valid at *some* yaw of the bin, not
necessarily the same one, and a resting box has one yaw. Halving the bins where a chain
changes grasp (:func:`regrasp_bins`) comes first. Halving any bins keeps the relaxation
sound; the choice only orders the work.
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


def regrasp_bins(path: Sequence[Node], widths: Sequence[float], finest: float) -> set[int]:
    """The bins in which ``path`` changes grasp (two consecutive parts of one bin).

    ``widths``: every bin's width (rad). Bins of ``finest`` width or narrower are never
    returned (they are not halved again).
    """
    return {u[0] for u, v in zip(path, path[1:], strict=False)
            if u[0] == v[0] and u[1] != v[1] and widths[u[0]] > finest}
