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
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pivot_ompl.errors import InputError, WholeBodyError
from pivot_ompl.humanoids import profile_of
from pivot_ompl.motionfile import Motion
from pivot_ompl.planfile import Plan, TransferPhase, TransferStep, TransitPhase
from pivot_ompl.se2 import Pose, rotate_about, wrap_angle
from pivot_ompl.wholebody.box import (
    DEFAULT_TILT,
    BoxHold,
    rotation_about_vertical,
)
from pivot_ompl.wholebody.footsteps import chunks
from pivot_ompl.wholebody.pivot_walk import (
    chain_pivot_footsteps,
    check_pivot_steps,
    object_before,
    rotation_windows,
    turn_progress,
)
from pivot_ompl.wholebody.plan_start import observed_robot
from pivot_ompl.wholebody.recording import GenerationStats, Recorder, Sample
from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.timeline import Timing, interpolate_frame, min_jerk
from pivot_ompl.wholebody.walk_windows import WindowedWalk
from pivot_ompl.wholebody.walker import PlacoWalker, SolverFailure

if TYPE_CHECKING:
    pass

log = logging.getLogger(__name__)

#: progress(fraction done in [0, 1], label)
Progress = Callable[[float, str], None]


@dataclass
class _HeldBox:
    """The box while the hands hold it: its grasp frame ``G`` and tilt give its pose."""

    hold: BoxHold
    grasp: int
    G: np.ndarray
    tilt: float = 0.0

    def T_world_box(self) -> np.ndarray:
        """The box frame."""
        return self.hold.T_world_box(self.G, self.grasp, self.tilt)


def _ticks(duration: float, dt: float) -> int:
    """Solver ticks of ``duration`` (s) at ``dt`` (s) a tick, at least one."""
    return max(1, int(round(duration / dt)))


class WholeBodyGenerator:
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

    # -- bookkeeping --------------------------------------------------------------------
    def _report(self, fraction: float, label: str) -> None:
        if self.progress is not None:
            self.progress(min(1.0, fraction), label)

    def _unit_done(self, label: str) -> None:
        self._units_done += 1
        self._report(self._units_done / self._units_total, label)

    def _fail(self, reason: str) -> WholeBodyError:
        return WholeBodyError(self._phase, self._step, reason)

    # -- hands --------------------------------------------------------------------------
    def _rest_hands(self) -> tuple[np.ndarray, np.ndarray]:
        T = self.walker.trunk_frame()
        return T @ self.walker.rest_hands[0], T @ self.walker.rest_hands[1]

    def _move_box(self, held: _HeldBox, *, G: np.ndarray | None = None,
                  tilt: float | None = None) -> None:
        """Set the held box's grasp frame and/or tilt; the recorded box follows."""
        if G is not None:
            held.G = G
        if tilt is not None:
            held.tilt = tilt
        self._box_T = held.T_world_box()

    # -- one tick -----------------------------------------------------------------------
    def _tick(self, walk: WindowedWalk | None, hands: tuple[np.ndarray, np.ndarray], *,
              holding: bool, grasp: int, tilt: float) -> None:
        try:
            support, zmp = self.walker.tick(self._t, walk, hands[0], hands[1])
        except SolverFailure as e:
            raise self._fail(f"infeasible QP at t = {self._t:.3f} s ({e})") from e
        if holding:
            err = self.stats.note_hands(self.walker.hand_frames(), hands)
            if err > self.timing.max_hand_error:
                raise self._fail(f"unreachable grip: a hand is {100 * err:.1f} cm from its "
                                 f"grip point at t = {self._t:.3f} s")
        self.recorder.record(self._t, self.walker.q(), self._box_T, self.walker.com(),
                             Sample(support, zmp, self._phase, self._step if holding else -1,
                                    holding, grasp if holding else -1, tilt))
        self._t += self.settings.solver_dt

    def _stand(self, duration: float, each: Callable[[float], None], *, holding: bool = False,
               grasp: int = -1, tilt_of: Callable[[float], float] | None = None,
               hands_of: Callable[[float], tuple[np.ndarray, np.ndarray]] | None = None
               ) -> None:
        """Stand still for ``duration``; ``each(s)`` updates the box for progress s in [0, 1]."""
        self.walker.stand()
        n = _ticks(duration, self.settings.solver_dt)
        for i in range(n):
            s = (i + 1) / n
            each(s)
            hands = hands_of(s) if hands_of is not None else self._rest_hands()
            self._tick(None, hands, holding=holding, grasp=grasp,
                       tilt=tilt_of(s) if tilt_of is not None else 0.0)

    # -- phases -------------------------------------------------------------------------
    def _walk_to(self, targets: list[Pose], *, holding: bool = False, grasp: int = -1,
                 tilt: float = 0.0,
                 each: Callable[[float], None] | None = None,
                 hands_of: Callable[[], tuple[np.ndarray, np.ndarray]] | None = None,
                 follow_path: bool = False) -> None:
        """Walk through ``targets``; ``each(s)`` (s in [0, 1] over the segment) moves the box.

        With ``follow_path`` the footsteps follow the straight lines between the targets
        (transits: the plan's path is what was checked against the obstacles); otherwise
        PlaCo's naive planner walks to each target.
        """
        if follow_path:
            footsteps = self.walker.path_footsteps(targets)
        else:
            footsteps = self.walker.plan_footsteps(targets)
        if not footsteps:
            if each is not None:
                self._stand(self.timing.min_rotate, each, holding=holding, grasp=grasp,
                            tilt_of=lambda s: tilt,
                            hands_of=(lambda s: hands_of()) if hands_of else None)
            return
        # a walk moving the box is planned in one piece (its rotation spans it); a transit is
        # cut into walks of at most max_steps steps, each coming to rest
        size = len(footsteps) if each is not None else self.timing.max_steps
        for chunk in chunks(footsteps, size):
            traj = self.walker.plan_walk(chunk, self._t)
            t0, t1 = traj.t_start, traj.t_end
            m = self.timing.rotate_margin
            n = _ticks(t1 - t0, self.settings.solver_dt)
            for _ in range(n):
                if each is not None:
                    each(((self._t - t0) - m) / max(t1 - t0 - 2 * m, 1e-6))
                hands = hands_of() if hands_of is not None else self._rest_hands()
                self._tick(traj, hands, holding=holding, grasp=grasp, tilt=tilt)
            self.walker.stand()

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
        held = _HeldBox(hold, k, G)
        self._move_box(held)
        # reach
        start_hands = self._rest_hands()  # the current targets: no jump in the tasks
        goal = self.hold.T_world_hands(G, k, 0.0)
        self._stand(tm.reach, lambda s: None, hands_of=lambda s: (
            interpolate_frame(start_hands[0], goal[0], min_jerk(s)),
            interpolate_frame(start_hands[1], goal[1], min_jerk(s))))
        self._unit_done(f"phase {i}: reach")

        # tilt
        def tilt_each(s: float) -> None:
            self._move_box(held, tilt=theta * min_jerk(s))

        self._stand(tm.tilt, tilt_each, holding=True, grasp=k, tilt_of=lambda s: theta *
                    min_jerk(s), hands_of=lambda s: self.hold.T_world_hands(held.G, k, held.tilt))
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

        # set down, release
        def untilt_each(s: float) -> None:
            self._move_box(held, tilt=theta * (1.0 - min_jerk(s)))

        self._stand(tm.tilt, untilt_each, holding=True, grasp=k,
                    tilt_of=lambda s: theta * (1.0 - min_jerk(s)),
                    hands_of=lambda s: self.hold.T_world_hands(held.G, k, held.tilt))
        grip = self.hold.T_world_hands(held.G, k, 0.0)
        self._stand(tm.release, lambda s: None, hands_of=lambda s: (
            interpolate_frame(grip[0], self._rest_hands()[0], min_jerk(s)),
            interpolate_frame(grip[1], self._rest_hands()[1], min_jerk(s))))
        self._unit_done(f"phase {i}: release")
        return obj

    def _rotation(self, step: TransferStep, G0: np.ndarray,
                  held: _HeldBox) -> Callable[[float], None]:
        """``each(s)``: the box turned by the step's angle times min_jerk(s) from ``G0``."""
        def each(s: float) -> None:
            self._move_box(held, G=rotation_about_vertical(step.pivot,
                                                           step.angle * min_jerk(s)) @ G0)
        return each

    def _pivot_alone(self, i: int, phase: TransferPhase, j: int, before: Pose,
                     held: _HeldBox) -> None:
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
                    held: _HeldBox) -> int:
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
        total = _ticks(traj.t_end - t0, self.settings.solver_dt)
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
