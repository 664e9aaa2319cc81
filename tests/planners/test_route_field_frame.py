"""The followed route's free field on a long floor turned in the world: laid in its walls' frame.

A floor turned by an angle fills a thin diagonal band of its axis-aligned bounds, whose area
grows with the square of its length; at the field's fixed number of cells those cells came
out wider than the box on a long turned floor, and no cell was blocked (the route ran straight
through the walls). The field now lies in the walls' frame: the same route however the floor
is turned.
"""

from __future__ import annotations

import math

import pytest
import shapely
from factories import rotated_scene_doc

from pivot_ompl.base.problem import make_problem
from pivot_ompl.planners.follow_route import free_route
from pivot_ompl.scene import scene_from_dict

LENGTH, WIDTH, T = 150.0, 4.0, 0.3
#: The cross wall at mid-length, leaving a gap of 1.2 m at the hall's far side.
CROSS = (0.5 * LENGTH - 0.15, T, 0.5 * LENGTH + 0.15, T + 2.2)


def _box(x0: float, y0: float, x1: float, y1: float) -> dict:
    return {"type": "box", "center": [0.5 * (x0 + x1), 0.5 * (y0 + y1)],
            "size": [x1 - x0, y1 - y0], "yaw": 0.0, "height": 2.0}


def _hall() -> dict:
    """A closed hall 150 x 4 m, a cross wall with a gap; start and goal on the near side."""
    x1, y1 = LENGTH + 2 * T, WIDTH + 2 * T
    walls = [_box(0.0, 0.0, x1, T), _box(0.0, y1 - T, x1, y1), _box(0.0, 0.0, T, y1),
             _box(x1 - T, 0.0, x1, y1), _box(*CROSS)]  # overlapping: the hall is closed
    return {"name": "long_hall", "bounds": [0.0, 0.0, x1, y1],
            "object": {"size": [0.8, 0.6, 1.3]}, "start": [3.0, 1.2, 0.0],
            "goal": [LENGTH - 3.0, 1.2, 0.0], "obstacles": walls}


def _route(doc: dict) -> list[tuple[float, float]]:
    scene = scene_from_dict(doc, source="<test>")
    route = free_route(make_problem(scene).checker, scene.start[:2], scene.goal[:2],
                       should_stop=lambda: False)
    assert route is not None and len(route) >= 2
    return route


def _length(route: list[tuple[float, float]]) -> float:
    return sum(math.dist(a, b) for a, b in zip(route, route[1:], strict=False))


@pytest.mark.parametrize("angle", [0.7, -2.3])
def test_a_long_turned_hall_s_route_passes_the_gap_as_the_square_one_does(angle):
    square = _route(_hall())
    about = (0.5 * LENGTH, 0.5 * WIDTH)
    turned = _route(rotated_scene_doc(_hall(), angle, about))
    c, s = math.cos(angle), math.sin(angle)
    wall = shapely.box(*CROSS).buffer(-0.05)
    back = [(about[0] + c * (x - about[0]) + s * (y - about[1]),
             about[1] - s * (x - about[0]) + c * (y - about[1])) for x, y in turned]
    for route in (square, back):
        assert not shapely.LineString(route).intersects(wall)  # through the gap
        assert max(y for _, y in route) > CROSS[3]
    assert _length(back) == pytest.approx(_length(square), abs=0.5)
