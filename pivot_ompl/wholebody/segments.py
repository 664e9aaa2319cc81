"""Segments of solver ticks, recorded: the clock the whole-body generator's phases run on.

One *tick* (:meth:`TickedSegments._tick`) solves the PlaCo controller once (its walk, if any,
and the hands' targets), checks the grips while holding, records a sample and advances the
clock by the solver's step. A segment is a run of ticks: standing still
(:meth:`TickedSegments._stand`) or walking through targets (:meth:`TickedSegments._walk_to`,
long transits cut into walks that each come to rest), a callback ``each(s)`` moving the held
box with the segment's progress ``s``. The phases' timeline is
:class:`~pivot_ompl.wholebody.generator.WholeBodyGenerator`'s.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from pivot_ompl.errors import WholeBodyError
from pivot_ompl.se2 import Pose
from pivot_ompl.wholebody.box import BoxHold
from pivot_ompl.wholebody.footsteps import chunks
from pivot_ompl.wholebody.recording import GenerationStats, Recorder, Sample
from pivot_ompl.wholebody.settings import WalkSettings
from pivot_ompl.wholebody.timeline import Timing
from pivot_ompl.wholebody.walk_windows import WindowedWalk
from pivot_ompl.wholebody.walker import PlacoWalker, SolverFailure

#: progress(fraction done in [0, 1], label)
Progress = Callable[[float, str], None]


@dataclass
class HeldBox:
    """The box while the hands hold it: its grasp frame ``G`` and tilt give its pose."""

    hold: BoxHold
    grasp: int
    G: np.ndarray
    tilt: float = 0.0

    def T_world_box(self) -> np.ndarray:
        """The box frame."""
        return self.hold.T_world_box(self.G, self.grasp, self.tilt)


def ticks(duration: float, dt: float) -> int:
    """Solver ticks of ``duration`` (s) at ``dt`` (s) a tick, at least one."""
    return max(1, int(round(duration / dt)))



class TickedSegments:
    """Standing and walking segments of solver ticks, recorded (see the module docstring).

    The generator sets the attributes before its first segment.

    Attributes:
        settings, timing, hold: walking and solver parameters, segment durations, the box.
        progress: optional callback ``progress(fraction, label)``.
        walker: the PlaCo controller.
        recorder: the samples recorded so far (:class:`~.recording.Recorder`).
        stats: the generation's statistics.
    """

    settings: WalkSettings
    timing: Timing
    hold: BoxHold
    progress: Progress | None
    walker: PlacoWalker
    recorder: Recorder
    stats: GenerationStats
    _t: float  # the clock (s)
    _phase: int  # the plan's phase and step being generated (for samples and errors)
    _step: int
    _box_T: np.ndarray  # the recorded box frame
    _units_total: int  # progress units of the whole plan, and done so far
    _units_done: int

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

    def _move_box(self, held: HeldBox, *, G: np.ndarray | None = None,
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
        n = ticks(duration, self.settings.solver_dt)
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
            n = ticks(t1 - t0, self.settings.solver_dt)
            for _ in range(n):
                if each is not None:
                    each(((self._t - t0) - m) / max(t1 - t0 - 2 * m, 1e-6))
                hands = hands_of() if hands_of is not None else self._rest_hands()
                self._tick(traj, hands, holding=holding, grasp=grasp, tilt=tilt)
            self.walker.stand()
