"""How far a whole-body motion leaves the planner's 2-D bodies (the floor envelope check).

The planner checks a holding robot as the prism over
:meth:`~pivot_ompl.grasp.BoxGraspModel.held_outline` and a walking robot as its footprint
rectangle (:mod:`pivot_ompl.validity.collision`). This module measures, on a motion made from a
plan, the floor projection of every link's collision geometry (box corners; cylinders as
circumscribed 24-gon prisms)
against those bodies:

* during a transfer phase, the held body of the phase's grasp and the box's footprint (a hand
  on the held face may reach over it), placed where the plan puts them: attached to the box
  (its grasp frame recovered from the motion's box pose and tilt);
* during a transit phase, the walking body
  (:meth:`~pivot_ompl.grasp.BoxGraspModel.walking_extent`) swept along the phase's
  ``robot_path`` (sampled every ``path_step``), which is what the planner certifies for a walk.

The result is the largest distance (m) any point leaves its body (<= 0: inside everywhere).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.wholebody.box import BoxHold, matrix_from_quat, transform
from pivot_ompl.wholebody.hull import convex_hull
from pivot_ompl.wholebody.urdf_model import load_urdf_model


@dataclass(frozen=True)
class Excursion:
    """The worst floor excursion of a link out of the planner's body.

    Attributes:
        distance: how far (m) the link's floor projection leaves the body (<= 0: inside).
        link: the URDF link.
        index: sample index.
        time: sample time (s).
        body: ``"held"`` or ``"walking"``.
    """

    distance: float
    link: str
    index: int
    time: float
    body: str


def _outside(poly: np.ndarray, pts: np.ndarray) -> np.ndarray:
    """Largest signed distance of ``pts`` (M x 2) beyond the edges of convex CCW ``poly``."""
    a = poly
    e = np.roll(poly, -1, axis=0) - a
    n = np.stack([e[:, 1], -e[:, 0]], axis=1) / np.linalg.norm(e, axis=1)[:, None]
    return ((pts[:, None, :] - a[None]) * n[None]).sum(axis=2).max(axis=1)


def _box_rect(model: BoxGraspModel, grasp: int) -> np.ndarray:
    """The held box's footprint in the robot frame (CCW): the planner checks it as the box."""
    face = 0.5 * model.robot_footprint[0] + model.standoff
    far, ell = face + 2.0 * model.half_extent(grasp), model.edge_half_length(grasp)
    return np.array([(face, -ell), (far, -ell), (far, ell), (face, ell)])


def outline_points(g) -> np.ndarray:  # noqa: ANN001 - a coal shape
    """Points (in the shape's frame) whose convex hull is the shape (a cylinder: 24-gons)."""
    import coal

    if isinstance(g, coal.Cylinder):
        a = np.linspace(0.0, 2 * np.pi, 24, endpoint=False)
        # circumscribed polygon: vertices at r / cos(pi / 24)
        r = g.radius / np.cos(np.pi / 24)
        ring = np.stack([r * np.cos(a), r * np.sin(a)], axis=1)
        return np.vstack([np.column_stack([ring, np.full(24, z)])
                          for z in (-g.halfLength, g.halfLength)])
    g.computeLocalAABB()
    lo, hi = np.asarray(g.aabb_local.min_), np.asarray(g.aabb_local.max_)
    return np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1])
                     for z in (lo[2], hi[2])])


def _path_poses(path: tuple, step: float) -> np.ndarray:
    """Poses (x, y, yaw) along a robot path, straight segments, yaw interpolated."""
    out = [path[0]]
    for a, b in zip(path, path[1:], strict=False):
        dyaw = math.remainder(b[2] - a[2], 2 * math.pi)
        n = max(1, int(math.ceil(max(math.hypot(b[0] - a[0], b[1] - a[1]),
                                     0.4 * abs(dyaw)) / step)))
        for k in range(1, n + 1):
            s = k / n
            out.append((a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * dyaw))
    return np.array(out)


def _outside_union(poly: np.ndarray, poses: np.ndarray, pts: np.ndarray) -> float:
    """Largest distance of any of ``pts`` outside the union of ``poly`` placed at ``poses``."""
    c, s = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    dx = pts[None, :, 0] - poses[:, None, 0]
    dy = pts[None, :, 1] - poses[:, None, 1]
    rel = np.stack([c[:, None] * dx + s[:, None] * dy, -s[:, None] * dx + c[:, None] * dy],
                   axis=2)  # poses x points x 2
    a = poly
    e = np.roll(poly, -1, axis=0) - a
    n = np.stack([e[:, 1], -e[:, 0]], axis=1) / np.linalg.norm(e, axis=1)[:, None]
    out = ((rel[:, :, None, :] - a[None, None]) * n[None, None]).sum(axis=3).max(axis=2)
    return float(out.min(axis=0).max())


def floor_excursion(motion: Motion, plan: Plan, *, stride: int = 10,
                    path_step: float = 0.02) -> list[Excursion]:
    """Per link and body, the worst excursion of its floor projection (worst first).

    Args:
        motion: a motion generated from ``plan``.
        plan: its plan (phases, grasps, robot geometry).
        stride: check every ``stride``-th sample.
        path_step: spacing (m) of the footprints along a transit's path.
    """
    import pinocchio as pin

    assert motion.phase is not None and motion.box_size is not None  # noqa: S101
    assert motion.tilt is not None  # noqa: S101
    model_g = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff,
                            robot_model=plan.robot_model)
    hold = BoxHold(tuple(float(x) for x in motion.box_size))  # type: ignore[arg-type]
    robot = load_urdf_model(motion.urdf)
    model, geom = robot.model, robot.geom
    data, gdata = model.createData(), geom.createData()
    local = [outline_points(obj.geometry) for obj in geom.geometryObjects]
    links = [model.frames[o.parentFrame].name for o in geom.geometryObjects]
    held = [convex_hull(np.array(model_g.held_outline(g))) for g in range(4)]
    boxes = [_box_rect(model_g, g) for g in range(4)]
    rect = np.array(model_g.walking_outline())
    paths = {p: _path_poses(ph.robot_path, path_step) for p, ph in enumerate(plan.phases)
             if isinstance(ph, TransitPhase)}
    best: dict[tuple[str, str], Excursion] = {}
    for i in range(0, len(motion.t), stride):
        q = motion.q[i]
        pin.framesForwardKinematics(model, data, q)
        pin.updateGeometryPlacements(model, data, geom, gdata)
        ph = plan.phases[int(motion.phase[i])]
        if isinstance(ph, TransferPhase):
            k = ph.grasp
            B = transform(matrix_from_quat(motion.box[i, 3:]), motion.box[i, :3])
            G = B @ np.linalg.inv(hold.T_G_box(k, float(motion.tilt[i])))
            car = (float(G[0, 3]), float(G[1, 3]), float(np.arctan2(G[1, 0], G[0, 0])))
            pose = model_g.robot_from_car(car, k)
            poly, box, body = held[k], boxes[k], "held"
        else:
            poses = paths[int(motion.phase[i])]
            for k_geom, M in enumerate(gdata.oMg):
                pts = (M.rotation @ local[k_geom].T).T[:, :2] + M.translation[:2]
                near = poses[np.linalg.norm(poses[:, :2] - pts.mean(axis=0), axis=1) < 1.0]
                v = _outside_union(rect, near, pts) if len(near) else math.inf
                key = (links[k_geom], "walking")
                if key not in best or v > best[key].distance:
                    best[key] = Excursion(v, key[0], i, float(motion.t[i]), "walking")
            continue
        c, s = np.cos(pose[2]), np.sin(pose[2])
        R = np.array([[c, s], [-s, c]])  # world -> robot frame
        for k_geom, M in enumerate(gdata.oMg):
            pts = (M.rotation @ local[k_geom].T).T[:, :2] + M.translation[:2]
            rel = (pts - np.array(pose[:2])) @ R.T
            v = float(np.minimum(_outside(poly, rel), _outside(box, rel)).max())
            key = (links[k_geom], body)
            if key not in best or v > best[key].distance:
                best[key] = Excursion(v, key[0], i, float(motion.t[i]), body)
    return sorted(best.values(), key=lambda e: -e.distance)
