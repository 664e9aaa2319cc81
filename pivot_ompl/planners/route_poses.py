"""Object poses that take the box's centre along a route of box positions.

A route of the box's centre (the route bound's polyline, :mod:`~pivot_ompl.analysis.route_path`)
is followed by the pivoting car, whose reference point is the supporting edge's centre: the
box's centre lies ``o`` ahead of it along its heading (``o`` half the box's depth at the
grasp). A corner of the box's route is therefore not a corner of the car's: the car that
brings the box's centre to the corner ``q`` with heading ``h`` stands at ``q - o u(h)``.
Taking the box's corners as the car's (:func:`car_corner_poses`, the other placement
:mod:`.follow_route` offers) shifts every leg by ``o``: where the route leaves a slot it
sends the car forwards into the slot first and back out again, a variant whose poses
collide.

:func:`route_poses` places the car's corners so that the box's centre passes through the
route's corners: a turn in place of the car to face the next corner and a straight push (or
pull: ``back``, the car's back to its way) that ends with the box's centre on it
(``spin``); or one pose per corner, the box's centre on it, heading halfway between the two
legs', joined by the steering's arcs. The phase's own start and end poses stay the ends.
"""

from __future__ import annotations

import math

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.se2 import Pose, wrap_angle

__all__ = ["NO_MOVE", "NO_TURN", "car_corner_poses", "route_poses", "turns_and_legs"]

#: Turns smaller than this (rad) are left out; moves shorter than this (m) too.
NO_TURN = 1e-6
NO_MOVE = 1e-3

Point = tuple[float, float]


def route_poses(checker: PivotChecker, a: Pose, b: Pose, grasp: int, route: list[Point], *,
                back: bool, spin: bool) -> tuple[Pose, ...]:
    """Object poses from ``a`` to ``b`` whose box centres pass the inner points of ``route``.

    Args:
        checker: the scene's checker (its box and grasp model).
        a: the first object pose (the route's start is its position).
        b: the last object pose (the route's end is its position).
        grasp: the grasp the box is moved with.
        route: the box centre's route, ``a``'s position first and ``b``'s last.
        back: the car faces away from its way (a pull).
        spin: turns in place and straight pushes; else one pose per corner, joined by arcs.

    Returns:
        ``a``, the poses at the corners, ``b``.
    """
    m = checker.model
    ca, cb = m.car_pose(a, grasp), m.car_pose(b, grasp)
    ahead = _ahead(checker, grasp)
    flip = math.pi if back else 0.0
    corners = list(route[1:-1])
    if not spin:
        pts = [(a[0], a[1]), *corners, (b[0], b[1])]
        out: list[Pose] = [a]
        for k in range(1, len(pts) - 1):
            h_in = math.atan2(pts[k][1] - pts[k - 1][1], pts[k][0] - pts[k - 1][0]) + flip
            h_out = math.atan2(pts[k + 1][1] - pts[k][1], pts[k + 1][0] - pts[k][0]) + flip
            h = h_in + 0.5 * wrap_angle(h_out - h_in)
            out.append(m.object_from_car(_behind(pts[k], h, ahead), grasp))
        return (*out, b)
    cars: list[Pose] = [ca]
    x, y, h = ca
    for q in corners:
        d = math.hypot(q[0] - x, q[1] - y)
        near = math.hypot(q[0] - x - ahead * math.cos(h), q[1] - y - ahead * math.sin(h))
        if d <= NO_MOVE or near <= ahead or (not back and d <= ahead + NO_MOVE):
            continue  # the box's centre is at the corner already (within the car's offset)
        turn = h + wrap_angle(math.atan2(q[1] - y, q[0] - x) + flip - h)
        if abs(turn - h) > NO_TURN:
            cars.append((x, y, turn))
        x, y, h = _behind(q, turn, ahead)
        cars.append((x, y, h))
    if math.hypot(cb[0] - x, cb[1] - y) > NO_MOVE:  # the last leg ends on b's car
        turn = h + wrap_angle(math.atan2(cb[1] - y, cb[0] - x) + flip - h)
        if abs(turn - h) > NO_TURN:
            cars.append((x, y, turn))
        cars.append((cb[0], cb[1], turn))
    if abs(wrap_angle(cb[2] - cars[-1][2])) > NO_TURN or len(cars) == 1:
        cars.append(cb)
    return (a, *(m.object_from_car(c, grasp) for c in cars[1:-1]), b)


def car_corner_poses(checker: PivotChecker, a: Pose, b: Pose, grasp: int,
                     poly: list[tuple[float, float]], *, back: bool, spin: bool
                     ) -> tuple[Pose, ...]:
    """Object poses from ``a`` to ``b`` whose car passes the corners of ``poly``.

    The car's corners are the polyline's inner points between the car's own ends; ``back``:
    the car faces away from its way (a pull). ``spin``: a turn in place at every corner and
    straight pushes between them; else one pose at each corner, heading halfway between its
    two segments', joined by the steering's arcs.
    """
    m = checker.model
    ca, cb = m.car_pose(a, grasp), m.car_pose(b, grasp)
    pts = [(ca[0], ca[1])]
    for p in [*poly[1:-1], (cb[0], cb[1])]:
        if math.hypot(p[0] - pts[-1][0], p[1] - pts[-1][1]) > NO_MOVE:
            pts.append(p)
    if len(pts) > 1 and math.hypot(cb[0] - pts[-1][0], cb[1] - pts[-1][1]) > 0:
        pts[-1] = (cb[0], cb[1])
    cars: list[Pose] = [ca]
    if not spin:
        heads = [math.atan2(q[1] - p[1], q[0] - p[0]) + (math.pi if back else 0.0)
                 for p, q in zip(pts, pts[1:], strict=False)]
        for k in range(1, len(pts) - 1):
            h = heads[k - 1] + 0.5 * wrap_angle(heads[k] - heads[k - 1])
            cars.append((pts[k][0], pts[k][1], h))
        cars.append(cb)
        return (a, *(m.object_from_car(c, grasp) for c in cars[1:-1]), b)
    for p, q in zip(pts, pts[1:], strict=False):
        h = math.atan2(q[1] - p[1], q[0] - p[0]) + (math.pi if back else 0.0)
        h = cars[-1][2] + wrap_angle(h - cars[-1][2])
        if abs(h - cars[-1][2]) > NO_TURN:
            cars.append((p[0], p[1], h))
        cars.append((q[0], q[1], h))
    if abs(wrap_angle(cb[2] - cars[-1][2])) > NO_TURN or len(cars) == 1:
        cars.append(cb)
    poses = [a, *(m.object_from_car(c, grasp) for c in cars[1:-1]), b]
    return tuple(poses)


def turns_and_legs(checker: PivotChecker, poses: tuple[Pose, ...], grasp: int) -> bool:
    """Whether ``poses`` are turns in place and straight legs of the car.

    Each step keeps the car's position (a turn) or its heading (a push or pull; the
    steering's reference path is then the straight line).
    """
    m = checker.model
    cars = [m.car_pose(q, grasp) for q in poses]
    return all(math.hypot(v[0] - u[0], v[1] - u[1]) <= NO_MOVE
               or abs(wrap_angle(v[2] - u[2])) <= NO_TURN
               for u, v in zip(cars, cars[1:], strict=False))


def _ahead(checker: PivotChecker, grasp: int) -> float:
    """How far (m) the box's centre lies ahead of the car along its heading."""
    car = checker.model.car_pose((0.0, 0.0, 0.0), grasp)
    return math.hypot(car[0], car[1])


def _behind(q: Point, heading: float, ahead: float) -> Pose:
    """The car pose at ``heading`` whose box centre is ``q``."""
    return (q[0] - ahead * math.cos(heading), q[1] - ahead * math.sin(heading), heading)
