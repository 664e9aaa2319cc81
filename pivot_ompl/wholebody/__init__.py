"""Whole-body pivoting motion of a humanoid (PlaCo): generator, motion checks and their parts.

* :mod:`.box` -- box, grasp-frame and grip-point kinematics (tilt 5 deg, grips on the held face);
* :mod:`.settings` -- walking and solver parameters, their footstep limits from a scene's walk;
* :mod:`.footsteps` -- footstep planning along robot paths and pivot arcs (pure geometry);
* :mod:`.walker` -- the PlaCo controller (walk pattern generator, kinematics solver, tasks);
* :mod:`.pivot_walk` -- pivot steps walked continuously (footsteps chained, rotation timing);
* :mod:`.timeline`, :mod:`.recording` -- segment durations, profiles, the recorded samples;
* :mod:`.generator` -- plan -> :class:`Motion` (timeline of reach, tilt, pivots, release, walks);
* :mod:`.segments` -- the generator's standing and walking segments of solver ticks, recorded;
* :mod:`.durations` -- a motion's seconds per plan element and the duration model they fit;
* :mod:`.motion_checks` -- the checks of a motion (:mod:`.checks_robot`, :mod:`.checks_box`
  over a :mod:`.check_context`), computed from the motion's own configurations;
* :mod:`.clearance` -- obstacle clearance of every link and the box;
* :mod:`.envelope` -- how far the links reach out of the planner's bodies;
* :mod:`.lipm`, :mod:`.hull`, :mod:`.urdf_model` -- the LIPM ZMP, planar convex hulls, the
  URDF's pinocchio model.

The motion file is :mod:`pivot_ompl.motionfile`; the CLI verbs are
:mod:`pivot_ompl.cli.animate`.
"""

from pivot_ompl.motionfile import Motion, load_motion
from pivot_ompl.wholebody.box import DEFAULT_TILT, BoxHold
from pivot_ompl.wholebody.generator import (
           GenerationStats,
           Timing,
           WholeBodyGenerator,
)
from pivot_ompl.wholebody.motion import generate_motion
from pivot_ompl.wholebody.motion_checks import CheckResult, MotionReport, check_motion
from pivot_ompl.wholebody.walker import WalkSettings

__all__ = ["DEFAULT_TILT", "BoxHold", "CheckResult", "GenerationStats", "Motion",
           "MotionReport", "Timing", "WalkSettings", "WholeBodyGenerator", "check_motion",
           "generate_motion", "load_motion"]
