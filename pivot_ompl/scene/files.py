"""Scene files on disk: a path or a shipped scene's name, loaded within a deadline, digested."""

from __future__ import annotations

import hashlib
import time
import weakref
from collections.abc import Callable
from pathlib import Path
from typing import Any

from pivot_ompl.errors import InputError, SceneError
from pivot_ompl.fileio import input_path, load_yaml, parse_deadline
from pivot_ompl.humanoids import DEFAULT_MODEL
from pivot_ompl.resources import shipped_scenes
from pivot_ompl.scene.model import Scene
from pivot_ompl.scene.reader import scene_from_dict


def scene_path(path: str | Path) -> Path:
    """The file :func:`load_scene` reads: ``path``, or the shipped scene of that name.

    Raises:
        InputError: ``path`` is neither a ``str`` nor an ``os.PathLike``.
        SceneError: no such file nor shipped scene (the shipped ones are listed).
    """
    path = input_path(path)
    if not path.exists():
        shipped = shipped_scenes()
        if str(path) not in shipped:
            raise SceneError("path", str(path), "no such file, nor a shipped scene's name "
                             f"(shipped: {', '.join(shipped)})")
        path = shipped[str(path)]
    return path


def load_scene(path: str | Path, *, deadline: float | None = None) -> Scene:
    """Read and validate a scene file, or the shipped scene of that name (``"fig10"``).

    Raises:
        SceneError: no such file nor shipped scene (the shipped ones are listed), unreadable
            file, invalid YAML, unknown key, missing field, wrong type or bad value, naming
            the file, the field and the value.
        Interrupted: ``deadline`` (``time.monotonic()`` s, a time limit) came while the file
            was parsed (stopped early enough to have freed what was parsed by then,
            :func:`~pivot_ompl.fileio.parse_deadline`) or its obstacles read.
    """
    path = scene_path(path)
    if deadline is None:
        return scene_from_dict(load_yaml(path, error=SceneError), source=str(path))
    doc = load_yaml(path, error=SceneError, should_stop=parse_deadline(deadline))
    return scene_from_dict(doc, source=str(path),
                           should_stop=lambda: time.monotonic() >= deadline)


#: Digests computed, by the scene object's id (the scene frozen, its digest never changes):
#: a building of 5000 walls takes 15 ms to digest, and a plan asks a dozen times. An entry
#: goes when its scene is collected.
_digests: dict[int, tuple[weakref.ref[Scene], str]] = {}


def _forget(key: int) -> Callable[[weakref.ref[Scene]], None]:
    """The callback that drops the digest of the scene whose id is ``key``."""
    def drop(_ref: weakref.ref[Scene]) -> None:
        _digests.pop(key, None)
    return drop


def scene_digest(scene: Scene) -> str:
    """SHA-256 (hex) of what a plan of ``scene`` depends on: its geometry, ends and pivoting.

    Not the name or the file: two files of one scene give one digest, and a plan records it
    (``scene_sha256``) so that a check against another scene says so first.

    Raises:
        InputError: ``scene`` is not a :class:`Scene`.
    """
    if not isinstance(scene, Scene):
        raise InputError("scene", type(scene).__name__, "must be a Scene")
    hit = _digests.get(id(scene))
    if hit is not None and hit[0]() is scene:
        return hit[1]
    parts: tuple[Any, ...] = (scene.bounds, scene.obstacles, scene.model, scene.start,
                              scene.goal, scene.alpha_max, scene.turning_radius, scene.walk)
    if scene.robot_model != DEFAULT_MODEL:  # the default model's digests are as they were
        parts += (scene.robot_model,)
    digest = hashlib.sha256(repr(parts).encode()).hexdigest()
    _digests[id(scene)] = (weakref.ref(scene, _forget(id(scene))), digest)
    return digest
