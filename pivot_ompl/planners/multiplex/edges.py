"""The multiplexed graph's vocabulary: its nodes, its states and what an edge between them is.

A node is ``(object node, grasp)``; a search state is ``(node, frame parity)``. An edge joining
two object nodes is a **transfer** (:func:`is_transfer`), one at a single object node a
**regrasp**; a transfer whose grasps differ turns the path's frame by a half turn
(:func:`frame_flip`). The graph itself is :mod:`~.graph`.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.grasp import BoxGraspModel

Node = tuple[int, int]  # (object roadmap index, grasp)
State = tuple[Node, int]  # (node, frame parity)
Stop = Callable[[], bool]


def is_transfer(a: Node, b: Node) -> bool:
    """Whether the edge ``a - b`` moves the box (else it is a regrasp at one pose)."""
    return a[0] != b[0]


def frame_flip(a: Node, b: Node) -> int:
    """1 if the edge ``a - b`` turns the path's frame by a half turn, else 0.

    That is a transfer whose grasps differ: the same car written from the other side.
    """
    return int(a[0] != b[0] and a[1] != b[1])


def successor(state: State, node: Node) -> State:
    """The state reached from ``state`` along the edge to ``node`` (parity carried on)."""
    return node, state[1] ^ frame_flip(state[0], node)


def walk_estimate(model: BoxGraspModel, a: int, b: int) -> float:
    """Estimated length (m) of the walk from grasp ``a`` to ``b``.

    Quarter circles round the box at the robot's distance.
    """
    quarters = min((b - a) % 4, (a - b) % 4)
    return model.robot_offset(a) * 0.5 * math.pi * quarters


def undirected(a: Node, b: Node) -> tuple[Node, Node]:
    """The key of the edge ``a - b`` whichever way it is taken."""
    return (a, b) if a <= b else (b, a)
