"""Distance queries among the pieces near the query: the whole floor's distances."""

from __future__ import annotations

import coal
import numpy as np
import pytest

from pivot_ompl.scene import BoxObstacle
from pivot_ompl.validity.collision import obstacle_objects, place
from pivot_ompl.validity.near_pieces import NearPieces


def _floor(seed: int, n: int) -> list[coal.CollisionObject]:
    """``n`` small boxes scattered over a 30 m floor (some overlapping)."""
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        box = BoxObstacle(center=(float(rng.uniform(0, 30)), float(rng.uniform(0, 30))),
                          size=(float(rng.uniform(0.05, 1.5)), float(rng.uniform(0.05, 0.4))),
                          yaw=float(rng.uniform(-3, 3)), height=1.0)
        out.extend(obstacle_objects(box))
    return out


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_near_pieces_give_the_whole_trees_distances(seed):
    objects = _floor(seed, 700)
    whole = coal.DynamicAABBTreeCollisionManager()
    for o in objects:
        whole.registerObject(o)
    whole.setup()
    near = NearPieces(objects, cell=2.0, margin=1.0)
    body = coal.CollisionObject(coal.Box(0.9, 0.6, 1.5))
    cb = coal.DistanceCallBackDefault()
    rng = np.random.default_rng(100 + seed)
    clear = 0
    for _ in range(400):
        # from well inside the floor to beyond its side (cells without pieces)
        x, y = float(rng.uniform(-5, 35)), float(rng.uniform(-5, 35))
        place(body, x, y, float(rng.uniform(-3, 3)), 0.75)
        body.computeAABB()
        cb.data.result.clear()
        whole.distance(body, cb)
        expected = cb.data.result.min_distance
        got = near.distance(body, whole, x, y, 0.55)  # the box's half diagonal
        if expected > 0.0:
            clear += 1
            assert got == pytest.approx(expected, abs=1e-8)  # the same pair, GJK's round-off
        else:
            assert got <= 0.0
    assert clear > 50 and near.local > 0 and near.fallback > 0
