"""Shared factories of the test suite: scenes, problems and paths of shipped files."""

from __future__ import annotations

import math
from pathlib import Path

from pivot_ompl.resources import data_root
from pivot_ompl.scene import Scene, load_scene, scene_from_dict

ROOT = Path(__file__).resolve().parents[1]
SCENES = data_root() / "scenes"
PAPER_BOX = (0.8, 0.6, 1.3)
ALPHA_MAX = math.pi / 8


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
