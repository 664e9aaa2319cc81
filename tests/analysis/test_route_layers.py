"""The route bound layered by transfer component: sound, and stronger where regrasps cannot be."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
import shapely
from hypothesis import example, given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.route_layers import layered_route

SCENES = Path(__file__).parents[1] / "data" / "scenes"


def _two_rooms(low: float, high: float, allow_low: bool):
    """Two 4 x 6 m rooms joined by two 0.6 m passages (at ``low`` and ``high`` m).

    Layer 0 (one piece): the left room and both passages; layer 1: the right room and both
    passages. One regrasp edge joins them in both passages; ``allowed`` admits it only in
    the high passage (and in the low one too with ``allow_low``).
    """
    passages = [shapely.box(4.0, y - 0.3, 5.0, y + 0.3) for y in (low, high)]
    left = shapely.union_all([shapely.box(0.0, 0.0, 4.0, 6.0), *passages])
    right = shapely.union_all([shapely.box(5.0, 0.0, 9.0, 6.0), *passages])

    def allowed(name, region) -> bool:
        return allow_low or region.intersects(passages[1])

    return [left, right], allowed


def _via(start, goal, y: float) -> float:
    """The shortest route from ``start`` to ``goal`` through the passage at ``y`` (m)."""
    best = math.inf
    for ya in (y - 0.3, y, y + 0.3):  # the passage's corners bound it closely enough
        for yb in (y - 0.3, y, y + 0.3):
            best = min(best, math.dist(start, (4.0, ya)) + 1.0 + math.dist((5.0, yb), goal))
    return best


@settings(max_examples=15, deadline=None)
@example(low=1.0, high=5.0, ys=1.0, yg=1.0)
@given(low=st.floats(0.6, 2.0), high=st.floats(4.0, 5.4), ys=st.floats(0.5, 2.0),
       yg=st.floats(0.5, 2.0))
def test_the_route_passes_where_a_regrasp_may_happen(low, high, ys, yg):
    # the start's layer holds the left room only, the goal's the right room: the route must
    # change layers in a passage where the regrasp is allowed (the high one), however much
    # shorter the low one is; and it is never above the route through the high passage
    pieces, allowed = _two_rooms(low, high, allow_low=False)
    start, goal = (1.0, ys, 0.0), (8.0, yg, 0.0)
    found = layered_route(pieces, [[], []], [(0, 1, "edge")], allowed, reached={0, 1},
                          starts=[0], goals=[1], start=start, goal=goal,
                          bounds=(0.0, 0.0, 9.0, 6.0))
    assert found is not None and found.complete and found.route is not None
    through_high = _via(start[:2], goal[:2], high)
    through_low = _via(start[:2], goal[:2], low)
    assert found.route <= through_high + 1e-9
    if through_high > through_low + 1.5:  # beyond the grid's slack and growth
        assert found.route > through_low + 0.5  # the plain bound: through the low one
    assert found.route >= 0.9 * through_high - 0.6  # the grid's slack and growth only


def test_where_every_regrasp_may_happen_the_shorter_passage_bounds_it():
    pieces, allowed = _two_rooms(1.0, 5.0, allow_low=True)
    start, goal = (1.0, 1.0, 0.0), (8.0, 1.0, 0.0)
    found = layered_route(pieces, [[], []], [(0, 1, "edge")], allowed, reached={0, 1},
                          starts=[0], goals=[1], start=start, goal=goal,
                          bounds=(0.0, 0.0, 9.0, 6.0))
    assert found is not None and found.route is not None
    assert found.route <= _via((1.0, 1.0), (8.0, 1.0), 1.0) + 1e-9
    assert found.route < _via((1.0, 1.0), (8.0, 1.0), 5.0) - 1.0


@pytest.mark.slow
def test_a_gap_the_walking_body_does_not_pass_sends_the_route_bound_round_by_the_other():
    # gen:walls:2's layout: the held box crosses either gap only to be regrasped there, with
    # the robot walking round through the other gap; its walking body (0.60 m deep side-on,
    # 10 mm kept each side) does not pass the 0.619 m gap, so no regrasp happens in the
    # 0.77 m one (the box would block the only way round). The bound was the straight line
    # through the 0.77 m gap (5.55 m); any plan goes through the 0.62 m one (about 8.4 m).
    from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
    from pivot_ompl.scene import load_scene

    scene = load_scene(SCENES / "walls_2_narrow_walk.yaml")
    bound = regrasp_lower_bound(scene)
    assert bound.regrasps == 1 and bound.shortest_route is not None
    line = math.dist(scene.start[:2], scene.goal[:2])
    assert line < 5.6
    assert 7.5 < bound.shortest_route < 8.45


@pytest.mark.slow
def test_the_walk_relaxation_refuses_the_gap_the_walking_body_passes_only_within_the_tolerance():
    # the 0.619 m gap: the walking body's centred disk (0.60 m) passes it with the clearance
    # less the tolerance (0.616 m) but not with the full clearance (0.620 m); a walk's poses
    # lie within the tolerance of samples that keep the full clearance, and the gap is far
    # longer than twice the tolerance: a regrasp with the box blocking the 0.77 m gap is
    # refused, one with the box in the 0.62 m gap is not
    from pivot_ompl.analysis.regrasp_bound import free_cover
    from pivot_ompl.analysis.regrasp_walk import WalkRelaxation
    from pivot_ompl.scene import load_scene
    from pivot_ompl.validity.certify import SWEEP_TOLERANCE
    from pivot_ompl.validity.collision import KEEP_CLEARANCE

    scene = load_scene(SCENES / "walls_2_narrow_walk.yaml")
    cover = free_cover(scene)
    assert cover is not None
    walk = WalkRelaxation(scene, width=cover.width, tolerance=SWEEP_TOLERANCE,
                          clearance=KEEP_CLEARANCE)
    b = cover.bins - 1  # the box square to the wall: grasp 0 holds it from one side, 2 the other
    both = shapely.union_all(cover.pieces(b, 0)).intersection(
        shapely.union_all(cover.pieces(b, 2)))
    yaw = -math.pi + (b + 0.5) * cover.width

    def near(x: float, y: float):
        return both.intersection(shapely.box(x - 0.25, y - 0.25, x + 0.25, y + 0.25))

    assert not near(4.62, 1.56).is_empty and not near(4.1, 5.0).is_empty
    assert not walk.may_regrasp(near(4.62, 1.56), yaw, 0, 2)  # the box in the 0.77 m gap
    assert walk.may_regrasp(near(4.1, 5.0), yaw, 0, 2)  # in the 0.62 m gap


@pytest.mark.slow
@pytest.mark.parametrize("name", ["slot", "door", "fig10", "walls"])
def test_no_plan_goes_a_shorter_way_than_the_layered_bound(name):
    from pivot_ompl import plan
    from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
    from pivot_ompl.quality import plan_quality
    from pivot_ompl.scene import load_scene

    scene = load_scene(SCENES / "walls_2_narrow_walk.yaml") if name == "walls" else name
    scene = load_scene(scene) if isinstance(scene, str) else scene
    bound = regrasp_lower_bound(scene)
    for seed in (0, 1):
        res = plan(scene, time_limit=30.0, seed=seed, bound=False)
        if not res.solved:
            continue
        route = plan_quality(res.plan)["route_length"]
        assert bound.shortest_route is not None and bound.shortest_route <= route + 1e-6
