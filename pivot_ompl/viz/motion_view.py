"""Whole-body motion view: the URDF robot, the box as moved (inclined), footsteps and ZMP.

The motion is resampled at ``fps`` keys per second (nearest samples, first and last kept);
the root link gets position and rotation tracks, every 1-dof joint only the track that its
joint moves (rotation for revolute, position for prismatic). Footsteps are the resting
placements of the foot links (``left_foot``/``right_foot``, else links named ``*foot*`` or
``*sole*``): runs of samples where the foot is near its lowest height and still.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Any

import meshcat
import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.humanoids import profile_of, urdf_file
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import DEFAULT_OBJECT_SIZE, Scene
from pivot_ompl.viz import draw
from pivot_ompl.viz.animation import AnimationBuilder
from pivot_ompl.viz.chapters import Chapter, ReplayGuide, replay_guide, standing_height
from pivot_ompl.viz.plan_view import ReplayInfo, draw_plan_markers, show_scene
from pivot_ompl.viz.shapes import quat_xyzw_to_matrix
from pivot_ompl.viz.urdf_visuals import RobotModel, draw_robot, load_robot

log = logging.getLogger(__name__)

FOOTSTEP_RATE = 50.0  # Hz, samples used to find resting feet


def resample_indices(t: np.ndarray, fps: float) -> np.ndarray:
    """Indices of the samples nearest to a ``fps`` grid over ``t`` (first and last kept)."""
    if len(t) <= 2 or fps <= 0:
        return np.arange(len(t))
    grid = np.arange(t[0], t[-1], 1.0 / fps)
    idx = np.clip(np.searchsorted(t, grid), 0, len(t) - 1)
    return np.unique(np.r_[0, idx, len(t) - 1])


def pose7_to_matrix(p: np.ndarray) -> np.ndarray:
    """``(K, 4, 4)`` transforms from ``(K, 7)`` xyz + quaternion xyzw."""
    m = np.repeat(np.eye(4)[None], len(p), axis=0)
    m[:, :3, :3] = quat_xyzw_to_matrix(p[:, 3:7])
    m[:, :3, 3] = p[:, :3]
    return m


def foot_links(model: RobotModel) -> list[str]:
    """The links whose resting placements are footsteps."""
    names = model.links
    exact: list[str] = [n for n in ("left_foot", "right_foot") if n in names]
    if exact:
        return exact
    return [n for n in names if "foot" in n.lower() or "sole" in n.lower()][:2]


def footsteps(tf: np.ndarray, t: np.ndarray, *, height_tol: float = 0.01,
              speed_tol: float = 0.05, min_time: float = 0.05,
              merge: float = 0.02) -> list[tuple[float, float, float]]:
    """Resting placements ``(x, y, yaw)`` of a foot from its world transforms ``(K, 4, 4)``."""
    if len(t) < 2:
        return [(float(tf[0, 0, 3]), float(tf[0, 1, 3]),
                 math.atan2(tf[0, 1, 0], tf[0, 0, 0]))] if len(t) else []
    p = tf[:, :3, 3]
    dt = np.maximum(np.diff(t), 1e-9)
    speed = np.r_[np.linalg.norm(np.diff(p, axis=0), axis=1) / dt, 0.0]
    rest = (p[:, 2] <= p[:, 2].min() + height_tol) & (speed <= speed_tol)
    out: list[tuple[float, float, float]] = []
    i, n = 0, len(t)
    while i < n:
        if not rest[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and rest[j + 1]:
            j += 1
        if t[j] - t[i] >= min_time or (i == 0 or j == n - 1):
            k = (i + j) // 2
            pose = (float(p[k, 0]), float(p[k, 1]), math.atan2(tf[k, 1, 0], tf[k, 0, 0]))
            if not out or math.hypot(pose[0] - out[-1][0], pose[1] - out[-1][1]) > merge:
                out.append(pose)
        i = j + 1
    return out


def resolve_urdf(motion: Motion, urdf: str | Path | None = None) -> Path:
    """The URDF to draw.

    ``urdf`` if given, else the model the motion names: a humanoid profile's URDF or a
    shipped file (:func:`pivot_ompl.humanoids.urdf_file`).

    Raises:
        InputError: the motion's ``urdf`` is neither, or the profile's data is not installed.
    """
    if urdf is not None:
        return Path(urdf)
    return urdf_file(motion.urdf, field="motion.urdf")


def show_motion(vis: meshcat.Visualizer, motion: Motion, *, scene: Scene | None = None,
                object_size: tuple[float, float, float] | None = None,
                urdf: str | Path | None = None, fps: float = 25.0,
                tolerance: float = 1e-3, plan: Plan | None = None, play: bool = True,
                camera: bool = True, sim_box: np.ndarray | None = None) -> ReplayInfo:
    """Draw ``scene`` and animate the whole-body ``motion`` (robot links, box, footsteps).

    Args:
        vis: the visualizer to draw into.
        motion: the motion (:func:`~pivot_ompl.motionfile.load_motion`).
        scene: floor and obstacles to draw, or ``None`` (a floor around the motion).
        object_size: box size (w, d, h) in m; default the motion's, then the scene's, then
            the paper's box.
        urdf: robot model file; default the motion's ``urdf`` (relative to the repo root).
        fps: animation keys per second (fewer keys, smaller HTML).
        tolerance: keys that linear interpolation reproduces within this (m, and rad/2 for
            rotations) are dropped; 0 keeps every key.
        plan: the plan the motion executes: its Reeds-Shepp paths and pivot points are drawn.
        play: start playing once loaded.
        camera: aim the default camera at the floor.
        sim_box: a second box's pose at each motion sample (N x 7, centre and quaternion
            x y z w, as ``motion.box``), drawn beside the motion's: the simulated box of
            ``pivot-ompl simulate``.
    """
    draw.check_view(vis, scene=scene, motion=(motion, Motion))
    if sim_box is not None and np.shape(sim_box) != np.shape(motion.box):
        raise InputError("sim_box", list(np.shape(sim_box)),
                         f"must have the motion's box shape {list(np.shape(motion.box))}")
    if plan is not None:
        draw.check_view(vis, plan=(plan, Plan))
    model = load_robot(resolve_urdf(motion, urdf))
    size = object_size or motion.object_size or (
        scene.model.object_size if scene is not None else None)
    if size is None:
        log.warning("no box size in the motion or a scene: drawing the paper's box %s",
                    DEFAULT_OBJECT_SIZE)
        size = DEFAULT_OBJECT_SIZE
    idx = resample_indices(motion.t, fps)
    t = motion.t[idx] - motion.t[0]
    q = motion.q[idx]
    root_tf = pose7_to_matrix(q[:, :7])
    values = model.joint_values(q[:, 7:], motion.joint_names)
    box_tf = pose7_to_matrix(motion.box[idx])

    bounds = None
    if scene is None:
        xy = np.r_[q[:, :2], motion.box[idx, :2]]
        bounds = (float(xy[:, 0].min()) - 1.5, float(xy[:, 1].min()) - 1.5,
                  float(xy[:, 0].max()) + 1.5, float(xy[:, 1].max()) + 1.5)
    draw.clear(vis)
    show_scene(vis, scene, bounds=bounds, camera=camera)

    robot = vis["robot"]
    n_vis = draw_robot(robot, model)
    draw.draw_box(vis["box"], size)
    vis["box"].set_transform(box_tf[0])
    robot[model.root].set_transform(root_tf[0])

    anim = _animation(vis, model, t, box_tf, root_tf, values, tolerance)
    if sim_box is not None:
        sim_tf = pose7_to_matrix(np.asarray(sim_box, dtype=float)[idx])
        draw.draw_sim_box(vis["sim_box"], size)
        vis["sim_box"].set_transform(sim_tf[0])
        anim.add_transforms("sim_box", t, sim_tf, position_tol=tolerance,
                            rotation_tol=0.5 * tolerance)

    n_steps = _draw_footsteps(vis, model, motion)
    n_piv = 0
    if plan is not None:
        n_piv, _ = draw_plan_markers(vis, plan)
    if motion.zmp is not None and len(motion.zmp) > 1:
        draw.draw_polyline(vis["zmp"], motion.zmp[idx], color=draw.PIVOT_COLOR, z=0.01)
    if len(t) > 1:
        anim.send(play=play)
    log.info("motion replay: %d visuals, %d samples, %d track keys, %.1f s, %d footsteps",
             n_vis, len(t), anim.keys, float(t[-1]), n_steps)
    nodes = ("floor", "box", "robot") + (("footsteps",) if n_steps else ()) + (
        ("sim_box",) if sim_box is not None else ())
    frame = scene.bounds if scene is not None else bounds
    assert frame is not None  # noqa: S101 - for mypy: bounds is set without a scene
    guide = motion_guide(motion, plan=plan, scene=scene).with_frame(
        frame, max(standing_height(None, scene), float(np.max(q[:, 2])) + 0.8, float(size[2])))
    guide.extra["legend"] = draw.legend(_drawn(motion, scene, plan, n_piv, n_steps) + (
        ["sim_box"] if sim_box is not None else []))
    return ReplayInfo(float(t[-1]), len(t), nodes, n_steps, n_piv, guide)


def _drawn(motion: Motion, scene: Scene | None, plan: Plan | None, n_piv: int,
           n_steps: int) -> list[str]:
    """The kinds of shape a motion replay draws (:func:`draw.legend` explains each)."""
    drawn = ["box", "robot_urdf"]
    if scene is not None and scene.obstacles:
        drawn.insert(0, "obstacles")
    if plan is not None:
        drawn += [k for k in ("rs_path", "walks") if any(
            (isinstance(ph, TransferPhase) and len(ph.rs_path) >= 2) if k == "rs_path" else
            isinstance(ph, TransitPhase) for ph in plan.phases)]
        drawn += ["pivots"] if n_piv else []
    return drawn + (["footsteps"] if n_steps else []) + (
        ["zmp"] if motion.zmp is not None and len(motion.zmp) > 1 else [])


def _animation(vis: meshcat.Visualizer, model: Any, t: Any, box_tf: np.ndarray,
               root_tf: np.ndarray, values: dict[str, np.ndarray],
               tolerance: float) -> AnimationBuilder:
    """The box's, the root's and every moving link's tracks."""
    anim = AnimationBuilder(vis)
    tol: dict[str, Any] = {"position_tol": tolerance, "rotation_tol": 0.5 * tolerance}
    anim.add_transforms("box", t, box_tf, **tol)
    anim.add_transforms(f"robot/{model.root}", t, root_tf, **tol)
    for link in model.links:
        j = model.joints.get(link)
        if j is None or j.type in ("fixed", "floating", "planar"):
            continue
        local = model.local_transforms(link, values[j.name])
        prismatic = j.type == "prismatic"
        anim.add_transforms(f"robot/{model.node_path(link)}", t, local,
                            rotation=not prismatic, position=prismatic, **tol)
    return anim


def _draw_footsteps(vis: meshcat.Visualizer, model: Any, motion: Motion) -> int:
    """The footsteps of the motion's feet; how many."""
    feet = foot_links(model)
    if not feet:
        log.warning("no foot link in %s: no footsteps drawn", model.path)
        return 0
    fine = resample_indices(motion.t, FOOTSTEP_RATE)
    full = motion.q[fine]
    wt = model.world_transforms(pose7_to_matrix(full[:, :7]),
                                model.joint_values(full[:, 7:], motion.joint_names), feet)
    poses = [p for f in feet for p in footsteps(wt[f], motion.t[fine])]
    sole = motion.sole_size or profile_of(motion.model).sole_size
    return draw.draw_footsteps(vis["footsteps"], poses, sole,
                               opacity=0.6)


def motion_guide(motion: Motion, *, plan: Plan | None = None,
                 scene: Scene | None = None) -> ReplayGuide:
    """Chapters and phase labels of a motion, from its ``phase`` and ``step`` arrays.

    Times are relative to the motion's first sample (as in the replay). A motion without a
    ``phase`` array has one label, ``"motion"``; a plan that does not match the motion's
    phases is ignored with a warning.
    """
    draw.check_view(scene=scene, require_vis=False, motion=(motion, Motion))
    t = motion.t - motion.t[0] if len(motion.t) else motion.t
    if motion.phase is None:
        return ReplayGuide(motion.duration, (Chapter(0.0, "start", "moment"),),
                           ((0.0, "motion"),))
    if plan is not None and len(motion.phase) and int(np.max(motion.phase)) >= len(plan.phases):
        log.warning("the motion has phases beyond the plan's %d: chapters without the plan",
                    len(plan.phases))
        plan = None
    return replay_guide(t, motion.phase, motion.step, plan=plan, scene=scene)
