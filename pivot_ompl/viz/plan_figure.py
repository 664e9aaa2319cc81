"""Figures with matplotlib.

The paper's Fig. 6 (RS path dotted, pivot sequence, pivots, box outlines) and plan figures
with obstacles, roadmaps, critical configurations and walks.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.patches import Circle, Polygon  # noqa: E402

from pivot_ompl.grasp import BoxGraspModel  # noqa: E402
from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase  # noqa: E402
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, Scene  # noqa: E402
from pivot_ompl.se2 import rectangle_corners  # noqa: E402

GRASP_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple")


def plot_plan(plan: Plan, path: str | Path, *, scene: Scene | None = None,
              search: Any = None, title: str = "") -> Path:
    """Draw ``plan`` (and the scene, and the planner's roadmaps if given) to a PNG file."""
    model = BoxGraspModel(plan.object_size, plan.robot_footprint, plan.standoff)
    fig, ax = plt.subplots(figsize=(10, 7))
    if scene is not None:
        x0, y0, x1, y1 = scene.bounds
        ax.add_patch(Polygon([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], fill=False, lw=1.5,
                             ec="black"))
        for o in scene.obstacles:
            if isinstance(o, BoxObstacle):
                pts = rectangle_corners((*o.center, o.yaw), *o.size)
                ax.add_patch(Polygon(pts, fc="0.6", ec="0.3"))
            elif isinstance(o, CylinderObstacle):
                ax.add_patch(Circle(o.center, o.radius, fc="0.6", ec="0.3"))
            else:
                ax.add_patch(Polygon(o.points, fc="0.6", ec="0.3"))
    if search is not None:
        _draw_roadmaps(ax, search)
    for ph in plan.phases:
        if isinstance(ph, TransferPhase):
            c = GRASP_COLOURS[ph.grasp]
            if ph.rs_path:
                ax.plot([p[0] for p in ph.rs_path], [p[1] for p in ph.rs_path], ":", c="k",
                        lw=1.0)
            poses = [ph.object_start] + [s.object for s in ph.steps]
            cars = [model.car_pose(p, ph.grasp) for p in poses]
            ax.plot([q[0] for q in cars], [q[1] for q in cars], "-", c=c, lw=1.5)
            ax.plot([s.pivot[0] for s in ph.steps], [s.pivot[1] for s in ph.steps], ".", c=c,
                    ms=4)
            every = max(1, len(poses) // 12)
            for p in poses[::every] + [poses[-1]]:
                ax.add_patch(Polygon(model.object_corners(p), fill=False, ec=c, lw=0.8))
            ax.add_patch(Polygon(model.robot_corners(ph.robot_start), fill=False, ec=c,
                                 ls="--", lw=0.8))
        elif isinstance(ph, TransitPhase):
            ax.plot([p[0] for p in ph.robot_path], [p[1] for p in ph.robot_path], "-",
                    c="tab:red", lw=1.2)
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title or f"{plan.scene}: {plan.pivots} pivots, {plan.regrasps} regrasps "
                 f"({plan.status})")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110, bbox_inches="tight")
    plt.close(fig)
    return path


def _draw_roadmaps(ax: Any, search: Any) -> None:
    obj = search.obj
    pts = obj.poses
    ax.plot([p[0] for p in pts], [p[1] for p in pts], ".", c="0.7", ms=2, label="object roadmap")
    for i, j in obj.edges:
        ax.plot([pts[i][0], pts[j][0]], [pts[i][1], pts[j][1]], "-", c="0.85", lw=0.5)
    crit = [pts[i] for i in search.critical]
    if crit:
        ax.plot([p[0] for p in crit], [p[1] for p in crit], "x", c="tab:red", ms=3,
                label="critical configurations")
    for (i, g), nbrs in search.adj.items():
        for (j, h) in nbrs:
            if h == g and j > i:
                ax.plot([pts[i][0], pts[j][0]], [pts[i][1], pts[j][1]], "-",
                        c=GRASP_COLOURS[g], lw=0.3, alpha=0.4)
    ax.legend(loc="upper right", fontsize=7)
