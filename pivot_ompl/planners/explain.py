"""Why a plan looks as it does: each regrasp's forcing passage, the pivot rate against its ideal.

:func:`explain_plan` adds to a plan's ``quality`` block (:func:`~pivot_ompl.quality.plan_quality`)
the fields a user asks about first (documented in ``docs/quality.md``):

``pivot_rate_ratio``
    pivots per metre over the ideal rate (``pivots_per_m / ideal_pivots_per_m``; 1 is a
    plan of full alternating rotations, ``null`` when the plan does not move the box).
``regrasps_unforced``
    how many regrasps neither a passage (below) nor the scene's proven lower bound forces:
    of the regrasps no passage forces, those the bound does not account for
    (:func:`unforced_regrasps`).
``regrasp_reasons``
    one entry per regrasp, in plan order: ``{"pose": [x, y, yaw], "from_grasp": g,
    "to_grasp": h, "forced": bool, "passage": {"pose": [x, y, yaw], "obstacles": [i, ...]}
    | null}``.

A regrasp from grasp ``g`` to ``h`` is *forced* by a passage when the box, held at ``g``,
cannot take the poses of the transfer that follows it: the passage is the first such pose
(where robot or box at ``g`` collides, :meth:`PivotChecker.state_valid`) and ``obstacles``
the indices (in the scene's ``obstacles`` list) of the obstacles nearest to the assembly
there (within :data:`NEAR` m). When ``g`` fits every pose of the next transfer the
regrasp is reported *not forced*: the plan could have kept its grasp along the same route,
pose by pose (the motions between the poses are not re-checked: a hint, not a proof).
"""

from __future__ import annotations

import logging
import math
from typing import Any

import shapely
from shapely.geometry import Polygon

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.footprints import obstacle_footprint, obstacle_footprints

log = logging.getLogger(__name__)

#: Obstacles within this distance (m) of the assembly at a forcing pose are named.
NEAR = 0.1


def _poses(phase: TransferPhase) -> list[Pose]:
    return [phase.object_start, *(st.object for st in phase.steps)]


def _rectangle(pose: Pose, length: float, width: float) -> Polygon:
    """The ``length`` x ``width`` rectangle centred at ``pose``, ``length`` along its yaw."""
    x, y, yaw = pose
    c, s = math.cos(yaw), math.sin(yaw)
    return Polygon([(x + c * u - s * v, y + s * u + c * v)
                    for u, v in ((-length / 2, -width / 2), (length / 2, -width / 2),
                                 (length / 2, width / 2), (-length / 2, width / 2))])


def _obstacles_near(checker: PivotChecker, pose: Pose, grasp: int,
                    tree: shapely.STRtree) -> list[int]:
    """Indices of the scene's obstacles within :data:`NEAR` of box or robot at ``pose``.

    ``tree``: the obstacles' footprints (:func:`_footprint_tree`), which pick the few to
    measure.
    """
    model, scene = checker.model, checker.scene
    depth, width = model.robot_footprint
    body = shapely.union_all([
        _rectangle(pose, model.object_size[0], model.object_size[1]),
        _rectangle(model.robot_pose(pose, grasp), depth, width)])
    near = tree.query(body, predicate="dwithin", distance=NEAR + TREE_SLACK)
    return [i for i in sorted(int(k) for k in near)
            if body.distance(obstacle_footprint(scene.obstacles[i])) <= NEAR]


#: How much farther (m) than :data:`NEAR` the footprints' tree looks: its footprints, built
#: together, may differ from :func:`~.footprints.obstacle_footprint`'s in their last bits.
TREE_SLACK = 1e-6


def _footprint_tree(scene: Scene) -> shapely.STRtree:
    """A tree of the scene's obstacles' footprints, numbered as ``scene.obstacles``."""
    return shapely.STRtree(obstacle_footprints(scene.obstacles))


def regrasp_places(plan: Plan) -> tuple[tuple[float, float], ...]:
    """The box's positions (m) where ``plan`` regrasps, in plan order."""
    return tuple((ph.object_pose[0], ph.object_pose[1]) for ph in plan.phases
                 if isinstance(ph, TransitPhase) and ph.from_grasp != ph.to_grasp)


def regrasp_reasons(plan: Plan, checker: PivotChecker) -> list[dict[str, Any]]:
    """One entry per regrasp of ``plan`` (see the module docstring), in plan order."""
    out: list[dict[str, Any]] = []
    phases = list(plan.phases)
    tree: shapely.STRtree | None = None  # built for the first passage
    for i, ph in enumerate(phases):
        if not isinstance(ph, TransitPhase) or ph.from_grasp == ph.to_grasp:
            continue
        nxt = next((p for p in phases[i + 1:] if isinstance(p, TransferPhase)), None)
        passage = None
        if nxt is not None:
            for q in _poses(nxt)[1:]:
                if not checker.state_valid(q, ph.from_grasp):
                    if tree is None:
                        tree = _footprint_tree(checker.scene)
                    passage = {"pose": list(q),
                               "obstacles": _obstacles_near(checker, q, ph.from_grasp, tree)}
                    break
        out.append({"pose": list(ph.object_pose), "from_grasp": ph.from_grasp,
                    "to_grasp": ph.to_grasp, "forced": passage is not None,
                    "passage": passage})
    return out


def explain_plan(plan: Plan, scene: Scene, quality: dict[str, Any], *,
                 checker: PivotChecker | None = None) -> dict[str, Any]:
    """The fields to add to the plan's ``quality`` block (module docstring), as a dict.

    ``checker``: the scene's (one is made when the plan has a regrasp and none is given).
    """
    ideal = quality.get("ideal_pivots_per_m") or 0.0
    reasons: list[dict[str, Any]] = []
    if plan.regrasps:
        reasons = regrasp_reasons(plan, checker or PivotChecker(scene))
    return {"pivot_rate_ratio": quality["pivots_per_m"] / ideal if ideal > 0 else None,
            "regrasps_unforced": unforced_regrasps(
                reasons, lower_bound=quality.get("regrasps_lower_bound")),
            "regrasp_reasons": reasons}


def unforced_regrasps(reasons: list[dict[str, Any]], *, lower_bound: int | None) -> int:
    """How many of a plan's regrasps nothing known forces.

    A regrasp is forced when its reason names a passage (``reasons``: :func:`regrasp_reasons`'
    entries, one per regrasp of the plan), and the scene's proven ``lower_bound`` (fewest
    regrasps any plan needs; ``None``: unknown) forces as many as it exceeds the passages'
    count by: of the ``u`` regrasps no passage forces, ``min(u, regrasps - lower_bound)``
    (never below 0) are unforced. A bound the passages already meet (a coarse 0 included)
    makes no forced regrasp unforced.
    """
    unforced = sum(not r["forced"] for r in reasons)
    if lower_bound is None:
        return unforced
    return max(0, min(unforced, len(reasons) - lower_bound))


def explain_lines(quality: dict[str, Any]) -> list[str]:
    """Lines for ``plan``'s output: the pivot rate against the ideal, each regrasp's reason."""
    lines = []
    ratio = quality.get("pivot_rate_ratio")
    if ratio is not None:
        lines.append(f"pivot rate {ratio:.2f} x the ideal")
    for k, r in enumerate(quality.get("regrasp_reasons") or [], 1):
        x, y, _ = r["pose"]
        head = f"regrasp {k} at ({x:.2f}, {y:.2f}), grasp {r['from_grasp']} -> {r['to_grasp']}"
        p = r["passage"]
        if p is None:
            lines.append(f"{head}: not forced")
            continue
        px, py, _ = p["pose"]
        near = ", ".join(str(i) for i in p["obstacles"]) or "none within 0.1 m"
        lines.append(f"{head}: forced by the passage at ({px:.2f}, {py:.2f}) "
                     f"(obstacles {near})")
    return lines
