"""Plan figures with matplotlib, drawn like the regrasp paper's figures 5 and 10.

The planner's roadmap faint in the background (object roadmap grey, per-grasp manipulation
edges in the grasp's colour, critical configurations as small crosses); the plan on top: the
box centre's path in the grasp's colour with the box footprints along it, the pivot corners
(dots), the robot's stance where each transfer starts (dashed rectangle), the Reeds-Shepp
path of the supporting edge's centre dotted; regrasps labelled where the box rests
(``regrasp k: grasp i→j``) and their walks drawn and labelled with their length; start and
goal footprints marked; when no plan exists, the passage that blocks every plan (the plan's
``passage`` field) drawn across its gap, with a dashed circle as wide as the held assembly
needs, or the place where the held box cannot turn (its ``turn`` field) crossed, with the
widest free circle there and a dashed one as long as the held assembly. Every marker has a
legend entry; the legend stands beside the floor and no two labels overlap
(:mod:`pivot_ompl.viz.labels`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402

from pivot_ompl.errors import counted, printable  # noqa: E402
from pivot_ompl.grasp import BoxGraspModel  # noqa: E402
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase  # noqa: E402
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Scene  # noqa: E402
from pivot_ompl.se2 import rectangle_corners  # noqa: E402
from pivot_ompl.viz.labels import Label, place_labels  # noqa: E402

GRASP_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple")
WALK_COLOUR = "tab:red"
PASSAGE_COLOUR = "crimson"
#: Box footprints drawn per metre of object path (at least the ends of each transfer).
FOOTPRINTS_PER_M = 1.5


def plan_figure(plan: Plan, *, scene: Scene | None = None, search: Any = None,
                title: str = "") -> Figure:
    """The plan figure (a matplotlib ``Figure``; :func:`plot_plan` writes it to a file).

    Every text is drawn as plain text: a ``$`` in a scene's name is a dollar sign, never
    mathtext (which would fail on ``$x^$``), and control characters are shown as escapes.
    """
    with matplotlib.rc_context({"text.parse_math": False}):
        return _plan_figure(plan, scene=scene, search=search, title=printable(title))


def _plan_figure(plan: Plan, *, scene: Scene | None, search: Any, title: str) -> Figure:
    model = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff)
    fig, ax = plt.subplots(figsize=(11, 7.5))
    if scene is not None:
        x0, y0, x1, y1 = scene.bounds
        ax.add_patch(Polygon([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], fill=False, lw=1.5,
                             ec="black"))
        for o in scene.obstacles:
            if isinstance(o, BoxObstacle):
                ax.add_patch(Polygon(rectangle_corners((*o.center, o.yaw), *o.size), fc="0.55",
                                     ec="0.3", zorder=2))
            elif isinstance(o, CylinderObstacle):
                ax.add_patch(Circle(o.center, o.radius, fc="0.55", ec="0.3", zorder=2))
            else:
                ax.add_patch(Polygon(o.points, fc="0.55", ec="0.3", zorder=2))
    if search is not None:
        _draw_roadmaps(ax, search)
    labels = _draw_plan(ax, plan, model, goal=scene.goal if scene is not None else None)
    labels += _draw_passage(ax, plan.extra.get("passage"))
    labels += _draw_turn(ax, plan.extra.get("turn"))
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    reached = "reaches the goal" if plan.status == "exact" else f"status {plan.status}"
    if plan.extra.get("no_plan"):
        reached = "no plan exists"
    ax.set_title(title or f"{printable(plan.scene)}: {counted(plan.pivots, 'pivot')}, "
                 f"{counted(plan.regrasps, 'regrasp')}, {reached}")
    handles, names = ax.get_legend_handles_labels()
    order = sorted(range(len(names)), key=lambda i: (names[i].startswith("box centre, grasp"),
                                                     names[i]))
    # beside the floor, never over it (the goal, the labels)
    ax.legend([handles[i] for i in order], [names[i] for i in order], loc="upper left",
              bbox_to_anchor=(1.01, 1.0), fontsize=7, framealpha=0.85)
    place_labels(fig, ax, labels)
    return fig


def plot_plan(plan: Plan, path: str | Path, *, scene: Scene | None = None,
              search: Any = None, title: str = "") -> Path:
    """Draw ``plan`` (and the scene, and the planner's roadmaps if given) to a PNG file."""
    fig = plan_figure(plan, scene=scene, search=search, title=title)
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def _draw_passage(ax: Any, passage: Any) -> list[Label]:
    """Mark the passage that blocks every plan (the plan's ``passage`` field), if any."""
    if not isinstance(passage, dict) or passage.get("ends") is None:
        return []
    (ax_, ay), (bx, by) = passage["ends"]
    cx, cy = passage["center"]
    ax.plot([ax_, bx], [ay, by], "-", c=PASSAGE_COLOUR, lw=3.0, zorder=7,
            label="passage that blocks every plan")
    ax.add_patch(Circle((cx, cy), 0.5 * passage["assembly_needs"], fill=False,
                        ec=PASSAGE_COLOUR, lw=1.5, ls="--", zorder=7))
    return [Label((cx, cy), f"{passage['width']:.2f} m; robot + box need "
                            f"{passage['assembly_needs']:.2f} m", PASSAGE_COLOUR)]


def _draw_turn(ax: Any, turn: Any) -> list[Label]:
    """Mark the place where the held box cannot turn (the plan's ``turn`` field), if any.

    A cross at the place, the widest free circle there (solid) and a dashed circle as long as
    the box and the robot holding it.
    """
    if not isinstance(turn, dict) or turn.get("center") is None:
        return []
    cx, cy = turn["center"]
    ax.plot([cx], [cy], "x", c=PASSAGE_COLOUR, ms=9, mew=2.5, zorder=7,
            label="where the box cannot turn")
    ax.add_patch(Circle((cx, cy), 0.5 * turn["width"], fill=False, ec=PASSAGE_COLOUR,
                        lw=1.5, zorder=7))
    ax.add_patch(Circle((cx, cy), 0.5 * turn["assembly_length"], fill=False,
                        ec=PASSAGE_COLOUR, lw=1.5, ls="--", zorder=7))
    return [Label((cx, cy), f"{turn['width']:.2f} m to turn in; robot + box "
                            f"{turn['assembly_width']:.2f} x {turn['assembly_length']:.2f} m",
                  PASSAGE_COLOUR)]


def _draw_plan(ax: Any, plan: Plan, model: BoxGraspModel,
               goal: Any = None) -> list[Label]:
    """Draw the plan's phases; the regrasp and walk labels to place once the limits are set.

    ``goal``: the goal pose drawn when the plan has no phases (nothing reaches it).
    """
    labels: list[Label] = []
    seen: set[str] = set()

    def once(label: str) -> str:
        if label in seen:
            return "_nolegend_"
        seen.add(label)
        return label

    ax.add_patch(Polygon(model.object_corners(plan.start), fill=False, ec="black", lw=2.0,
                         zorder=5, label=once("start")))
    end = plan.object_end if plan.phases or goal is None else goal
    ax.add_patch(Polygon(model.object_corners(end), fill=False, ec="black", lw=2.0, ls="--",
                         zorder=5, label=once("goal")))
    k_rg = 0
    for ph in plan.phases:
        if isinstance(ph, TransferPhase):
            c = GRASP_COLOURS[ph.grasp]
            if ph.rs_path:
                ax.plot([p[0] for p in ph.rs_path], [p[1] for p in ph.rs_path], ":", c="k",
                        lw=0.8, zorder=3, label=once("Reeds-Shepp path (supporting edge's centre)"))
            poses = [ph.object_start] + [s.object for s in ph.steps]
            ax.plot([p[0] for p in poses], [p[1] for p in poses], "-", c=c, lw=1.6, zorder=4,
                    label=once(f"box centre, grasp {ph.grasp}"))
            ax.plot([s.pivot[0] for s in ph.steps], [s.pivot[1] for s in ph.steps], ".", c=c,
                    ms=4, zorder=4, label=once("pivot corners"))
            length = sum(((b[0] - a[0]) ** 2 + (b[1] - a[1]) ** 2) ** 0.5
                         for a, b in zip(poses, poses[1:], strict=False))
            n = max(2, int(length * FOOTPRINTS_PER_M) + 1)
            idx = sorted({round(i * (len(poses) - 1) / (n - 1)) for i in range(n)})
            for i in idx:
                ax.add_patch(Polygon(model.object_corners(poses[i]), fc=c, alpha=0.18, ec=c,
                                     lw=1.0, zorder=4, label=once("box footprint on the way")))
            ax.add_patch(Polygon(model.robot_corners(ph.robot_start), fill=False, ec="0.2",
                                 ls="--", lw=0.9, zorder=4,
                                 label=once("robot's stance as it grasps")))
        elif isinstance(ph, TransitPhase):
            k_rg += 1
            xs, ys = [p[0] for p in ph.robot_path], [p[1] for p in ph.robot_path]
            ax.plot(xs, ys, "-", c=WALK_COLOUR, lw=1.6, zorder=5, label=once("regrasp walk"))
            ax.annotate("", (xs[-1], ys[-1]), (xs[-2], ys[-2]) if len(xs) > 1 else (xs[0], ys[0]),
                        arrowprops={"arrowstyle": "->", "color": WALK_COLOUR, "lw": 1.4},
                        zorder=5)
            o = ph.object_pose
            ax.plot([o[0]], [o[1]], "o", mfc="white", mec=WALK_COLOUR, ms=7, mew=2, zorder=6,
                    label=once("regrasp position"))
            labels.append(Label((o[0], o[1]),
                                f"regrasp {k_rg}: grasp {ph.from_grasp}→{ph.to_grasp}",
                                WALK_COLOUR))
            mid = ph.robot_path[len(ph.robot_path) // 2]
            labels.append(Label((mid[0], mid[1]), f"walk {k_rg}: {ph.length:.1f} m",
                                WALK_COLOUR))
    return labels


def _draw_roadmaps(ax: Any, search: Any) -> None:
    """The planner's roadmaps, faint: they are the background of the plan."""
    obj = search.roadmap
    pts = obj.poses
    ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", c="0.75", ms=1.5,
            label="object roadmap", zorder=1)
    for i, j in obj.edges:
        ax.plot([pts[i][0], pts[j][0]], [pts[i][1], pts[j][1]], "-", c="0.88", lw=0.4,
                zorder=1)
    crit = [pts[i] for i in search.critical.indices]
    if crit:
        ax.plot([p[0] for p in crit], [p[1] for p in crit], "x", c="0.6", ms=2.5, mew=0.6,
                label="critical configurations", zorder=1)
    for (i, g), (j, _) in search.graph.transfer_edges():
        ax.plot([pts[i][0], pts[j][0]], [pts[i][1], pts[j][1]], "-",
                c=GRASP_COLOURS[g], lw=0.3, alpha=0.1, zorder=1)
