"""Whole-body HRP-2 pivoting motion (PlaCo): generator, motion file and checks.

* :mod:`.box` -- box, grasp-frame and grip-point kinematics (tilt 5 deg, grips on the held face);
* :mod:`.walker` -- the PlaCo controller (walk pattern generator, kinematics solver, tasks);
* :mod:`.generator` -- plan -> :class:`Motion` (timeline of reach, tilt, pivots, release, walks);
* :mod:`.durations` -- a motion's seconds per plan element and the duration model they fit;
* :mod:`.motion` -- the ``.npz`` motion file contract;
* :mod:`.checks` -- checks computed from the motion's own configurations;
* :mod:`.cli` -- ``pivot-ompl animate`` and ``pivot-ompl check-motion``.
"""

from pivot_ompl.motionfile import Motion, load_motion
from pivot_ompl.wholebody.box import DEFAULT_TILT, BoxHold
from pivot_ompl.wholebody.generator import (
           GenerationStats,
           Timing,
           WholeBodyGenerator,
           generate_motion,
)
from pivot_ompl.wholebody.motion_checks import CheckResult, MotionReport, check_motion
from pivot_ompl.wholebody.walker import WalkSettings

__all__ = ["DEFAULT_TILT", "BoxHold", "CheckResult", "GenerationStats", "Motion",
           "MotionReport", "Timing", "WalkSettings", "WholeBodyGenerator", "check_motion",
           "generate_motion", "load_motion"]
