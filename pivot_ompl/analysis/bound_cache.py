"""The regrasp lower bound of a scene, computed once: kept in memory and on disk by content.

The bound depends only on the scene's geometry (not its name) and on the relaxation's
parameters, so its key is the SHA-256 of those (:func:`scene_key`: the scene's
:func:`~pivot_ompl.scene.scene_digest` with :data:`BOUND_VERSION`, which changes whenever the
relaxation does).
Results live in memory (:data:`MEMORY_ENTRIES` scenes) and as small JSON files under
``$XDG_CACHE_HOME/pivot_ompl/bounds`` (``~/.cache`` when unset). ``PIVOT_OMPL_BOUND_CACHE=0``
turns the disk cache off; an unreadable or foreign cache file is ignored and recomputed.
Results stopped by the time limit are never kept.
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path

from pivot_ompl.analysis.regrasp_bound import RESOLUTION, RegraspBound, regrasp_lower_bound
from pivot_ompl.cache import BoundedCache
from pivot_ompl.fileio import atomic_output
from pivot_ompl.scene import Scene, scene_digest

log = logging.getLogger(__name__)

#: Version of the relaxation: part of every key (a new relaxation never reads old results).
BOUND_VERSION = 4
#: Scenes whose bound is kept in memory.
MEMORY_ENTRIES = 64
#: Environment variable that turns the disk cache off when ``0``.
CACHE_ENV = "PIVOT_OMPL_BOUND_CACHE"

_memory: BoundedCache[str, RegraspBound] = BoundedCache(MEMORY_ENTRIES)


def clear_memory() -> None:
    """Forget the bounds kept in memory (the disk cache stays): the next ask reads or computes."""
    _memory.clear()


def scene_key(scene: Scene, *, resolution: float = RESOLUTION) -> str:
    """SHA-256 (hex) of the relaxation's version and parameters and the scene's digest."""
    text = f"{BOUND_VERSION}:{resolution!r}:{scene_digest(scene)}"
    return hashlib.sha256(text.encode()).hexdigest()


def cache_dir() -> Path:
    """Folder of the disk cache."""
    root = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(root) / "pivot_ompl" / "bounds"


def _disk_enabled() -> bool:
    return os.environ.get(CACHE_ENV, "1") != "0"


def _read(path: Path) -> RegraspBound | None:
    try:
        doc = json.loads(path.read_text())
        return RegraspBound(**{k: doc[k] for k in ("regrasps", "solvable", "bins", "pieces",
                                                    "seconds", "shortest_route")})
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _write(path: Path, bound: RegraspBound) -> None:
    try:
        with atomic_output(path) as tmp:
            tmp.write_text(json.dumps(asdict(bound)))
    except OSError as e:  # a read-only home loses the cache, not the bound
        log.debug("bound cache not written (%s)", e)


def cached_bound(scene: Scene, *, resolution: float = RESOLUTION) -> RegraspBound | None:
    """The bound of ``scene`` if a cache (memory, then disk) holds it; nothing is computed."""
    key = scene_key(scene, resolution=resolution)
    hit = _memory.get(key)
    if hit is None and _disk_enabled():
        hit = _read(cache_dir() / f"{key}.json")
        if hit is not None:
            _memory.put(key, hit)
    return hit


def lower_bound(scene: Scene, *, use_cache: bool = True, resolution: float = RESOLUTION,
                should_stop: Callable[[], bool] | None = None) -> RegraspBound:
    """:func:`~pivot_ompl.analysis.regrasp_bound.regrasp_lower_bound` of ``scene``, cached.

    Args:
        scene: the scene.
        use_cache: read and write the caches (memory and disk); ``False`` always computes.
        resolution: the relaxation's yaw-bin erosion (m; part of the cache's key).
        should_stop: polled by a computation; a stopped result is returned, never kept.

    Returns:
        The :class:`~pivot_ompl.analysis.regrasp_bound.RegraspBound` (``seconds`` is the time
        of the computation that produced it, however long ago).
    """
    key = scene_key(scene, resolution=resolution)
    if use_cache:
        hit = cached_bound(scene, resolution=resolution)
        if hit is not None:
            return hit
    bound = regrasp_lower_bound(scene, resolution=resolution, should_stop=should_stop)
    if use_cache and bound.solvable is not None and bound.complete:
        _memory.put(key, bound)
        if _disk_enabled():
            _write(cache_dir() / f"{key}.json", bound)
    return bound
