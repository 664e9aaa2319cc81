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
