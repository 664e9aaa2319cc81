"""Setup counts against the time limit and polls it (issue 28, class 3).

Reading a scene file, building the obstacles and triangulating a polygon all poll their stop
condition: a large scene stops within its time limit as ``TIMEOUT`` (the CLI's exit 1,
leaving an existing output as it was), with the time spent counted as ``setup``.
"""

from __future__ import annotations

import gc
import inspect
import math
import time

import numpy as np
import pytest
import yaml
from factories import DeadlineWatch, make_scene

from pivot_ompl.api import plan
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cli.main import build_parser, main
from pivot_ompl.errors import Interrupted, PivotError, SceneError
from pivot_ompl.fileio import POLL_NODES, load_yaml
from pivot_ompl.scene import load_scene, scene_from_dict
from pivot_ompl.se2 import triangulate
from pivot_ompl.validity.collision import CollisionWorld

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

#: Cylinders of the generated large scene: its setup takes seconds without a limit.
MANY = 10_000


def _star(n: int, cx: float, cy: float) -> list[list[float]]:
    a = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    r = np.where(np.arange(n) % 2 == 0, 3.0, 2.0)
    return [[float(cx + q * math.cos(t)), float(cy + q * math.sin(t))]
            for t, q in zip(a, r, strict=True)]


def _big_doc() -> dict:
    rng = np.random.default_rng(0)
    obstacles: list[dict] = []
    while len(obstacles) < MANY:
        x, y = (float(v) for v in rng.uniform(0.5, 99.5, 2))
        if math.hypot(x - 5, y - 5) < 4 or math.hypot(x - 95, y - 95) < 4:
            continue
        obstacles.append({"type": "cylinder", "center": [round(x, 3), round(y, 3)],
                          "radius": 0.1, "height": 1.0})
    obstacles.append({"type": "polygon", "points": _star(10_000, 50.0, 50.0), "height": 1.0})
    return {"name": "big", "bounds": [0, 0, 100, 100], "object": {"size": [0.8, 0.4, 1.0]},
            "start": [5, 5, 0], "goal": [95, 95, 0], "obstacles": obstacles}


@pytest.fixture(scope="module")
def big_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("big") / "big.yaml"
    path.write_text(yaml.safe_dump(_big_doc()))
    return path


def test_a_limit_that_has_run_out_stops_plan_at_once(big_file):
    """10 000 cylinders and a 10 000-point polygon: without polling, reading and building
    them took seconds before the limit was looked at."""
    t0 = time.perf_counter()
    res = plan(big_file, time_limit=1e-3, bound=False)
    wall = time.perf_counter() - t0
    assert res.status == "TIMEOUT" and not res.solved and res.plan.phases == []
    assert res.plan.extra["stopped"] == "reading the scene"
    assert wall < 0.25, wall
    assert res.timings["solve"] == 0.0 and 0.0 < res.timings["setup"] <= wall


@pytest.mark.parametrize("limit", [0.3, 0.6])
def test_plan_stops_within_its_limit_while_setting_up(big_file, limit):
    """Stopped in reading, building the world or slot finding: within the limit (+20 % of
    work after it here; benchmarks/time_limit.py --largest measures +-5 %), and the time
    spent counted as setup."""
    with DeadlineWatch(limit) as watch:
        res = plan(big_file, time_limit=limit, bound=False)
    assert res.status == "TIMEOUT"
    # the work after the deadline in this process's CPU seconds (not stretched by other work
    # on the machine, as the wall clock is)
    assert watch.cpu_past_deadline < 0.2 * limit + 0.05, watch.cpu_past_deadline
    assert watch.wall < 3 * limit + 0.05, watch.wall
    assert res.timings["setup"] + res.timings["solve"] <= watch.wall + 1e-6
    if "stopped" in res.plan.extra:
        assert res.timings["setup"] > 0.9 * limit


def test_the_world_of_a_large_scene_stops_when_told(big_file):
    """A scene given as a Scene object: the collision world's build polls."""
    scene = load_scene(big_file)
    t0 = time.perf_counter()
    res = plan(scene, time_limit=0.05, bound=False)
    # about 0.06 s alone; 0.36 s once on a 2-core machine under a load of four; unpolled, the
    # build takes seconds
    assert time.perf_counter() - t0 < 0.6
    assert res.status == "TIMEOUT"
    assert res.plan.extra["stopped"] in {"building the collision world",
                                         "triangulating a polygon"}
    assert res.scene is scene


def test_cli_timeout_in_setup_keeps_an_existing_output(big_file, tmp_path, capsys):
    out = tmp_path / "plan.json"
    out.write_text("kept\n")
    build_parser()  # the verbs' imports, before the clock starts
    t0 = time.perf_counter()
    code = main(["plan", str(big_file), "--time", "0.2", "--no-bound", "--out", str(out)])
    assert time.perf_counter() - t0 < 0.4
    assert code == 1  # docs/cli.md: exit 1, stopped by the time limit
    assert out.read_text() == "kept\n"
    assert capsys.readouterr().out.startswith("TIMEOUT")


# --- each stage raises the package's Interrupted when its stop condition says so ---------

def test_the_yaml_parse_polls(big_file):
    calls = []

    def stop() -> bool:
        calls.append(1)
        return len(calls) >= 3

    was = gc.isenabled()
    with pytest.raises(Interrupted) as e:
        load_yaml(big_file, error=SceneError, should_stop=stop)
    assert isinstance(e.value, PivotError) and e.value.what == "reading the scene"
    assert len(calls) == 3
    assert gc.isenabled() == was  # the pause of the collector is over, stopped or not
    assert load_yaml(big_file, error=SceneError)["name"] == "big"
    assert gc.isenabled() == was



def _in_construction() -> bool:
    """True when called from within the building of the document (not its parse).

    PyYAML's constructor (``construct_document``) or the lean one of plain documents.
    """
    frame = inspect.currentframe()
    while frame is not None and frame.f_code.co_name not in ("construct_document",
                                                               "build_plain"):
        frame = frame.f_back
    return frame is not None


def test_a_parse_stopped_while_building_frees_its_nodes_at_once(big_file):
    """Stopped in the construction's last polls: nothing of the document outlives the stop.

    PyYAML's pending generators hold the loader that holds them: left as they were, the
    nodes were freed only by a collection (0.05-0.13 s unpolled after a 0.3 s limit).
    """
    calls = []
    load_yaml(big_file, should_stop=lambda: calls.append(_in_construction()) or False)
    assert calls[-1], "the last polls are in the construction"
    total = len(calls)
    was = gc.isenabled()
    gc.disable()
    try:
        seen = []
        with pytest.raises(Interrupted):
            load_yaml(big_file, should_stop=lambda: seen.append(1) or len(seen) >= total - 1)
        left = sum(isinstance(o, yaml.Node) for o in gc.get_objects())
    finally:
        if was:
            gc.enable()
    assert left == 0


def test_building_a_document_of_lists_polls(tmp_path):
    """Lists of lists (a polygon's points) are polled while built, not only mappings."""
    path = tmp_path / "points.yaml"
    n = 20 * POLL_NODES
    path.write_text(yaml.safe_dump([[float(i), 0.5] for i in range(n)]))
    calls = []
    load_yaml(path, should_stop=lambda: calls.append(_in_construction()) or False)
    assert sum(calls) >= n // POLL_NODES - 1


def test_reading_the_obstacles_polls(big_file):
    doc = load_yaml(big_file, error=SceneError)
    with pytest.raises(Interrupted):
        scene_from_dict(doc, should_stop=lambda: True)
    one_polygon = dict(doc, obstacles=doc["obstacles"][-1:])
    calls = []
    with pytest.raises(Interrupted):  # before the polygon's validity check too
        scene_from_dict(one_polygon, should_stop=lambda: calls.append(1) or len(calls) > 1)


def test_the_world_builder_polls(big_file):
    scene = load_scene(big_file)
    with pytest.raises(Interrupted):
        CollisionWorld.from_scene(scene, should_stop=lambda: True)
    with pytest.raises(Interrupted):
        PivotChecker(scene, should_stop=lambda: True)
    polygon = scene.obstacles[-1]
    with pytest.raises(Interrupted):  # a polygon alone: its triangulation polls
        triangulate([tuple(p) for p in _star(1000, 20.0, 20.0)], should_stop=lambda: True)
    world = CollisionWorld(scene.model, scene.bounds)
    calls = []
    with pytest.raises(Interrupted):  # and the building of its 10 000 prisms
        world.add_obstacle(polygon, should_stop=lambda: calls.append(1) or len(calls) > 2)
    assert world.obstacles == []  # an interrupted obstacle is not added


def test_a_stop_condition_that_never_fires_changes_nothing():
    scene = make_scene(obstacles=[{"type": "polygon", "height": 1.0,
                                   "points": [[3, 2], [4, 2], [4, 2], [4, 4], [3, 4]]}])
    a = CollisionWorld.from_scene(scene)
    b = CollisionWorld.from_scene(scene, should_stop=lambda: False)
    for q in [(3.5, 3.0, 0.0), (2.0, 3.0, 0.3), (5.5, 1.0, 1.0)]:
        assert a.box_distance(q) == b.box_distance(q)


# --- the walking floor field of a many-point polygon polls while it is summed ------------

def _polygon_scene(n: int):
    return make_scene(bounds=[0.0, 0.0, 20.0, 20.0], start=[2.0, 2.0, 0.0],
                      goal=[18.0, 18.0, 0.0],
                      obstacles=[{"type": "polygon", "height": 1.0,
                                  "points": _star(n, 10.0, 10.0)}])


def test_summing_pieces_and_bodies_polls_and_batches_change_nothing(monkeypatch):
    """meeting_edges of thousands of pairs polls between batches; the batches' edges are
    the ones summed all at once."""
    from pivot_ompl.validity import minkowski

    rng = np.random.default_rng(3)
    pieces = [rng.uniform(-1, 1, (3, 2)) for _ in range(3000)]
    body = np.array([[-0.3, -0.2], [0.3, -0.2], [0.3, 0.2], [-0.3, 0.2]])
    bodies = [body] * len(pieces)
    calls = []
    with pytest.raises(Interrupted):
        minkowski.meeting_edges(pieces, bodies,
                                should_stop=lambda: calls.append(1) or len(calls) > 2)
    assert len(calls) == 3
    batched = minkowski.meeting_edges(pieces, bodies, should_stop=lambda: False)
    monkeypatch.setattr(minkowski, "MEETING_BATCH", 10**9)
    whole = minkowski.meeting_edges(pieces, bodies)
    for a, b in zip(batched.__dict__.values(), whole.__dict__.values(), strict=True):
        assert np.array_equal(a, b)


def test_the_walking_floor_field_polls_within_a_block_of_yaws():
    """A 10 000-point polygon: one block of yaws took 7 s, polled only before it."""
    checker = PivotChecker(_polygon_scene(10_000))
    field = checker.walker.field
    calls = []
    with pytest.raises(Interrupted):
        field.static_open(should_stop=lambda: calls.append(1) or len(calls) > 3)
    assert field.yaws_done == 0 and len(calls) == 4  # stopped inside the first block

