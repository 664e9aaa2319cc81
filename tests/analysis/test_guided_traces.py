"""The guided bound's rounds on seeded scenes: the same counts, windows and paths as recorded.

The rounds' windows drive the next round, so the graph's nodes, their joins' order and the walk
relaxation's answers must all stay as they were for a faster version to keep them: these
traces were recorded before the rounds were made cheaper (ba82ba4).
"""

from __future__ import annotations

import hashlib
import pickle

import pytest
from factories import shipped

from pivot_ompl.analysis.guided_refine import GuidedRound, guided_lower_bound
from pivot_ompl.analysis.raster_bound import CELL
from pivot_ompl.analysis.raster_cover import raster_cover
from pivot_ompl.analysis.refined_bound import refined_graph
from pivot_ompl.generate import generate
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

#: Per scene: the bound and per round (regrasps, window cells, path nodes), no target.
RECORDED = {
    ("slot", None): (1, [(0, 0, 1), (0, 111, 1), (0, 336, 3), (1, 411, 4), (1, 441, 4),
                         (1, 485, 4)]),
    ("t_junction", None): (1, [(0, 0, 35), (1, 720, 2), (1, 824, 4), (1, 1294, 4),
                               (1, 1316, 4), (1, 1340, 4)]),
    ("corridor", 0): (0, [(0, 0, 6), (0, 766, 3), (0, 1220, 3), (0, 1542, 2)]),
}


@pytest.mark.parametrize(("name", "seed"), sorted(RECORDED, key=str))
def test_the_rounds_are_those_recorded(name, seed):
    scene = shipped(name) if seed is None else generate(name, seed=seed).scene
    trace: list[GuidedRound] = []
    got = guided_lower_bound(scene, cover=raster_cover(scene, cell=CELL), trace=trace)
    assert got is not None
    bound, rounds = RECORDED[(name, seed)]
    assert (got.regrasps, [(r.regrasps, r.window, r.path) for r in trace]) == (bound, rounds)


#: Per shipped scene: the nodes and a digest of the joins (each node's transfers and regrasps,
#: in order) of the mixed graph round the default necks, recorded before the graph was built
#: faster (ba82ba4).
GRAPHS = {
    "slot": (826, "b4c607944e2dae4e4630e8afeacd55aca0233e7d"),
    "door": (1040, "cad11d130e1b684dd8f3dfe8d93f65d80cbbf83c"),
    "t_junction": (1354, "8b6fd98db4813ef8d06b955c6c346e29307e2876"),
}


@pytest.mark.parametrize("name", sorted(GRAPHS))
def test_the_mixed_graph_is_the_one_recorded(name):
    """The same nodes, joined in the same order (the rounds' best paths follow that order)."""
    scene = shipped(name)
    mixed = refined_graph(scene, raster_cover(scene, cell=CELL), tolerance=SWEEP_TOLERANCE,
                          clearance=KEEP_CLEARANCE)
    assert mixed is not None
    graph = mixed.coarse.graph
    digest = hashlib.sha1(pickle.dumps((graph.zero, graph.one), protocol=4)).hexdigest()
    assert (len(graph.zero), digest) == GRAPHS[name]
