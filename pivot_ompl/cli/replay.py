"""The ``replay`` verb: meshcat replay of a plan or a whole-body motion.

``pivot-ompl replay PLAN.json|MOTION.npz [--scene S] [--plan P] [--before OLD.json]
[--html F] [--serve] [--open]``. ``--before OLD.json`` with a plan made by ``replan``: the old
plan up to the drift (its step nearest the new plan's start), then the new plan, with a
chapter at the switch.
Without ``--html`` or ``--serve`` the replay is written next to the input
(``<input>.html``). The scene is ``--scene``, else the one the plan or motion records (its
``scene_path`` file, else the shipped scene of its name);
without one no obstacle is drawn (a warning says so). The HTML file is never one of the
inputs (exit 2) and is written through a temporary file.
"""

from __future__ import annotations

import argparse
import logging
import webbrowser
from pathlib import Path
from typing import TYPE_CHECKING

from pivot_ompl.cli.args import output_file, output_files, positive
from pivot_ompl.cli.scenes import SceneRecord, find_scene, missing_text
from pivot_ompl.errors import InputError
from pivot_ompl.fileio import regular_file
from pivot_ompl.planfile import load_plan
from pivot_ompl.scene import Scene

if TYPE_CHECKING:  # meshcat (with IPython, tornado, zmq) costs every verb ~0.07 s to import
    import meshcat

log = logging.getLogger(__name__)



def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``replay`` verb."""
    p = subparsers.add_parser(
        "replay", help="meshcat replay of a plan or a whole-body motion (HTML or live)",
        description=__doc__.splitlines()[0])
    p.add_argument("input", help="a pivot-plan/1 JSON file or a motion .npz")
    p.add_argument("--scene", help="scene file or shipped scene's name (default: the scene "
                   "the plan or motion records: its scene_path, else its shipped name)")
    p.add_argument("--plan", help="with a motion: the plan it executes (draws its Reeds-Shepp "
                   "paths and pivot points; its scene name is used)")
    p.add_argument("--before", metavar="OLD.json",
                   help="with a replanned plan: the plan it replaced; replays OLD up to the "
                        "drift, then the new plan (a chapter at the switch)")
    p.add_argument("--html", help="write one self-contained offline HTML file here")
    p.add_argument("--serve", action="store_true",
                   help="start a live meshcat viewer, print its URL, stop on Ctrl-C")
    p.add_argument("--open", action="store_true", help="open the result in a web browser")
    p.add_argument("--urdf", default=None,
                   help="robot model of a motion made for another robot (default: the model "
                        "the motion names: a humanoid profile's, see 'pivot-ompl robots')")
    p.add_argument("--fps", type=positive("--fps"), default=25.0,
                   help="animation keys per second of a motion replay (default 25)")
    p.set_defaults(func=run)


def _scene(record: SceneRecord, given: str | None) -> Scene | None:
    """The scene to draw (:func:`pivot_ompl.cli.scenes.find_scene`); none: a warning."""
    scene = find_scene(record, given)
    if scene is None:
        log.warning("no obstacles drawn: the %s's scene %r: %s", record.kind, record.name,
                    missing_text(record))
    return scene


def _builder(args: argparse.Namespace):
    """Load the input and return ``(build(vis), title)``."""
    src = regular_file(args.input, field="input")  # a FIFO would block the reader
    if not 0 < args.fps <= 1000:
        raise InputError("--fps", args.fps, "must be in (0, 1000] keys per second")
    if src.suffix.lower() == ".npz":
        from pivot_ompl.motionfile import load_motion
        from pivot_ompl.viz.motion_view import show_motion

        if args.before:
            raise InputError("--before", args.before, "only goes with a plan (.json) input")
        motion = load_motion(src)
        plan = load_plan(args.plan) if args.plan else None
        scene = _scene(SceneRecord.of(motion, "motion").merged(SceneRecord.of(plan)),
                       args.scene)

        def build(vis: meshcat.Visualizer) -> object:
            return show_motion(vis, motion, scene=scene, fps=args.fps, plan=plan,
                               urdf=args.urdf)
    else:
        for opt, value in (("--plan", args.plan), ("--urdf", args.urdf)):
            if value:
                raise InputError(opt, value, "only goes with a motion (.npz) input")
        from pivot_ompl.viz.plan_view import show_plan, show_replanned

        plan = load_plan(src)
        scene = _scene(SceneRecord.of(plan), args.scene)
        before = load_plan(args.before) if args.before else None

        def build(vis: meshcat.Visualizer) -> object:
            if before is not None:
                return show_replanned(vis, scene, before, plan)
            return show_plan(vis, scene, plan)
    return build, f"pivot-ompl replay: {src.name}"


def run(args: argparse.Namespace) -> int:
    """Run ``replay``; returns the exit code (0 ok, 1 failure; bad input raises)."""
    inputs = [args.input, args.plan, args.scene, args.urdf, args.before]
    (html,) = output_files(inputs, suffixes={"html": [".html", ".htm"]}, html=args.html)
    build, title = _builder(args)
    if args.serve:
        from pivot_ompl.viz.serve import serve

        def ready(url: str) -> None:
            print(f"replay viewer: {url}  (Ctrl-C to stop)", flush=True)

        if html:
            _write(build, html, title, open_it=False)
        return serve(build, open_browser=args.open, on_ready=ready, title=title)
    out = html or output_file(str(Path(args.input).with_suffix(".html")), "input",
                              inputs=inputs)
    assert out is not None  # noqa: S101 - for mypy
    return _write(build, out, title, open_it=args.open)


def _write(build, out: str | Path, title: str, *, open_it: bool) -> int:
    from pivot_ompl.viz.html import write_html
    from pivot_ompl.viz.recorder import recording_visualizer

    vis = recording_visualizer()
    info = build(vis)
    res = write_html(vis, out, title=title, guide=getattr(info, "guide", None))
    print(f"replay: {res.path} ({res.size_bytes / 1e6:.2f} MB, {res.seconds:.2f} s)",
          flush=True)
    if open_it:
        webbrowser.open(res.path.resolve().as_uri(), new=2)
    return 0
