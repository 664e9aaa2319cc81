"""Shared factories: scenes, problems and paths of shipped files."""

from __future__ import annotations

import math
from pathlib import Path

import pytest
from ompl import util as ou

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.scene import Scene, load_scene, scene_from_dict

ou.setLogLevel(ou.LogLevel.LOG_ERROR)

ROOT = Path(__file__).resolve().parents[1]
SCENES = ROOT / "scenes"
PAPER_BOX = (0.8, 0.6, 1.3)
ALPHA_MAX = math.pi / 8


@pytest.fixture
def paper_model() -> BoxGraspModel:
    return BoxGraspModel(PAPER_BOX)


def scene_file(name: str) -> Path:
    return SCENES / f"{name}.yaml"


def shipped(name: str) -> Scene:
    return load_scene(scene_file(name))


def make_scene(**overrides) -> Scene:
    """A small scene dict (8 x 6 m, paper box) with overrides, parsed."""
    doc = {"name": "test", "bounds": [0.0, 0.0, 8.0, 6.0], "object": {"size": list(PAPER_BOX)},
           "start": [1.5, 3.0, 0.0], "goal": [6.0, 3.0, 0.0], "obstacles": []}
    doc.update(overrides)
    return scene_from_dict(doc, source="<test>")
