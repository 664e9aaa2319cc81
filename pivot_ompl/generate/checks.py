"""Argument checks of the generator's public entry points.

Each check raises :class:`~pivot_ompl.errors.InputError` naming the argument and its value,
so a wrong argument never surfaces as a ``TypeError`` or ``AttributeError`` deep inside.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

from pivot_ompl.argcheck import guard
from pivot_ompl.errors import InputError, require_type
from pivot_ompl.scene import Scene

__all__ = ["check_name", "check_path", "check_scene", "check_states"]


def check_scene(scene: Any, field: str = "scene") -> None:
    """InputError unless ``scene`` is a :class:`Scene`."""
    require_type(scene, Scene, field, "a Scene (pivot_ompl.load_scene(name) gives one)")


def check_path(path: Any, field: str) -> None:
    """InputError unless ``path`` is a non-empty ``str`` or ``os.PathLike`` of a ``str``."""
    text = os.fspath(path) if isinstance(path, os.PathLike) else path
    if not isinstance(text, str) or not text or "\0" in text:
        raise InputError(field, path, "must be a non-empty path (str or pathlib.Path)")


def check_name(name: Any, field: str = "name") -> None:
    """InputError unless ``name`` is a non-empty string."""
    if not isinstance(name, str) or not name:
        raise InputError(field, name, "must be a non-empty string")


def check_states(states: Any, field: str = "states") -> None:
    """InputError unless ``states`` is a sequence of ``(pose, grasp)`` pairs."""
    if isinstance(states, str | bytes) or not isinstance(states, Sequence):
        raise InputError(field, states, "must be a sequence of (pose, grasp) pairs")
    for i, s in enumerate(states):
        if isinstance(s, str | bytes) or not isinstance(s, Sequence) or len(s) != 2:
            raise InputError(f"{field}[{i}]", s, "must be a (pose, grasp) pair")
        guard(f"{field}[{i}]", pose=(s[0], 3), grasp=(s[1], -1))
