"""Writing a :class:`~pivot_ompl.scene.Scene` back to the scene YAML contract.

``scene_from_dict(scene_to_dict(s))`` gives back ``s`` (every number in full precision).
A file is written to a temporary name first and renamed, so a failed write never destroys an
existing file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from pivot_ompl.errors import InputError
from pivot_ompl.fileio import atomic_output
from pivot_ompl.generate.checks import check_path, check_scene
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Obstacle, Scene


def _obstacle_dict(o: Obstacle) -> dict[str, Any]:
    if isinstance(o, BoxObstacle):
        return {"type": "box", "center": [float(v) for v in o.center],
                "size": [float(v) for v in o.size], "yaw": float(o.yaw),
                "height": float(o.height)}
    if isinstance(o, CylinderObstacle):
        return {"type": "cylinder", "center": [float(v) for v in o.center],
                "radius": float(o.radius), "height": float(o.height)}
    return {"type": "polygon", "points": [[float(x), float(y)] for x, y in o.points],
            "height": float(o.height)}


def scene_to_dict(scene: Scene) -> dict[str, Any]:
    """The scene YAML document of ``scene`` (see :mod:`pivot_ompl.scene`).

    Raises:
        InputError: ``scene`` is not a Scene.
    """
    check_scene(scene)
    m = scene.model
    return {
        "name": scene.name,
        "bounds": [float(v) for v in scene.bounds],
        "object": {"size": [float(v) for v in m.object_size]},
        "robot": {"model": scene.robot_model,
                  "footprint": [float(v) for v in m.robot_footprint],
                  "standoff": float(m.standoff)},
        "pivot": {"alpha_max": float(scene.alpha_max),
                  "turning_radius": float(scene.turning_radius)},
        "obstacles": [_obstacle_dict(o) for o in scene.obstacles],
        "start": [float(v) for v in scene.start],
        "goal": [float(v) for v in scene.goal],
    }


def scene_text(scene: Scene, *, comment: str = "") -> str:
    """``scene`` as YAML text; ``comment`` lines head it."""
    head = "".join(f"# {line}\n" for line in comment.splitlines())
    body = yaml.safe_dump(scene_to_dict(scene), sort_keys=False, default_flow_style=None,
                          width=100)
    return head + body


def write_scene(scene: Scene, path: str | Path, *, comment: str = "") -> Path:
    """Write ``scene`` as YAML to ``path`` (atomically); ``comment`` lines head the file.

    Raises:
        InputError: ``scene`` not a Scene, ``path`` not a path, ``comment`` not a string.
    """
    check_scene(scene)
    check_path(path, "path")
    if not isinstance(comment, str):
        raise InputError("comment", comment, "must be a string")
    with atomic_output(path) as tmp:
        tmp.write_text(scene_text(scene, comment=comment), encoding="utf-8")
    return Path(path)
