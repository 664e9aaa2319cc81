"""Box obstacles that touch along a whole side, merged into one box (the same floor).

A scene may come cut into many pieces: an occupancy grid is one box per cell, a CAD export
or a converted benchmark layout one box per wall segment. The planner's collision world and
the floor fields sum or query every piece near a body, so :func:`merge_boxes` joins the
pieces first; the covered set does not change, only how it is cut.

Two boxes are merged when they stand on the same height and yaw modulo pi/2 (a box of yaw
``t`` and size ``(a, b)`` is the box of yaw ``t + pi/2`` and size ``(b, a)``), and in their
common frame they have the same extent across one axis and their extents along it touch or
overlap: their union is then one rectangle. Merging runs along one axis, then the other,
until nothing changes, so a grid of ``k x m`` touching cells becomes one box. Coordinates
(in the common frame, and heights) that differ by at most :data:`TOLERANCE` m count as equal,
and yaws that differ by at most :data:`YAW_TOLERANCE` rad (chained: values sorted, a new
value starts wherever the gap to the previous one exceeds the tolerance). Cylinders and
polygons pass unchanged, as does every box that was not merged (the same object).

The cost is ``O(n log n)`` per pass (sides are sorted and grouped, never compared pair by
pair); a pass that merges nothing ends the loop.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import BoxObstacle, Obstacle

logger = logging.getLogger(__name__)

#: Coordinates (m) and heights that differ by at most this count as equal.
TOLERANCE = 1e-9

#: Yaws (rad, modulo pi/2) that differ by at most this count as equal.
YAW_TOLERANCE = 1e-12

#: Boxes handled between two polls of ``should_stop``.
POLL_BOXES = 1000

_QUARTER = 0.5 * math.pi


@dataclass
class _Rect:
    """A box in its group's frame: ``[u0, u1] x [v0, v1]``; ``source`` if not merged yet."""

    u0: float
    v0: float
    u1: float
    v1: float
    first: int  # the smallest scene index among the boxes it covers
    source: BoxObstacle | None


def _labels(values: np.ndarray, tolerance: float) -> np.ndarray:
    """Cluster labels of ``values``: sorted, a new label where a gap exceeds ``tolerance``."""
    order = np.argsort(values, kind="stable")
    gaps = np.diff(values[order]) > tolerance
    labels = np.empty(len(values), dtype=np.int64)
    labels[order] = np.concatenate([[0], np.cumsum(gaps)])
    return labels


def _normal_yaw(box: BoxObstacle) -> tuple[float, tuple[float, float]]:
    """The box's yaw in ``[-YAW_TOLERANCE, pi/2 - YAW_TOLERANCE)`` and its size in that frame."""
    turns = math.floor(box.yaw / _QUARTER)
    yaw = box.yaw - turns * _QUARTER
    if yaw >= _QUARTER - YAW_TOLERANCE:
        yaw -= _QUARTER
        turns += 1
    size = box.size if turns % 2 == 0 else (box.size[1], box.size[0])
    return yaw, size


def _groups(obstacles: Sequence[Obstacle]) -> list[tuple[float, float, list[_Rect]]]:
    """The boxes grouped by height and yaw: ``(yaw, height, rects in that frame)``."""
    boxes = [(i, o) for i, o in enumerate(obstacles) if isinstance(o, BoxObstacle)]
    if not boxes:
        return []
    frames = [_normal_yaw(o) for _, o in boxes]
    yaws = np.array([y for y, _ in frames])
    heights = np.array([o.height for _, o in boxes], dtype=float)
    keys = zip(_labels(yaws, YAW_TOLERANCE).tolist(), _labels(heights, TOLERANCE).tolist(),
               strict=True)
    out: dict[tuple[int, int], tuple[float, float, list[_Rect]]] = {}
    for (i, o), (yaw, (a, b)), key in zip(boxes, frames, keys, strict=True):
        group = out.setdefault(key, (yaw, o.height, []))
        c, s = math.cos(group[0]), math.sin(group[0])
        u, v = c * o.center[0] + s * o.center[1], -s * o.center[0] + c * o.center[1]
        group[2].append(_Rect(u - 0.5 * a, v - 0.5 * b, u + 0.5 * a, v + 0.5 * b, i, o))
    return list(out.values())


def _merge_along(rects: list[_Rect], along_u: bool, poll: Callable[[], None]) -> list[_Rect]:
    """One pass: rects of one extent across the axis whose extents along it touch, joined."""
    if len(rects) < 2:
        return rects
    if along_u:
        lo = np.array([r.v0 for r in rects] + [r.v1 for r in rects])
    else:
        lo = np.array([r.u0 for r in rects] + [r.u1 for r in rects])
    labels = _labels(lo, TOLERANCE)
    n = len(rects)
    rows: dict[tuple[int, int], list[_Rect]] = {}
    for k, r in enumerate(rects):
        rows.setdefault((int(labels[k]), int(labels[n + k])), []).append(r)
    out: list[_Rect] = []
    done = 0
    for row in rows.values():
        row.sort(key=(lambda r: r.u0) if along_u else (lambda r: r.v0))
        cur = row[0]
        for r in row[1:]:
            done += 1
            if done % POLL_BOXES == 0:
                poll()
            start, end = (r.u0, cur.u1) if along_u else (r.v0, cur.v1)
            if start > end + TOLERANCE:
                out.append(cur)
                cur = r
                continue
            if along_u:
                cur = _Rect(cur.u0, cur.v0, max(cur.u1, r.u1), cur.v1, min(cur.first, r.first),
                            None)
            else:
                cur = _Rect(cur.u0, cur.v0, cur.u1, max(cur.v1, r.v1), min(cur.first, r.first),
                            None)
        out.append(cur)
    return out


def _box(r: _Rect, yaw: float, height: float) -> BoxObstacle:
    if r.source is not None:
        return r.source
    c, s = math.cos(yaw), math.sin(yaw)
    u, v = 0.5 * (r.u0 + r.u1), 0.5 * (r.v0 + r.v1)
    return BoxObstacle((c * u - s * v, s * u + c * v), (r.u1 - r.u0, r.v1 - r.v0), yaw, height)


#: Tuples of obstacles merged lately, by identity (a tuple of frozen obstacles never
#: changes): the scene's tuple is merged by half a dozen callers a plan, 30 ms each on a
#: building of 5000 walls. Holds the tuples it names, the oldest dropped beyond
#: :data:`MERGED_KEPT`.
_merged: dict[int, tuple[tuple[Obstacle, ...], tuple[Obstacle, ...]]] = {}
MERGED_KEPT = 4


def merge_boxes(obstacles: Sequence[Obstacle], *,
                should_stop: Callable[[], bool] | None = None) -> list[Obstacle]:
    """The obstacles with touching boxes merged (see the module docstring).

    The result covers the same floor with no more obstacles; each obstacle or merged box
    stands where the first of the scene's obstacles it covers stood. A tuple's merge is
    kept (:data:`MERGED_KEPT` tuples, by identity) and handed again as a new list.

    Raises:
        Interrupted: ``should_stop()`` became true (polled before every pass and every
            :data:`POLL_BOXES` boxes within one).
    """
    hit = _merged.get(id(obstacles)) if isinstance(obstacles, tuple) else None
    if hit is not None and hit[0] is obstacles:
        return list(hit[1])
    merged = _merged_boxes(obstacles, should_stop)
    if isinstance(obstacles, tuple):
        _merged.pop(id(obstacles), None)
        _merged[id(obstacles)] = (obstacles, tuple(merged))
        while len(_merged) > MERGED_KEPT:
            del _merged[next(iter(_merged))]
    return merged


def _merged_boxes(obstacles: Sequence[Obstacle],
                  should_stop: Callable[[], bool] | None) -> list[Obstacle]:
    """:func:`merge_boxes` computed."""
    def poll() -> None:
        if should_stop is not None and should_stop():
            raise Interrupted("merging the box obstacles")

    poll()
    placed: list[tuple[int, Obstacle]] = [(i, o) for i, o in enumerate(obstacles)
                                          if not isinstance(o, BoxObstacle)]
    for yaw, height, rects in _groups(obstacles):
        along_u, idle = True, 0
        while idle < 2 and len(rects) > 1:
            poll()
            count = len(rects)
            rects = _merge_along(rects, along_u, poll)
            idle = idle + 1 if len(rects) == count else 0
            along_u = not along_u
        placed += [(r.first, _box(r, yaw, height)) for r in rects]
    placed.sort(key=lambda p: p[0])
    if len(placed) < len(obstacles):
        logger.debug("merged %d obstacles into %d", len(obstacles), len(placed))
    return [o for _, o in placed]
