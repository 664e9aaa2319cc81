"""The box centre's room's narrow passages, and the obstacle pieces near them.

The held poses' proof (:func:`~pivot_ompl.analysis.pose_proof.prove_no_plan`) sums every
obstacle piece near the box centre's room with the held assembly's bodies, once per yaw bin
and grasp. Summing fewer pieces is always sound: a piece left out only adds floor to the free
regions, so they still over-approximate every valid pose, and start and goal found apart are
apart. Which pieces are worth summing is a question of efficiency only, answered here:

- A passage of the room at least as wide as the held assembly's diameter lets the assembly
  through at every yaw and grasp; only the room's parts narrower than that, where the yaw
  and grasp decide whether it passes, are *narrow*: the room less its opening by
  ``half_width`` (the room shrunk by ``half_width``, its parts grown back; polygons
  approximate both, which only changes which pieces are chosen).
- The room's wide parts and narrow parts form a graph (a narrow part joins the wide parts it
  touches). A part other than the start's or the goal's with at most one neighbour is a dead
  end: it is dropped, repeatedly, and the narrow parts left are the *passages* on the ways
  between start and goal.
- The pieces within ``reach`` of a passage are those a body can meet there
  (:func:`passage_pieces`).
"""

from __future__ import annotations

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

#: Gap (m) within which a narrow part touches a wide part (both cut from one room).
TOUCH = 1e-4


def _parts(geometry: BaseGeometry) -> list[BaseGeometry]:
    return [g for g in getattr(geometry, "geoms", [geometry]) if not g.is_empty]


def passages(room: BaseGeometry, half_width: float,
             ends: list[tuple[float, float]]) -> list[BaseGeometry]:
    """The narrow parts of ``room`` on the ways between ``ends`` (see the module docstring).

    ``room``: the box centre's room (m, world); ``half_width``: half the width (m) from
    which a passage of the room is wide; ``ends``: the start's and goal's box positions.
    """
    if room.is_empty or half_width <= 0.0:
        return []
    wide = [p.buffer(half_width) for p in _parts(room.buffer(-half_width))]
    narrow = _parts(room.difference(shapely.union_all(wide))) if wide else _parts(room)
    if not narrow:
        return []
    nodes = wide + narrow
    links: list[set[int]] = [set() for _ in nodes]
    tested = np.asarray(narrow, dtype=object)
    for i, part in enumerate(wide):
        for j in np.nonzero(shapely.dwithin(part, tested, TOUCH))[0]:
            links[i].add(len(wide) + int(j))
            links[len(wide) + int(j)].add(i)
    tree = shapely.STRtree(nodes)
    kept = {int(tree.nearest(shapely.Point(xy))) for xy in ends}
    alive = set(range(len(nodes)))
    dropped = True
    while dropped:  # dead ends, repeatedly
        dead = {v for v in alive if v not in kept and len(links[v] & alive) <= 1}
        alive -= dead
        dropped = bool(dead)
    return [nodes[v] for v in sorted(alive) if v >= len(wide)]


def passage_pieces(grown: dict[int, np.ndarray], room: BaseGeometry, *, half_width: float,
                   reach: float, ends: list[tuple[float, float]]
                   ) -> dict[int, np.ndarray]:
    """The pieces of ``grown`` (stacked by vertex count) within ``reach`` (m) of a passage.

    :func:`passages` of ``room``; empty when the room has none.
    """
    found = passages(room, half_width, ends)
    if not found:
        return {}
    joined = shapely.union_all(found)
    shapely.prepare(joined)
    out = {}
    for k, stack in grown.items():
        keep = shapely.dwithin(joined, shapely.polygons(stack), reach)
        if keep.any():
            out[k] = stack[keep]
    return out


def diameter(bodies: list[list[np.ndarray]]) -> float:
    """The largest distance (m) between two points of one grasp's bodies, over the grasps."""
    out = 0.0
    for grasp in bodies:
        points = np.concatenate(grasp)
        gaps = points[:, None, :] - points[None, :, :]
        out = max(out, float(np.sqrt((gaps ** 2).sum(axis=-1)).max()))
    return out
