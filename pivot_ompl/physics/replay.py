"""Replay of a simulated run: the motion(s) executed, the simulated box beside the planned one.

The stretches of motion a run simulated (the first plan's, then each replan's) are joined
into one :class:`~pivot_ompl.motionfile.Motion` on the run's time line (their phases
numbered on, so that each plan's phases are chapters of their own); the replay draws its
robot and planned box, the simulated box translucent beside it, and a chapter at each replan.
"""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.motionfile import Motion
from pivot_ompl.physics.report import SimulationReport
from pivot_ompl.scene import Scene


def run_motion(report: SimulationReport) -> Motion:
    """The motion the run executed, on its time line (``report.trace["t"]``).

    Raises:
        InputError: the report holds no simulated samples (nothing ran).
    """
    if not report.segments:
        raise InputError("report.segments", 0, "holds no simulated motion to replay")
    parts = [(m, a, b) for m, a, b in report.segments]
    first = parts[0][0]
    offset, phases = 0, list[np.ndarray]()
    for k, (m, a, b) in enumerate(parts):
        ph = (m.phase if m.phase is not None else np.zeros(len(m.t), dtype=int))[a:b + 1]
        if k and m is not parts[k - 1][0]:
            offset = int(phases[-1].max()) + 1 if phases else 0
        phases.append(ph + offset)

    def cat(key: str) -> np.ndarray:
        return np.concatenate([getattr(m, key)[a:b + 1] for m, a, b in parts])

    return Motion(t=np.asarray(report.trace["t"], dtype=float), q=cat("q"),
                  joint_names=first.joint_names, urdf=first.urdf, box=cat("box"),
                  phase=np.concatenate(phases), step=cat("step"), holding=cat("holding"),
                  grasp=cat("grasp"), tilt=cat("tilt"), box_size=first.box_size,
                  grip_box=first.grip_box, sole_size=first.sole_size, scene=first.scene)


def sim_box_poses(report: SimulationReport) -> np.ndarray:
    """The simulated box's poses (N x 7: centre, quaternion x y z w) of the run's samples."""
    q = np.asarray(report.trace["sim_quat"])
    return np.column_stack([report.trace["sim_pos"], q[:, 1:4], q[:, 0]])


def write_replay(report: SimulationReport, path: str | Path, *, scene: Scene | None = None,
                 fps: float = 25.0) -> Path:
    """Write the HTML replay of a simulated run (see the module docstring); return its path.

    The file is written through a temporary one (an existing file survives a failure).
    """
    from pivot_ompl.viz.chapters import Chapter
    from pivot_ompl.viz.html import write_html
    from pivot_ompl.viz.motion_view import show_motion
    from pivot_ompl.viz.recorder import recording_visualizer

    motion = run_motion(report)
    vis = recording_visualizer()
    info = show_motion(vis, motion, scene=scene, fps=fps, sim_box=sim_box_poses(report))
    guide = info.guide
    assert guide is not None  # noqa: S101 - show_motion always returns one
    extra = [Chapter(r.time, f"replan {k + 1}/{len(report.replans)}: box "
                     f"{100 * r.error_m:.1f} cm, {math.degrees(r.yaw_error_rad):.1f} deg off; "
                     f"{r.pivots} pivots, {r.regrasps} regrasps", "moment")
             for k, r in enumerate(report.replans)]
    if extra:
        guide = replace(guide, chapters=tuple(sorted((*guide.chapters, *extra),
                                                     key=lambda c: c.time)))
    out = write_html(vis, path, title=f"pivot-ompl simulate: {report.scene}", guide=guide)
    return out.path
