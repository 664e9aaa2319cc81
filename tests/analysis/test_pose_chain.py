"""The held poses' chain search: its stop, polled every round, and the callers passing theirs."""

from __future__ import annotations

import pytest
from factories import shipped

from pivot_ompl.analysis import pose_chain
from pivot_ompl.analysis.pose_chain import Node, Searches, walked_chain
from pivot_ompl.analysis.pose_proof import PoseGraph, prove_no_plan
from pivot_ompl.analysis.pose_regrasps import pose_regrasp_bound
from pivot_ompl.errors import Interrupted


def _ladder(rungs: int) -> dict[Node, list[Node]]:
    """Two grasps' parts along ``rungs`` bins, a regrasp link at every bin."""
    links: dict[Node, list[Node]] = {}

    def link(a: Node, b: Node) -> None:
        links.setdefault(a, []).append(b)
        links.setdefault(b, []).append(a)

    for i in range(rungs):
        link((i, 0, 0), (i, 1, 0))
        if i + 1 < rungs:
            link((i, 0, 0), (i + 1, 0, 0))
            link((i, 1, 0), (i + 1, 1, 0))
    return links


def test_a_stop_already_true_raises_before_any_search():
    links = _ladder(4)
    asked: list[tuple[Node, Node]] = []
    with pytest.raises(Interrupted):
        walked_chain(links, [(0, 0, 0)], [(3, 1, 0)], [0.1] * 4,
                     may_regrasp=lambda u, v: asked.append((u, v)) is not None,
                     should_stop=lambda: True)
    assert asked == []
    assert links == _ladder(4)  # nothing cut


def test_the_stop_is_polled_before_every_round():
    # every regrasp refused: each round cuts one link and searches again; a stop true from
    # the third poll on lets exactly two rounds ask the walks
    links, polls, asked = _ladder(4), [], []

    def refuse(u: Node, v: Node) -> bool:
        asked.append((u, v))
        return False

    def stop() -> bool:
        polls.append(None)
        return len(polls) > 2

    with pytest.raises(Interrupted):
        walked_chain(links, [(0, 0, 0)], [(3, 1, 0)], [0.1] * 4, may_regrasp=refuse,
                     should_stop=stop)
    assert len(polls) == 3 and len(asked) == 2
    never = walked_chain(_ladder(4), [(0, 0, 0)], [(3, 1, 0)], [0.1] * 4, may_regrasp=refuse,
                         should_stop=lambda: False)
    assert never.price is None and len(never.refused) == 4  # unstopped: every rung cut


@pytest.mark.parametrize("count", [False, True])
def test_a_stop_that_turns_true_once_the_bins_are_built_searches_no_chain(monkeypatch, count):
    # the proof and the count pass their stop to the chain search: once it is true, no
    # chain is sought, and the answer is the stopped one
    flag, searched = [], []
    found_at = PoseGraph.nodes_at

    def nodes_at(self, *args):
        flag.append(True)
        return found_at(self, *args)

    real = pose_chain.cheapest

    def cheapest(*args, **kwargs):
        searched.append(bool(flag))
        return real(*args, **kwargs)

    monkeypatch.setattr(PoseGraph, "nodes_at", nodes_at)
    monkeypatch.setattr(pose_chain, "cheapest", cheapest)
    scene = shipped("fig10")
    if count:
        found = pose_regrasp_bound(scene, should_stop=lambda: bool(flag), jumps=False)
        assert found.regrasps is None and not found.complete and not found.apart
    else:
        proof = prove_no_plan(scene, should_stop=lambda: bool(flag))
        assert proof.apart is None and proof.rounds == 1
    assert flag and not searched


def _highest_rung(links: dict[Node, list[Node]], starts: list[Node], goals: list[Node]
                  ) -> tuple[float | None, list[Node], set[Node]]:
    """A chain search up the ladder at grasp 0, across at the highest rung left, then down."""
    rung = max((i for i in range(4) if (i, 1, 0) in links[(i, 0, 0)]), default=None)
    if rung is None:
        return None, [], set(starts)
    nodes = [(i, 0, 0) for i in range(rung + 1)] + [(i, 1, 0) for i in range(rung, 4)]
    return 1.0, nodes, set(nodes)


@pytest.mark.parametrize("left", [None, 1])
def test_a_given_search_is_asked_every_round_and_only_its_chains_regrasps_walked(left):
    links, asked, rounds = _ladder(4), [], []

    def search(*args):
        out = _highest_rung(*args)
        rounds.append(out[1])
        return out

    def refuse_the_last_rung(u: Node, v: Node) -> bool:
        asked.append((u, v))
        return u[0] != 3

    found = walked_chain(links, [(0, 0, 0)], [(3, 1, 0)], [], search=search,
                         may_regrasp=refuse_the_last_rung,
                         searches=None if left is None else Searches(left))
    assert len(rounds) == 2 and found.nodes == rounds[-1]
    assert found.nodes == [(0, 0, 0), (1, 0, 0), (2, 0, 0), (2, 1, 0), (3, 1, 0)]
    assert found.refused == [((3, 0, 0), (3, 1, 0))]
    assert (3, 1, 0) not in links[(3, 0, 0)]  # the refused link cut, both ways
    # with one search left the second chain is given unasked
    assert asked == [((3, 0, 0), (3, 1, 0))] + ([((2, 0, 0), (2, 1, 0))] if left is None else [])
