"""The held poses' graph: links computed one way, two-way and complete; chains whatever order."""

from __future__ import annotations

import math
import random

import pytest
import shapely
from corner_factories import corner_slot
from factories import shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis import pose_regrasps
from pivot_ompl.analysis.pose_chain import Node, cheapest
from pivot_ompl.analysis.pose_graph import PoseGraph
from pivot_ompl.analysis.pose_proof import MOTION_CLEARANCE, HeldParts
from pivot_ompl.analysis.pose_regrasps import pose_regrasp_bound


@pytest.mark.parametrize("bins", [12, 32])
def test_every_link_is_two_way_and_joins_parts_that_meet_and_none_is_missing(bins):
    # the eager graph asks every node its links: a motion link joins one grasp's parts in
    # neighbouring bins, a regrasp link two grasps' parts in one bin, always parts that meet,
    # each link both ways, and every such pair that meets is linked
    scene = corner_slot(3.0, 0.95)
    edges = [2.0 * math.pi * i / bins for i in range(bins + 1)]
    graph = PoseGraph(HeldParts(scene, MOTION_CLEARANCE, None), edges, None)
    nodes = [(i, g, k) for i in range(bins) for g, here in enumerate(graph.bin(i))
             for k in range(len(here))]
    assert set(graph.links) == set(nodes)

    def part(u: Node) -> shapely.Geometry:
        return graph.bin(u[0])[u[1]][u[2]]

    expected = {u: set() for u in nodes}
    for u in nodes:
        for v in nodes:
            motion = v[1] == u[1] and (v[0] - u[0]) % bins in (1, bins - 1)
            regrasp = v[0] == u[0] and v[1] != u[1]
            if (motion or regrasp) and part(u).intersects(part(v)):
                expected[u].add(v)
    motions = regrasps = 0
    for u in nodes:
        links = graph.links[u]
        assert len(links) == len(set(links)), u  # no link twice
        assert set(links) == expected[u], u
        for v in links:
            assert u in graph.links[v]
            motions += v[1] == u[1]
            regrasps += v[1] != u[1]
    assert motions and regrasps


def _graph(pairs: list[tuple[int, int]], size: int) -> dict[Node, list[Node]]:
    nodes = [(i, g, 0) for i in range(size) for g in range(2)]
    links: dict[Node, list[Node]] = {u: [] for u in nodes}
    for a, b in pairs:
        u, v = nodes[a % len(nodes)], nodes[b % len(nodes)]
        if u != v and v not in links[u]:
            links[u].append(v)
            links[v].append(u)
    return links


@settings(max_examples=200)
@given(pairs=st.lists(st.tuples(st.integers(0, 99), st.integers(0, 99)), min_size=4,
                      max_size=40),
       size=st.integers(3, 8), change=st.sampled_from([0.0, 1e6]), seed=st.integers(0, 2**32))
def test_the_cheapest_chain_does_not_depend_on_the_links_order(pairs, size, change, seed):
    # equal bin widths: many chains tie, and the one taken must not follow the order in
    # which a node's links are listed (the eager and lazy graphs list them differently)
    links = _graph(pairs, size)
    widths = [0.25] * size
    starts, goals = [(0, 0, 0)], [(size - 1, 1, 0), (size // 2, 0, 0)]
    shuffled = {u: random.Random(seed + n).sample(vs, len(vs))
                for n, (u, vs) in enumerate(links.items())}
    assert cheapest(shuffled, starts, goals, widths, change=change) == \
        cheapest(links, starts, goals, widths, change=change)


@pytest.mark.parametrize("name", ["door", "fig10"])
def test_the_regrasp_count_is_the_same_whatever_the_links_order(name, monkeypatch):
    # every eager graph of the count's rounds with each node's links reversed: the same
    # count, rounds and bins
    scene = shipped(name)
    plain = pose_regrasp_bound(scene)

    class Reversed(PoseGraph):
        def __init__(self, *args, **kwargs) -> None:  # noqa: ANN002, ANN003
            super().__init__(*args, **kwargs)
            for links in self.links.values():
                links.reverse()

    monkeypatch.setattr(pose_regrasps, "PoseGraph", Reversed)
    turned = pose_regrasp_bound(scene)
    assert plain.regrasps is not None and plain.regrasps >= 1
    assert (turned.regrasps, turned.apart, turned.complete, turned.bins, turned.finest,
            turned.rounds) == (plain.regrasps, plain.apart, plain.complete, plain.bins,
                               plain.finest, plain.rounds)
