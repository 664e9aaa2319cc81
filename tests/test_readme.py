"""The README's examples work as written: the scene of "Writing a scene", the first commands."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

from pivot_ompl.analysis.regrasp_bound import regrasp_lower_bound
from pivot_ompl.api import plan
from pivot_ompl.scene import scene_from_dict
from pivot_ompl.validity.plan_check import check_plan

README = Path(__file__).resolve().parents[1] / "README.md"


def _example_scene():
    text = README.read_text(encoding="utf-8")
    block = re.search(r"```yaml\n(name: my_room.*?)```", text, re.S)
    assert block, "the README's scene example is missing"
    return scene_from_dict(yaml.safe_load(block.group(1)), source="README")


def test_the_example_scene_needs_the_regrasp_the_readme_says():
    scene = _example_scene()
    assert regrasp_lower_bound(scene).regrasps == 1


@pytest.mark.slow
def test_the_example_scene_plans_with_one_regrasp():
    scene = _example_scene()
    res = plan(scene, time_limit=30.0, seed=0, bound=False)
    assert res.solved and res.regrasps == 1
    assert check_plan(res.plan, scene).ok


def test_readme_starts_with_the_title_then_the_two_commands():
    lines = README.read_text(encoding="utf-8").splitlines()
    assert lines[0] == "# pivot_ompl"
    text = "\n".join(lines[:30])
    assert "make demo" in text and "make test" in text
