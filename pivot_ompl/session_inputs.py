"""A planning session's inputs, validated: its arguments, observed poses, obstacles, routes.

:class:`~pivot_ompl.session.PlanningSession` takes its scene, planner and flags when made, and
at every replan an observed box (and robot) pose, obstacles that appeared or went, and the
route of the plan being executed (a plan file's ``route`` field). Each is checked here and an
error names the argument at fault (:class:`~pivot_ompl.errors.InputError`); obstacles given as
mappings are read as a scene file's are.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import Any

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.grasp import GRASPS, check_grasp
from pivot_ompl.plan_arguments import MAX_SEED
from pivot_ompl.planfile import Plan
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.registry import check_planner_name
from pivot_ompl.planners.repair import State, route_of
from pivot_ompl.scene import (
    MAX_COORD,
    MAX_YAW,
    BoxObstacle,
    CylinderObstacle,
    Obstacle,
    PolygonObstacle,
    Scene,
    check_pose,
    obstacles_from_list,
)


def route_of_plan(p: Plan) -> list[State]:
    """A plan's route (its ``route`` field), ``[]`` for a plan without one.

    Raises:
        InputError: a state of the route is not ``[x, y, yaw, grasp]`` within a scene's
            limits (naming ``executing.route[i]``).
    """
    raw = p.extra.get("route")
    if not isinstance(raw, list) or len(raw) < 2:
        return []
    try:  # the whole route at once (200 000 states in 0.1 s); a bad state is then named
        a = np.array(raw, dtype=float)
        ok = a.ndim == 2 and a.shape[1] == 4 and bool(
            np.all(np.abs(a[:, :2]) <= MAX_COORD) and np.all(np.abs(a[:, 2]) <= MAX_YAW)
            and np.all(np.isin(a[:, 3], GRASPS)))
        ok = ok and all(type(q[3]) is int for q in raw)
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        for i, q in enumerate(raw):
            field = f"executing.route[{i}]"
            if not isinstance(q, list | tuple) or len(q) != 4:
                raise InputError(field, q, "must be [x, y, yaw, grasp]")
            check_pose(list(q[:3]), field=field)
            check_grasp(q[3], field=f"{field}[3]")
    return route_of(raw)


def check_session(scene: Any, planner: Any, config: Any, seed: Any, bound: Any,
                   executing: Any, repair: Any) -> None:
    """Validate :class:`PlanningSession`'s arguments (naming the one at fault)."""
    if not isinstance(scene, Scene | str | os.PathLike):
        raise InputError("scene", type(scene).__name__,
                         "must be a Scene, a scene file path or a shipped scene name")
    if not isinstance(planner, str):
        raise InputError("planner", type(planner).__name__, "must be a planner's name")
    check_planner_name(planner)
    if config is not None and not isinstance(config, RegraspConfig):
        raise InputError("config", type(config).__name__, "must be a RegraspConfig or None")
    check_seed(seed, field="seed", optional=False)
    for name, flag in (("bound", bound), ("repair", repair)):
        if not isinstance(flag, bool):
            raise InputError(name, flag, "must be True or False")
    if executing is not None and not isinstance(executing, Plan):
        raise InputError("executing", type(executing).__name__,
                         "must be a Plan (pivot_ompl.load_plan(path) reads one) or None")


def check_seed(seed: Any, *, field: str = "seed", optional: bool = True) -> None:
    """Raise unless ``seed`` is an integer in ``[0, MAX_SEED]`` (or ``None`` when optional)."""
    if optional and seed is None:
        return
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise InputError(field, seed, f"must be an integer in [0, {MAX_SEED}]")


def observed_pose(value: Any, field: str) -> tuple[float, float, float]:
    """The observed pose ``value`` (x, y, yaw) checked as a scene's pose, named ``field``."""
    if value is None:
        raise InputError(field, None, "is required: the observed pose (x, y, yaw)")
    if isinstance(value, str | bytes) or not isinstance(value, Sequence | np.ndarray):
        raise InputError(field, type(value).__name__, "must be a sequence (x, y, yaw)")
    return check_pose(list(value), field=field)


def listed(value: Any, field: str) -> list:
    """``value`` as a list, or an error naming ``field`` when it is not a sequence."""
    if isinstance(value, str | bytes | dict) or not isinstance(value, Sequence | np.ndarray):
        raise InputError(field, type(value).__name__, "must be a list")
    return list(value)


def added_obstacles(items: Any) -> tuple[Obstacle, ...]:
    """The obstacles of ``add_obstacles``, validated as a scene file's are.

    Each item is a mapping as in a scene file or an obstacle object.
    """
    docs = []
    for i, o in enumerate(listed(items, "add_obstacles")):
        if isinstance(o, dict):
            docs.append(o)
        elif isinstance(o, BoxObstacle):
            docs.append({"type": "box", "center": list(o.center), "size": list(o.size),
                         "yaw": o.yaw, "height": o.height})
        elif isinstance(o, CylinderObstacle):
            docs.append({"type": "cylinder", "center": list(o.center), "radius": o.radius,
                         "height": o.height})
        elif isinstance(o, PolygonObstacle):
            docs.append({"type": "polygon", "points": [list(p) for p in o.points],
                         "height": o.height})
        else:
            raise InputError(f"add_obstacles[{i}]", type(o).__name__,
                             "must be an obstacle or a mapping as in a scene file")
    return obstacles_from_list(docs, field="add_obstacles")
