"""The gap-closed disk route of a scene, kept on disk beside its regrasp bound.

:func:`~pivot_ompl.analysis.plan_bounds.held_route` closes, round by round, the passages no
held pose fits along the disk relaxation's route: about a second on a 5000-piece office, in
every plan process. Like the regrasp bound it depends only on the scene's geometry and the
relaxation, so a finished route (not one stopped partway, which may be weaker) is kept under
a key made of :data:`ROUTE_VERSION` and the bound's key
(:func:`~pivot_ompl.analysis.bound_cache.scene_key`), as ``<key>.route.json`` in the bound
cache's folder: ``{"format": "pivot-route/1", "key": <key>, "route": <m>}``, mode 0600.

An entry is used only when it answers the key asked for, reads as a small regular file of
this user's that no one else may write (:func:`~pivot_ompl.cache.read_entry_bytes`) and holds
a finite length in the range a computed route lies in
(:func:`~pivot_ompl.analysis.bound_cache.route_range`); any other entry is discarded with one
warning. ``PIVOT_OMPL_BOUND_CACHE=0`` turns it off with the bound's disk cache; a plan that
refutes the route drops it (:func:`forget_route`).
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import logging
import math
import os
from pathlib import Path

from pivot_ompl.analysis.bound_cache import CACHE_ENV, cache_dir, route_range, scene_key
from pivot_ompl.cache import CacheEntryError, read_entry_bytes
from pivot_ompl.errors import printable
from pivot_ompl.fileio import atomic_output
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


def _enabled() -> bool:
    return os.environ.get(CACHE_ENV, "1") != "0"


def _no_constant(name: str) -> float:
    raise ValueError(f"{name} is not a number")


def _read(path: Path, key: str, scene: Scene) -> float | None:
    """The route at ``path`` answering ``key``; ``None`` when there is none.

    Raises:
        CacheEntryError: an entry is there but is not one to use (module docstring).
    """
    data = read_entry_bytes(path, max_bytes=MAX_ROUTE_BYTES)
    if data is None:
        return None
    try:
        doc = json.loads(data.decode("utf-8"), parse_constant=_no_constant)
    except (ValueError, RecursionError):
        raise CacheEntryError(path, "is not JSON") from None
    if not isinstance(doc, dict) or doc.get("format") != ROUTE_FORMAT:
        raise CacheEntryError(path, f"is not a {ROUTE_FORMAT} entry")
    if doc.get("key") != key:
        raise CacheEntryError(path, "answers another key (another scene or relaxation)")
    route = doc.get("route")
    if isinstance(route, bool) or not isinstance(route, int | float) or not math.isfinite(route):
        raise CacheEntryError(path, f"route = {route!r} is not a finite length")
    low, high = route_range(scene)
    if not low - 1e-9 <= route <= high:
        raise CacheEntryError(path, f"route = {route!r} m is outside [{low:.6g}, {high:.6g}] m")
    return float(route)


def kept_route(scene: Scene) -> float | None:
    """The gap-closed route (m) kept on disk for ``scene``, or ``None`` (a bad entry dropped)."""
    if not _enabled():
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
    if not _enabled():
        return
    key = _key(scene)
    try:
        with atomic_output(_path(key)) as tmp:
            tmp.write_text(json.dumps({"format": ROUTE_FORMAT, "key": key, "route": route}))
            os.chmod(tmp, 0o600)  # read back only if no one else may write it
    except OSError as e:
        log.debug("route cache not written (%s)", e)


def forget_route(scene: Scene) -> None:
    """Drop ``scene``'s kept route from the disk (a plan refuted it, or the entry was bad)."""
    with contextlib.suppress(OSError):
        path = _path(_key(scene))
        if not path.is_dir():
            path.unlink()
