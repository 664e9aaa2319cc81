"""Transit walks round the resting box: from one grasp pose to the other, every segment free."""

from __future__ import annotations

import math

import numpy as np
import pytest
from factories import make_scene, rotated_scene_doc, shipped, shipped_doc, walk_problems
from hypothesis import given, settings
from hypothesis import strategies as st

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.scene import WalkParameters, scene_from_dict
from pivot_ompl.se2 import wrap_angle
from pivot_ompl.transit.lattice import HEADING_YAWS, N_HEADINGS, motion_cost, primitives
from pivot_ompl.validity.plan_check import check_plan

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

POSE = (4.0, 3.0, 0.3)


@pytest.mark.parametrize(("g1", "g2"), [(0, 1), (0, 2), (1, 3), (3, 2), (2, 0)])
def test_walks_join_the_grasp_poses_and_pass_check(g1, g2):
    scene = make_scene(start=list(POSE), goal=list(POSE))
    ck = PivotChecker(scene, seed=0)
    walk = ck.transit(POSE, g1, g2)
    assert walk.valid
    m = scene.model
    assert walk.robot_path[0] == pytest.approx(m.robot_pose(POSE, g1))
    assert walk.robot_path[-1] == pytest.approx(m.robot_pose(POSE, g2))
    assert walk.length > 0
    assert walk_problems(scene, POSE, g1, g2, walk) == []


def test_no_walk_through_a_wall_round_the_box():
    # the box stands in a 1.5 m wide corridor closed at one end: beside the box there is
    # 0.45 m, less than the robot's 0.40 m depth plus the 0.08 m kept from the box, so not
    # even a side step gets it round
    walls = [{"type": "box", "center": [4.0, 2.0], "size": [8.0, 0.5], "yaw": 0.0,
              "height": 2.0},
             {"type": "box", "center": [4.0, 4.0], "size": [8.0, 0.5], "yaw": 0.0,
              "height": 2.0},
             {"type": "box", "center": [2.6, 3.0], "size": [0.2, 3.0], "yaw": 0.0,
              "height": 2.0}]
    scene = make_scene(obstacles=walls, start=[4.0, 3.0, 0.0], goal=[6.0, 3.0, 0.0])
    ck = PivotChecker(scene, seed=0)
    assert ck.state_valid((4.0, 3.0, 0.0), 2)
    assert not ck.transit((4.0, 3.0, 0.0), 2, 0).valid


def test_walk_search_honours_the_termination_condition():
    """A large floor's field takes a second: the walk stops at the limit and resumes later."""
    import time

    from pivot_ompl.errors import Interrupted

    # 601 x 601 grid positions (the field's build polls once per yaw and per graph direction)
    scene = make_scene(bounds=[0.0, 0.0, 60.0, 60.0], start=[30.0, 30.0, 0.0],
                       goal=[40.0, 30.0, 0.0],
                       obstacles=[{"type": "cylinder", "center": [55.0, 55.0], "radius": 0.3,
                                   "height": 1.0}])
    ck = PivotChecker(scene, seed=0)
    field = ck.walker.field

    def progress() -> int:  # large floor: the walk's distances are built over tiles round it
        return field.yaws_done + field.rows_done + field.tiles.tiles_built

    done = [progress()]
    deadline = time.monotonic() + 0.01
    t0 = time.monotonic()
    with pytest.raises(Interrupted):  # stopped: neither valid nor invalid
        ck.transit(scene.start, 0, 2, should_stop=lambda d=deadline: time.monotonic() > d)
    assert time.monotonic() - t0 < 1.0
    done.append(progress())
    assert done[0] < done[1]  # the work done before the stop is kept
    before = ck.counters.valid + ck.counters.invalid
    with pytest.raises(Interrupted):
        ck.transit(scene.start, 0, 2, should_stop=lambda: True)
    assert ck.counters.valid + ck.counters.invalid == before  # interrupted: not cached
    assert ck.transit(scene.start, 0, 2).valid  # resumed without a limit, it ends


def test_an_interrupted_floor_field_resumes_where_it_stopped():
    from pivot_ompl.errors import Interrupted
    from pivot_ompl.transit.field import OPEN_YAWS, YAW_CHUNK

    scene = shipped("fig10")
    field = PivotChecker(scene, seed=0).walker.field
    with pytest.raises(Interrupted):
        field.static_open(lambda: field.yaws_done >= 3 * YAW_CHUNK)
    assert field.yaws_done == 3 * YAW_CHUNK < len(OPEN_YAWS)
    assert field.grid.stats.yaws_summed == 3 * YAW_CHUNK
    built = field.static_open(lambda: False)
    assert field.yaws_done == len(OPEN_YAWS)
    assert field.grid.stats.yaws_summed == len(OPEN_YAWS)  # none summed again
    fresh = PivotChecker(scene, seed=0).walker.field.static_open()
    assert np.array_equal(built, fresh)


def test_the_floor_field_sums_footprints_a_block_of_yaws_between_polls(monkeypatch):
    # regression: the footprints of all 32 yaws were summed in one call before the first
    # block was rasterised, past the next poll: fig10 at a 0.5 s limit ended 30 ms late
    from pivot_ompl.errors import Interrupted
    from pivot_ompl.transit import floor_grid
    from pivot_ompl.transit.field import YAW_CHUNK

    field = PivotChecker(shipped("fig10"), seed=0).walker.field
    summed = []
    orig = floor_grid.meeting_edges

    def counted(pieces, bodies, **kw):  # noqa: ANN001, ANN003, ANN202
        summed.append(len(pieces))
        return orig(pieces, bodies, **kw)

    monkeypatch.setattr(floor_grid, "meeting_edges", counted)
    polls = iter(range(100))
    with pytest.raises(Interrupted):
        field.static_open(lambda: next(polls) >= 1 and field.yaws_done > 0)
    assert summed == [YAW_CHUNK * len(field.grid.pieces)]

# -- free walking: doors and corridors narrower than the turning disk ----------------------
# (box resting in the wall's slot, the robot walks round from one side to the other)
SLOT_POSES = {"door": (4.85, 2.0, 0.0), "t_junction": (4.85, 2.5, 0.0)}


def _rot(p, angle):
    c, s = math.cos(angle), math.sin(angle)
    return (c * p[0] - s * p[1], s * p[0] + c * p[1], p[2] + angle)


def _walk_round(scene, obj):
    ck = PivotChecker(scene, seed=0)
    grasps = [g for g in range(4) if ck.state_valid(obj, g)]
    # the two grasps on either side of the wall
    g1, g2 = min(grasps, key=lambda g: scene.model.robot_pose(obj, g)[0]), \
        max(grasps, key=lambda g: scene.model.robot_pose(obj, g)[0])
    return ck, g1, g2, ck.transit(obj, g1, g2)


@pytest.mark.parametrize("name", ["door", "t_junction"])
def test_no_turn_in_place_in_the_narrow_passage(name):
    scene = shipped(name)
    ck = PivotChecker(scene, seed=0)
    # door centre / corridor: the turning disk collides there, the robot walking does not
    x, y = (4.85, 5.5) if name == "door" else (6.0, 6.45)
    assert ck.world.turning_disk_distance(x, y) < 0.0
    assert 2.0 * scene.model.robot_radius() > 0.9


@pytest.mark.parametrize("name", ["door", "t_junction"])
def test_walks_round_through_the_narrow_passage(name):
    scene = shipped(name)
    obj = SLOT_POSES[name]
    ck, g1, g2, walk = _walk_round(scene, obj)
    assert walk.valid
    m = scene.model
    assert walk.robot_path[0] == pytest.approx(m.robot_pose(obj, g1), abs=1e-12)
    assert walk.robot_path[-1] == pytest.approx(m.robot_pose(obj, g2), abs=1e-12)
    assert walk_problems(scene, obj, g1, g2, walk) == []
    # it goes through the door / the corridor (the slot is too narrow for the robot)
    if name == "door":
        assert any(4.6 < p[0] < 5.1 and 5.0 < p[1] < 6.0 for p in walk.robot_path) or \
            any(a[0] < 4.7 < b[0] and a[1] > 4.9 for a, b in
                zip(walk.robot_path, walk.robot_path[1:], strict=False))
    else:
        assert max(p[1] for p in walk.robot_path) > 6.0
    assert walk.cost >= walk.length
    # smoothed all along (regression: a shortcut budget spent on the first poses left the
    # lattice's staircase at the end of the walk, 32 and 43 key poses with the footprint
    # alone; with the walking body widened by the trunk's sway the 0.9 m corridor leaves less
    # room for shortcuts: 38 measured, 41 with the whole walking envelope; the door's walk
    # stays short: 28 with the envelope)
    assert len(walk.robot_path) <= (30 if name == "door" else 45)


@pytest.mark.parametrize(("name", "angle"), [("door", 0.5), ("t_junction", -1.1),
                                              ("door", 2.3)])
def test_rotated_copies_walk_too(name, angle):
    doc = rotated_scene_doc(shipped_doc(name), angle)
    scene = scene_from_dict(doc, source="<rotated>")
    obj = _rot(SLOT_POSES[name], angle)
    ck = PivotChecker(scene, seed=0)
    grasps = [g for g in range(4) if ck.state_valid(obj, g)]
    left = [g for g in grasps if _rot(scene.model.robot_pose(obj, g), -angle)[0] < 4.85]
    right = [g for g in grasps if _rot(scene.model.robot_pose(obj, g), -angle)[0] > 4.85]
    walk = ck.transit(obj, left[0], right[0])
    assert walk.valid
    assert walk_problems(scene, obj, left[0], right[0], walk) == []


@settings(max_examples=200, deadline=None)
@given(st.floats(-5, 5), st.floats(-5, 5), st.floats(-7, 7), st.floats(-5, 5),
       st.floats(-5, 5), st.floats(-7, 7))
def test_motion_cost_bounds_the_heuristic(x0, y0, t0, x1, y1, t1):
    # every motion costs at least hypot(length, turn_cost * turn): the A* heuristic is
    # admissible; and forward walking costs exactly its length
    w = WalkParameters()
    a, b = (x0, y0, t0), (x1, y1, t1)
    c = motion_cost(a, b, w)
    low = math.hypot(math.hypot(x1 - x0, y1 - y0), w.turn_cost * abs(wrap_angle(t1 - t0)))
    assert c >= low - 1e-9
    d = math.hypot(x1 - x0, y1 - y0)
    assert motion_cost((x0, y0, t0), (x0 + d * math.cos(t0), y0 + d * math.sin(t0), t0),
                       w) == pytest.approx(d, abs=1e-9)


def test_floor_distance_is_a_lower_bound_of_the_walk():
    scene = shipped("t_junction")
    obj = SLOT_POSES["t_junction"]
    ck, g1, g2, walk = _walk_round(scene, obj)
    wp = ck.walker
    b, res = scene.bounds, wp.resolution
    goal = walk.robot_path[-1]
    cell = (round((goal[0] - b[0]) / res), round((goal[1] - b[1]) / res))
    dist = wp.field.distances(obj, [cell])
    s = walk.robot_path[0]
    d0 = dist[round((s[0] - b[0]) / res), round((s[1] - b[1]) / res)]
    assert math.isfinite(d0)
    assert d0 <= walk.length + 2 * res  # ends attach within 1.5 resolution
    assert d0 > 5.0  # round the wall, not through the slot (2 m straight)


def test_primitives_cover_every_kind_on_the_grid():
    prims = primitives(0.1, WalkParameters())
    assert len(prims) == N_HEADINGS
    for h, ps in enumerate(prims):
        kinds = sorted({p.kind for p in ps})
        assert kinds == ["back", "forward", "left", "right", "turn"]
        fwd = [p for p in ps if p.kind == "forward" and p.dh == 0][0]
        side = [p for p in ps if p.kind == "left"][0]
        back = [p for p in ps if p.kind == "back"][0]
        # exactly along / square to / against the heading
        yaw = HEADING_YAWS[h]
        assert math.atan2(fwd.diy, fwd.dix) == pytest.approx(yaw)
        assert wrap_angle(math.atan2(side.diy, side.dix) - yaw) == pytest.approx(math.pi / 2)
        assert abs(wrap_angle(math.atan2(back.diy, back.dix) - yaw)) == pytest.approx(math.pi)
        assert side.cost > fwd.cost * 1.5 and back.cost > fwd.cost * 1.5


@pytest.mark.parametrize("name", ["door", "t_junction"])
def test_regrasp_plan_through_the_narrow_passage_passes_check(name):
    from pivot_ompl.api import plan

    scene = shipped(name)
    res = plan(scene, planner="regrasp", time_limit=60.0, seed=1)
    assert res.solved and res.regrasps >= 1
    rep = check_plan(res.plan, scene)
    assert rep.ok, rep.problems


def test_walk_query_stops_at_once_when_the_condition_holds():
    """A walk asked after the deadline raises at once (no floor field, no search, no
    smoothing: the field's Dijkstra alone runs tens of ms in C)."""
    from pivot_ompl.checking.pivot_checker import PivotChecker
    from pivot_ompl.errors import Interrupted

    scene = shipped("fig10")
    checker = PivotChecker(scene)
    walker = checker.walker
    walker.field.static_open()  # built before: its own build polls the condition
    with pytest.raises(Interrupted):
        walker.plan(scene.start, 0, 2, should_stop=lambda: True)
    assert walker.expansions == 0 and walker.cached_fields() == (0, 0)
    with pytest.raises(Interrupted):  # smoothing polls too
        walker.smoother.smooth([(2.0, 2.0, 0.0), (2.1, 2.0, 0.0), (2.2, 2.0, 0.0),
                                (2.3, 2.0, 0.0)], scene.start, should_stop=lambda: True)


@pytest.mark.parametrize("name", ["fig10", "cluttered_room"])
def test_every_free_lattice_state_lies_on_an_open_floor_position(name):
    # the floor field tests the walking body at 32 yaws: a relaxation only if it never closes a
    # position where a lattice state (or a step's midpoint, at a half-way yaw) is free
    from pivot_ompl.transit.field import OPEN_YAWS

    scene = shipped(name)
    wp = PivotChecker(scene, seed=0).walker
    open_ = wp.field.static_open()
    rng = np.random.default_rng(7)
    w, m = wp.world, scene.model
    tested = 0
    for _ in range(4000):
        ix, iy = int(rng.integers(wp.field.grid.nx)), int(rng.integers(wp.field.grid.ny))
        x, y = wp.clearance.pose((ix, iy, 0))[:2]
        yaw = OPEN_YAWS[int(rng.integers(len(OPEN_YAWS)))]
        if w.bounds_margin(m.robot_corners((x, y, yaw))) > 0 and \
                w.robot_distance((x, y, yaw)) > 0:
            tested += 1
            assert open_[ix, iy], (x, y, yaw)
    assert tested > 1000


def test_a_walk_whose_only_way_is_a_slot_fails_at_once():
    # regression: the box resting in wall B's robot door of fig10; the only other way from the
    # door's pocket is wall B's slot (0.62 m), which the walking body (0.60 m deep, 1 cm kept
    # on both sides) cannot pass at any lattice heading. The field's inscribed disk passed it,
    # so the lattice search expanded every state it could reach (19.5k, ~1.6 s) to fail.
    scene = shipped("fig10_narrow")
    wp = PivotChecker(scene, seed=0).walker
    box = (7.9, 0.925, 0.0)
    wp.expansions = 0
    walk = wp.plan_between((8.75, 0.925, math.pi), (7.05, 0.925, 0.0), box)
    assert not walk.valid
    assert wp.expansions == 0


def _lattice_fixture(scene, obj, start, goal, monkeypatch):
    """The walker, its cheapest lattice walk (no smoothing, no inflation) and its field."""
    wp = PivotChecker(scene, seed=0).walker
    wp.inflation = 1.0
    monkeypatch.setattr(type(wp.smoother), "smooth",
                        lambda self, poses, obj, memo=None, should_stop=None: poses)
    walk = wp.plan_between(start, goal, obj)
    f = wp.frame  # the lattice's methods take poses in its frame
    starts = wp.attach(f.into(start), f.into(obj), leaving=True)
    goals = wp.attach(f.into(goal), f.into(obj), leaving=False)
    return wp, walk, starts, wp.lattice_costs(f.into(obj), goals)


@pytest.mark.parametrize(("name", "angle"), [("fig10", 0.0), ("fig10", 0.65), ("door", -1.1)])
def test_lattice_costs_bound_the_cheapest_lattice_walk(name, angle, monkeypatch):
    # the heuristic is admissible: from the start's lattice states, the relaxed cost-to-go
    # never exceeds what the cheapest lattice walk (A* unweighted, unsmoothed) costs
    doc = shipped_doc(name)
    scene = scene_from_dict(rotated_scene_doc(doc, angle) if angle else doc)
    rng = np.random.default_rng(3)
    ck = PivotChecker(scene, seed=0)
    x0, y0, x1, y1 = scene.bounds
    tested = 0
    while tested < 4:
        obj = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
               float(rng.uniform(-math.pi, math.pi)))
        grasps = [g for g in range(4) if ck.state_valid(obj, g)]
        if len(grasps) < 2:
            continue
        m = scene.model
        start, goal = m.robot_pose(obj, grasps[0]), m.robot_pose(obj, grasps[-1])
        wp, walk, starts, costs = _lattice_fixture(scene, obj, start, goal, monkeypatch)
        if not walk.valid:
            continue
        tested += 1
        bound = min(c + costs[s] for s, c in starts.items())
        assert bound <= walk.cost + 1e-9
        assert bound >= 0.5 * walk.cost  # and close: it knows the obstacles and headings


@pytest.mark.parametrize("name", ["fig10", "door"])
def test_every_free_lattice_state_is_free_in_the_lattice_relaxation(name):
    # a lattice state the search may stand on (clearance > 0 to obstacles, bounds and the
    # resting box) is never closed by the relaxation, the box's part included
    from pivot_ompl.transit.field import OPEN_YAWS

    scene = shipped(name)
    wp = PivotChecker(scene, seed=0).walker
    f = wp.field.grid
    rng = np.random.default_rng(11)
    tested = near_box = 0
    for _ in range(6):
        x0, y0, x1, y1 = scene.bounds
        obj = (float(rng.uniform(x0, x1)), float(rng.uniform(y0, y1)),
               float(rng.uniform(-math.pi, math.pi)))
        meets = f.meets_box(obj)
        boxed = wp.clearance.with_box(obj)
        for _ in range(600):  # states within 1.2 m of the box: its part matters
            x = obj[0] + rng.uniform(-1.2, 1.2)
            y = obj[1] + rng.uniform(-1.2, 1.2)
            s = (round((x - x0) / wp.resolution), round((y - y0) / wp.resolution),
                 int(rng.integers(N_HEADINGS)))
            if not (0 <= s[0] < f.nx and 0 <= s[1] < f.ny):
                continue
            if boxed.state(s) > 0.0:
                tested += 1
                near_box += boxed.box_state(s) < 0.1
                fits = f.fits_index(OPEN_YAWS.index(HEADING_YAWS[s[2]]))
                assert fits[s[0], s[1]], s
                assert not meets[s[2]][s[0], s[1]], (s, obj)
    assert tested > 500 and near_box > 20


#: fig10 seed 5's second walk: the robot turning between the resting box and the wall
#: (box pose, start and goal robot poses)
TIGHT_TURN = ((4.881849527519183, 3.8451219714433633, -1.4253664043695728),
              (5.005029680573598, 3.004094831635443, 1.7162262492202203),
              (5.524987928548769, 3.9393185590732096, 3.287022576015117))


def _tight_turn(**settings):
    """fig10 with the box at the tight turn's pose, its walk planner, and the walk planned.

    The scene starts and ends at the box's pose, so that ``check_plan`` takes a plan from
    there; ``settings`` are set on the walk planner first.
    """
    obj, start, goal = TIGHT_TURN
    doc = shipped_doc("fig10_narrow")
    doc["start"] = doc["goal"] = list(obj)
    scene = scene_from_dict(doc)
    wp = PivotChecker(scene, seed=0).walker
    for name, value in settings.items():
        setattr(wp, name, value)
    return scene, wp, wp.plan_between(start, goal, obj)


def _assert_checked(scene, walk) -> None:
    """The tight turn's walk ends exactly at its poses and passes the independent check."""
    obj, start, goal = TIGHT_TURN
    assert walk.robot_path[0] == start and walk.robot_path[-1] == goal
    m = scene.model
    g1 = next(g for g in range(4) if np.allclose(m.robot_pose(obj, g), start))
    g2 = next(g for g in range(4) if np.allclose(m.robot_pose(obj, g), goal))
    assert walk_problems(scene, obj, g1, g2, walk) == []


def test_a_tight_turn_beside_the_box_is_found_with_few_expansions():
    # regression: guided by the floor distance alone (no headings) the search expanded 5485
    # states (~0.5 s) for a walk costing 13.2 m. Now the floor-guided search stops at
    # quick_expansions and the lattice-guided one finishes in a few hundred
    scene, wp, walk = _tight_turn()
    assert walk.valid and wp.expansions < wp.quick_expansions + 500
    assert walk.cost < 13.2
    _assert_checked(scene, walk)


def test_a_walk_by_turned_walls_is_found_in_their_frame():
    # regression: fig10 mirrored at 20 deg (seed 3's ninth walk): the box resting by a wall.
    # On a lattice along the world's axes no walk existed (the search then failed after the
    # quick search). The lattice now lies in the walls' frame (turned 40 deg): the walk is
    # found at once, ends exactly at the grasp poses and passes the independent check
    from pivot_ompl.generate import mirror_scene

    scene = mirror_scene(shipped("fig10_narrow"), math.radians(20.0))
    wp = PivotChecker(scene, seed=0).walker
    assert wp.frame.yaw == pytest.approx(math.radians(40.0))
    obj = (7.045387948164916, 3.018113151730951, 0.07624539214062409)
    m = scene.model
    g1, g2 = 0, 1
    start, goal = m.robot_pose(obj, g1), m.robot_pose(obj, g2)
    walk = wp.plan_between(start, goal, obj)
    assert walk.valid and wp.expansions <= wp.quick_expansions
    assert walk.robot_path[0] == start and walk.robot_path[-1] == goal
    assert walk_problems(scene, obj, g1, g2, walk) == []


def test_floors_too_large_for_the_lattice_costs_walk_with_the_floor_distance():
    # beyond max_field_states the heuristic is the floor distance (no headings): the same
    # tight turn is still found, exact at both ends and passing the independent check
    scene, wp, walk = _tight_turn(max_field_states=0)
    assert walk.valid and wp.cached_fields()[1] == 0 and wp.cached_fields()[0] > 0
    _assert_checked(scene, walk)


def test_the_walk_search_certifies_only_the_motions_it_takes(monkeypatch):
    # regression: every motion out of an expanded state to a free state was certified (the
    # slot walk of fig10, round wall A through its door: 1426 motions for 297 expansions).
    # The search now certifies a motion when it takes it from the queue
    from pivot_ompl.transit.clearance import BoxedClearance

    obj = (4.15, 1.5, 0.0)  # the box in wall A's slot
    doc = shipped_doc("fig10_narrow")
    doc["start"] = doc["goal"] = list(obj)
    ck = PivotChecker(scene_from_dict(doc), seed=0)
    wp, calls = ck.walker, []
    motion_free = BoxedClearance.motion_free

    def counted(self, u, v):  # noqa: ANN001, ANN202
        calls.append((u, v))
        return motion_free(self, u, v)

    monkeypatch.setattr(BoxedClearance, "motion_free", counted)
    walk = ck.transit(obj, 0, 2)
    assert walk.valid and walk.length > 9.0  # round through the door
    assert 100 < wp.expansions and len(calls) < 2 * wp.expansions
    assert walk_problems(ck.scene, obj, 0, 2, walk) == []


def test_the_walks_floor_distances_grow_their_limit_until_the_start_is_exact():
    # round the wall, the walk is far longer than the first limit (the straight distance
    # plus half a circle round the box, inflated): the limit grows until the start is settled
    scene = shipped("t_junction")
    obj = SLOT_POSES["t_junction"]
    ck, g1, g2, walk = _walk_round(scene, obj)
    wp = ck.walker
    m = scene.model
    starts = wp.attach(m.robot_pose(obj, g1), obj, leaving=True)
    goals = wp.attach(m.robot_pose(obj, g2), obj, leaving=False)
    whole = wp.field.distances(obj, sorted({(s[0], s[1]) for s in goals}))
    near = min(float(whole[s[0], s[1]]) for s in starts)
    assert wp.first_limit(starts, goals) < near < math.inf
    dist = wp.floor_distances(obj, goals, starts=starts)
    assert min(float(dist[s[0], s[1]]) for s in starts) == pytest.approx(near)
    assert np.all(dist <= whole + 1e-9)  # a lower bound everywhere
    limit = wp.cached_limit(obj, goals)
    assert limit is not None
    assert wp.floor_inflation * near <= limit < math.inf  # not the whole floor
