"""The transfer check's distance queries: ends between rotations bounded, not measured.

Within one check of a run of rotations, a sweep whose start clearance exceeds the farthest a
point moves is free without a query, and its end keeps a lower bound of the clearance. The
answer must be the one every end measured gives: each rotation of a valid edge passes a
sweep certified from measured clearances.
"""

from __future__ import annotations

import math

import numpy as np
from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import rotate_about
from pivot_ompl.validity.certify import certify

WALLS = [{"type": "box", "center": [4.0, 2.0], "size": [0.3, 2.6], "height": 1.0},
         {"type": "box", "center": [2.6, 4.6], "size": [1.2, 0.4], "height": 1.0},
         {"type": "cylinder", "center": [6.0, 4.2], "radius": 0.35, "height": 1.0}]


def _sweep_free(ck: PivotChecker, base, rot, grasp: int, tol: float) -> bool:
    """Box and holding robot certified along the rotation from measured clearances."""
    m, w = ck.model, ck.world
    box_r, rob_r = ck.transfers.reach(grasp)
    for dist, reach in ((lambda c: w.box_distance(m.object_from_car(c, grasp)), box_r),
                        (lambda c: w.held_distance(m.robot_from_car(c, grasp), grasp), rob_r)):
        def at(s: float, dist=dist) -> float:  # noqa: ANN001
            return dist(rotate_about(base, rot.pivot, s * rot.angle))

        if not certify(at, reach * abs(rot.angle), tolerance=tol, exact=True).valid:
            return False
    return True


#: Posts 1.6 m apart: edges between random poses often pass one closely.
POSTS = [{"type": "cylinder", "center": [x, y], "radius": 0.12, "height": 1.0}
         for x in (1.6, 3.2, 4.8, 6.4) for y in (1.5, 3.0, 4.5)]


def test_every_rotation_of_a_valid_edge_passes_with_measured_clearances():
    ck = PivotChecker(make_scene(obstacles=POSTS))
    rng = np.random.default_rng(7)
    x0, y0, x1, y1 = ck.world.bounds
    tol = ck.transfers.tolerance
    valid = invalid = 0
    for _ in range(300):
        a = (float(rng.uniform(x0 + 1, x1 - 1)), float(rng.uniform(y0 + 1, y1 - 1)),
             float(rng.uniform(-math.pi, math.pi)))
        step = rng.uniform(-1.2, 1.2, 2)
        b = (a[0] + float(step[0]), a[1] + float(step[1]), a[2] + float(rng.uniform(-0.3, 0.3)))
        g = int(rng.integers(4))
        if not (ck.state_valid(a, g) and ck.state_valid(b, g)):
            continue
        res = ck.transfer(a, b, g)
        if not res.valid:
            invalid += 1
            continue
        valid += 1
        prev = res.sequence.start
        for rot in res.sequence.rotations:
            assert _sweep_free(ck, prev, rot, g, tol)
            prev = rot.car
    assert valid >= 5 and invalid >= 5  # both answers were given


def test_a_transfer_in_open_floor_measures_fewer_ends_than_it_rotates():
    # regression: every rotation's end was measured for the box and the robot (two queries
    # a rotation at least) though most sweeps in open floor are free by their start's
    # clearance alone; the Willow Garage office's plan: 111 000 -> 79 000 queries
    ck = PivotChecker(make_scene(obstacles=WALLS[2:]))
    a, b = (1.5, 1.5, 0.0), (5.0, 1.6, 0.0)
    before = ck.world.queries
    res = ck.transfer(a, b, 0)
    assert res.valid
    assert ck.world.queries - before < 2 * len(res.sequence.rotations)
