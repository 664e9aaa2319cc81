"""The scene of a plan or motion, found the same way by every verb (replay, animate, check...).

A plan records its scene three ways: ``scene`` (the name), ``scene_path`` (the file it was
made from) and ``scene_sha256`` (:func:`~pivot_ompl.scene.scene_digest`). The scene used is,
in order: the one the user gives (``--scene`` or ``check``'s ``SCENE``), the recorded file
when it is still there, the shipped scene of that name. When the scene used is not the one
the plan was made for (another digest), a note says so before anything else is printed.
"""

from __future__ import annotations

import logging
import os
import sys
from dataclasses import dataclass
from typing import Any

from pivot_ompl.errors import InputError, SceneError
from pivot_ompl.resources import shipped_scenes
from pivot_ompl.scene import Scene, load_scene, scene_digest

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class SceneRecord:
    """What a plan or motion file says about its scene (each part may be empty).

    Attributes:
        name: the ``scene`` field.
        path: the ``scene_path`` field, absolute (resolved against the file that holds it).
        digest: the ``scene_sha256`` field.
        kind: ``"plan"`` or ``"motion"``, for messages.
    """

    name: str = ""
    path: str = ""
    digest: str = ""
    kind: str = "plan"

    @classmethod
    def of(cls, doc: Any, kind: str = "plan") -> SceneRecord:
        """The record of a :class:`~pivot_ompl.planfile.Plan` or a motion (``None``: empty)."""
        if doc is None:
            return cls(kind=kind)
        extra = getattr(doc, "extra", None) or {}
        path = extra.get("scene_path", getattr(doc, "scene_path", ""))
        digest = extra.get("scene_sha256", getattr(doc, "scene_sha256", ""))
        return cls(str(getattr(doc, "scene", "") or ""),
                   path if isinstance(path, str) else "",
                   digest if isinstance(digest, str) else "", kind)

    def merged(self, other: SceneRecord) -> SceneRecord:
        """The record with its empty parts taken from ``other``."""
        return SceneRecord(self.name or other.name, self.path or other.path,
                           self.digest or other.digest, self.kind)


def find_scene(record: SceneRecord, given: str | Scene | None) -> Scene | None:
    """The scene to use: ``given``, else the recorded file, else the shipped scene of its name.

    ``given``: a file, a shipped scene's name or a scene already loaded. ``None`` when none
    of them is there. Prints a note on stderr, first, when the scene used is not the one recorded.

    Raises:
        SceneError: the scene file is invalid.
    """
    if isinstance(given, Scene):
        _note_mismatch(record, given, given.source or given.name)
        return given
    if given:
        scene = load_scene(given)
        _note_mismatch(record, scene, given)
        return scene
    if record.path and os.path.lexists(record.path):
        log.info("scene %r from %s (the %s's scene_path)", record.name, record.path,
                 record.kind)
        scene = _recorded_scene(record)
        _note_mismatch(record, scene, record.path, recorded=True)
        return scene
    shipped = shipped_scenes().get(record.name) if record.name else None
    if shipped is not None:
        log.info("scene %r from %s", record.name, shipped)
        scene = load_scene(shipped)
        _note_mismatch(record, scene, record.name)
        return scene
    return None


def _recorded_scene(record: SceneRecord) -> Scene:
    """The scene file a plan or motion names (its ``scene_path``), which must be one.

    The file is named by the plan, not by the user: whatever it holds, no part of it is
    echoed (a secret file named as a scene gives only "is not a scene file").

    Raises:
        SceneError: the file is not a regular file, or does not parse as a scene.
    """
    try:
        return load_scene(record.path)
    except SceneError:
        raise SceneError("scene_path", record.path, "is not a scene file",
                         source=f"the {record.kind}") from None


def require_scene(record: SceneRecord, given: str | Scene | None, *, field: str) -> Scene:
    """:func:`find_scene`, or an :class:`InputError` saying what was looked for.

    Raises:
        InputError: no scene given and the recorded one is nowhere.
    """
    scene = find_scene(record, given)
    if scene is not None:
        return scene
    raise InputError(field, record.name or None, missing_text(record))


def missing_text(record: SceneRecord) -> str:
    """Why the recorded scene is not found, and what to pass instead."""
    where = f"its file {record.path} is gone and it " if record.path else ""
    if not record.name and not record.path:
        return f"the {record.kind} names no scene: pass --scene FILE"
    return (f"{where}is not a shipped scene ({', '.join(shipped_scenes())}): "
            "pass --scene FILE")


def _note_mismatch(record: SceneRecord, scene: Scene, given: str, *,
                   recorded: bool = False) -> None:
    """Say first, on stderr, that ``scene`` is not the one the plan was made for."""
    if not record.digest or record.digest == scene_digest(scene):
        return
    made = f"scene {record.name!r}" if record.name else "another scene"
    if recorded:
        print(f"note: {record.kind} made for {made}, whose file {given} has changed since: "
              "expect collisions and mismatches below", file=sys.stderr)
        return
    same = " (same name, other geometry, ends or pivoting)" if scene.name == record.name else ""
    print(f"note: {record.kind} made for {made}, given {scene.name!r} ({given}){same}: "
          "expect collisions and mismatches below", file=sys.stderr)
