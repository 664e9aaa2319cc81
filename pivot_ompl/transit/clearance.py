"""The walking robot's clearances and its certified straight motions (linear yaw).

Clearances come in two parts, each certified apart (each is larger than their minimum:
fewer samples): to the obstacles and the floor's bounds (:meth:`WalkClearance.static_exact`,
cached per lattice state for the whole scene), and to the resting box, kept ``box_margin``
away (the robot's bounding box does not cover its arms' sway while it walks; cached per box
pose in :class:`BoxedClearance`). A lattice state's clearance is a lower bound: the turning
disk's where it is clear (one query per grid position for every heading), the robot body's
own distance otherwise.

A straight motion ``a -> b`` with linear yaw moves no point of the walking body farther than
``hypot(b - a) + radius * |yaw change|`` (:meth:`WalkClearance.sweep`: the pose's translation
plus the yaw about the pose, ``radius`` the body's farthest point from it), so each
clearance is Lipschitz in the motion's parameter with that bound. A motion is certified only
where the clearances prove it free at every point, never by the tolerance alone
(:func:`~pivot_ompl.validity.certify.certify` with ``exact=True``): the ends' clearances
certify it when their sum exceeds the sweep by ``2 EXACT_MARGIN`` (:meth:`WalkClearance.proves`),
bisection does otherwise, and an interval that reaches the tolerance unproven refuses the
motion. A walk certified so keeps every margin at every pose along it, so no sampling of it
(finer than the planner's, or of a part of it) finds it closer.
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.cache import BoundedCache
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.lattice import HEADING_YAWS
from pivot_ompl.validity.certify import EXACT_MARGIN, certify
from pivot_ompl.validity.collision import CollisionWorld

State = tuple[int, int, int]  # (grid x, grid y, heading)


class WalkClearance:
    """Clearances of the walking robot on one floor (see the module docstring).

    Args:
        model: the walking body.
        world: obstacles and bounds.
        resolution: lattice grid spacing (m).
        box_margin: clearance kept from the resting box (m).
        tolerance: swept-check tolerance (m).
        box_cache: resting-box poses whose lattice clearances are kept.
    """

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, *, resolution: float,
                 box_margin: float, tolerance: float, box_cache: int) -> None:
        """Empty caches."""
        self.model, self.world = model, world
        self.resolution, self.box_margin, self.tolerance = resolution, box_margin, tolerance
        self.radius = model.robot_radius()
        self._disk: dict[tuple[int, int], float] = {}
        self._static: dict[State, float] = {}
        self._static_motions: dict[tuple[State, State], bool] = {}
        self._boxed: BoundedCache[Pose, BoxedClearance] = BoundedCache(box_cache)

    def pose(self, s: State) -> Pose:
        """The robot pose of lattice state ``s``."""
        b = self.world.bounds
        return (b[0] + s[0] * self.resolution, b[1] + s[1] * self.resolution,
                HEADING_YAWS[s[2]])

    def sweep(self, a: Pose, b: Pose) -> float:
        """Farthest (m) any point of the walking body moves along ``a -> b`` (linear yaw)."""
        return math.hypot(b[0] - a[0], b[1] - a[1]) + self.radius * abs(wrap_angle(b[2] - a[2]))

    def proves(self, da: float, db: float, a: Pose, b: Pose) -> bool:
        """End clearances ``da`` and ``db`` alone prove ``a -> b`` free at every point.

        Their sum exceeds the :meth:`sweep` by ``2 EXACT_MARGIN`` (the exact test of
        :func:`~pivot_ompl.validity.certify.certify`).
        """
        return da > 0.0 and db > 0.0 and da + db > self.sweep(a, b) + 2.0 * EXACT_MARGIN

    def with_box(self, obj: Pose) -> BoxedClearance:
        """The clearances with the box resting at ``obj`` (kept for the last poses asked)."""
        return self._boxed.get_or_compute(obj, lambda: BoxedClearance(self, obj))

    # -- the obstacles and the bounds ---------------------------------------------------
    def static_exact(self, p: Pose) -> float:
        """Clearance (m) of the robot at ``p`` to the obstacles and the bounds."""
        w = self.world
        b, r = w.bounds, self.radius
        d = min(p[0] - b[0], b[2] - p[0], p[1] - b[1], b[3] - p[1]) - r  # disk: a lower bound
        if d < 2.0 * r:
            d = w.robot_bounds_margin(p)
            if d <= 0.0:
                return d
        return min(d, w.robot_distance(p))

    def static_state(self, s: State) -> float:
        """Lower bound of the robot's clearance to obstacles and bounds at ``s`` (cached)."""
        v = self._static.get(s)
        if v is not None:
            return v
        x, y, yaw = self.pose(s)
        cell = (s[0], s[1])
        dd = self._disk.get(cell)
        if dd is None:
            b, r = self.world.bounds, self.radius
            dd = min(x - b[0] - r, b[2] - x - r, y - b[1] - r, b[3] - y - r)
            if dd > 0.0:
                dd = min(dd, self.world.turning_disk_distance(x, y))
            self._disk[cell] = dd
        if dd > 2.0 * self.resolution:
            v = dd
        else:
            w = self.world
            v = w.robot_bounds_margin((x, y, yaw))
            if v > 0.0:
                v = min(v, w.robot_distance((x, y, yaw)))
        self._static[s] = v
        return v

    def static_motion_free(self, key: tuple[State, State]) -> bool:
        """The lattice motion ``key`` (end states in order) is clear of obstacles and bounds."""
        ok = self._static_motions.get(key)
        if ok is None:
            ok = self.certified(self.pose(key[0]), self.pose(key[1]), self.static_exact,
                                self.static_state(key[0]), self.static_state(key[1]))
            self._static_motions[key] = ok
        return ok

    def certified(self, a: Pose, b: Pose, clearance: Callable[[Pose], float], da: float,
                  db: float) -> bool:
        """The straight motion ``a -> b`` (linear yaw) keeps ``clearance`` positive all along.

        ``da``/``db``: lower bounds of ``clearance`` at the ends. Proven at every point
        (:func:`~pivot_ompl.validity.certify.certify` with ``exact=True``), or refused.
        """
        if da <= 0.0 or db <= 0.0:
            return False
        if self.proves(da, db, a, b):
            return True
        dyaw = wrap_angle(b[2] - a[2])
        lip = self.sweep(a, b)

        def at(s: float) -> float:
            return clearance((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]),
                              a[2] + s * dyaw))

        return certify(at, lip, tolerance=self.tolerance, d0=da, d1=db, exact=True).valid

    # -- the resting box ----------------------------------------------------------------
    def box_lower_bound(self, p: Pose, obj: Pose) -> float:
        """Lower bound of the robot's clearance to the box at ``obj``, less the box margin.

        The robot's centre to the box rectangle, less the turning radius.
        """
        c, sn = math.cos(obj[2]), math.sin(obj[2])
        ex, ey = p[0] - obj[0], p[1] - obj[1]
        lx, ly = abs(c * ex + sn * ey), abs(-sn * ex + c * ey)
        hw, hd = 0.5 * self.model.object_size[0], 0.5 * self.model.object_size[1]
        return math.hypot(max(0.0, lx - hw), max(0.0, ly - hd)) - self.radius - self.box_margin

    def box_clear(self, p: Pose, obj: Pose, enough: float) -> float:
        """Lower bound of the robot's clearance at ``p`` to the box at ``obj``, less the margin.

        The cheap bound (:meth:`box_lower_bound`) when it reaches ``enough``, else exact.
        """
        lb = self.box_lower_bound(p, obj)
        if lb < enough:
            return self.world.robot_box_distance(p, obj) - self.box_margin
        return lb

    def exact(self, p: Pose, obj: Pose | None) -> float:
        """Clearance (m) of the robot at ``p`` to obstacles, bounds and the resting box."""
        d = self.static_exact(p)
        if obj is not None and d > 0.0:
            d = min(d, self.box_clear(p, obj, d))
        return d

    def exact_parts(self, p: Pose, obj: Pose) -> tuple[float, float]:
        """:meth:`exact` in two parts: to the obstacles and bounds, and to the box.

        The second is a lower bound less the margin, ``-inf`` when the first is not positive.
        """
        d = self.static_exact(p)
        return d, (self.box_clear(p, obj, d) if d > 0.0 else -math.inf)

    def free_between(self, a: Pose, b: Pose, obj: Pose, ca: tuple[float, float],
                     cb: tuple[float, float]) -> bool:
        """:meth:`segment_free` from both ends' :meth:`exact_parts` (no query at the ends)."""
        if min(ca) <= 0.0 or min(cb) <= 0.0:
            return False
        if a == b:
            return True
        if self.proves(min(ca), min(cb), a, b):
            return True  # the ends' clearances alone certify it
        sweep = self.sweep(a, b)
        if not self.certified(a, b, self.static_exact, ca[0], cb[0]):
            return False
        return self.certified(a, b, lambda p: self.box_clear(p, obj, sweep), ca[1], cb[1])

    def segment_free(self, a: Pose, b: Pose, obj: Pose | None, *, da: float | None = None,
                     db: float | None = None) -> bool:
        """The straight motion ``a -> b`` (linear yaw) is certified free.

        ``da``/``db``: lower bounds of the end clearances (obstacles, bounds and box), if
        known. The obstacles and bounds, and the box, are certified apart.
        """
        if da is not None and da <= 0.0:
            return False
        if a == b:
            return (da if da is not None else self.exact(a, obj)) > 0.0
        if da is not None and db is not None and self.proves(da, db, a, b):
            return True  # the ends' clearances alone certify it
        sa = da if da is not None else self.static_exact(a)
        sb = db if db is not None and db > 0.0 else self.static_exact(b)
        if not self.certified(a, b, self.static_exact, sa, sb):
            return False
        if obj is None:
            return True
        enough = self.sweep(a, b)
        ba = max(self.box_clear(a, obj, enough), da if da is not None else -math.inf)
        bb = max(self.box_clear(b, obj, enough), db if db is not None else -math.inf)
        return self.certified(a, b, lambda p: self.box_clear(p, obj, enough), ba, bb)


class BoxedClearance:
    """What is known of the lattice with the box resting at one pose (cached per state)."""

    def __init__(self, base: WalkClearance, obj: Pose) -> None:
        """Nothing known yet."""
        self.base, self.obj = base, obj
        #: lower bound of each state's clearance (obstacles, bounds and box)
        self._states: dict[State, float] = {}
        #: lower bound of each state's clearance to the box, less the margin
        self._box: dict[State, float] = {}
        #: lattice motions (end states in order) certified clear of the box
        self._motions: dict[tuple[State, State], bool] = {}

    def box_state(self, s: State) -> float:
        """Lower bound of the robot's clearance at ``s`` to the box (cached)."""
        v = self._box.get(s)
        if v is None:
            base = self.base
            v = self._box[s] = base.box_clear(base.pose(s), self.obj, 2.0 * base.resolution)
        return v

    def state(self, s: State) -> float:
        """Lower bound of the robot's clearance at ``s`` to everything (cached)."""
        v = self._states.get(s)
        if v is not None:
            return v
        v = self.base.static_state(s)
        if v > 0.0:
            v = min(v, self.box_state(s))
        self._states[s] = v
        return v

    def motion_free(self, u: State, v: State) -> bool:
        """The lattice motion between ``u`` and ``v`` is certified free (both ends free).

        Against the obstacles and bounds (cached for the scene: the same motions recur in
        every walk) and against the resting box (cached here), each from its own clearances.
        """
        key = (u, v) if u < v else (v, u)
        if not self.base.static_motion_free(key):
            return False
        ok = self._motions.get(key)
        if ok is None:
            base, obj = self.base, self.obj
            a, b = base.pose(key[0]), base.pose(key[1])
            enough = base.sweep(a, b)
            ok = base.certified(a, b, lambda p: base.box_clear(p, obj, enough),
                                self.box_state(key[0]), self.box_state(key[1]))
            self._motions[key] = ok
        return ok
