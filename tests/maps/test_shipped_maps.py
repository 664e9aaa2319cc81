"""The public maps shipped as examples import as documented (docs/maps.md) and plan."""

from __future__ import annotations

import math

import pytest

from pivot_ompl import import_map
from pivot_ompl.resources import data_path

HALF_PI = 0.5 * math.pi
#: name -> (start, goal, boxes): the tasks of docs/maps.md and benchmarks/buildings.py.
EXAMPLES = {
    "aws_small_house": ((-6.0, -3.0, 0.0), (7.0, -1.0, HALF_PI), 137),
    "aws_bookstore": ((-2.3, 5.4, 0.0), (2.6, -3.1, HALF_PI), 521),
    "aws_small_warehouse": ((-4.5, -7.8, HALF_PI), (0.6, 6.4, 0.0), 866),
}


@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_a_shipped_map_imports_with_its_provenance(name):
    start, goal, boxes = EXAMPLES[name]
    yaml_path = data_path(f"scenes/maps/{name}/map.yaml")
    result = import_map(yaml_path, start=start, goal=goal)
    assert result.scene.name == name and len(result.scene.obstacles) == boxes
    assert result.map.resolution == 0.05
    assert f"image {result.map.image.name} " in result.header
    provenance = (yaml_path.parent / "PROVENANCE.md").read_text()
    assert "Licence:" in provenance and result.image_sha256 in provenance


@pytest.mark.slow
def test_the_house_example_plans(tmp_path):
    from pivot_ompl import plan

    start, goal, _ = EXAMPLES["aws_small_house"]
    scene = import_map(data_path("scenes/maps/aws_small_house/map.yaml"), start=start,
                       goal=goal).scene
    result = plan(scene, time_limit=60.0, seed=0)
    assert result.solved
