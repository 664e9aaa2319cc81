"""The regrasp lower bound of a scene, computed once: kept in memory and on disk by content.

The bound depends only on the scene's geometry (not its name) and on the relaxation's
parameters, so its key is the SHA-256 of those (:func:`scene_key`: the scene's
:func:`~pivot_ompl.scene.scene_digest` with :data:`BOUND_VERSION`, which changes whenever the
relaxation does).
Results live in memory (:data:`MEMORY_ENTRIES` scenes) and as small JSON files under
``$XDG_CACHE_HOME/pivot_ompl/bounds`` (``~/.cache`` when unset). ``PIVOT_OMPL_BOUND_CACHE=0``
turns the disk cache off; an unreadable or foreign cache file is ignored and recomputed.
Results stopped by the time limit are never kept.

An entry on disk is a JSON object ``{"format": "pivot-bound/1", "key": <its key>, "bound":
{...}}`` written with mode 0600. It is used only when it answers the key asked for, reads as
a small regular file of this user's that no one else may write
(:func:`~pivot_ompl.cache.read_entry_bytes`: no link, no FIFO, never blocking) and passes
:func:`bound_problem`, the check every fresh result passes too; any other entry is discarded
(deleted) with one warning and the bound computed again. A cache that cannot be written only
costs the time of computing again. A plan that refutes a kept bound (fewer regrasps, a shorter
route: :func:`refuted_by`) drops it (:func:`forget`).
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import logging
import math
import os
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import Any

from pivot_ompl.analysis.bound_frames import framed_lower_bound
from pivot_ompl.analysis.bound_levels import (
    REFINE_SECONDS,
    may_guide,
    may_pose,
    may_refine,
)
from pivot_ompl.analysis.guided_refine import Hint
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.regrasp_bound import RESOLUTION, RegraspBound
from pivot_ompl.analysis.route_bound import GRID_SLACK, MAX_CELLS, MIN_CELL
from pivot_ompl.analysis.wall_frame import relaxed_scene
from pivot_ompl.cache import BoundedCache, CacheEntryError, read_json_entry
from pivot_ompl.errors import InputError, printable, require_type
from pivot_ompl.fileio import atomic_output
from pivot_ompl.scene import Scene, scene_digest

log = logging.getLogger(__name__)

#: Version of the relaxation: part of every key (a new relaxation never reads old results).
BOUND_VERSION = 10
#: Scenes whose bound is kept in memory.
MEMORY_ENTRIES = 64
#: Environment variable that turns the disk cache off when ``0``.
CACHE_ENV = "PIVOT_OMPL_BOUND_CACHE"
#: The ``format`` of a disk entry.
ENTRY_FORMAT = "pivot-bound/1"
#: Largest disk entry read (bytes): an entry is about 200.
MAX_ENTRY_BYTES = 4096

_FIELDS = {f.name for f in dataclasses.fields(RegraspBound)}

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


def disk_enabled() -> bool:
    """Whether the disk cache is on (``PIVOT_OMPL_BOUND_CACHE`` is not ``0``)."""
    return os.environ.get(CACHE_ENV, "1") != "0"


def bound_problem(bound: object, scene: Scene) -> str | None:
    """What makes ``bound`` impossible as a kept bound of ``scene``, or ``None`` when nothing.

    Every result, fresh or read from the disk, passes this before it is kept or used: the
    types of :class:`~pivot_ompl.analysis.regrasp_bound.RegraspBound`, finite numbers, and
    ranges: ``solvable`` known, ``regrasps`` an integer >= 0 when solvable (at most the
    number of pieces: a shortest path passes a piece once) and ``None`` when not,
    ``shortest_route`` finite, >= 0, at least what the raster can give below the straight
    line between the box's start and goal, and at most a walk through every raster cell.
    """
    if not isinstance(bound, RegraspBound):
        return "not a regrasp bound"

    def whole(v: object) -> bool:
        return isinstance(v, int) and not isinstance(v, bool) and v >= 0

    if not isinstance(bound.solvable, bool):
        return f"solvable = {bound.solvable!r} is not true or false"
    if not all(isinstance(f, bool)
               for f in (bound.complete, bound.exhaustive, bound.guided, bound.held)):
        return (f"complete = {bound.complete!r}, exhaustive = {bound.exhaustive!r}, "
                f"guided = {bound.guided!r}, held = {bound.held!r} are not flags")
    if not (whole(bound.bins) and bound.bins >= 1 and whole(bound.pieces)):
        return f"bins = {bound.bins!r}, pieces = {bound.pieces!r} are not counts"
    if (isinstance(bound.seconds, bool) or not isinstance(bound.seconds, int | float)
            or not math.isfinite(bound.seconds) or bound.seconds < 0):
        return f"seconds = {bound.seconds!r} is not a time"
    if bound.solvable:
        if not whole(bound.regrasps) or bound.regrasps > bound.pieces:  # type: ignore[operator]
            return f"regrasps = {bound.regrasps!r} is not a count within the pieces"
    elif bound.regrasps is not None or bound.shortest_route is not None:
        return "an unsolvable scene has no regrasp count nor route"
    if bound.shortest_route is None:
        return None
    return route_problem(bound.shortest_route, scene, name="shortest_route")


def route_problem(route: object, scene: Scene, *, name: str) -> str | None:
    """What makes ``route`` (field ``name``) impossible as a route bound of ``scene``.

    ``None`` when nothing: a finite length in :func:`route_range`.
    """
    if isinstance(route, bool) or not isinstance(route, int | float) or not math.isfinite(route):
        return f"{name} = {route!r} is not a finite length"
    low, high = route_range(scene)
    if not low - 1e-9 <= route <= high:
        return f"{name} = {route!r} m is outside [{low:.6g}, {high:.6g}] m"
    return None


def route_range(scene: Scene) -> tuple[float, float]:
    """The range a computed :func:`~pivot_ompl.analysis.route_bound.shortest_route` lies in."""
    raster = FloorRaster(scene.bounds, min_cell=MIN_CELL, max_cells=MAX_CELLS)
    cell = raster.cell
    nx, ny = raster.shape
    straight = math.hypot(scene.goal[0] - scene.start[0], scene.goal[1] - scene.start[1])
    low = max(0.0, (straight - 2.0 * cell * math.sqrt(2.0)) / (1.0 + GRID_SLACK)
              - 2.0 * cell * math.sqrt(2.0))
    return low, nx * ny * cell * math.sqrt(5.0)


def refuted_by(bound: RegraspBound, *, regrasps: int, route: float) -> bool:
    """Whether a valid plan of ``regrasps`` regrasps and a ``route`` m box route refutes ``bound``.

    It does when a bound lies above what the plan achieves, or says "no plan" while one exists.
    """
    if bound.solvable is False:
        return True
    if bound.regrasps is not None and bound.regrasps > regrasps:
        return True
    return (bound.shortest_route is not None
            and bound.shortest_route > route * (1.0 + 1e-9) + 1e-6)


def forget(scene: Scene) -> None:
    """Drop ``scene``'s kept bound from memory and disk (a plan refuted it)."""
    key = scene_key(scene)
    _memory.discard(key)
    with contextlib.suppress(OSError):
        (cache_dir() / f"{key}.json").unlink()


def _read(path: Path, key: str, scene: Scene) -> RegraspBound | None:
    """The entry at ``path`` answering ``key``; ``None`` when there is none.

    Raises:
        CacheEntryError: an entry is there but is not one to use (see the module docstring).
    """
    doc = read_json_entry(path, entry_format=ENTRY_FORMAT, key=key, max_bytes=MAX_ENTRY_BYTES)
    if doc is None:
        return None
    raw = doc.get("bound")
    if not isinstance(raw, dict) or set(raw) != _FIELDS:
        raise CacheEntryError(path, f"its bound does not hold exactly {sorted(_FIELDS)}")
    bound = RegraspBound(**raw)
    problem = bound_problem(bound, scene)
    if problem is not None:
        raise CacheEntryError(path, problem)
    return bound


def _write(path: Path, key: str, bound: RegraspBound) -> None:
    write_entry(path, {"format": ENTRY_FORMAT, "key": key, "bound": asdict(bound)})


def write_entry(path: Path, doc: dict[str, Any]) -> None:
    """Write a disk cache's JSON entry at ``path``, mode 0600, whole or not at all.

    A cache that cannot be written (a read-only home) loses the entry, not the result.
    """
    try:
        with atomic_output(path) as tmp:
            tmp.write_text(json.dumps(doc))
            os.chmod(tmp, 0o600)  # read back only if no one else may write it
    except OSError as e:
        log.debug("cache entry not written (%s)", e)


def _disk_hit(path: Path, key: str, scene: Scene) -> RegraspBound | None:
    """The disk entry of ``key``, or ``None`` (a bad one discarded with one warning)."""
    try:
        return _read(path, key, scene)
    except CacheEntryError as e:
        log.warning("bound cache entry %s discarded, recomputing: %s", printable(path),
                    printable(e.reason))
        with contextlib.suppress(OSError):
            if not os.path.isdir(path):
                path.unlink()
        return None


def cached_bound(scene: Scene, *, resolution: float = RESOLUTION) -> RegraspBound | None:
    """The bound of ``scene`` if a cache (memory, then disk) holds it; nothing is computed."""
    key = scene_key(scene, resolution=resolution)
    hit = _memory.get(key)
    if hit is None and disk_enabled():
        hit = _disk_hit(cache_dir() / f"{key}.json", key, scene)
        if hit is not None:
            _memory.put(key, hit)
    return hit


def lower_bound(scene: Scene, *, use_cache: bool = True, resolution: float = RESOLUTION,
                target: int | None = None, refine_seconds: float = REFINE_SECONDS,
                should_stop: Callable[[], bool] | None = None,
                guided_seconds: float = 0.0,
                places: tuple[tuple[float, float], ...] = (),
                hint: Hint | None = None) -> RegraspBound:
    """:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound` of ``scene``, cached.

    Computed in the walls' frame (:func:`~pivot_ompl.analysis.wall_frame.relaxed_scene`: a
    floor turned in the world costs what a square one does) and, while below ``target``, in
    the other frames (:func:`~pivot_ompl.analysis.bound_frames.framed_lower_bound`: the
    largest count kept), kept under ``scene``'s key.

    Args:
        scene: the scene.
        use_cache: read and write the caches (memory and disk); ``False`` always computes.
        resolution: the relaxation's yaw-bin erosion (m; part of the cache's key).
        target: the regrasps of the plan the bound is to judge (``None``: none).
        refine_seconds: largest estimated time (s) of the finer levels together.
        should_stop: polled by a computation; a stopped result is returned, never kept.
        guided_seconds: time (s) by estimate for the raster refined where its best path
            passes narrow places, when the bound is still below ``target``
            (:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound`; 0: never; a kept
            result not so refined is computed again when it now fits).
        places: where the plan of ``target`` regrasps (m, in ``scene``): the guided
            refinement's first window (cost only; not part of the key).
        hint: what a search beside expects so far (regrasps, places in ``scene``), asked by
            the guided refinement every round
            (:func:`~pivot_ompl.analysis.guided_refine.guided_lower_bound`; cost only).

    Returns:
        The :class:`~pivot_ompl.analysis.regrasp_bound.RegraspBound` (``seconds`` is the time
        of the computation that produced it, however long ago). A kept result that the
        polygons did not refine is computed again when they are now wanted and fit
        (:func:`~pivot_ompl.analysis.bound_levels.scaled_lower_bound`'s rule).
    """
    require_type(scene, Scene, "scene", "a Scene (load_scene(...) gives one)")
    require_type(use_cache, bool, "use_cache", "True or False")
    if should_stop is not None and not callable(should_stop):
        raise InputError("should_stop", type(should_stop).__name__, "must be callable or None")
    key = scene_key(scene, resolution=resolution)
    if use_cache:
        hit = cached_bound(scene, resolution=resolution)
        if hit is not None and not _refinable(hit, scene, resolution, target,
                                              refine_seconds, guided_seconds):
            return hit
    bound = framed_lower_bound(scene, resolution=resolution, target=target,
                               refine_seconds=refine_seconds, should_stop=should_stop,
                               guided_seconds=guided_seconds, places=places, hint=hint)
    if bound.solvable is None or not bound.complete:  # stopped: returned, never kept
        return bound
    problem = bound_problem(bound, scene)
    if problem is not None:  # the relaxation's own result out of range: a bug, never kept
        log.warning("regrasp bound not kept: %s", problem)
        return bound
    if use_cache:
        _memory.put(key, bound)
        if disk_enabled():
            _write(cache_dir() / f"{key}.json", key, bound)
    return bound


def keep_bound(scene: Scene, bound: RegraspBound, *, resolution: float = RESOLUTION) -> bool:
    """Keep in memory ``bound``, computed for ``scene`` by another process; whether kept.

    Kept as :func:`lower_bound` keeps its own results: complete and passing
    :func:`bound_problem` (the other process's :func:`lower_bound` wrote the disk).
    """
    if not isinstance(bound, RegraspBound) or bound.solvable is None or not bound.complete:
        return False
    if (problem := bound_problem(bound, scene)) is not None:
        log.warning("regrasp bound not kept: %s", problem)
        return False
    _memory.put(scene_key(scene, resolution=resolution), bound)
    return True


def _refinable(hit: RegraspBound, scene: Scene, resolution: float, target: int | None,
               refine_seconds: float, guided_seconds: float = 0.0) -> bool:
    """Whether a finer level may now refine a kept result (then computed again)."""
    if hit.exhaustive or hit.solvable is not True:
        return False
    if target is not None and hit.regrasps is not None and hit.regrasps >= target:
        return False
    if not (hit.guided or hit.held) and (may_pose(relaxed_scene(scene), guided_seconds)
                           or may_guide(relaxed_scene(scene), guided_seconds)):
        return True
    return may_refine(relaxed_scene(scene), resolution=resolution,
                      refine_seconds=refine_seconds,
                      paid_seconds=0.0 if target is None else guided_seconds)
