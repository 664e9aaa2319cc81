"""Chains through the held poses' joined parts: the cheapest, and one whose regrasps walk.

A part is a ``(bin, grasp, part)`` node (:mod:`~pivot_ompl.analysis.pose_proof`); the links
join parts that meet, at one grasp in neighbouring bins (a motion) or at two grasps in one
bin (a regrasp). :func:`cheapest` is the least-priced chain (Dijkstra); :func:`walked_chain`
asks the regrasps of the chain a search found (:func:`cheapest`, or any :data:`Search`)
whether the robot may walk round the resting box, cuts the links refused and searches again
(the walk is the costly question, asked of a chain's regrasps only; most links are never on
a chain), polling its stop every round.
:class:`LazyLinks` gives a node's links the first time the search asks for them, so a search
computes only the parts it meets.
"""

from __future__ import annotations

import heapq
import math
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.errors import Interrupted

Node = tuple[int, int, int]  # (bin, grasp, part)
#: A chain search over ``(links, starts, goals)``: the chain's price (``None`` when no chain
#: joins them), the chain from its start to its goal, and the parts reached (as
#: :func:`cheapest` gives them).
Search = Callable[[dict[Node, list[Node]], list[Node], list[Node]],
                  tuple[float | None, list[Node], set[Node]]]


class LazyLinks(dict[Node, list[Node]]):
    """A node's links, computed by ``expand(node)`` the first time they are asked.

    A ``dict`` to :func:`cheapest` and :func:`walked_chain`: ``links[u]`` and
    ``links.get(u)`` both give ``u``'s links (computed and kept once), so a link cut from a
    kept list stays cut; only the nodes asked are held.
    """

    def __init__(self, expand: Callable[[Node], list[Node]]) -> None:
        """No node's links computed yet."""
        super().__init__()
        self._expand = expand

    def __missing__(self, node: Node) -> list[Node]:
        out = self[node] = self._expand(node)
        return out

    def get(self, node: Node, default: object = None) -> list[Node]:
        """``node``'s links (computed on first asking; ``default`` is never needed)."""
        return self[node]


def cheapest(links: dict[Node, list[Node]], starts: list[Node], goals: list[Node],
             widths: list[float], *, change: float = 0.0
             ) -> tuple[float | None, list[Node], set[Node]]:
    """The least-priced chain of joined parts from a start to a goal (Dijkstra).

    Entering part ``v`` costs ``widths[v[0]]`` (its bin's width, rad), plus ``change`` when
    its grasp is not the part's before (a start costs its width). Prices ranked first by
    grasp changes, then by widths, are one float: ``change`` above any chain's summed widths.
    Gives the chain's price (``None`` when none joins them), the chain from its start to its
    goal, and the parts reached.
    """
    goal = set(goals)
    before: dict[Node, Node | None] = dict.fromkeys(starts)
    cost = {u: widths[u[0]] for u in starts}
    todo = [(c, u) for u, c in cost.items()]
    heapq.heapify(todo)
    done: set[Node] = set()
    while todo:
        c, u = heapq.heappop(todo)
        if u in done:
            continue
        done.add(u)
        if u in goal:
            out = [u]
            while (p := before[out[-1]]) is not None:
                out.append(p)
            return c, out[::-1], set(before)
        g = u[1]
        for v in links.get(u, ()):
            if v in done:
                continue
            cv = c + widths[v[0]] + (change if v[1] != g else 0.0)
            if cv < cost.get(v, math.inf):
                cost[v], before[v] = cv, u
                heapq.heappush(todo, (cv, v))
    return None, [], set(before)


@dataclass
class Searches:
    """Chain searches left to :func:`walked_chain` (shared by a count's rounds)."""

    left: int


@dataclass(frozen=True)
class Chain:
    """What :func:`walked_chain` found.

    Attributes:
        price: the chain's price (:func:`cheapest`); ``None`` when no chain joins start and
            goal over the links left.
        nodes: the chain, from its start to its goal (``[]`` with no chain).
        reached: the parts the last search reached.
        refused: the regrasp links refused and cut, over every search.
    """

    price: float | None
    nodes: list[Node]
    reached: set[Node]
    refused: list[tuple[Node, Node]]


def walked_chain(links: dict[Node, list[Node]], starts: list[Node], goals: list[Node],
                 widths: list[float], *, may_regrasp: Callable[[Node, Node], bool] | None,
                 change: float = 0.0, searches: Searches | None = None,
                 should_stop: Callable[[], bool] | None = None,
                 search: Search | None = None) -> Chain:
    """A chain whose regrasps the walks allow: the cheapest (:func:`cheapest`), or ``search``'s.

    ``search``: the chain search asked every round in place of :func:`cheapest` (then
    ``widths`` and ``change`` are unused, the chain is the one it gives and priced as it
    prices it).

    ``may_regrasp(u, v)``: whether the regrasp link from part ``u`` to part ``v`` (one bin,
    two grasps) may be taken; asked lazily, of the chain found only: a link it refuses is cut
    from ``links`` (both ways) and the chain sought again. ``None``: every link is taken. At
    most ``searches.left`` searches (each takes one; none left, the last chain is given
    unasked: a chain over more links than the walks allow).

    Raises:
        Interrupted: ``should_stop()`` was true before a round (polled before every search).
    """
    refused: list[tuple[Node, Node]] = []
    while True:
        if should_stop is not None and should_stop():
            raise Interrupted("the held poses' chain search")
        price, nodes, reached = (cheapest(links, starts, goals, widths, change=change)
                                 if search is None else search(links, starts, goals))
        if price is None:
            return Chain(None, [], reached, refused)
        if searches is not None:
            searches.left -= 1
            if searches.left < 0:
                return Chain(price, nodes, reached, refused)
        cut = [] if may_regrasp is None else [
            (u, v) for u, v in zip(nodes, nodes[1:], strict=False)
            if u[0] == v[0] and u[1] != v[1] and not may_regrasp(u, v)]
        if not cut:
            return Chain(price, nodes, reached, refused)
        for u, v in cut:
            links[u].remove(v)
            links[v].remove(u)
        refused += cut
