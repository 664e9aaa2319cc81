"""The followed route's names: importable from ``follow_route`` as before its field moved out."""

from __future__ import annotations

import pytest

from pivot_ompl.planners import follow_route, route_field, route_waypoints


@pytest.mark.parametrize("name", ["MARGINS", "FollowStats", "follow_route", "free_route"])
def test_every_listed_name_imports_from_follow_route(name):
    assert name in follow_route.__all__
    assert callable(getattr(follow_route, name)) or name == "MARGINS"


def test_free_route_is_the_route_fields_own():
    assert follow_route.free_route is route_field.free_route


def test_the_waypoints_keep_each_sequence_in_order_along_the_route():
    guide = [(0.0, 0.0), (10.0, 0.0)]
    old = [(0.0, 0.0, 0.0), (6.0, 0.5, 0.0), (10.0, 0.0, 0.0)]
    variant = ((0.0, 0.0, 0.0), (2.0, -0.5, 0.0), (8.0, -0.5, 0.0), (10.0, 0.0, 0.0))
    poses, path, links = route_waypoints.merged(guide, old, [variant], 3)
    assert [p[0] for p in poses] == [0.0, 2.0, 6.0, 8.0, 10.0]
    assert path == [(0, 3), (2, 3), (4, 3)]
    assert links == ((0, 1), (1, 3), (3, 4))
