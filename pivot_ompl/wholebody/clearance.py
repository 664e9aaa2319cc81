"""Obstacle clearance of a whole-body motion: every link and the (tilted) box, every sample.

Every collision geometry of the URDF (placed by pinocchio from the motion's ``q``) and the box
(placed by the motion's ``box`` poses) is measured against the scene's obstacles with coal's
broad phase (:class:`~pivot_ompl.validity.collision.CollisionWorld`'s obstacle tree).

Every sample is covered without querying every body at every sample: a body's clearance can
shrink between two samples by no more than the largest displacement of any of its points, and
that displacement has a configuration-independent bound computed from ``q`` alone:

* a link: ``|dt| + theta * rho_base + sum_j |dq_j| * rho_j``, where ``dt``/``theta`` are the
  free flyer's translation and rotation angle, ``dq_j`` the motion of each revolute joint on
  the link's chain, and ``rho`` the distance bound from that joint's origin to any point of the
  geometry (sum of the chain's joint offsets plus the geometry's local bounding sphere);
* the box: ``|dc| + theta * r`` (centre motion, rotation angle, half-diagonal).

After a query at sample ``i`` gives clearance ``d``, the body is queried again at the first
sample where the accumulated bound reaches ``d - exact_below``; the samples in between are
certified to keep more than ``exact_below`` of clearance. So every sample where a body comes
closer than ``exact_below`` is measured exactly, and the reported minimum per body is exact
when below ``exact_below`` and otherwise a proven lower bound.

The bodies' next queries wait in a priority queue (:mod:`heapq`) keyed by sample index: an
event queue that walks the samples forward in time, not a search of a graph (no costs, no
paths), so it is not :func:`pivot_ompl.graph.astar`, the package's one graph search.
"""

from __future__ import annotations

import heapq
import logging
import math
import time
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion
from pivot_ompl.scene import Scene
from pivot_ompl.validity.collision import obstacle_objects
from pivot_ompl.wholebody.urdf_model import UrdfModel, load_urdf_model

log = logging.getLogger(__name__)

#: Name of the box among the bodies of a :class:`ClearanceReport`.
BOX = "box"
#: Default distance (m) below which every sample's clearance is measured exactly.
EXACT_BELOW = 0.05


@dataclass(frozen=True)
class BodyClearance:
    """The smallest obstacle clearance of one body over a motion.

    Attributes:
        body: URDF collision geometry name (``<link>_<index>``) or ``"box"``.
        link: the URDF link (``"box"`` for the box).
        clearance: smallest distance to any obstacle (m; < 0: penetration depth). Exact when
            below the report's ``exact_below``; otherwise a proven lower bound.
        index: sample index where it occurs.
        time: time of that sample (s).
        obstacle: the nearest obstacle there (``obstacles[i] (type)``; ``""`` if none).
        exact: ``clearance`` was measured at that sample (always when below the report's
            ``exact_below``); otherwise it is a lower bound and ``measured`` the smallest
            value measured.
        measured: the smallest clearance measured at a checked sample (m).
    """

    body: str
    link: str
    clearance: float
    index: int
    time: float
    obstacle: str = ""
    exact: bool = True
    measured: float = math.inf


@dataclass
class ClearanceReport:
    """Outcome of :func:`obstacle_clearance`.

    Attributes:
        bodies: per body (every collision geometry and the box), its smallest clearance.
        samples: number of samples of the motion.
        queries: coal distance queries made (bodies x samples would check them all).
        seconds: wall-clock time of the check.
        exact_below: clearances below this (m) are exact at every sample.
    """

    bodies: list[BodyClearance] = field(default_factory=list)
    samples: int = 0
    queries: int = 0
    seconds: float = 0.0
    exact_below: float = EXACT_BELOW

    @property
    def worst(self) -> BodyClearance | None:
        """The body that comes closest to an obstacle (``None`` without bodies)."""
        return min(self.bodies, key=lambda b: b.clearance, default=None)

    def per_link(self) -> dict[str, BodyClearance]:
        """The smallest clearance of each link (its geometries merged) and of the box."""
        out: dict[str, BodyClearance] = {}
        for b in self.bodies:
            if b.link not in out or b.clearance < out[b.link].clearance:
                out[b.link] = b
        return out

    def table(self) -> str:
        """Per link: smallest clearance, time and nearest obstacle (closest first)."""
        lines = [f"{'link':14s} {'clearance':>10s} {'t (s)':>9s}  obstacle"]
        for b in sorted(self.per_link().values(), key=lambda b: b.clearance):
            value = f"{b.clearance:10.4f}" if b.exact else f"> {self.exact_below:8.4f}"
            lines.append(f"{b.link:14s} {value} {b.time:9.2f}  {b.obstacle}")
        return "\n".join(lines)


def _obstacle_label(scene: Scene, i: int) -> str:
    return f"obstacles[{i}] ({scene.obstacles[i].type})"


def _rotation_angles(quats: np.ndarray) -> np.ndarray:
    """Angle (rad) between consecutive unit quaternions (N x 4, any order of components)."""
    dots = np.abs((quats[1:] * quats[:-1]).sum(axis=1))
    return 2.0 * np.arccos(np.clip(dots, 0.0, 1.0))


def _cumulative(step: np.ndarray) -> np.ndarray:
    """Prefix sums with a leading zero: ``C[j] - C[i]`` bounds the motion from ``i`` to ``j``."""
    return np.concatenate(([0.0], np.cumsum(step)))


def _link_bounds(model, geom, q: np.ndarray) -> list[np.ndarray]:  # noqa: ANN001
    """Per geometry, the cumulative displacement bound of its points (see the module doc)."""
    import pinocchio as pin

    dt = np.linalg.norm(np.diff(q[:, :3], axis=0), axis=1)
    theta = _rotation_angles(q[:, 3:7])
    dq = np.abs(np.diff(q, axis=0))
    out = []
    for obj in geom.geometryObjects:
        g = obj.geometry
        g.computeLocalAABB()
        lo, hi = np.asarray(g.aabb_local.min_), np.asarray(g.aabb_local.max_)
        rho = float(np.linalg.norm(obj.placement.act(0.5 * (lo + hi)))
                    + 0.5 * np.linalg.norm(hi - lo))
        step = np.zeros(len(q) - 1)
        j = obj.parentJoint
        while j > 1:  # revolute joints up to the free flyer
            jm = model.joints[j]
            if jm.nq != 1 or jm.nv != 1 or "Prismatic" in jm.shortname():
                raise InputError("motion.urdf", model.names[j],
                                 f"joint type {jm.shortname()} is not supported (revolute only)")
            step += rho * dq[:, jm.idx_q]
            rho += float(np.linalg.norm(model.jointPlacements[j].translation))
            j = model.parents[j]
        if j != 1 or not isinstance(model.joints[1].extract(), pin.JointModelFreeFlyer):
            raise InputError("motion.urdf", model.names[j], "the root must be a free flyer")
        step += dt + theta * rho
        out.append(_cumulative(step))
    return out


def obstacle_clearance(motion: Motion, scene: Scene, *, exact_below: float = EXACT_BELOW,
                       robot: UrdfModel | None = None) -> ClearanceReport:
    """Smallest obstacle clearance of every link geometry and of the box over ``motion``.

    Args:
        motion: the whole-body motion (``q``, ``box``, ``box_size`` are read).
        scene: the scene whose obstacles are checked.
        exact_below: below this clearance (m) every sample is measured exactly.
        robot: the pinocchio model of the motion's URDF (built from ``motion.urdf`` when
            not given).

    Raises:
        InputError: the motion has no box size, or its URDF is not a free-flyer tree of
            revolute joints.
    """
    t0 = time.perf_counter()
    motion.require("box_size")
    assert motion.box_size is not None  # required above
    if not exact_below > 0:
        raise InputError("exact_below", exact_below, "must be a positive length in m")
    n = len(motion.t)
    rep = ClearanceReport(samples=n, exact_below=exact_below)
    objects, owner = _obstacle_objects(scene)
    if robot is None:
        robot = load_urdf_model(motion.urdf)
    model, geom = robot.model, robot.geom
    names = [o.name for o in geom.geometryObjects] + [BOX]
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects] + [BOX]
    if not objects or n == 0:
        rep.bodies = [BodyClearance(b, lk, math.inf, 0, float(motion.t[0]) if n else 0.0)
                      for b, lk in zip(names, links, strict=True)]
        rep.seconds = time.perf_counter() - t0
        return rep
    q = np.asarray(motion.q, dtype=float)
    boxes = np.asarray(motion.box, dtype=float)
    size = np.array([float(x) for x in motion.box_size])
    bounds = _link_bounds(model, geom, q)
    bounds.append(_cumulative(np.linalg.norm(np.diff(boxes[:, :3], axis=0), axis=1)
                              + _rotation_angles(boxes[:, 3:]) * 0.5 * float(np.linalg.norm(size))))
    bodies = _Bodies(robot, q, boxes, size)
    sweep = _sweep(bodies, objects, bounds, exact_below)
    rep.queries = sweep.queries
    for b in range(len(bodies.shapes)):  # name the nearest obstacle at each body's worst
        exact = sweep.seen[b] <= sweep.best[b]
        i = sweep.seen_i[b] if exact else sweep.best_i[b]
        k = _nearest(bodies, b, i, objects)
        rep.bodies.append(BodyClearance(names[b], links[b], min(sweep.best[b], sweep.seen[b]),
                                        i, float(motion.t[i]), _obstacle_label(scene, owner[k]),
                                        exact, sweep.seen[b]))
    rep.seconds = time.perf_counter() - t0
    log.debug("obstacle clearance: %d queries for %d samples x %d bodies in %.2f s",
              rep.queries, n, len(bodies.shapes), rep.seconds)
    return rep


def _obstacle_objects(scene: Scene) -> tuple[list, list[int]]:
    """The scene's coal collision objects and, for each, the index of its obstacle."""
    objects, owner = [], []
    for i, o in enumerate(scene.obstacles):
        for obj in obstacle_objects(o):
            objects.append(obj)
            owner.append(i)
    return objects, owner


class _Bodies:
    """The motion's bodies (every collision geometry, then the box) placed at a sample."""

    def __init__(self, robot: UrdfModel, q: np.ndarray, boxes: np.ndarray,
                 size: np.ndarray) -> None:
        import coal

        self.model, self.geom = robot.model, robot.geom
        self.data, self.gdata = self.model.createData(), self.geom.createData()
        self.q, self.boxes = q, boxes
        self.shapes = [o.geometry for o in self.geom.geometryObjects] + [coal.Box(*size)]
        self.n_geom = len(self.geom.geometryObjects)
        self._placed = -1

    def transform(self, b: int, i: int):  # noqa: ANN201 - a coal.Transform3s
        """The frame of body ``b`` at sample ``i``."""
        import coal
        import pinocchio as pin

        from pivot_ompl.wholebody.box import matrix_from_quat

        if b < self.n_geom:
            if self._placed != i:
                pin.updateGeometryPlacements(self.model, self.data, self.geom, self.gdata,
                                             self.q[i])
                self._placed = i
            M = self.gdata.oMg[b]
            return coal.Transform3s(M.rotation, M.translation)
        return coal.Transform3s(matrix_from_quat(self.boxes[i, 3:]), self.boxes[i, :3])


@dataclass
class _Sweep:
    """Per body, the smallest certified bound (``best``) and measured clearance (``seen``)."""

    best: list[float]
    best_i: list[int]
    seen: list[float]
    seen_i: list[int]
    queries: int = 0


def _sweep(bodies: _Bodies, objects: list, bounds: list[np.ndarray],
           exact_below: float) -> _Sweep:
    """Query each body at the samples its displacement bound leaves uncertified."""
    import coal

    manager = coal.DynamicAABBTreeCollisionManager()
    for obj in objects:
        manager.registerObject(obj)
    manager.setup()
    cb = coal.DistanceCallBackDefault()
    objs = [coal.CollisionObject(shape) for shape in bodies.shapes]
    m, n = len(objs), len(bodies.q)
    out = _Sweep([math.inf] * m, [0] * m, [math.inf] * m, [0] * m)
    heap = [(0, b) for b in range(m)]
    while heap:
        i, b = heapq.heappop(heap)
        obj = objs[b]
        obj.setTransform(bodies.transform(b, i))
        obj.computeAABB()
        cb.data.result.clear()
        manager.distance(obj, cb)
        d = float(cb.data.result.min_distance)
        out.queries += 1
        C = bounds[b]
        nxt = max(int(np.searchsorted(C, C[i] + d - exact_below, side="left")), i + 1)
        low = d if nxt == i + 1 else min(d, d - float(C[nxt - 1] - C[i]))
        if low < out.best[b]:
            out.best[b], out.best_i[b] = low, i
        if d < out.seen[b]:
            out.seen[b], out.seen_i[b] = d, i
        if nxt < n:
            heapq.heappush(heap, (nxt, b))
    return out


def _nearest(bodies: _Bodies, b: int, i: int, objects: list) -> int:
    """Index of the object nearest to body ``b`` at sample ``i``."""
    import coal

    req, res = coal.DistanceRequest(), coal.DistanceResult()
    T = bodies.transform(b, i)
    dists = []
    for obj in objects:
        res.clear()
        dists.append(coal.distance(bodies.shapes[b], T, obj.collisionGeometry(),
                                   obj.getTransform(), req, res))
    return int(np.argmin(dists))
