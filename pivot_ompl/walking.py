"""The robot walking alone round the resting box (transit, the regrasping roadmap).

Local steering (the regrasp paper, Section IV): forward walking plus short straight steps.
A walk between two robot poses is: a short straight backward step away from the held face,
turns in place at roadmap nodes and straight forward walks between them, and a short forward
step onto the new grasp pose. Nodes are floor positions where the robot can turn in place
(the disk it sweeps is clear); edges are straight forward walks.

The roadmap has two parts: a scene-wide part (random turn-in-place positions, built once and
shared by every query, edges validated lazily against the static obstacles and cached) and
per-query nodes round the resting box (the two grasp poses, their back-off points and a ring
of stations). The box itself is an obstacle of the query: edges near it are rechecked.
The search is a lazy shortest path (A*): edges are validated only when on the best path.
"""

from __future__ import annotations

import heapq
import logging
import math
from dataclasses import dataclass, field

import numpy as np

from .collision import CollisionWorld
from .grasp import BoxGraspModel
from .se2 import Pose, wrap_angle
from .sweep import SWEEP_TOLERANCE, certify

log = logging.getLogger(__name__)


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


@dataclass
class WalkPlanner:
    """Plans the robot's walk between two grasps of a resting box.

    Args:
        model: box and robot geometry.
        world: the static obstacles.
        rng: random generator for the scene-wide roadmap nodes.
        n_nodes: scene-wide roadmap size (turn-in-place positions).
        neighbours: nearest neighbours tried per node.
        back_off: length of the straight backward step off a grasp pose (m).
        turn_cost: cost of turning in place (m per rad).
        margin: clearance kept round the turning disk at roadmap nodes (m).
        tolerance: swept-check tolerance (m).
    """

    model: BoxGraspModel
    world: CollisionWorld
    rng: np.random.Generator
    n_nodes: int = 250
    neighbours: int = 10
    back_off: float = 0.30
    turn_cost: float = 0.15
    margin: float = 0.02
    tolerance: float = SWEEP_TOLERANCE
    _nodes: list[tuple[float, float]] = field(default_factory=list, init=False)
    _static_edge: dict[tuple[int, int], bool] = field(default_factory=dict, init=False)
    _built: bool = field(default=False, init=False)

    # -- scene-wide roadmap --------------------------------------------------------------
    def _disk_clear(self, x: float, y: float, obj: Pose | None) -> bool:
        r = self.model.robot_radius() + self.margin
        b = self.world.bounds
        if not (b[0] + r <= x <= b[2] - r and b[1] + r <= y <= b[3] - r):
            return False
        return self.world.turning_disk_distance(x, y, obj) > self.margin

    def build(self) -> None:
        """Sample the scene-wide turn-in-place positions (once)."""
        if self._built:
            return
        b = self.world.bounds
        tries = 0
        while len(self._nodes) < self.n_nodes and tries < 20 * self.n_nodes:
            tries += 1
            x, y = self.rng.uniform(b[0], b[2]), self.rng.uniform(b[1], b[3])
            if self._disk_clear(x, y, None):
                self._nodes.append((x, y))
        self._built = True
        log.debug("walk roadmap: %d nodes after %d samples", len(self._nodes), tries)

    # -- local steering ----------------------------------------------------------------
    def _segment_clearance(self, a: Pose, b: Pose, obj: Pose | None) -> bool:
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
                d = min(d, self.world.robot_box_distance(p, obj))
            return d

        return certify(clearance, lip, tolerance=self.tolerance).valid

    def _walk_edge(self, p: tuple[float, float], q: tuple[float, float], obj: Pose) -> bool:
        yaw = math.atan2(q[1] - p[1], q[0] - p[0])
        return self._segment_clearance((p[0], p[1], yaw), (q[0], q[1], yaw), obj)

    # -- query -------------------------------------------------------------------------
    def plan(self, obj: Pose, from_grasp: int, to_grasp: int) -> WalkResult:
        """Walk from grasp ``from_grasp`` to grasp ``to_grasp`` of the box resting at ``obj``."""
        m = self.model
        start, goal = m.robot_pose(obj, from_grasp), m.robot_pose(obj, to_grasp)
        # exits: (turn-node position, key poses from the grasp pose to it)
        exits_s = self._exits(start, obj)
        exits_g = self._exits(goal, obj)
        if not exits_s or not exits_g:
            return WalkResult(False, (), math.inf, math.inf)
        self.build()
        # query nodes: ring stations round the box
        ring: list[tuple[float, float]] = []
        r0 = 0.5 * math.hypot(m.object_size[0], m.object_size[1]) + m.robot_radius() + 0.05
        for rr in (r0, r0 + 0.3):
            for i in range(8):
                a = obj[2] + i * math.pi / 4
                x, y = obj[0] + rr * math.cos(a), obj[1] + rr * math.sin(a)
                if self._disk_clear(x, y, obj):
                    ring.append((x, y))
        n_static = len(self._nodes)
        pos: list[tuple[float, float]] = list(self._nodes) + ring
        s_ids, g_ids = [], []
        for node, _ in exits_s:
            s_ids.append(len(pos))
            pos.append(node)
        for node, _ in exits_g:
            g_ids.append(len(pos))
            pos.append(node)
        pts = np.array(pos)
        box_r = 0.5 * math.hypot(m.object_size[0], m.object_size[1]) + m.robot_radius() + 0.05
        near_box = np.hypot(pts[:, 0] - obj[0], pts[:, 1] - obj[1])

        def edge_ok(i: int, j: int) -> bool:
            key = (min(i, j), max(i, j))
            static = i < n_static and j < n_static
            p, q = pos[i], pos[j]
            # does the swept corridor come near the box?
            close = _segment_point_distance(p, q, (obj[0], obj[1])) < box_r + 0.5
            if static and not close:
                if key not in self._static_edge:
                    self._static_edge[key] = self._walk_edge(p, q, None)  # type: ignore[arg-type]
                return self._static_edge[key]
            if static and key in self._static_edge and not self._static_edge[key]:
                return False
            return self._walk_edge(p, q, obj)

        goal_xy = (goal[0], goal[1])
        k = self.neighbours
        conn_r = max(2.5, 3.0 * math.sqrt((self.world.bounds[2] - self.world.bounds[0])
                                          * (self.world.bounds[3] - self.world.bounds[1])
                                          / max(1, len(pos))))

        def neighbours(i: int) -> list[int]:
            d = np.hypot(pts[:, 0] - pts[i, 0], pts[:, 1] - pts[i, 1])
            order = np.argsort(d)[1:k + 1 + len(g_ids)]
            out = [int(j) for j in order if d[j] <= conn_r]
            for g in g_ids:
                if g not in out and g != i and d[g] <= 2 * conn_r:
                    out.append(g)
            return out

        # lazy A* over positions; heuristic = straight distance to the goal grasp pose
        bad: set[tuple[int, int]] = set()
        checked: set[tuple[int, int]] = set()
        del near_box
        for _ in range(200):
            path = _astar(s_ids, set(g_ids), pos, neighbours, goal_xy, bad)
            if not path:
                return WalkResult(False, (), math.inf, math.inf)
            ok = True
            for i, j in zip(path, path[1:], strict=False):
                key = (min(i, j), max(i, j))
                if key in checked:
                    continue
                if edge_ok(i, j):
                    checked.add(key)
                else:
                    bad.add(key)
                    ok = False
                    break
            if ok:
                return self._assemble(path, pos, exits_s, exits_g, s_ids, g_ids, start, goal)
        return WalkResult(False, (), math.inf, math.inf)

    def _exits(self, grasp_pose: Pose, obj: Pose) -> list[tuple[tuple[float, float], list[Pose]]]:
        """Ways off a grasp pose to a turn-in-place node: turn where it stands, or back off first."""
        out = []
        c, s = math.cos(grasp_pose[2]), math.sin(grasp_pose[2])
        for back in (0.0, self.back_off, 2 * self.back_off):
            p = (grasp_pose[0] - back * c, grasp_pose[1] - back * s, grasp_pose[2])
            if back > 0 and not self._segment_clearance(grasp_pose, p, obj):
                break
            if self._disk_clear(p[0], p[1], obj):
                keys = [grasp_pose] if back == 0 else [grasp_pose, p]
                out.append(((p[0], p[1]), keys))
        return out

    def _assemble(self, path: list[int], pos: list[tuple[float, float]], exits_s: list,
                  exits_g: list, s_ids: list[int], g_ids: list[int], start: Pose,
                  goal: Pose) -> WalkResult:
        keys = list(exits_s[s_ids.index(path[0])][1])
        last = keys[-1]
        for j in path[1:]:
            q = pos[j]
            yaw = math.atan2(q[1] - last[1], q[0] - last[0])
            yaw = last[2] + wrap_angle(yaw - last[2])
            keys.append((last[0], last[1], yaw))  # turn in place
            keys.append((q[0], q[1], yaw))        # walk straight
            last = keys[-1]
        tail = list(reversed(exits_g[g_ids.index(path[-1])][1]))  # node ... grasp pose
        for p in tail:
            yaw = last[2] + wrap_angle(p[2] - last[2])
            if p[0] != last[0] or p[1] != last[1]:
                keys.append((last[0], last[1], yaw))  # turn to the final heading
            keys.append((p[0], p[1], yaw))
            last = keys[-1]
        keys[-1] = goal
        # drop repeated poses
        clean = [keys[0]]
        for p in keys[1:]:
            q = clean[-1]
            if abs(p[0] - q[0]) + abs(p[1] - q[1]) + abs(wrap_angle(p[2] - q[2])) > 1e-12:
                clean.append(p)
        length = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(clean, clean[1:],
                                                                          strict=False))
        turn = sum(abs(wrap_angle(b[2] - a[2])) for a, b in zip(clean, clean[1:], strict=False))
        return WalkResult(True, tuple(clean), length, length + self.turn_cost * turn)


def _segment_point_distance(p: tuple[float, float], q: tuple[float, float],
                            c: tuple[float, float]) -> float:
    dx, dy = q[0] - p[0], q[1] - p[1]
    n2 = dx * dx + dy * dy
    t = 0.0 if n2 == 0 else max(0.0, min(1.0, ((c[0] - p[0]) * dx + (c[1] - p[1]) * dy) / n2))
    return math.hypot(p[0] + t * dx - c[0], p[1] + t * dy - c[1])


def _astar(starts: list[int], goals: set[int], pos: list[tuple[float, float]], neighbours,
           goal_xy: tuple[float, float], bad: set[tuple[int, int]]) -> list[int]:
    """Shortest path by Euclidean length from any start to any goal, avoiding ``bad`` edges."""
    def h(i: int) -> float:
        return math.hypot(pos[i][0] - goal_xy[0], pos[i][1] - goal_xy[1])

    g = {s: 0.0 for s in starts}
    parent: dict[int, int] = {}
    heap = [(h(s), s) for s in starts]
    heapq.heapify(heap)
    done: set[int] = set()
    while heap:
        _, i = heapq.heappop(heap)
        if i in done:
            continue
        done.add(i)
        if i in goals:
            path = [i]
            while path[-1] in parent:
                path.append(parent[path[-1]])
            return path[::-1]
        for j in neighbours(i):
            if (min(i, j), max(i, j)) in bad:
                continue
            c = g[i] + math.hypot(pos[j][0] - pos[i][0], pos[j][1] - pos[i][1]) + 0.05
            if c < g.get(j, math.inf):
                g[j] = c
                parent[j] = i
                heapq.heappush(heap, (c + h(j), j))
    return []
