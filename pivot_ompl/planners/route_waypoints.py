"""A transfer phase's poses and its variants' merged into one order along a route.

:func:`~pivot_ompl.planners.follow_route.follow_route` offers the path optimiser
(:func:`~pivot_ompl.planners.optimiser.optimise_over`) the poses of a phase and of the
variants that follow its route, as one list of waypoints: :func:`merged` orders them by where
they lie along the route (:func:`along`), each sequence keeping its own order, and names the
phase's path and the variants' legs over those waypoints.
"""

from __future__ import annotations

import math

from pivot_ompl.se2 import Pose

__all__ = ["along", "merged"]


def merged(guide: list[tuple[float, float]], old: list[Pose],
           variants: list[tuple[Pose, ...]], grasp: int
           ) -> tuple[list[Pose], list[tuple[int, int]], tuple[tuple[int, int], ...]]:
    """The phase's and the variants' poses in one order along ``guide``.

    Each sequence keeps its own order (a pose's place along the guide, never behind the
    sequence's previous pose); the ends are shared. ``(poses, path, links)``: the waypoints,
    the phase as ``(waypoint, grasp)`` nodes and the variants' legs as waypoint pairs.
    """
    keyed: list[tuple[float, int, int, Pose]] = []
    for s, seq in enumerate([old, *variants]):
        at = 0.0
        for k, q in enumerate(seq[1:-1], start=1):
            at = max(at, along(guide, q))
            keyed.append((at, s, k, q))
    keyed.sort(key=lambda e: e[:3])
    poses = [old[0], *(e[3] for e in keyed), old[-1]]
    index = {(s, k): n for n, (_, s, k, _) in enumerate(keyed, start=1)}
    last = len(poses) - 1

    def place(s: int, k: int, n: int) -> int:
        return 0 if k == 0 else last if k == n - 1 else index[(s, k)]

    path = [(place(0, k, len(old)), grasp) for k in range(len(old))]
    links = tuple((place(s, k, len(v)), place(s, k + 1, len(v)))
                  for s, v in enumerate(variants, start=1) for k in range(len(v) - 1))
    return poses, path, links


def along(guide: list[tuple[float, float]], q: Pose) -> float:
    """Where along ``guide`` (m from its start) the point nearest to ``q``'s position lies."""
    best, at, done = math.inf, 0.0, 0.0
    for (x0, y0), (x1, y1) in zip(guide, guide[1:], strict=False):
        dx, dy = x1 - x0, y1 - y0
        n = math.hypot(dx, dy)
        t = 0.0 if n == 0 else min(1.0, max(0.0, ((q[0] - x0) * dx + (q[1] - y0) * dy) / n**2))
        d = math.hypot(x0 + t * dx - q[0], y0 + t * dy - q[1])
        if d < best:
            best, at = d, done + t * n
        done += n
    return at
