"""The transfer check's bounds test: its quick accept agrees with the corners measured."""

from __future__ import annotations

import numpy as np
from factories import make_scene

from pivot_ompl.checking.pivot_checker import PivotChecker


def _by_corners(ck: PivotChecker, car, grasp: int, with_robot: bool, bulge_b: float,
                bulge_r: float) -> bool:
    m, w = ck.model, ck.world
    if w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))) < bulge_b:
        return False
    return not with_robot or \
        w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)) >= bulge_r


def test_the_bounds_test_is_the_corners_test_everywhere_on_the_floor():
    ck = PivotChecker(make_scene())
    x0, y0, x1, y1 = ck.world.bounds
    rng = np.random.default_rng(3)
    tc = ck.transfers
    agree = inside = 0
    for _ in range(4000):
        car = (float(rng.uniform(x0 - 0.5, x1 + 0.5)), float(rng.uniform(y0 - 0.5, y1 + 0.5)),
               float(rng.uniform(-np.pi, np.pi)))
        g = int(rng.integers(4))
        with_robot = bool(rng.integers(2))
        bulge_b, bulge_r = (float(v) for v in rng.uniform(0.0, 0.3, 2))
        want = _by_corners(ck, car, g, with_robot, bulge_b, bulge_r)
        agree += tc.in_bounds(car, g, with_robot, bulge_b, bulge_r) == want
        inside += want
    assert agree == 4000
    assert 1000 < inside < 3900  # both answers were asked, near the sides too
