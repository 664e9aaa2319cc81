"""A plan's quality block: its figures and its cost, from the plan alone.

The optional extra field ``quality`` of a ``pivot-plan/1`` file (:mod:`pivot_ompl.planfile`),
written by ``pivot-ompl plan``; plans without it load as before, and a reader recomputes it
with :func:`plan_quality`::

    "quality": {"pivots": n, "transfer_length": m, "pivots_per_m": r,
                "ideal_pivots_per_m": r0, "regrasps": k, "regrasps_lower_bound": k0 | null,
                "walking_length": w, "duration_estimate": s, "regrasp_cost": c,
                "cost": s + c * k, "route_length": b, "shortest_route": b0 | null,
                "route_ratio": b / b0 | null}

``transfer_length`` is the distance travelled by the supporting edge's centre (the
Reeds-Shepp car) through the step poses; ``ideal_pivots_per_m`` the rate of an alternating
push with full rotations, ``1 / (2 l sin(alpha_max/2))`` per phase (``l`` that grasp's
half-edge), weighted by length; ``walking_length`` the transits' length;
``duration_estimate`` the whole-body motion's duration (s) by
:class:`~pivot_ompl.cost.DurationModel` (per phase, pivot, radian turned and metre walked);
``regrasp_cost`` the price (s) of one regrasp on top of its execution seconds and ``cost``
the plan's cost, ``duration_estimate + regrasp_cost * regrasps``
(:class:`~pivot_ompl.cost.CostModel`: what the planner minimises); ``regrasps_lower_bound``
the fewest regrasps any valid plan of the scene needs (a proven bound,
:mod:`pivot_ompl.analysis.regrasp_bound`; ``null`` when unknown). ``route_length`` is the
box centre's route through every second step pose of each transfer (a pair of pivots is the
gait's stride: the zigzag within it is not route), ``shortest_route`` a proven lower bound on
any plan's route (:mod:`pivot_ompl.analysis.route_bound`) and ``route_ratio`` their ratio (how
far the route is from the shortest; ``null`` when either is unknown).
"""

from __future__ import annotations

import math
from typing import Any

from pivot_ompl.cost import CostModel, DurationModel
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.planfile import Plan, TransitPhase

__all__ = ["plan_quality"]


def plan_quality(plan: Plan, *, regrasps_lower_bound: int | None = None,
                 shortest_route: float | None = None,
                 durations: DurationModel | None = None,
                 costs: CostModel | None = None) -> dict[str, Any]:
    """The ``quality`` block of a plan (see the module docstring); pure, from the plan alone.

    Args:
        plan: the plan.
        regrasps_lower_bound: fewest regrasps any plan of the scene needs, if known.
        shortest_route: lower bound (m) on any plan's box route, if known.
        durations: the whole-body duration model (default: ``costs``'s).
        costs: the cost model whose price per regrasp the block reports.
    """
    costs = costs or CostModel()
    d = durations or costs.durations
    model = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff)
    half = math.sin(0.5 * plan.alpha_max)
    length = ideal = walking = turned = route = 0.0
    transfers = transits = 0
    for p in plan.phases:
        if isinstance(p, TransitPhase):
            transits += 1
            walking += p.length
            continue
        if not p.steps:
            continue
        transfers += 1
        turned += sum(abs(st.angle) for st in p.steps)
        cars = [model.car_pose(q, p.grasp) for q in
                (p.object_start, *(st.object for st in p.steps))]
        run = sum(math.hypot(b[0] - a[0], b[1] - a[1]) for a, b in zip(cars, cars[1:],
                                                                      strict=False))
        length += run
        ideal += run / (2.0 * model.edge_half_length(p.grasp) * half)
        poses = [p.object_start, *(st.object for st in p.steps)]
        stride = poses[::2] if len(poses) % 2 else [*poses[::2], poses[-1]]
        route += sum(math.hypot(b[0] - a[0], b[1] - a[1])
                     for a, b in zip(stride, stride[1:], strict=False))
    pivots = plan.pivots
    seconds = d.seconds(transfers=transfers, pivots=pivots, turned=turned, transits=transits,
                        walked=walking)
    return {
        "pivots": pivots,
        "transfer_length": length,
        "pivots_per_m": pivots / length if length > 0 else 0.0,
        "ideal_pivots_per_m": ideal / length if length > 0 else 0.0,
        "regrasps": plan.regrasps,
        "regrasps_lower_bound": regrasps_lower_bound,
        "walking_length": walking,
        "duration_estimate": seconds,
        "regrasp_cost": costs.regrasp,
        "cost": costs.plan_cost(seconds, plan.regrasps),
        "route_length": route,
        "shortest_route": shortest_route,
        "route_ratio": route / shortest_route if shortest_route else None,
    }
