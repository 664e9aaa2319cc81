"""The regrasp search's focus: slot poses seeded once where a plan may use them, and the
search's heuristic, the cheapest cost to the goal over the graph (a lower bound)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import shapely
from factories import shipped, sliced

from pivot_ompl.base.problem import make_problem
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.multiplex.graph import is_transfer
from pivot_ompl.planners.multiplex.search import cost_to_go
from pivot_ompl.planners.objects.roadmap import pose_metric
from pivot_ompl.planners.objects.slots import slot_poses, slots
from pivot_ompl.planners.regrasp_search import RegraspSearch


def _search(scene, seed=0):
    ck = make_problem(scene).checker
    return ck, RegraspSearch(ck, scene.start, scene.goal, RegraspConfig(),
                             np.random.default_rng(seed))


def _sliced(scene, pieces=3):
    """``scene`` with every box cut across its long side into ``pieces`` boxes.

    Every other piece stands 1 cm higher, so the pieces stay pieces (touching boxes of one
    height are merged into one) and face each other across every gap.
    """
    cut = sliced(scene.obstacles, pieces)
    cut = [dataclasses.replace(o, height=o.height + 0.01 * (k % 2)) for k, o in enumerate(cut)]
    return dataclasses.replace(scene, obstacles=tuple(cut))


def test_slot_poses_are_seeded_once_and_only_where_the_box_can_get():
    # a turned building whose walls are made of several pieces (each gap found once per pair
    # of pieces) and floor outside the building that no plan reaches
    scene = _sliced(generate("building", 0, params=GeneratorParams(rooms=4)).scene)
    ck, search = _search(scene)
    search.prepare(lambda: False)
    rm = search.roadmap
    seeded = rm.of_kind("slot")
    assert seeded
    region = search.sampler.region()
    assert region is not None
    arr = np.array([rm.poses[i] for i in seeded])
    for k, i in enumerate(seeded):
        assert shapely.contains_xy(region, *rm.poses[i][:2])
        d = pose_metric(np.delete(arr, k, axis=0), rm.poses[i])
        assert d.min() >= 0.5 * RegraspConfig().sampling.slot_spacing - 1e-9
    every = slot_poses(ck, slots(ck, play=RegraspConfig().sampling.slot_play),
                       spacing=0.2, approach=RegraspConfig().sampling.slot_approach)
    assert len(seeded) < len(every)  # duplicates and unreachable poses left out


def test_cost_to_go_is_consistent_and_the_heuristic_admissible():
    scene = shipped("fig10")
    _ck, search = _search(scene)
    search.prepare(lambda: False)
    for _ in range(40):
        search.visibility.step(lambda: False)
    search.graph.multiplex_pending(lambda: False)
    g = search.graph
    to_go = cost_to_go(g, lambda: False)
    assert to_go is not None
    assert all(to_go[n] == 0.0 for n in g.goal_nodes)
    for u, nbrs in g.adj.items():
        if u not in to_go:
            continue
        for v, c in nbrs.items():
            if not is_transfer(u, v) or g.known_plausible(u, v):
                # an edge the relaxation may use: the costs to go differ by at most its cost
                assert v in to_go and abs(to_go[v] - to_go[u]) <= c + 1e-9
    path = search.paths.cheapest(lambda: False)
    assert path, "fig10's graph joins start and goal after 40 visibility samples"
    for k, node in enumerate(path):  # a lower bound of the cost of the rest of the path
        rest = sum(g.adj[a][b] for a, b in zip(path[k:], path[k + 1:], strict=False))
        assert to_go[node] <= rest + 1e-6
    h = search.paths.heuristic(path[0])
    assert math.isfinite(h) and h <= search.config.search.weight * to_go[path[0]] + 1e-9
