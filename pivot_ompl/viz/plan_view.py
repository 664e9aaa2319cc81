"""Scene and plan views: static objects plus the box / robot-footprint animation of a plan."""

from __future__ import annotations

import dataclasses
import logging
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import meshcat
import numpy as np

from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.humanoids import profile_of
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.viz import draw
from pivot_ompl.viz.animation import AnimationBuilder
from pivot_ompl.viz.camera import frame_scene
from pivot_ompl.viz.chapters import Chapter, ReplayGuide, replay_guide, standing_height
from pivot_ompl.viz.timeline import ReplayTiming, plan_keyframes

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class ReplayInfo:
    """What a ``show_*`` call sent.

    Attributes:
        duration: animation length (s), 0 for a static view.
        keys: number of animation keys per animated node.
        nodes: names of the top-level nodes drawn.
        footsteps: footsteps drawn.
        pivots: pivot markers drawn.
        guide: chapters, phase labels and camera framing of an animated replay (give it to
            :func:`~pivot_ompl.viz.html.write_html` or :func:`~pivot_ompl.viz.serve.serve`
            for the page's controls), ``None`` for a static view.
    """

    duration: float
    keys: int
    nodes: tuple[str, ...]
    footsteps: int = 0
    pivots: int = 0
    guide: ReplayGuide | None = None


def plan_bounds(plan: Plan, *, margin: float = 1.5) -> tuple[float, float, float, float]:
    """A floor area around every pose of ``plan`` (m)."""
    xs, ys = [plan.start[0]], [plan.start[1]]
    for ph in plan.phases:
        poses: Iterable[Pose] = (
            [ph.robot_start, *(s.object for s in ph.steps), *(s.robot for s in ph.steps)]
            if isinstance(ph, TransferPhase) else ph.robot_path)
        for p in poses:
            xs.append(p[0])
            ys.append(p[1])
    return (min(xs) - margin, min(ys) - margin, max(xs) + margin, max(ys) + margin)


def show_scene(vis: meshcat.Visualizer, scene: Scene | None, *,
               bounds: tuple[float, float, float, float] | None = None,
               camera: bool = True) -> ReplayInfo:
    """Draw the floor and the obstacles of ``scene`` (or only a floor over ``bounds``)."""
    draw.check_view(vis, scene=scene)
    draw.clear(vis, ("floor", "obstacles"))
    draw.draw_scene(vis, scene, bounds=bounds)
    b = scene.bounds if scene is not None else bounds
    if camera and b is not None:
        frame_scene(vis, b, height=standing_height(None, scene))
    n = len(scene.obstacles) if scene is not None else 0
    return ReplayInfo(0.0, 0, ("floor",) + (("obstacles",) if n else ()))


def _footprint_poses(plan: Plan) -> list[Pose]:
    """Robot poses where the robot stands.

    Every transfer step's start/end and every transit waypoint (repeats within 1 cm and
    about 1 deg dropped).
    """
    out: list[Pose] = []
    for ph in plan.phases:
        poses: Sequence[Pose] = ([ph.robot_start, *(s.robot for s in ph.steps)]
                                 if isinstance(ph, TransferPhase) else ph.robot_path)
        for p in poses:
            if out and abs(out[-1][0] - p[0]) < 0.01 and abs(out[-1][1] - p[1]) < 0.01 \
                    and abs(math.remainder(out[-1][2] - p[2], 2 * math.pi)) < 0.02:
                continue
            out.append(p)
    return out


def draw_plan_markers(vis: meshcat.Visualizer, plan: Plan) -> tuple[int, list[str]]:
    """Draw a plan's paths and pivot points; return the pivot count and top-level nodes.

    Nodes: Reeds-Shepp paths ``rs_path/<i>``, transit walks ``walks/<i>``, pivot points
    ``pivots/<j>``.
    """
    nodes: list[str] = []
    for i, ph in enumerate(plan.phases):
        if isinstance(ph, TransferPhase) and len(ph.rs_path) >= 2:
            draw.draw_polyline(vis[f"rs_path/{i}"], ph.rs_path, color=draw.PATH_COLOR)
            if "rs_path" not in nodes:
                nodes.append("rs_path")
        elif isinstance(ph, TransitPhase) and len(ph.robot_path) >= 2:
            draw.draw_polyline(vis[f"walks/{i}"], ph.robot_path, color=draw.ROBOT_COLOR)
            if "walks" not in nodes:
                nodes.append("walks")
    pivots = [s.pivot for ph in plan.phases if isinstance(ph, TransferPhase) for s in ph.steps]
    n_piv = draw.draw_points(vis["pivots"], pivots, color=draw.PIVOT_COLOR, radius=0.03)
    return n_piv, nodes + (["pivots"] if n_piv else [])


def show_plan(vis: meshcat.Visualizer, scene: Scene | None, plan: Plan, *,
              timing: ReplayTiming | None = None, play: bool = True,
              camera: bool = True) -> ReplayInfo:
    """Draw ``scene`` and ``plan`` and animate the box and the robot footprint.

    Static: floor, obstacles, the Reeds-Shepp paths of transfer phases (``rs_path``, line
    ``rs_path/<i>``), the pivot points (``pivots/<j>``), robot footprints where it stands
    (``footsteps/<j>``), transit walks (``walks/<i>``). Animated: ``box`` (inclined towards
    the robot while pivoting) and ``robot`` (footprint plate and translucent volume).
    """
    draw.check_view(vis, scene=scene, plan=(plan, Plan))
    model = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff,
                          scene.model.robot_height if scene is not None
                          else profile_of(plan.robot_model).height, plan.robot_model)
    bounds = None if scene is not None else plan_bounds(plan)
    draw.clear(vis)
    show_scene(vis, scene, bounds=bounds, camera=camera)
    nodes = ["floor", "box", "robot"]
    if scene is not None and scene.obstacles:
        nodes.append("obstacles")
    n_piv, marks = draw_plan_markers(vis, plan)
    n_feet = draw.draw_footsteps(vis["footsteps"], _footprint_poses(plan), plan.robot_footprint,
                                 opacity=0.25)
    nodes += marks + (["footsteps"] if n_feet else [])
    draw.draw_box(vis["box"], plan.object_size)
    draw.draw_robot_volume(vis["robot"], model)
    kf = plan_keyframes(plan, timing=timing)
    vis["box"].set_transform(kf.box[0])
    vis["robot"].set_transform(kf.robot[0])
    anim = AnimationBuilder(vis)
    anim.add_transforms("box", kf.times, np.asarray(kf.box))
    anim.add_transforms("robot", kf.times, np.asarray(kf.robot))
    if len(kf.times) > 1:
        anim.send(play=play)
    guide = replay_guide(kf.times, kf.phase, kf.step, plan=plan, scene=scene).with_frame(
        scene.bounds if scene is not None else plan_bounds(plan), standing_height(model, scene))
    entry = {"robot": "robot_volume", "footsteps": "footprints"}  # node -> legend entry
    guide.extra["legend"] = draw.legend(entry.get(n, n) for n in nodes if n != "floor")
    log.info("plan replay: %d phases, %d pivots, %.1f s", len(plan.phases), n_piv, kf.duration)
    return ReplayInfo(kf.duration, len(kf.times), tuple(nodes), n_feet, n_piv, guide)


def show_roadmap(vis: meshcat.Visualizer, nodes: Sequence[Sequence[float]],
                 edges: Iterable[tuple[int, int]], *, name: str = "roadmap",
                 color: int = 0x808080, node_color: int = 0x404040) -> ReplayInfo:
    """Draw a planner's roadmap under ``roadmap/<name>``.

    Vertices are drawn as a point cloud and edges as line segments, just above the floor.

    Args:
        vis: the visualizer to draw into.
        nodes: vertex positions (x, y, ...) in m; extra coordinates are ignored.
        edges: pairs of vertex indices.
        name: sub-node name, so several roadmaps can be shown side by side.
        color: edge colour (0xRRGGBB).
        node_color: vertex colour (0xRRGGBB).
    """
    import meshcat.geometry as g

    base = vis[f"roadmap/{name}"]
    pts = np.asarray([[p[0], p[1], 0.03] for p in nodes], dtype=np.float32)
    if len(pts):
        cols = np.tile(np.array([[((node_color >> s) & 255) / 255 for s in (16, 8, 0)]],
                                dtype=np.float32), (len(pts), 1))
        base["nodes"].set_object(g.PointCloud(pts.T, cols.T, size=0.05))
    segs = [(nodes[a], nodes[b]) for a, b in edges]
    draw.draw_segments(base["edges"], segs, color=color, z=0.025)
    return ReplayInfo(0.0, 0, (f"roadmap/{name}",))


def replanned_plan(old: Plan, new: Plan) -> tuple[Plan, int]:
    """``old`` up to the drift, then ``new``: one plan to replay, and ``new``'s first phase.

    ``old`` is cut after its pivot step (or phase start) whose box centre is nearest
    ``new``'s start, the observed pose: the replay shows the old plan executed up to there,
    the box where it was observed (the drift as a jump), then the new plan. The result has
    ``new``'s geometry, status and extra fields; its transfers cut short lose their
    ``rs_path``.
    """
    best: tuple[float, int, int] | None = None  # (distance, phase, steps kept)
    for i, ph in enumerate(old.phases):
        if not isinstance(ph, TransferPhase):
            continue
        poses = [ph.object_start, *(s.object for s in ph.steps)]
        for k, q in enumerate(poses):
            d = math.hypot(q[0] - new.start[0], q[1] - new.start[1])
            if best is None or d < best[0]:
                best = (d, i, k)
    kept: list[TransferPhase | TransitPhase] = []
    if best is not None:
        _, i, k = best
        kept = list(old.phases[:i])
        ph = old.phases[i]
        assert isinstance(ph, TransferPhase)  # noqa: S101 - chosen above
        if k:
            kept.append(TransferPhase(ph.grasp, ph.robot_start, ph.steps[:k], ph.object_start))
    both = Plan(new.scene, new.status, new.object_size, new.robot_footprint, new.standoff,
                new.alpha_max, old.start, [*kept, *new.phases], dict(new.extra))
    return both, len(kept)


def show_replanned(vis: meshcat.Visualizer, scene: Scene | None, old: Plan, new: Plan, *,
                   timing: ReplayTiming | None = None, play: bool = True) -> ReplayInfo:
    """Replay ``old`` up to the drift and ``new`` after it, a chapter at the switch.

    ``scene`` is the scene as observed (``new``'s): its obstacles are drawn throughout.
    """
    both, switch = replanned_plan(old, new)
    info = show_plan(vis, scene, both, timing=timing, play=play)
    guide = info.guide
    if guide is None or switch >= len(both.phases):
        return info
    at = next((c.time for c in guide.chapters if c.phase == switch and c.kind != "moment"),
              guide.duration)
    x, y, yaw = new.start
    chapters = sorted([*guide.chapters, Chapter(at, f"replanned · the box observed at "
                                                    f"({x:.2f}, {y:.2f}, {yaw:.2f})",
                                                "moment", switch)],
                      key=lambda c: c.time)
    return dataclasses.replace(info, guide=dataclasses.replace(guide, chapters=tuple(chapters)))
