"""The held poses' relaxation: sound cores and sums, proofs where no plan exists, none with one."""

from __future__ import annotations

import math
import time

import numpy as np
import pytest
import shapely
from corner_factories import corner_slot
from factories import clear_lane_boxes, floor_with_clear_lane, shipped
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.analysis.late_proof import HELD_POSES, LateProof, held_pose_proof
from pivot_ompl.analysis.passage import assembly_width, blocking_passage
from pivot_ompl.analysis.pose_cells import convex_sums, rotation_core
from pivot_ompl.analysis.pose_proof import (
    FIRST_BINS,
    MOTION_CLEARANCE,
    HeldParts,
    PoseGraph,
    prove_no_plan,
)
from pivot_ompl.scene.shared import shared_value

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


def _convex(points: np.ndarray) -> np.ndarray:
    hull = shapely.orient_polygons(shapely.MultiPoint(points).convex_hull)
    return np.asarray(hull.exterior.coords)[:-1]


def _turn(points: np.ndarray, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    return points @ np.array([[c, s], [-s, c]])


points = st.lists(st.tuples(st.floats(-2.0, 2.0), st.floats(-2.0, 2.0)), min_size=3, max_size=8)


@settings(max_examples=60, deadline=None)
@given(body=points, half=st.floats(0.0, 0.4), shift=st.tuples(st.floats(-1, 1), st.floats(-1, 1)))
def test_the_core_lies_inside_the_body_turned_by_every_yaw_of_its_bin(body, half, shift):
    pts = np.array(body) + np.array(shift)
    if shapely.MultiPoint(pts).convex_hull.area < 1e-3:
        return
    k = _convex(pts)
    core = rotation_core(k, half)
    if core is None:
        return
    inner = shapely.Polygon(core)
    for t in np.linspace(-half, half, 33):
        assert shapely.Polygon(_turn(k, t)).buffer(1e-9).contains(inner)


@settings(max_examples=60, deadline=None)
@given(a=points, b=points)
def test_a_convex_sum_is_the_hull_of_the_vertex_sums(a, b):
    pa, pb = np.round(np.array(a), 1), np.round(np.array(b), 1)  # parallel edges are common
    if min(shapely.MultiPoint(p).convex_hull.area for p in (pa, pb)) < 1e-3:
        return
    ka, kb = _convex(pa), _convex(pb)
    got = shapely.Polygon(convex_sums(ka[None], kb)[0])
    want = shapely.MultiPoint((ka[:, None] + kb[None]).reshape(-1, 2)).convex_hull
    assert got.is_valid
    assert got.symmetric_difference(want).area < 1e-9



@settings(max_examples=40, deadline=None)
@given(boxes=st.lists(st.tuples(st.floats(-3, 3), st.floats(-3, 3), st.floats(0.05, 2.0),
                                st.floats(0.05, 2.0), st.sampled_from([0.0, 0.5 * math.pi,
                                                                       math.pi, 0.3])),
                      min_size=1, max_size=6), body=points, repeat=st.booleans())
def test_every_sum_of_a_stack_is_the_hull_of_its_vertex_sums(boxes, body, repeat):
    """Stacked pieces (rectangles at any yaw, edges parallel to the body's, a repeated
    vertex) each summed with one body: each sum is the hull of the vertex sums."""
    pb = np.round(np.array(body), 1)
    if shapely.MultiPoint(pb).convex_hull.area < 1e-3:
        return
    kb = _convex(pb)
    rect = np.array([(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)])
    stack = np.stack([_turn(rect * (w, h), -yaw) + (x, y) for x, y, w, h, yaw in boxes])
    if repeat:  # a vertex twice (an edge of length zero), as grown pieces may have
        stack = np.concatenate([stack[:, :1], stack], axis=1)
    got = convex_sums(stack, kb)
    assert got.shape == (len(stack), stack.shape[1] + len(kb), 2)
    for piece, sum_ in zip(stack, got, strict=True):
        polygon = shapely.Polygon(sum_)
        want = shapely.MultiPoint((piece[:, None] + kb[None]).reshape(-1, 2)).convex_hull
        assert polygon.is_valid
        assert polygon.symmetric_difference(want).area < 1e-9


def test_a_slot_wide_enough_but_not_to_turn_into_is_proven_with_the_passage_named():
    scene = corner_slot(0.90, 0.92)
    assert 0.92 > assembly_width(scene.model)  # as wide as the held assembly...
    assert blocking_passage(scene) is None  # ...so the width alone explains nothing
    proof = prove_no_plan(scene)
    assert proof.apart is True
    assert not proof.start_reach.covers(shapely.Point(scene.goal[:2]))
    no_plan = held_pose_proof(scene)
    assert no_plan is not None and no_plan.passage is not None
    assert "0.92 m" in no_plan.reason and "(4.00, 1.40)" in no_plan.reason
    assert no_plan.passage.width == pytest.approx(0.92)
    assert no_plan.fields()["passage"]["reason"] == no_plan.reason


@pytest.mark.parametrize("scene", [
    shipped("fig10"), shipped("slot"), shipped("corridor"), shipped("door"),
    corner_slot(3.0, 0.95),  # room to turn in front of the slot
], ids=["fig10", "slot", "corridor", "door", "room_to_turn"])
def test_a_scene_with_a_plan_is_never_proven_infeasible(scene):
    end = time.monotonic() + 20.0
    proof = prove_no_plan(scene, should_stop=lambda: time.monotonic() > end)
    assert proof.apart is not True


def test_a_stopped_proof_proves_nothing():
    proof = prove_no_plan(corner_slot(0.90, 0.92), should_stop=lambda: True)
    assert proof.apart is None


@settings(max_examples=8, deadline=None)
@given(boxes=clear_lane_boxes(12))
def test_a_floor_with_a_straight_clear_lane_is_never_proven_infeasible(boxes):
    # a plan exists: the box pivots straight along the lane
    assert prove_no_plan(floor_with_clear_lane(boxes)).apart is not True


def test_the_late_proof_tries_the_held_poses_only_once_their_time_has_come():
    scene = corner_slot(3.0, 0.95)  # a plan exists: every relaxation joins start and goal
    now = [1.0]
    late = LateProof(scene, begin=0.0, end=100.0, clock=lambda: now[0], held_begin=5.0)
    assert late() is False  # the poses' relaxation joins them; too early for the held poses
    assert shared_value(scene, HELD_POSES) is None
    now[0] = 6.0
    assert late() is False  # tried now, and nothing proven
    assert shared_value(scene, HELD_POSES) is False


@settings(max_examples=6, deadline=None)
@given(boxes=clear_lane_boxes(8), bins=st.sampled_from([FIRST_BINS, 12]))
def test_a_lazy_pose_graph_has_the_eager_ones_links_and_chain(boxes, bins):
    """Each node's links, asked one by one, are the eager graph's (each graph with its own
    parts, so no kept meeting answers the other's), and so is the cheapest chain."""
    scene = floor_with_clear_lane(boxes)
    edges = [2.0 * math.pi * i / bins for i in range(bins + 1)]
    eager_parts = HeldParts(scene, MOTION_CLEARANCE, None)
    lazy_parts = HeldParts(scene, MOTION_CLEARANCE, None)
    eager = PoseGraph(eager_parts, edges, None)
    lazy = PoseGraph(lazy_parts, edges, None, lazy=True)
    ends = [(g.nodes_at(edges, scene.start), g.nodes_at(edges, scene.goal)) for g in (eager, lazy)]
    assert ends[0] == ends[1] and ends[0][0] and ends[0][1]
    found = [g.walked(p, edges, *ends[0]) for g, p in ((eager, eager_parts), (lazy, lazy_parts))]
    assert found[0].price == pytest.approx(found[1].price)
    assert found[0].nodes == found[1].nodes and found[0].reached == found[1].reached
    assert lazy_parts.bins.computed <= eager_parts.bins.computed
    nodes = [(i, g, k) for i in range(bins) for g, parts in enumerate(eager.bin(i))
             for k in range(len(parts))]
    assert any(eager.links.get(u) for u in nodes)
    for u in nodes:
        assert sorted(lazy.links[u]) == sorted(eager.links.get(u, [])), u


def test_the_arenas_proof_halves_its_chains_coarse_regrasps_first(tmp_path):
    # regression: the TurtleBot3 arena's false chains all regrasp in coarse bins (the two
    # grasps valid at different yaws of one bin); halving their regrasps' bins first proves
    # it in 4 rounds, where halving the parts spanning more floor first took 8
    from factories import benchmark_script

    from pivot_ompl.scene import load_scene

    mod = benchmark_script("buildings")
    m = next(m for m in mod.CORPUS if m.name == "turtlebot3_world")
    scene = load_scene(mod.import_corpus_map(m, tmp_path)["scene"])
    proof = prove_no_plan(scene)
    assert proof.apart is True
    assert not proof.start_reach.covers(shapely.Point(scene.goal[:2]))
    assert proof.rounds <= 4
