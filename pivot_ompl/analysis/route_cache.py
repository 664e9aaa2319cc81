"""The gap-closed disk route of a scene, kept on disk beside its regrasp bound.

:func:`~pivot_ompl.analysis.plan_bounds.held_route` closes, round by round, the passages no
held pose fits along the disk relaxation's route: about a second on a 5000-piece office, in
every plan process. Like the regrasp bound it depends only on the scene's geometry and the
relaxation, so a finished route (not one stopped partway, which may be weaker) is kept under
a key made of :data:`ROUTE_VERSION` and the bound's key
(:func:`~pivot_ompl.analysis.bound_cache.scene_key`), as ``<key>.route.json`` in the bound
cache's folder: ``{"format": "pivot-route/1", "key": <key>, "route": <m>}``, mode 0600.

An entry is used only when it answers the key asked for, reads as a small regular file of
this user's that no one else may write (:func:`~pivot_ompl.cache.read_json_entry`) and holds
a finite length in the range a computed route lies in
(:func:`~pivot_ompl.analysis.bound_cache.route_problem`); any other entry is discarded with one
warning. ``PIVOT_OMPL_BOUND_CACHE=0`` turns it off with the bound's disk cache; a plan that
refutes the route drops it (:func:`forget_route`).
"""

from __future__ import annotations

import contextlib
import hashlib
import logging
from pathlib import Path

from pivot_ompl.analysis.bound_cache import (
    cache_dir,
    disk_enabled,
    route_problem,
    scene_key,
    write_entry,
)
from pivot_ompl.cache import CacheEntryError, read_json_entry
from pivot_ompl.errors import printable
from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)

#: Version of the gap-closed route (:mod:`~pivot_ompl.analysis.route_gaps`): part of the key.
ROUTE_VERSION = 1
#: The ``format`` of a disk entry.
ROUTE_FORMAT = "pivot-route/1"
#: Largest entry read (bytes): an entry is about 120.
MAX_ROUTE_BYTES = 1024


def _key(scene: Scene) -> str:
    return hashlib.sha256(f"route:{ROUTE_VERSION}:{scene_key(scene)}".encode()).hexdigest()


def _path(key: str) -> Path:
    return cache_dir() / f"{key}.route.json"


def _read(path: Path, key: str, scene: Scene) -> float | None:
    """The route at ``path`` answering ``key``; ``None`` when there is none.

    Raises:
        CacheEntryError: an entry is there but is not one to use (module docstring).
    """
    doc = read_json_entry(path, entry_format=ROUTE_FORMAT, key=key, max_bytes=MAX_ROUTE_BYTES)
    if doc is None:
        return None
    route = doc.get("route")
    problem = route_problem(route, scene, name="route")
    if problem is not None:
        raise CacheEntryError(path, problem)
    return float(route)  # type: ignore[arg-type]


def kept_route(scene: Scene) -> float | None:
    """The gap-closed route (m) kept on disk for ``scene``, or ``None`` (a bad entry dropped)."""
    if not disk_enabled():
        return None
    key = _key(scene)
    path = _path(key)
    try:
        return _read(path, key, scene)
    except CacheEntryError as e:
        log.warning("route cache entry %s discarded: %s", printable(path), printable(e.reason))
        forget_route(scene)
        return None


def keep_route(scene: Scene, route: float) -> None:
    """Keep ``scene``'s finished gap-closed route (m) on disk (an unwritable cache: not kept)."""
    if disk_enabled():
        key = _key(scene)
        write_entry(_path(key), {"format": ROUTE_FORMAT, "key": key, "route": route})


def forget_route(scene: Scene) -> None:
    """Drop ``scene``'s kept route from the disk (a plan refuted it, or the entry was bad)."""
    with contextlib.suppress(OSError):
        path = _path(_key(scene))
        if not path.is_dir():
            path.unlink()
