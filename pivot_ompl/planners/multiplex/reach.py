"""The states a search may reach: a start's component over the edges that pass the cheap test.

A sound filter of the multiplexed graph (:mod:`~.graph`): a search whose goal state is outside
the set cannot succeed and is skipped. The set is grown from the starts until it holds a goal
state (:meth:`ReachableSet.grow`), and again when a new edge joins a state inside it to one
outside (:meth:`ReachableSet.joined`); a growth stopped by the termination condition forgets
the set (:attr:`ReachableSet.states` is ``None``: it tells nothing until computed again).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

from pivot_ompl.planners.multiplex.edges import (
    Node,
    State,
    Stop,
    frame_flip,
    is_transfer,
    successor,
)

#: The cheap test of a transfer ``(a, b)`` (cached by the graph; a failed edge is removed).
Plausible = Callable[[Node, Node], bool]


class ReachableSet:
    """States reachable from a start over candidate edges that pass the cheap test.

    Args:
        adj: the graph's candidate edges, both ways (``adj[a][b]`` is a cost), read live.
        plausible: the cheap test of a transfer (regrasps need none).

    Attributes:
        states: the set (a superset of the truth once full checks remove edges), grown until
            it holds a goal state; ``None`` before :meth:`compute`, or after the termination
            condition stopped its growth.
        reached: a goal state is in the set: it grows no more.
    """

    states: set[State] | None
    reached: bool

    def __init__(self, adj: Mapping[Node, Mapping[Node, float]], plausible: Plausible) -> None:
        """An empty set, not computed yet."""
        self._adj = adj
        self._plausible = plausible
        self.states = None
        self.reached = False
        self._goal_states: set[State] = set()

    def compute(self, start_nodes: list[Node], goal_nodes: set[Node], should_stop: Stop) -> None:
        """The states connected to a start, grown until one is a goal state (:meth:`grow`)."""
        self.states = set()
        self._goal_states = {(g, 0) for g in goal_nodes}
        self.reached = False
        for s in start_nodes:
            if self.states is None or self.reached:  # stopped, or a goal state reached
                return
            if (s, 0) not in self.states:
                self.grow((s, 0), should_stop)

    def joined(self, a: Node, b: Node, should_stop: Stop) -> None:
        """Grow the set across the new candidate edge ``a - b`` (if it joins it to a state)."""
        reach = self.states
        if reach is None or self.reached:
            return
        flip = frame_flip(a, b)
        for parity in (0, 1):
            sa, sb = (a, parity), (b, parity ^ flip)
            if (sa in reach) == (sb in reach):
                continue
            if is_transfer(a, b) and not self._plausible(a, b):
                return
            self.grow(sb if sa in reach else sa, should_stop)
            if self.states is None or self.reached:
                return

    def grow(self, state: State, should_stop: Stop) -> None:
        """Add ``state`` and the states joined to it by plausible edges to the set.

        Each transfer that would add a state is tested first (cached): the set is the start's
        component over the edges that survive the test. Stopped, the set is forgotten. The
        growth ends at the first goal state added: the set then answers
        :meth:`excludes_goal` (edges linked later only add states), and testing the rest of
        the component would test, eagerly, transfers the search may never take (on a
        cluttered floor most of the graph's). A search that finds no path computes it anew.
        """
        reach = self.states
        assert reach is not None
        stack = [state]
        reach.add(state)
        if state in self._goal_states:
            self.reached = True
            return
        steps = 0
        while stack:
            steps += 1
            if steps % 64 == 1 and should_stop():
                self.states = None  # incomplete: computed again after a failed search
                return
            u = stack.pop()
            for v in list(self._adj[u[0]]):
                sv = successor(u, v)
                if sv in reach or (is_transfer(u[0], v) and not self._plausible(u[0], v)):
                    continue
                reach.add(sv)
                if sv in self._goal_states:
                    self.reached = True
                    return
                stack.append(sv)

    def excludes_goal(self, goal_nodes: set[Node]) -> bool:
        """Whether the set is known and holds no goal state (in the start's frame)."""
        r = self.states
        return r is not None and not any((g, 0) in r for g in goal_nodes)
