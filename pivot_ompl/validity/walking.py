"""The robot walking alone round the resting box (transit, the regrasping roadmap).

Local steering (the regrasp paper, Section IV): forward walking plus short straight steps. A
walk is a short straight backward step off the held face, turns in place and straight forward
walks, and a short forward step onto the new grasp pose.

The regrasping roadmap is a grid of floor positions (spacing ``resolution``) where the robot
can turn in place: the disk its footprint sweeps, inflated by ``margin``, is clear. It is built
once per scene against the static obstacles; the resting box of a query blocks the positions
near it. Between two neighbouring clear positions (up to ``2.3 * resolution`` apart) the walk
is valid with no further check: the capsule swept by the turning disk along the step leaves
the two end disks by less than the margin. The grid path found by A* is then shortened by
straight forward walks, each certified collision-free (:mod:`pivot_ompl.validity.certify`), so
the walk has few turns.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.graph import astar
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.validity.certify import SWEEP_TOLERANCE, certify
from pivot_ompl.validity.collision import CollisionWorld

log = logging.getLogger(__name__)

#: Grid moves (in cells): 8 neighbours and the 8 knight moves.
_MOVES = [(dx, dy) for dx in (-2, -1, 0, 1, 2) for dy in (-2, -1, 0, 1, 2)
          if (dx, dy) != (0, 0) and abs(dx) + abs(dy) <= 3 and max(abs(dx), abs(dy)) <= 2
          and not (abs(dx) == 2 and dy == 0) and not (abs(dy) == 2 and dx == 0)
          and not (abs(dx) == 2 and abs(dy) == 2)]


@dataclass(frozen=True)
class WalkResult:
    """A transit walk.

    Attributes:
        valid: a collision-free walk was found.
        robot_path: key poses (straight segments, yaw interpolated linearly between them).
        length: walking distance of the robot's centre (m).
        cost: length plus the turning cost (m).
    """

    valid: bool
    robot_path: tuple[Pose, ...]
    length: float
    cost: float


INVALID_WALK = WalkResult(False, (), math.inf, math.inf)


@dataclass
class WalkPlanner:
    """Plans the robot's walk between two grasps of a resting box.

    Args:
        model: box and robot geometry.
        world: the static obstacles.
        resolution: grid spacing of the turn-in-place positions (m).
        back_off: length of the straight backward steps tried off a grasp pose (m).
        turn_cost: cost of turning in place (m per rad).
        margin: clearance kept round the turning disk (m); must exceed the capsule sliver
            ``r - sqrt(r^2 - (1.15 resolution)^2)``.
        box_margin: extra clearance kept from the resting box while walking (m): the robot's
            bounding box does not cover its arms' sway while it walks (about 7 cm measured
            on HRP-2 by the whole-body generator), and the box is what it walks closest to.
        tolerance: swept-check tolerance of straight walks (m).
    """

    model: BoxGraspModel
    world: CollisionWorld
    resolution: float = 0.1
    back_off: float = 0.3
    turn_cost: float = 0.15
    margin: float = 0.02
    box_margin: float = 0.08
    tolerance: float = SWEEP_TOLERANCE
    _free: np.ndarray | None = field(default=None, init=False, repr=False)
    _partial: np.ndarray | None = field(default=None, init=False, repr=False)
    _rows_done: int = field(default=0, init=False, repr=False)

    def __post_init__(self) -> None:
        """Check that the margin covers the capsule sliver of the longest grid move."""
        r = self.model.robot_radius()
        step = math.hypot(2, 1) * self.resolution / 2
        sliver = r - math.sqrt(max(0.0, r * r - step * step))
        if self.margin <= sliver:
            from pivot_ompl.errors import InputError
            raise InputError("margin", self.margin, f"must exceed the grid sliver {sliver:.4f} m")
        b = self.world.bounds
        self._nx = int(math.floor((b[2] - b[0]) / self.resolution)) + 1
        self._ny = int(math.floor((b[3] - b[1]) / self.resolution)) + 1

    # -- grid ------------------------------------------------------------------------------
    def _xy(self, ix: int, iy: int) -> tuple[float, float]:
        b = self.world.bounds
        return (b[0] + ix * self.resolution, b[1] + iy * self.resolution)

    def _disk_clear(self, x: float, y: float, obj: Pose | None) -> bool:
        r = self.model.robot_radius() + self.margin
        b = self.world.bounds
        if not (b[0] + r <= x <= b[2] - r and b[1] + r <= y <= b[3] - r):
            return False
        if self.world.turning_disk_distance(x, y) <= self.margin:
            return False
        return obj is None or \
            self.world.turning_disk_box_distance(x, y, obj) > self.margin + self.box_margin

    def build(self, should_stop: Callable[[], bool] | None = None) -> np.ndarray:
        """The grid of turn-in-place positions clear of the static obstacles (built once).

        Raises:
            Interrupted: ``should_stop()`` became true (polled once per grid row); the rows
                done are kept and the next call resumes there.
        """
        if self._free is None:
            if self._partial is None:
                self._partial = np.zeros((self._nx, self._ny), dtype=bool)
            free = self._partial
            for ix in range(self._rows_done, self._nx):
                if should_stop is not None and should_stop():
                    raise Interrupted("walking grid")
                for iy in range(self._ny):
                    free[ix, iy] = self._disk_clear(*self._xy(ix, iy), None)
                self._rows_done = ix + 1
            self._free, self._partial = free, None
            log.debug("walk grid %dx%d: %d free", self._nx, self._ny, int(free.sum()))
        return self._free

    # -- local steering ----------------------------------------------------------------
    def segment_valid(self, a: Pose, b: Pose, obj: Pose | None) -> bool:
        """Straight motion a -> b with linearly interpolated yaw, certified collision-free."""
        dyaw = wrap_angle(b[2] - a[2])
        lip = math.hypot(b[0] - a[0], b[1] - a[1]) + self.model.robot_radius() * abs(dyaw)
        if lip == 0.0:
            return True

        def clearance(s: float) -> float:
            p = (a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * dyaw)
            if not self.world.robot_in_bounds(p):
                return -1.0
            d = self.world.robot_distance(p)
            if obj is not None:
                d = min(d, self.world.robot_box_distance(p, obj) - self.box_margin)
            return d

        return certify(clearance, lip, tolerance=self.tolerance).valid

    def _walk_valid(self, p: tuple[float, float], q: tuple[float, float], obj: Pose) -> bool:
        yaw = math.atan2(q[1] - p[1], q[0] - p[0])
        return self.segment_valid((p[0], p[1], yaw), (q[0], q[1], yaw), obj)

    def _exits(self, grasp_pose: Pose, obj: Pose) -> list[tuple[tuple[float, float], list[Pose]]]:
        """Ways off a grasp pose to a turn-in-place spot: where it stands, or after a step back."""
        out = []
        c, s = math.cos(grasp_pose[2]), math.sin(grasp_pose[2])
        for k in range(4):
            back = k * self.back_off
            p = (grasp_pose[0] - back * c, grasp_pose[1] - back * s, grasp_pose[2])
            if back > 0 and not self.segment_valid(grasp_pose, p, obj):
                break
            if self._disk_clear(p[0], p[1], obj):
                out.append(((p[0], p[1]), [grasp_pose] if back == 0 else [grasp_pose, p]))
        return out

    # -- query -------------------------------------------------------------------------
    def plan(self, obj: Pose, from_grasp: int, to_grasp: int, *,
             should_stop: Callable[[], bool] | None = None) -> WalkResult:
        """Walk from grasp ``from_grasp`` to grasp ``to_grasp`` of the box resting at ``obj``.

        Raises:
            Interrupted: ``should_stop()`` became true (grid build and A* poll it).
        """
        m = self.model
        start, goal = m.robot_pose(obj, from_grasp), m.robot_pose(obj, to_grasp)
        exits_s, exits_g = self._exits(start, obj), self._exits(goal, obj)
        if not exits_s or not exits_g:
            return INVALID_WALK
        free = self.build(should_stop).copy()
        # the resting box blocks the positions near it
        b = self.world.bounds
        res = self.resolution
        reach = 0.5 * math.hypot(m.object_size[0], m.object_size[1]) + m.robot_radius() \
            + self.margin
        x0 = max(0, int((obj[0] - reach - b[0]) / res))
        x1 = min(self._nx - 1, int((obj[0] + reach - b[0]) / res) + 1)
        y0 = max(0, int((obj[1] - reach - b[1]) / res))
        y1 = min(self._ny - 1, int((obj[1] + reach - b[1]) / res) + 1)
        for ix in range(x0, x1 + 1):
            for iy in range(y0, y1 + 1):
                if free[ix, iy]:
                    free[ix, iy] = self._disk_clear(*self._xy(ix, iy), obj)
        # attach the exits to clear grid positions within one knight move
        attach = math.hypot(2, 1) * res / 2 * 2

        def attached(p: tuple[float, float]) -> list[tuple[int, int]]:
            cx, cy = int(round((p[0] - b[0]) / res)), int(round((p[1] - b[1]) / res))
            out = []
            for ix in range(cx - 2, cx + 3):
                for iy in range(cy - 2, cy + 3):
                    if 0 <= ix < self._nx and 0 <= iy < self._ny and free[ix, iy]:
                        q = self._xy(ix, iy)
                        if math.hypot(q[0] - p[0], q[1] - p[1]) <= attach:
                            out.append((ix, iy))
            return out

        starts: dict[tuple[int, int], int] = {}
        for e, (pos, _) in enumerate(exits_s):
            for c in attached(pos):
                starts.setdefault(c, e)
        goals: dict[tuple[int, int], int] = {}
        for e, (pos, _) in enumerate(exits_g):
            for c in attached(pos):
                goals.setdefault(c, e)
        if not starts or not goals:
            return INVALID_WALK
        cells = _astar(free, list(starts), goals, res, should_stop)
        if not cells:
            return INVALID_WALK
        e_s, e_g = starts[cells[0]], goals[cells[-1]]
        pts = [exits_s[e_s][0]] + [self._xy(*c) for c in cells] + [exits_g[e_g][0]]
        pts = self._shorten(pts, obj)
        return self._assemble(pts, exits_s[e_s][1], exits_g[e_g][1], goal)

    def _shorten(self, pts: list[tuple[float, float]], obj: Pose) -> list[tuple[float, float]]:
        """Greedy shortcuts by certified straight forward walks (farthest reachable first)."""
        out = [pts[0]]
        i = 0
        while i < len(pts) - 1:
            j = len(pts) - 1
            lo = i + 1
            # binary-search-like descent: try far points first, then closer ones
            while j > lo and not self._walk_valid(pts[i], pts[j], obj):
                j = lo + (j - lo) // 2 if j - lo > 8 else j - 1
            out.append(pts[j])
            i = j
        return out

    def _assemble(self, pts: list[tuple[float, float]], head: list[Pose], tail: list[Pose],
                  goal: Pose) -> WalkResult:
        keys = list(head)
        last = keys[-1]
        for q in pts[1:]:
            if math.hypot(q[0] - last[0], q[1] - last[1]) < 1e-12:
                continue
            yaw = math.atan2(q[1] - last[1], q[0] - last[0])
            yaw = last[2] + wrap_angle(yaw - last[2])
            keys.append((last[0], last[1], yaw))  # turn in place
            keys.append((q[0], q[1], yaw))        # walk straight
            last = keys[-1]
        for p in reversed(tail):  # turn-in-place spot ... grasp pose
            yaw = last[2] + wrap_angle(p[2] - last[2])
            keys.append((last[0], last[1], yaw))
            keys.append((p[0], p[1], yaw))
            last = keys[-1]
        keys[-1] = goal
        clean = [keys[0]]
        for p in keys[1:]:
            kept = clean[-1]
            if abs(p[0] - kept[0]) + abs(p[1] - kept[1]) + abs(wrap_angle(p[2] - kept[2])) > 1e-12:
                clean.append(p)
        length = sum(math.hypot(b[0] - a[0], b[1] - a[1])
                     for a, b in zip(clean, clean[1:], strict=False))
        turn = sum(abs(wrap_angle(b[2] - a[2])) for a, b in zip(clean, clean[1:], strict=False))
        return WalkResult(True, tuple(clean), length, length + self.turn_cost * turn)


def _astar(free: np.ndarray, starts: list[tuple[int, int]], goals: dict[tuple[int, int], int],
           res: float, should_stop: Callable[[], bool] | None = None) -> list[tuple[int, int]]:
    """A* over the free grid cells (8 neighbours and knight moves), Euclidean costs."""
    gx = float(np.mean([g[0] for g in goals]))
    gy = float(np.mean([g[1] for g in goals]))
    spread = max(math.hypot(g[0] - gx, g[1] - gy) for g in goals)
    nx, ny = free.shape
    moves = [(dx, dy, math.hypot(dx, dy)) for dx, dy in _MOVES]

    def neighbours(c: tuple[int, int]):
        for dx, dy, w in moves:
            x, y = c[0] + dx, c[1] + dy
            if 0 <= x < nx and 0 <= y < ny and free[x, y]:
                yield (x, y), w

    def h(c: tuple[int, int]) -> float:
        return max(0.0, math.hypot(c[0] - gx, c[1] - gy) - spread)

    return astar(starts, goals, neighbours, h, should_stop=should_stop)
