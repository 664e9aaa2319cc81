"""A run of pivot rotations checked: inside the bounds, and every sweep certified free.

The kernel of :class:`~pivot_ompl.checking.transfer_check.TransferCheck`. Rotation by
rotation, the box and the robot must stay inside the bounds (their farthest points bulge out
by ``r (1 - cos(alpha/2))`` mid-rotation) and their swept volumes must be certified free
(:func:`~pivot_ompl.validity.certify.certify` with ``exact=True``: a point moves at most
``r |alpha|``, ``r`` the body's reach from the pivot corner, and a sweep passes only where the
clearances prove it free at every angle, never by the tolerance alone: the plan writes
consecutive rotations about one corner as one, and any sampling of a sweep proved free so,
whole or in parts, finds it free).

Clearances are measured lazily (:class:`Clearance`): a rotation whose start clearance ``d0``
exceeds the farthest any point moves (``r |alpha|``) is free with no query, and its end keeps
at least ``d0 - r |alpha|``; that lower bound, with the pose it bounds, is carried on and the
clearance measured only where a decision needs more than the bound (a sweep the bound does
not certify, a refinement's clearance bound). A lower bound never changes whether a sweep
passes: :func:`~pivot_ompl.validity.certify.certify` would only bisect intervals the exact
clearance accepts as free; and every sweep the bound does not decide is certified from the
measured clearance, as without the bound.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.pivoting.kinematics import LEFT, Rotation
from pivot_ompl.se2 import Pose, rotate_about
from pivot_ompl.validity.certify import certify
from pivot_ompl.validity.collision import CollisionWorld

__all__ = ["Clearance", "RotationSweeps"]


class Clearance(NamedTuple):
    """A body's clearance (m, beyond the kept one) at a car pose: measured or bounded below.

    Attributes:
        value: the measured clearance where ``at`` is ``None``; else a positive lower bound
            of the clearance at car pose ``at``.
        at: ``None`` (measured), or the car pose to measure the clearance at on demand.
    """

    value: float
    at: Pose | None = None


#: The clearance of a body that is not checked (or of a world without obstacles).
UNCHECKED = Clearance(math.inf)

#: Round-off (m) allowed for between two distance queries: coal's GJK answers within about a
#: micrometre, so a bound carried from one query is lowered by this before it stands for
#: another (a rotation by 1e-12 rad measured 4.5e-7 m less at its end than at its start).
BOUND_SLACK = 1e-5

#: Edge starts whose clearances :meth:`RotationSweeps.start` keeps (then it starts afresh):
#: the edges a planner checks share their starts (an optimiser's node, a search's vertex).
KEPT_STARTS = 4096


class RotationSweeps:
    """The sweeps of pivot rotations of one scene, checked (see the module docstring).

    Args:
        model: box and robot geometry.
        world: obstacles and bounds.
        tolerance: swept-check tolerance (m).

    Attributes:
        reach: per grasp, the farthest points (m) of the box and of the holding robot from a
            pivot corner.
        spread: per grasp, the farthest corner (m) of the box and of the holding robot from
            the car.
    """

    def __init__(self, model: BoxGraspModel, world: CollisionWorld, *,
                 tolerance: float) -> None:
        """Each body's reach from a pivot corner and spread round the car, per grasp."""
        self.model, self.world, self.tolerance = model, world, tolerance
        self.reach: dict[int, tuple[float, float]] = {}
        self.spread: dict[int, tuple[float, float]] = {}
        for g in range(4):
            car = (0.0, 0.0, 0.0)
            a = model.pivots(car, g)[LEFT]
            box = model.object_corners(model.object_from_car(car, g))
            rob = model.held_corners(model.robot_from_car(car, g), g)
            self.reach[g] = (max(math.hypot(x - a[0], y - a[1]) for x, y in box),
                             max(math.hypot(x - a[0], y - a[1]) for x, y in rob))
            self.spread[g] = (max(math.hypot(x, y) for x, y in box),
                              max(math.hypot(x, y) for x, y in rob))
        #: by edge start and grasp, the clearances measured there: 0 the box's, 1 the robot's
        self._starts: dict[tuple[Pose, int], dict[int, float]] = {}

    def box_distance(self, car: Pose, grasp: int) -> float:
        """The box's clearance (m) at car pose ``car``."""
        return self.world.box_distance(self.model.object_from_car(car, grasp))

    def robot_distance(self, car: Pose, grasp: int) -> float:
        """The holding robot's clearance (m) at car pose ``car``."""
        return self.world.held_distance(self.model.robot_from_car(car, grasp), grasp)

    def start(self, car: Pose, grasp: int, with_robot: bool) -> tuple[Clearance, Clearance]:
        """The box's and (``with_robot``) the robot's clearances measured at an edge's start.

        Kept by pose (:data:`KEPT_STARTS` of them): the same numbers as measured again.
        """
        key = (car, grasp)
        starts = self._starts
        if len(starts) >= KEPT_STARTS and key not in starts:
            starts.clear()
        kept = starts.setdefault(key, {})
        db = kept.get(0)
        if db is None:
            db = kept[0] = self.box_distance(car, grasp)
        if not with_robot:
            return Clearance(db), UNCHECKED
        dr = kept.get(1)
        if dr is None:
            dr = kept[1] = self.robot_distance(car, grasp)
        return Clearance(db), Clearance(dr)

    def measured(self, clear: tuple[Clearance, Clearance],
                 grasp: int) -> tuple[Clearance, Clearance]:
        """The box's and the robot's clearances, each measured where it was a lower bound."""
        cb, cr = clear
        if cb.at is not None:
            cb = Clearance(self.box_distance(cb.at, grasp))
        if cr.at is not None:
            cr = Clearance(self.robot_distance(cr.at, grasp))
        return cb, cr

    def in_bounds(self, car: Pose, grasp: int, with_robot: bool, bulge_b: float,
                  bulge_r: float) -> bool:
        """Whether the box's (and robot's) corners at ``car`` keep the bulges from the sides.

        Accepted at once when the car keeps a body's farthest corner (:attr:`spread`) plus
        its bulge from every side (a corner is no farther from a side than that); else the
        corners are placed and measured.
        """
        m, w = self.model, self.world
        x0, y0, x1, y1 = w.bounds
        margin = min(car[0] - x0, x1 - car[0], car[1] - y0, y1 - car[1])
        s_box, s_rob = self.spread[grasp]
        if margin - s_box >= bulge_b and (not with_robot or margin - s_rob >= bulge_r):
            return True
        if w.bounds_margin(m.object_corners(m.object_from_car(car, grasp))) < bulge_b:
            return False
        return not with_robot or \
            w.bounds_margin(m.held_corners(m.robot_from_car(car, grasp), grasp)) >= bulge_r

    def _swept(self, dist: Callable[[Pose, int], float], base: Pose, rot: Rotation,
               grasp: int, reach: float, c0: Clearance) -> Clearance | None:
        """The body's clearance at the rotation's end, or ``None`` if its sweep is not free.

        ``dist``: the body's clearance at a car pose; ``reach``: its farthest point from the
        pivot (a point moves at most ``reach |angle|``); ``c0``: its clearance at ``base``.
        A sweep whose start clearance (bound or measured) exceeds the farthest any point
        moves (by :data:`BOUND_SLACK`) is free with no query, and its end keeps at least
        ``d0 - reach |angle|`` (a lower bound, returned less the slack); else it is
        certified from the measured clearances at both ends, and the end's returned.
        """
        lipschitz = reach * abs(rot.angle)
        if c0.value > lipschitz + BOUND_SLACK:
            return Clearance(c0.value - lipschitz - BOUND_SLACK, rot.car)

        def at(s: float) -> float:
            return dist(rotate_about(base, rot.pivot, s * rot.angle), grasp)

        d0, d1 = c0.value, dist(rot.car, grasp)
        if c0.at is not None and d1 > 0.0 and d0 + d1 <= lipschitz:
            d0 = dist(c0.at, grasp)  # the bound does not certify the sweep: measured
        ok = certify(at, lipschitz, tolerance=self.tolerance, d0=d0, d1=d1, exact=True).valid
        return Clearance(d1) if ok else None

    def rotations(self, prev: Pose, rots: tuple[Rotation, ...], grasp: int, with_robot: bool,
                  cb: Clearance, cr: Clearance) -> tuple[str, tuple[Clearance, Clearance]]:
        """``(failure, clearances at the end)``; failure ``""`` when every rotation passes.

        ``cb``, ``cr``: the box's and the robot's clearances at ``prev``
        (:data:`UNCHECKED` for a body not checked). The clearances returned may be lower
        bounds (the module docstring): :meth:`measured` gives them measured.
        """
        r_box, r_rob = self.reach[grasp]
        obstacles = self.world.has_obstacles
        for rot in rots:
            bulge = 1.0 - math.cos(0.5 * rot.angle)
            if not (self.in_bounds(prev, grasp, with_robot, r_box * bulge, r_rob * bulge)
                    and self.in_bounds(rot.car, grasp, with_robot, r_box * bulge,
                                       r_rob * bulge)):
                return "leaves the bounds", (cb, cr)
            if obstacles:
                cb_end = self._swept(self.box_distance, prev, rot, grasp, r_box, cb)
                if cb_end is None:
                    return "box collides", (cb, cr)
                cb = cb_end
                if with_robot:
                    cr_end = self._swept(self.robot_distance, prev, rot, grasp, r_rob, cr)
                    if cr_end is None:
                        return "robot collides", (cb, cr)
                    cr = cr_end
            prev = rot.car
        return "", (cb, cr)
