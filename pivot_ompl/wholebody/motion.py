"""The whole-body motion of a plan in one call: options checked, the generator run."""

from __future__ import annotations

import dataclasses
import logging
import math
from typing import TYPE_CHECKING

from pivot_ompl.errors import InputError
from pivot_ompl.humanoids import profile_of
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan
from pivot_ompl.wholebody.box import DEFAULT_TILT
from pivot_ompl.wholebody.generator import Progress, WholeBodyGenerator
from pivot_ompl.wholebody.recording import GenerationStats
from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.timeline import Timing

if TYPE_CHECKING:
    from pivot_ompl.scene import WalkParameters

log = logging.getLogger(__name__)


def generate_motion(plan: Plan, *, walk: WalkParameters | None = None,
                    settings: WalkSettings | None = None, timing: Timing | None = None,
                    tilt: float = DEFAULT_TILT, dt: float | None = None,
                    substeps: int | None = None,
                    progress: Progress | None = None) -> tuple[Motion, GenerationStats]:
    """Generate the whole-body motion of ``plan``; return it with its generation statistics.

    Args:
        plan: the pivoting plan.
        walk: the scene's walk model (``Scene.walk``): the footstep limits follow it
            (:meth:`WalkSettings.from_walk`); the plan's robot's when neither it nor
            ``settings`` is given.
        settings: walking and solver parameters (instead of ``walk``).
        timing: segment durations and tolerances.
        tilt: inclination of the held box about its supporting edge (rad).
        dt: the sampling period of the motion (s), instead of the settings' (5 ms).
        substeps: samples per solver tick, instead of the settings' (2: one QP every
            10 ms; 1: one QP per sample).
        progress: optional callback ``progress(fraction, label)``.

    Raises:
        WholeBodyError: the solver failed or a grip became unreachable (names phase and step).
        InputError: the plan is inconsistent, or both ``walk`` and ``settings`` are given.
    """
    if walk is not None:
        if settings is not None:
            raise InputError("walk", walk, "give the walk model or the settings, not both")
        settings = WalkSettings.from_walk(walk, robot=profile_of(plan.robot_model))
        log.debug("footstep limits of the scene's walk model: %s", walk)
    if dt is not None:
        if not (math.isfinite(dt) and dt > 0.0):
            raise InputError("dt", dt, "must be a finite tick > 0 s")
        settings = dataclasses.replace(settings or WalkSettings.of(profile_of(plan.robot_model)),
                                       dt=dt)
    if substeps is not None:
        if isinstance(substeps, bool) or not isinstance(substeps, int) or not 1 <= substeps <= 8:
            raise InputError("substeps", substeps, "must be an integer in [1, 8]")
        settings = dataclasses.replace(settings or WalkSettings.of(profile_of(plan.robot_model)),
                                       substeps=substeps)
    gen = WholeBodyGenerator(plan, settings=settings, timing=timing, tilt=tilt,
                             progress=progress)
    motion = gen.run()
    return motion, gen.stats
