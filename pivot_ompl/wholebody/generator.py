"""Whole-body pivoting motion of the plan's humanoid from a ``pivot-plan/1`` plan (PlaCo).

Timeline of a **transfer phase** (grasp ``k``), each part a segment of solver ticks:

1. *reach* (:attr:`Timing.reach`): the hands move from their rest frames to the grip points
   on the resting box (``holding`` is false until the end of the reach);
2. *tilt* (:attr:`Timing.tilt`): the box is inclined towards the robot about the supporting
   edge to :attr:`BoxHold.tilt` (5 deg by default), the hands riding on it;
3. one *pivot* segment per plan step: the robot walks (LIPM/ZMP pattern generator;
   forward, sideways and backward steps) along the arc its attached pose describes about the
   pivot, from its pose before the step to the step's ``robot`` pose, while the inclined box
   turns about the vertical through the step's ``pivot`` corner by the step's ``angle``,
   smoothly over the segment; the box pose at the end is exactly the plan's;
4. *untilt* then *release*: the box is set down flat and the hands return to rest.

A **transit phase** walks along the phase's ``robot_path`` (footsteps placed along its
straight segments, see :func:`~pivot_ompl.wholebody.footsteps.path_footsteps`) with the box
resting; long walks are planned in pieces of :attr:`Timing.max_steps` steps, each coming to
rest (each piece's CoM planned in windows of supports, :mod:`.walk_windows`).
A replanned plan whose robot was observed away from the box (its ``observed_robot`` field,
``replan`` with the box at rest) starts there: the robot settles at the observed pose, then
walks (PlaCo's footstep planner, as to a transfer start off the robot's pose) to the plan's
first stance.
Grip points and the tilt are defined in :mod:`pivot_ompl.wholebody.box`; tasks and the
lift-off delay that keeps the ZMP inside real support polygons in
:mod:`pivot_ompl.wholebody.walker`.

Failures raise :class:`~pivot_ompl.errors.WholeBodyError` naming the phase and step: a QP
that fails (infeasible hard tasks under the limits) or a hand further than
:attr:`Timing.max_hand_error` from its grip point while holding ("unreachable grip").
The box's weight is not modelled (kinematic generation; the CoM is the robot's own).
"""

from __future__ import annotations

import logging
import math
import time
from collections.abc import Callable

import numpy as np

from pivot_ompl.errors import InputError, WholeBodyError
from pivot_ompl.humanoids import profile_of
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.wholebody.box import DEFAULT_TILT, BoxHold, rotation_about_vertical
from pivot_ompl.wholebody.pivot_walk import (
    chain_pivot_footsteps,
    check_pivot_steps,
    object_before,
    rotation_windows,
    turn_progress,
)
from pivot_ompl.wholebody.plan_start import observed_robot
from pivot_ompl.wholebody.recording import GenerationStats, Recorder
from pivot_ompl.wholebody.segments import HeldBox, Progress, TickedSegments, ticks
from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.timeline import Timing, interpolate_frame, min_jerk
from pivot_ompl.wholebody.walker import PlacoWalker

__all__ = ["GenerationStats", "Progress", "Timing", "WholeBodyGenerator"]

log = logging.getLogger(__name__)


class WholeBodyGenerator(TickedSegments):
    """Turns a plan into a :class:`Motion` (see the module docstring).

    Args:
        plan: the pivoting plan.
        settings: walking and solver parameters.
        timing: segment durations and tolerances.
        tilt: inclination of the held box about its supporting edge (rad).
        progress: optional callback ``progress(fraction, label)``.

    Attributes:
        recorder: the samples recorded so far (:class:`~.recording.Recorder`).
        stats: the generation's statistics.
    """

    def __init__(self, plan: Plan, *, settings: WalkSettings | None = None,
                 timing: Timing | None = None, tilt: float = DEFAULT_TILT,
                 progress: Progress | None = None) -> None:
        if not plan.phases:
            raise InputError("phases", [], "the plan has no phase to animate")
        if not 0.0 <= tilt < math.radians(20):
            raise InputError("tilt", tilt, "must be in [0, 20 deg)")
        self.plan = plan
        self.settings = settings or WalkSettings.of(profile_of(plan.robot_model))
        if self.settings.robot != plan.robot_model:
            raise InputError("settings.robot", self.settings.robot,
                             f"the plan is for {plan.robot_model!r}")
        self.timing = timing or Timing()
        self.hold = BoxHold(tuple(plan.object_size), tilt=tilt)  # type: ignore[arg-type]
        self.progress = progress
        self.stats = GenerationStats()
        self.recorder = Recorder()
        self._t = 0.0
        self._phase = 0
        self._step = -1

    # -- public -------------------------------------------------------------------------
    def run(self) -> Motion:
        """Generate the whole motion.

        Raises:
            WholeBodyError: the solver failed or a grip became unreachable.
            InputError: the plan is inconsistent (a step that is not a pivot rotation).
        """
        t_wall = time.perf_counter()
        plan = self.plan
        first = plan.phases[0]
        start = first.robot_start if isinstance(first, TransferPhase) else first.robot_path[0]
        observed = observed_robot(plan)
        self._phase, self._step = 0, -1
        try:
            self.walker = PlacoWalker(self.settings, observed or start)
        except Exception as e:  # pragma: no cover - model/setup failure
            raise WholeBodyError(0, -1, f"cannot set up the PlaCo robot ({e})") from e
        self._box_T = self.hold.T_world_box(self.hold.T_world_G(plan.start, 0), 0, 0.0)
        units = sum(len(p.steps) + 2 if isinstance(p, TransferPhase) else 1
                    for p in plan.phases)
        self._units_total, self._units_done = max(units, 1), 0
        self._stand(self.timing.settle, lambda s: None)
        if observed is not None and (math.dist(observed[:2], start[:2]) > 0.01
                                     or abs(wrap_angle(observed[2] - start[2])) > 0.01):
            log.info("walking from the observed robot pose to the plan's first stance")
            self._walk_to([start])
        obj = plan.start
        for i, phase in enumerate(plan.phases):
            self._phase, self._step = i, -1
            if isinstance(phase, TransferPhase):
                obj = self._transfer(i, phase)
            else:
                self._transit(i, phase, obj)
        self._report(1.0, "done")
        names = tuple(str(n) for n in self.walker.robot.model.names[2:])
        motion = self.recorder.motion(plan, self.hold, names, substeps=self.settings.substeps)
        self.stats.compute = time.perf_counter() - t_wall
        self.stats.ticks, self.stats.samples = len(self.recorder.t), len(motion.t)
        self.stats.duration = float(motion.t[-1] - motion.t[0])
        return motion

    def _transfer(self, i: int, phase: TransferPhase) -> Pose:
        hold, tm = self.hold, self.timing
        k = phase.grasp
        obj = phase.object_start
        pose = self.walker.robot_pose()
        d = math.hypot(pose[0] - phase.robot_start[0], pose[1] - phase.robot_start[1])
        if d > 0.01 or abs(wrap_angle(pose[2] - phase.robot_start[2])) > 0.01:
            log.info("phase %d: walking %.3f m to the transfer start", i, d)
            self._walk_to([phase.robot_start])
        G = hold.T_world_G(obj, k)
        theta = hold.tilt
        held = HeldBox(hold, k, G)
        self._move_box(held)
        # reach
        start_hands = self._rest_hands()  # the current targets: no jump in the tasks
        goal = self.hold.T_world_hands(G, k, 0.0)
        self._stand(tm.reach, lambda s: None, hands_of=lambda s: (
            interpolate_frame(start_hands[0], goal[0], min_jerk(s)),
            interpolate_frame(start_hands[1], goal[1], min_jerk(s))))
        self._unit_done(f"phase {i}: reach")

        self._incline(held, lambda s: theta * min_jerk(s))  # tilt
        # pivot steps: the plan is checked first, then walked in continuous walks
        check_pivot_steps(hold, phase, i)
        robots = [phase.robot_start, *(st.robot for st in phase.steps)]
        j = 0
        while j < len(phase.steps):
            n = self._pivot_walk(i, phase, j, robots, held)
            if n == 0:  # no continuous stepping for this pivot: step it alone
                self._pivot_alone(i, phase, j, robots[j], held)
                n = 1
            j += n
            self._move_box(held, G=hold.T_world_G(phase.steps[j - 1].object, k))
        obj = phase.steps[-1].object if phase.steps else obj
        self._step = -1

        self._incline(held, lambda s: theta * (1.0 - min_jerk(s)))  # set down, release
        grip = self.hold.T_world_hands(held.G, k, 0.0)
        self._stand(tm.release, lambda s: None, hands_of=lambda s: (
            interpolate_frame(grip[0], self._rest_hands()[0], min_jerk(s)),
            interpolate_frame(grip[1], self._rest_hands()[1], min_jerk(s))))
        self._unit_done(f"phase {i}: release")
        return obj

    def _incline(self, held: HeldBox, tilt_of: Callable[[float], float]) -> None:
        """Stand for :attr:`Timing.tilt` while the held box's tilt follows ``tilt_of(s)``."""
        k = held.grasp
        self._stand(self.timing.tilt, lambda s: self._move_box(held, tilt=tilt_of(s)),
                    holding=True, grasp=k, tilt_of=tilt_of,
                    hands_of=lambda s: self.hold.T_world_hands(held.G, k, held.tilt))

    def _rotation(self, step: TransferStep, G0: np.ndarray,
                  held: HeldBox) -> Callable[[float], None]:
        """``each(s)``: the box turned by the step's angle times min_jerk(s) from ``G0``."""
        def each(s: float) -> None:
            self._move_box(held, G=rotation_about_vertical(step.pivot,
                                                           step.angle * min_jerk(s)) @ G0)
        return each

    def _pivot_alone(self, i: int, phase: TransferPhase, j: int, before: Pose,
                     held: HeldBox) -> None:
        """Pivot step ``j`` as a walk of its own along its arc (or standing, if no step)."""
        k, theta = phase.grasp, self.hold.tilt
        step = phase.steps[j]
        self._step = j
        arc = [rotate_about(before, step.pivot, step.angle * u)
               for u in (0.25, 0.5, 0.75)] + [step.robot]
        self._walk_to(arc, holding=True, grasp=k, tilt=theta,
                      each=self._rotation(step, held.G, held),
                      hands_of=lambda: self.hold.T_world_hands(held.G, k, theta),
                      follow_path=True)
        self._unit_done(f"phase {i}: pivot {j + 1}/{len(phase.steps)}")

    def _pivot_walk(self, i: int, phase: TransferPhase, j0: int, robots: list[Pose],
                    held: HeldBox) -> int:
        """Pivot steps ``j0, j0 + 1, ...`` in one continuous walk; return how many.

        The footsteps of each pivot come from :func:`.footsteps.pivot_footsteps` (two or
        three steps, the feet alternating across pivots) and the walk is planned in one
        piece of at most :attr:`Timing.pivot_walk_steps` steps, coming to rest only at its
        end. Pivot ``j``'s rotation runs from the middle of the double support that ends
        pivot ``j - 1`` (or the walk's start) to the middle of the double support after its
        own last step, where both feet stand at the step's ``robot`` pose (the walk's first
        rotation starts with its first step). Returns 0 when
        pivot ``j0`` needs no step or cannot be stepped so (the caller steps it alone).
        """
        walker, hold = self.walker, self.hold
        k, theta = phase.grasp, hold.tilt
        footsteps, last = chain_pivot_footsteps(walker, phase, j0, robots,
                                                max_steps=self.timing.pivot_walk_steps)
        if not last:
            return 0
        t0 = self._t
        traj = walker.plan_walk(footsteps, t0)
        starts, ends = rotation_windows(traj, last, t0, self.settings.solver_dt)
        total = ticks(traj.t_end - t0, self.settings.solver_dt)
        G0: np.ndarray | None = None
        p, u = 0, 0.0
        for tick in range(total):
            while p < len(ends) - 1 and tick > ends[p]:
                self._unit_done(f"phase {i}: pivot {j0 + p + 1}/{len(phase.steps)}")
                p += 1
                G0 = None
            step = phase.steps[j0 + p]
            if G0 is None:
                self._step = j0 + p
                G0 = hold.T_world_G(object_before(phase, j0 + p), k)
                u = 0.0
            if tick >= ends[p]:
                u = 1.0
            elif tick > starts[p]:
                u = max(u, turn_progress(traj, self._t, robots[j0 + p], step,
                                          (tick - starts[p]) / (ends[p] - starts[p]),
                                          follow_feet=self.timing.follow_feet))
            self._move_box(held, G=rotation_about_vertical(step.pivot, step.angle * u) @ G0)
            self._tick(traj, self.hold.T_world_hands(held.G, k, theta), holding=True, grasp=k,
                       tilt=theta)
        self._unit_done(f"phase {i}: pivot {j0 + len(last)}/{len(phase.steps)}")
        walker.stand()
        return len(last)

    def _transit(self, i: int, phase: TransitPhase, obj: Pose) -> None:
        self._box_T = self.hold.T_world_box(self.hold.T_world_G(obj, 0), 0, 0.0)
        self._walk_to(list(phase.robot_path), follow_path=True)
        self._unit_done(f"phase {i}: transit")
