"""The floor distances over the free floor's components, within a limit, against a reference.

The reference is the plain definition: one Dijkstra (scipy) over the whole grid, an edge
along each of the 16 heading vectors between two positions open with the box resting
(:meth:`FloorField.open_with_box`). The field's own Dijkstra runs over the component of the
goals only, settles only the positions within ``limit``, and must agree exactly there; beyond
the limit it holds a lower bound (the limit) or ``inf`` where no walk exists.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import dijkstra

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.transit.lattice import HEADING_VECTORS
from tests.factories import shipped


def _reference(field, obj, goals) -> np.ndarray:
    ok = field.open_with_box(obj).ravel()
    nx, ny = field.grid.nx, field.grid.ny
    ix, iy = np.divmod(np.arange(nx * ny), ny)
    rows, cols, w = [], [], []
    for vx, vy in HEADING_VECTORS:
        tx, ty = ix + vx, iy + vy
        inside = (tx >= 0) & (tx < nx) & (ty >= 0) & (ty < ny)
        src = np.flatnonzero(inside)
        dst = tx[inside] * ny + ty[inside]
        both = ok[src] & ok[dst]
        rows.append(src[both])
        cols.append(dst[both])
        w.append(np.full(both.sum(), field.grid.resolution * math.hypot(vx, vy)))
    g = coo_matrix((np.concatenate(w), (np.concatenate(rows), np.concatenate(cols))),
                   shape=(nx * ny, nx * ny)).tocsr()
    d = dijkstra(g, directed=True, indices=[x * ny + y for x, y in goals], min_only=True)
    return np.asarray(d).reshape(nx, ny)


def _cell(field, x, y):
    b, res = field.grid.world.bounds, field.grid.resolution
    return round((x - b[0]) / res), round((y - b[1]) / res)


def _cases():
    out = []
    for name in ("t_junction", "fig10"):
        sc = shipped(name)
        out.append((name, sc, sc.start, sc.goal))
    sc = generate("building", 0, params=GeneratorParams(rooms=2)).scene  # turned, open outside
    out.append(("building", sc, sc.start, sc.goal))
    return out


@pytest.mark.parametrize("case", _cases(), ids=lambda c: c[0])
def test_distances_within_the_limit_are_the_whole_floor_ones(case):
    _name, scene, obj, far = case
    field = PivotChecker(scene).walker.field
    m = scene.model
    goals = [_cell(field, *m.robot_pose(obj, 1)[:2]), _cell(field, *m.robot_pose(obj, 2)[:2])]
    want = _reference(field, obj, goals)
    assert np.isfinite(want).sum() > 100 and np.isinf(want).sum() > 100
    got = field.distances(obj, goals)
    assert np.array_equal(np.isinf(got), np.isinf(want))
    assert np.allclose(got[np.isfinite(want)], want[np.isfinite(want)])
    for limit in (0.5, 2.0, 6.0, 1e4):
        got = field.distances(obj, goals, limit=limit)
        near = want <= limit
        assert near.sum() > 0
        assert np.allclose(got[near], want[near]), limit  # exact within the limit
        beyond = ~near
        assert np.all((got[beyond] == limit) | np.isinf(got[beyond])), limit
        assert np.all(np.isinf(want[np.isinf(got)])), limit  # inf: no walk for certain
    # the far end's distance is the same whatever the limit it is settled within
    fx, fy = _cell(field, *far[:2])
    if math.isfinite(want[fx, fy]):
        limit = want[fx, fy] + 0.01
        assert field.distances(obj, goals, limit=limit)[fx, fy] == pytest.approx(want[fx, fy])


def test_a_limit_past_the_whole_component_proves_the_rest_unreachable():
    scene = generate("building", 0, params=GeneratorParams(rooms=2)).scene
    field = PivotChecker(scene).walker.field
    obj = scene.start
    goals = [_cell(field, *scene.model.robot_pose(obj, 1)[:2])]
    want = _reference(field, obj, goals)
    got = field.distances(obj, goals, limit=float(np.nanmax(want[np.isfinite(want)])) + 1.0)
    assert np.array_equal(np.isinf(got), np.isinf(want))


def test_the_dijkstra_runs_over_the_goals_component_not_the_open_floor_outside():
    scene = generate("building", 0, params=GeneratorParams(rooms=2)).scene
    field = PivotChecker(scene).walker.field
    obj = scene.start
    goal = _cell(field, *scene.model.robot_pose(obj, 1)[:2])
    want = _reference(field, obj, [goal])
    field.distances(obj, [goal])
    goal_node = field.graph.node[[goal[0] * field.grid.ny + goal[1]]]
    cells, graph = field.graph.component_graph(goal_node)
    assert field.stats.searched_positions == len(cells)  # the query ran over that component
    reached = np.flatnonzero(np.isfinite(want).ravel())
    assert np.isin(reached, cells).all()  # the component holds every position reached
    assert len(cells) < field.static_open().sum()  # the open floor outside is left out
    assert graph.shape == (len(cells), len(cells))
