"""Scene files: the shipped ones load; every bad input names file, field and value."""

from __future__ import annotations

import math
import subprocess
import sys

import pytest
import yaml
from factories import SCENES, make_scene

from pivot_ompl.errors import SceneError
from pivot_ompl.scene import PolygonObstacle, load_scene

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


@pytest.mark.parametrize("path", sorted(SCENES.glob("*.yaml")), ids=lambda p: p.stem)
def test_shipped_scenes_load(path):
    s = load_scene(path)
    assert s.name and s.model.object_size[0] > 0
    assert s.source == str(path)


def test_defaults():
    s = make_scene()
    assert s.robot_model == "hrp2"
    assert s.alpha_max == pytest.approx(math.pi / 8)
    assert s.turning_radius == 2.0
    assert s.model.standoff > 0 and s.model.robot_footprint[0] > 0


@pytest.mark.parametrize("override, field", [
    ({"colour": "red"}, "colour"),
    ({"object": {"size": [0.8, -0.6, 1.3]}}, "object.size[1]"),
    ({"object": {"size": [0.8, 0.6]}}, "object.size"),
    ({"object": {"size": "big"}}, "object.size"),
    ({"start": [100.0, 3.0, 0.0]}, "start"),
    ({"goal": [1.0, "x", 0.0]}, "goal[1]"),
    ({"bounds": [5.0, 0.0, 1.0, 6.0]}, "bounds"),
    ({"pivot": {"alpha_max": 2.0}}, "pivot.alpha_max"),
    ({"pivot": {"turning_radius": 0}}, "pivot.turning_radius"),
    ({"robot": {"model": "asimo"}}, "robot.model"),
    ({"robot": {"standoff": -0.1}}, "robot.standoff"),
    ({"robot": {"walk": {"side_cost": 0.5}}}, "robot.walk.side_cost"),
    ({"robot": {"walk": {"back_cost": "high"}}}, "robot.walk.back_cost"),
    ({"robot": {"walk": {"step_forward": 0.0}}}, "robot.walk.step_forward"),
    ({"robot": {"walk": {"step_turn": 2.0}}}, "robot.walk.step_turn"),
    ({"robot": {"walk": {"turn_cost": -1.0}}}, "robot.walk.turn_cost"),
    ({"robot": {"walk": {"stride": 0.3}}}, "robot.walk.stride"),
    ({"robot": {"walk": [0.1]}}, "robot.walk"),
    ({"obstacles": [{"type": "cone", "center": [1, 1]}]}, "obstacles[0].type"),
    ({"obstacles": [{"type": "box", "center": [1, 1], "size": [1, 1]}]}, "obstacles[0].height"),
    ({"obstacles": [{"type": "cylinder", "center": [1, 1], "radius": -1, "height": 1}]},
     "obstacles[0].radius"),
    ({"obstacles": [{"type": "polygon", "points": [[0, 0], [1, 1]], "height": 1}]},
     "obstacles[0].points"),
    ({"obstacles": [{"type": "box", "center": [1, 1], "size": [1, 1], "height": 1,
                     "mass": 3}]}, "obstacles[0].mass"),
])
def test_errors_name_field_and_value(override, field):
    with pytest.raises(SceneError) as e:
        make_scene(**override)
    assert e.value.field == field
    assert "<test>" in str(e.value) and field in str(e.value)


def test_walk_defaults_follow_the_hrp2_step_limits():
    from pivot_ompl import hrp2

    w = make_scene().walk
    assert (w.step_forward, w.step_backward, w.step_lateral, w.step_turn) == (
        hrp2.STEP_FORWARD, hrp2.STEP_BACKWARD, hrp2.STEP_LATERAL, hrp2.STEP_TURN)
    # costs in metres of forward walking = steps taken: sideways and backward dearer
    assert w.side_cost == pytest.approx(hrp2.STEP_FORWARD / hrp2.STEP_LATERAL)
    assert w.back_cost == pytest.approx(hrp2.STEP_FORWARD / hrp2.STEP_BACKWARD)
    assert w.side_cost > 1 and w.back_cost > 1
    assert w.turn_cost == pytest.approx(hrp2.STEP_FORWARD / hrp2.STEP_TURN)
    custom = make_scene(robot={"walk": {"side_cost": 4.0, "turn_cost": 0.0}}).walk
    assert custom.side_cost == 4.0 and custom.turn_cost == 0.0
    assert custom.back_cost == w.back_cost


def test_missing_field(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump({"name": "x", "bounds": [0, 0, 5, 5], "object": {"size": [1, 1, 1]},
                                 "start": [2, 2, 0]}))
    with pytest.raises(SceneError) as e:
        load_scene(p)
    assert e.value.field == "goal" and str(p) in str(e.value)


def test_invalid_yaml(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("name: [unclosed\n")
    with pytest.raises(SceneError):
        load_scene(p)


def test_polygon_kept_in_order():
    s = make_scene(obstacles=[{"type": "polygon", "points": [[3, 4], [5, 4], [5, 5], [4, 4.5],
                                                             [3, 5]], "height": 1.0}])
    assert isinstance(s.obstacles[0], PolygonObstacle) and len(s.obstacles[0].points) == 5


def test_cli_bad_scene_exits_2(tmp_path):
    p = tmp_path / "s.yaml"
    p.write_text(yaml.safe_dump({"name": "x", "bounds": [0, 0, 5, 5],
                                 "object": {"size": [1, -1, 1]}, "start": [2, 2, 0],
                                 "goal": [3, 3, 0]}))
    r = subprocess.run([sys.executable, "-m", "pivot_ompl.cli.main", "plan", str(p)],
                       capture_output=True, text=True, timeout=120)
    assert r.returncode == 2
    assert "object.size[1]" in r.stderr and "Traceback" not in r.stderr


# --- hostile input (issue 15): absurd values are refused at the loader, naming the field ------

@pytest.mark.parametrize("override, field", [
    ({"object": {"size": [1e-9, 1e-9, 1e-9]}}, "object.size[0]"),        # hang: 1e-9 m box
    ({"object": {"size": [1e-4, 0.6, 1.3]}}, "object.size[0]"),          # 0.1 mm box: 7 s
    ({"bounds": [0.0, 0.0, 1.3e6, 6.0], "goal": [1.27e6, 3.0, 0.0]}, "bounds[2]"),  # far goal
    ({"bounds": [0.0, 0.0, 1000.0, 6.0], "goal": [900.0, 3.0, 0.0]}, "bounds"),  # 1 km floor
    ({"goal": [1e308, 3.0, 0.0]}, "goal[0]"),
    ({"goal": [6.0, 3.0, 1e300]}, "goal[2]"),
    ({"goal": [6.0, 3.0, 90.0]}, "goal[2]"),                             # degrees by mistake
    ({"goal": [10**400, 3.0, 0.0]}, "goal[0]"),                          # 401-digit integer
    ({"pivot": {"alpha_max": 1e-9}}, "pivot.alpha_max"),
    ({"pivot": {"turning_radius": 1e-9}}, "pivot.turning_radius"),
    ({"robot": {"footprint": [1e-9, 0.5]}}, "robot.footprint[0]"),
    ({"obstacles": [{"type": "polygon", "points": [[1, 1], [3, 3], [3, 1], [1, 2]],
                     "height": 1}]}, "obstacles[0].points"),              # a bow tie
    ({"obstacles": [{"type": "box", "center": [1, 1], "size": [1, 1], "height": 1,
                     "yaw": 1e300}]}, "obstacles[0].yaw"),
])
def test_absurd_values_refused(override, field):
    with pytest.raises(SceneError) as e:
        make_scene(**override)
    assert e.value.field == field
    assert len(str(e.value)) < 400  # values abridged


def test_simple_nonconvex_polygon_still_accepted():
    s = make_scene(obstacles=[{"type": "polygon", "points": [[3, 4], [5, 4], [5, 5], [4, 4.5],
                                                             [3, 5]], "height": 1.0}])
    assert len(s.obstacles) == 1


@pytest.mark.parametrize("yaw, wrapped", [(2 * math.pi, 0.0), (-2 * math.pi, 0.0),
                                          (1.5 * math.pi, -0.5 * math.pi), (math.pi, math.pi),
                                          (0.3, 0.3)])
def test_yaw_wrapped_into_minus_pi_pi(yaw, wrapped):
    s = make_scene(goal=[6.0, 3.0, yaw], start=[1.5, 3.0, yaw])
    assert s.goal[2] == pytest.approx(wrapped, abs=1e-12)
    assert s.start[2] == pytest.approx(wrapped, abs=1e-12)
    assert -math.pi <= s.goal[2] <= math.pi


def _write(tmp_path, text: str | bytes):
    p = tmp_path / "s.yaml"
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text)
    return p


GOOD = ("name: t\nbounds: [0, 0, 8, 6]\nobject: {size: [0.8, 0.6, 1.3]}\n"
        "start: [1.5, 3.0, 0.0]\ngoal: [6.0, 3.0, 0.0]\n")


def test_duplicate_key_refused(tmp_path):
    with pytest.raises(SceneError) as e:
        load_scene(_write(tmp_path, GOOD + "goal: [5.0, 3.0, 0.0]\n"))
    assert "duplicate key" in str(e.value) and "goal" in str(e.value)


def test_not_utf8_refused(tmp_path):
    with pytest.raises(SceneError) as e:
        load_scene(_write(tmp_path, GOOD.encode() + b"# \xff\xfe caf\xe9\n"))
    assert "UTF-8" in str(e.value)


def test_deep_nesting_refused(tmp_path):
    with pytest.raises(SceneError) as e:
        load_scene(_write(tmp_path, GOOD.replace("name: t", "name: " + "[" * 50_000
                                                 + "]" * 50_000)))
    assert "nested too deeply" in str(e.value) or "YAML" in str(e.value)


def test_alias_bomb_is_refused_fast_and_short(tmp_path):
    lines = ['a: &a ["lol","lol","lol","lol","lol","lol","lol","lol","lol"]']
    for i in range(1, 9):
        prev, cur = chr(ord("a") + i - 1), chr(ord("a") + i)
        lines.append(f"{cur}: &{cur} [{', '.join(['*' + prev] * 9)}]")
    bomb = "\n".join(lines) + "\nname: *i\n"
    import time
    t0 = time.perf_counter()
    with pytest.raises(SceneError) as e:
        load_scene(_write(tmp_path, bomb))
    assert time.perf_counter() - t0 < 2.0
    assert len(str(e.value)) < 400 and "aliases" in str(e.value)


def test_small_aliases_still_work(tmp_path):
    text = GOOD.replace("object: {size: [0.8, 0.6, 1.3]}",
                        "object: {size: &s [0.8, 0.6, 1.3]}\nobstacles:\n"
                        "  - {type: box, center: [4, 1], size: [0.5, 0.5], height: 1}")
    assert load_scene(_write(tmp_path, text)).model.object_size == (0.8, 0.6, 1.3)


def test_directory_is_not_a_scene(tmp_path):
    with pytest.raises(SceneError) as e:
        load_scene(tmp_path)
    assert "directory" in str(e.value)


def test_control_characters_refused(tmp_path):
    """Found by the fuzz test: PyYAML's reader refuses NUL when the loader is built."""
    with pytest.raises(SceneError, match="YAML"):
        load_scene(_write(tmp_path, b"\x00"))


def test_a_scene_digest_is_kept_per_scene_and_follows_each_scene():
    # the digest is remembered per scene object (a 5000-wall building took 15 ms a call,
    # a dozen calls a plan): equal scenes give one digest, a changed scene its own, and a
    # scene collected leaves nothing behind that a new scene could be given
    import dataclasses
    import gc

    from pivot_ompl.scene import scene_digest

    a = load_scene("fig10")
    first = scene_digest(a)
    assert scene_digest(a) == first
    moved = dataclasses.replace(a, goal=(a.goal[0] + 0.5, a.goal[1], a.goal[2]))
    assert scene_digest(moved) != first
    seen = {first}
    for i in range(50):  # new scenes, each its own, perhaps at a collected scene's address
        b = dataclasses.replace(a, start=(a.start[0] + 0.01 * (i + 1), a.start[1], a.start[2]))
        digest = scene_digest(b)
        assert digest not in seen
        seen.add(digest)
        del b
        gc.collect()
    assert scene_digest(load_scene("fig10")) == first
