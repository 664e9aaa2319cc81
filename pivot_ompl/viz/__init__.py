"""Meshcat views of scenes, plans, roadmaps and whole-body motions (notebooks and replays).

Every ``show_*`` function takes the ``meshcat.Visualizer`` to draw into (there is no
module-global viewer)::

    import meshcat
    from pivot_ompl import load_scene, load_plan
    from pivot_ompl.viz import show_plan

    vis = meshcat.Visualizer()          # live server, or recording_visualizer() for export
    show_plan(vis, load_scene("scenes/fig10.yaml"), load_plan("out/fig10_plan.json"))

:func:`recording_visualizer` records without a server; :func:`write_html` then writes one
self-contained offline HTML file. :func:`serve` runs a live viewer until Ctrl-C.
"""

from __future__ import annotations

from pivot_ompl.motionfile import Motion, load_motion
from pivot_ompl.viz.html import HtmlExport, write_html
from pivot_ompl.viz.motion_view import show_motion
from pivot_ompl.viz.plan_view import ReplayInfo, show_plan, show_roadmap, show_scene
from pivot_ompl.viz.recorder import RecordingWindow, recording_visualizer
from pivot_ompl.viz.serve import LiveViewer, serve
from pivot_ompl.viz.timeline import ReplayTiming

__all__ = [
    "HtmlExport", "LiveViewer", "Motion", "RecordingWindow", "ReplayInfo", "ReplayTiming",
    "load_motion", "recording_visualizer", "serve", "show_motion", "show_plan", "show_roadmap",
    "show_scene", "write_html",
]
