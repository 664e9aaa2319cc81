"""``pivot-ompl animate`` and ``pivot-ompl check-motion``: whole-body motion from a plan.

* ``pivot-ompl animate PLAN.json --out motion.npz [--scene S] [--tick DT] [--substeps N]``:
  generate the
  whole-body motion of the plan's robot (progress bar on stderr; footsteps within the scene's
  ``robot.walk`` step limits; one sample every ``DT`` s, 5 ms by default, and one QP every
  ``--substeps`` samples, 2 by default), check it, write
  it. Exit 1 with a message naming the phase and step when the solver fails or the motion
  fails its checks (nothing is written then).
* ``pivot-ompl check-motion motion.npz [--plan PLAN.json] [--scene S]``: print the checks'
  margins, every link's obstacle clearance and every joint's speed and acceleration peaks;
  exit 0 when all pass, 1 when one fails, 2 on bad input.

Both check every link and the box against the scene's obstacles. The scene is ``--scene``
(a file or a shipped scene's name), else the one the plan or motion records (its
``scene_path`` file, else the shipped scene of its name); otherwise exit 2.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import time
from typing import TYPE_CHECKING, TextIO

from pivot_ompl.cli.args import finite, output_files
from pivot_ompl.cli.scenes import SceneRecord, require_scene
from pivot_ompl.cli.terminal import control_stream
from pivot_ompl.errors import InputError, WholeBodyError, printable

if TYPE_CHECKING:
    from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)

#: Sampling periods ``animate --tick`` accepts (s).
MIN_TICK, MAX_TICK = 0.002, 0.01
#: Largest ``animate --substeps`` (samples per solver tick).
MAX_SUBSTEPS = 4


class ProgressBar:
    """A one-line text progress bar (redrawn in place) on a stream, stderr by default."""

    def __init__(self, label: str, *, stream: TextIO | None = None, width: int = 30) -> None:
        self.label = label
        self.stream = stream if stream is not None else sys.stderr
        self.width = width
        self._t0 = time.perf_counter()

    def __call__(self, fraction: float, text: str) -> None:
        """Redraw with ``fraction`` in [0, 1] done and a status ``text``."""
        n = int(round(self.width * fraction))
        el = time.perf_counter() - self._t0
        control_stream(self.stream).write(
            f"\r{self.label} [{'#' * n}{'.' * (self.width - n)}] "
            f"{100 * fraction:5.1f}% {el:6.1f}s {printable(text)[:40]:40s}")
        if fraction >= 1.0:
            self.stream.write("\n")
        self.stream.flush()


def plan_scene(args: argparse.Namespace, record: SceneRecord) -> Scene | None:
    """The plan's scene (its walk model sets the footstep limits; its obstacles are checked).

    With ``--no-check`` a plan whose scene is not found is animated with its robot's walk
    model (the profile's).
    """
    try:
        return require_scene(record, args.scene, field="plan.scene")
    except InputError:
        if not args.no_check:
            raise
        log.info("scene %r not found: the robot profile's walk model", record.name)
        return None


def _animate(args: argparse.Namespace) -> int:
    from pivot_ompl.planfile import load_plan
    from pivot_ompl.wholebody.motion import generate_motion
    from pivot_ompl.wholebody.motion_checks import check_motion

    output_files([args.plan], suffixes={"out": [".npz"]}, out=args.out)
    plan = load_plan(args.plan)
    scene = plan_scene(args, SceneRecord.of(plan))
    bar = None if args.no_progress else ProgressBar("animate")
    if not MIN_TICK <= args.tick <= MAX_TICK:
        raise InputError("--tick", args.tick, f"must be in [{MIN_TICK}, {MAX_TICK}] s")
    if not 1 <= args.substeps <= MAX_SUBSTEPS:
        raise InputError("--substeps", args.substeps, f"must be in [1, {MAX_SUBSTEPS}]")
    motion, stats = generate_motion(plan, walk=None if scene is None else scene.walk,
                                    dt=args.tick, substeps=args.substeps,
                                    tilt=math.radians(args.tilt_deg), progress=bar)
    print(f"motion: {stats.duration:.2f} s in {stats.compute:.2f} s "
          f"({stats.real_time_factor:.1f}x real time), {stats.samples} samples "
          f"({stats.ticks} solver ticks), "
          f"max hand error {1000 * stats.max_hand_error:.2f} mm")
    if not args.no_check:
        report = check_motion(motion, plan, scene=scene)
        print(report.table())
        if not report.passed:
            failed = [r for r in report.results if not r.passed]
            first = min(failed, key=lambda r: r.index if r.index >= 0 else len(motion.t))
            i = first.index if first.index >= 0 else 0
            bad = ", ".join(f"{r.name} ({r.detail})" for r in failed)
            phase, step = motion.phase, motion.step
            assert phase is not None and step is not None  # required by check_motion
            raise WholeBodyError(int(phase[i]), int(step[i]),
                                 f"generated motion fails its checks: {bad}; not written")
    path = motion.save(args.out)
    print(f"wrote {path}")
    return 0


def _check(args: argparse.Namespace) -> int:
    from pivot_ompl.motionfile import load_motion
    from pivot_ompl.planfile import load_plan
    from pivot_ompl.wholebody.motion_checks import check_motion

    motion = load_motion(args.motion)
    plan = load_plan(args.plan) if args.plan else None
    record = SceneRecord.of(motion, "motion").merged(SceneRecord.of(plan))
    scene = require_scene(record, args.scene, field="motion.scene")
    report = check_motion(motion, plan, scene=scene)
    if report.clearance is not None:
        print(f"obstacle clearance per link (scene {printable(scene.name)}; smallest distance "
              "in m over the motion, at time t, to the nearest obstacle):")
        print(report.clearance.table())
    if report.peaks is not None:
        print("joint speed and acceleration peaks over the whole motion (|v| rad/s, |a| "
              "rad/s², each passes at or below its limit; at t: when):")
        print(report.peaks.table())
    print(report.table())
    return 0 if report.passed else 1


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``animate`` and ``check-motion`` verbs."""
    p = subparsers.add_parser("animate", help="whole-body motion (PlaCo) of a plan",
                              description=_animate.__doc__ or __doc__.splitlines()[0])
    p.add_argument("plan", help="pivot-plan/1 JSON file")
    p.add_argument("--out", required=True, help="motion file to write (.npz)")
    p.add_argument("--tilt-deg", type=finite("--tilt-deg"), default=5.0,
                   help="inclination of the held box about its supporting edge (deg)")
    p.add_argument("--scene", default=None,
                   help="scene whose obstacles are checked (file or shipped name; default: "
                        "the plan's scene)")
    p.add_argument("--tick", type=finite("--tick"), default=0.005,
                   help="sampling period of the motion (s, 0.002-0.01)")
    p.add_argument("--substeps", type=int, default=2,
                   help="samples per solver tick (1-4; default 2: one QP every 2 samples, "
                        "the samples between blended; 1: one QP per sample)")
    p.add_argument("--no-check", action="store_true", help="skip the motion checks")
    p.add_argument("--no-progress", action="store_true", help="no progress bar")
    p.set_defaults(func=_animate)
    c = subparsers.add_parser("check-motion", help="check a whole-body motion file",
                              description="ZMP, feet, hands, joint limits, pivot corner, "
                                          "obstacle clearance of every link and plan "
                                          "agreement of a motion file")
    c.add_argument("motion", help="motion file (.npz)")
    c.add_argument("--plan", default=None, help="the plan the motion was generated from")
    c.add_argument("--scene", default=None,
                   help="scene whose obstacles are checked (file or shipped name; default: "
                        "the motion's scene)")
    c.set_defaults(func=_check)
