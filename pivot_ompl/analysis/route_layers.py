"""A route bound that knows where regrasps may happen: one layer of cells per transfer component.

The relaxation of :mod:`~pivot_ompl.analysis.regrasp_bound` joins its free pieces by
transfers (free) and regrasps (allowed only where the walk relaxation admits a walk round the
resting box). The pieces joined by transfers alone fall into *transfer components*: a plan's
transfer phase (one grasp, the box moving with the robot) stays inside one component, so the
box's route during it lies in the component's *footprint* (the union of its pieces'
positions); a regrasp passes from one component to another only at a point shared by two of
their pieces whose regrasp edge is allowed (the relaxation's own condition, sound); a regrasp
between pieces of one component changes nothing here.

**The layered graph.** One layer per component reached by the relaxation, over a raster of
cells (:class:`~pivot_ompl.analysis.raster.FloorRaster`): a layer holds the cells that meet
its footprint, joined by :func:`~pivot_ompl.analysis.route_bound.route_on`'s 16-neighbour
moves; two layers are joined at no cost at the cells that meet an allowed regrasp region
between them. Both sets are grown by :data:`GROW` cells (supersets: the grid path that bounds
a continuous route, built as :func:`~pivot_ompl.analysis.route_bound.route_on`'s argument
builds it, visits cells within two cells of the route's points in their order, so it may
change layers at a vertex near, not at, the regrasp point). Every plan's box route, cut at its
regrasps, is then a path of this graph from a start layer to a goal layer, and the shortest
one, reduced by the grid's slack (:func:`~pivot_ompl.analysis.route_bound.grid_bound`), is a
lower bound of every plan's route whatever its regrasp count. Where the relaxation proves a
regrasp is needed, that route must pass a place where one is possible: the plain route
through the union of every piece (today's bound) does not know it.

**Lazily checked regrasps.** The walk relaxation is costly; a regrasp edge not checked yet is
taken as allowed (a superset again: every round's route is a proof). Round by round: the
shortest layered route; the regrasp edges its layer changes use are checked; where all those
a change could use are refused, its cells are removed and the next round starts. The rounds
end when every change of the route is allowed (``complete``), at :data:`MAX_ROUNDS`, or when
``should_stop`` says stop (polled between rounds and checks; the last route stands).

**Bounded cost.** At most :data:`MAX_NODES` cells over all layers (the raster coarsens with
the layers' count); where that needs cells larger than :data:`MAX_CELL` the bound is not
computed (``None``: the caller keeps the plain route bound).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Hashable, Sequence

import numpy as np
import shapely
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.route_layer_graph import (
    CHECK_HALF,
    GROW,
    MAX_CELL,
    MAX_CHECKS,
    MAX_NODES,
    MAX_ROUNDS,
    MIN_CELL,
    Components,
    Edge,
    LayeredRoute,
    LayerGraph,
)
from pivot_ompl.errors import Interrupted
from pivot_ompl.se2 import Pose

__all__ = ["CHECK_HALF", "GROW", "MAX_CELL", "MAX_CHECKS", "MAX_NODES", "MAX_ROUNDS", "MIN_CELL",
           "Components", "LayeredRoute", "layered_route", "transfer_components"]


def layered_route(pieces: Sequence[BaseGeometry], transfers: Sequence[Sequence[int]],
                  regrasps: Sequence[Edge], allowed: Callable[[Hashable, BaseGeometry], bool], *,
                  reached: set[int], starts: Sequence[int], goals: Sequence[int],
                  start: Pose, goal: Pose, bounds: tuple[float, float, float, float],
                  should_stop: Callable[[], bool] | None = None,
                  max_rounds: int = MAX_ROUNDS, max_checks: int = MAX_CHECKS,
                  components: Components | None = None, min_cell: float = MIN_CELL
                  ) -> LayeredRoute | None:
    """The layered route bound (module docstring) over the relaxation's pieces.

    Args:
        pieces: each node's free positions (a polygon, the floor's frame).
        transfers: each node's neighbours by a transfer.
        regrasps: the regrasp edges ``(u, v, name)``.
        allowed: whether the regrasp edge ``name`` may happen with the box in a part of its
            region (the walk relaxation: ``False`` proves it cannot there).
        reached: the nodes the relaxation reaches from the start (the others are left out).
        starts: the nodes holding the start pose.
        goals: the nodes holding the goal pose.
        start: the box's start pose.
        goal: the box's goal pose.
        bounds: the floor ``(xmin, ymin, xmax, ymax)``.
        should_stop: polled between the steps, rounds and checks.
        max_rounds: most graph searches.
        max_checks: most regrasp parts asked about.
        components: :func:`transfer_components` of these arguments when already made.
        min_cell: the raster's smallest cell side (m; larger where :data:`MAX_NODES` needs).

    Returns:
        The bound, or ``None`` when the raster would need cells over :data:`MAX_CELL`. Stopped
        after a first route, the last route found (``stopped``: a proof, but one that more
        rounds might have raised).

    Raises:
        Interrupted: ``should_stop()`` said stop before a first route.
    """
    t0 = time.perf_counter()

    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("the layered route bound")

    if components is None:
        components = transfer_components(pieces, transfers, reached, should_stop=should_stop)
    layers = LayerGraph.build(pieces, regrasps, bounds, poll, components, min_cell)
    if layers is None:
        return None
    return layers.search(allowed, starts, goals, start, goal, poll, max_rounds, max_checks, t0)


def transfer_components(pieces: Sequence[BaseGeometry], transfers: Sequence[Sequence[int]],
                        reached: set[int], *, should_stop: Callable[[], bool] | None = None
                        ) -> Components:
    """The transfer components of the nodes ``reached``: each node's layer, each layer's footprint.

    The footprints' union is the union of the pieces reached (the plain route bound's).
    ``should_stop`` is polled between the footprints.

    Raises:
        Interrupted: ``should_stop()`` said stop.
    """
    n = len(pieces)
    rows = [u for u in range(n) for _ in transfers[u]]
    cols = [v for u in range(n) for v in transfers[u]]
    joined = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n, n))
    _, label = connected_components(joined, directed=False)
    comps = sorted({int(label[u]) for u in reached})
    index = {c: i for i, c in enumerate(comps)}
    layer_of = {u: index[int(label[u])] for u in reached}
    groups: list[list[BaseGeometry]] = [[] for _ in comps]
    for u in reached:
        groups[layer_of[u]].append(pieces[u])
    unions = []
    for group in groups:
        if should_stop is not None and should_stop():
            raise Interrupted("the route bound's transfer components")
        unions.append(shapely.union_all(group))
    return layer_of, unions
