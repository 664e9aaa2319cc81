"""Meshcat views of scenes, plans, roadmaps and whole-body motions (notebooks and replays).

Every ``show_*`` function takes the ``meshcat.Visualizer`` to draw into (there is no
module-global viewer)::

    import meshcat
    from pivot_ompl import load_scene, load_plan
    from pivot_ompl.viz import show_plan

    vis = meshcat.Visualizer()          # live server, or recording_visualizer() for export
    show_plan(vis, load_scene("scenes/fig10.yaml"), load_plan("out/fig10_plan.json"))

:func:`recording_visualizer` records without a server; :func:`write_html` then writes one
self-contained offline HTML file. :func:`serve` runs a live viewer until Ctrl-C. Both pages
carry the replay controls when given the ``guide`` a ``show_*`` call returns (chapters,
phase label, speeds, camera views). Camera helpers: :func:`frame_scene` (three-quarter view
of the scene, the view on load), :func:`top_view`, :func:`follow_view`, :func:`look_at`;
chapter helpers: :func:`replay_guide`, :func:`motion_guide` (:class:`ReplayGuide`:
``chapters``, ``label_at(t)``).
"""

from __future__ import annotations

from pivot_ompl.motionfile import Motion, load_motion
from pivot_ompl.viz.camera import (
    CameraPose,
    fit_pose,
    follow_pose,
    follow_view,
    frame_scene,
    look_at,
    overview_pose,
    top_pose,
    top_view,
)
from pivot_ompl.viz.chapters import Chapter, ReplayGuide, narrowest_steps, replay_guide
from pivot_ompl.viz.html import HtmlExport, write_html
from pivot_ompl.viz.motion_view import motion_guide, show_motion
from pivot_ompl.viz.plan_view import ReplayInfo, show_plan, show_roadmap, show_scene
from pivot_ompl.viz.recorder import RecordingWindow, recording_visualizer
from pivot_ompl.viz.serve import LiveViewer, serve
from pivot_ompl.viz.timeline import ReplayTiming

__all__ = [
    "CameraPose", "Chapter", "fit_pose", "HtmlExport", "LiveViewer", "Motion", "RecordingWindow",
    "ReplayGuide", "ReplayInfo", "ReplayTiming", "follow_pose", "follow_view", "frame_scene",
    "load_motion", "look_at", "motion_guide", "narrowest_steps", "overview_pose",
    "recording_visualizer", "replay_guide", "serve", "show_motion", "show_plan",
    "show_roadmap", "show_scene", "top_pose", "top_view", "write_html",
]
