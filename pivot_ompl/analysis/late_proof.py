"""The relaxation's proof that no plan exists, tried late: only when the search is slow to plan.

Before the search, :func:`pivot_ompl.api.plan` proves only what a narrow passage explains
(:func:`~pivot_ompl.analysis.passage.explain_no_plan`: milliseconds when there is none). A
scene without a plan for want of room to turn has no such passage, and its search would run
the whole limit. Running the relaxation before every search costs easy scenes its time
(about 0.1 s of the coarse raster on fig10, a fifth of its solve), so :class:`LateProof` is
asked by the search *while it has no path* (the regrasp search polls it; an OMPL planner's
solve is stopped at ``begin`` to ask it, :mod:`pivot_ompl.base.staged_solve`) and does
nothing before ``begin``; then, once, it runs the relaxation, stopped at ``end``, in the form
that proves and places at once: the exact polygons
(:func:`~pivot_ompl.analysis.turning.turning_place`) where they are estimated to fit, else
the coarse raster in the walls' frame (:func:`framed_turning_place`); a bound the cache holds
answers at once (a solvable one: only the held poses are left to try; an unsolvable one:
only the place is looked for, until ``explain_end``). When no plan exists the reason is the
passage that blocks every plan (:func:`~pivot_ompl.analysis.passage.blocking_passage`) if
there is one, else the place where the held box cannot turn, else (the place not found in
time) a line naming the width the held assembly needs; and the search stops. Where that
relaxation joins start and goal, or where the exact polygons are estimated to need more
than the whole late window (``begin`` to ``held_end``: a large map, where only the framed
raster runs and may prove nothing), the held poses' relaxation is tried
(:func:`held_pose_proof`: it needs no other relaxation's word), behind a gate that spares
it scenes whose poses valid at every yaw join start and goal
(:meth:`LateProof._held_poses`). Its cost to a scene that has a plan
is at most ``end - begin`` and the held poses' window, and only when the search is slow to
find a path; once the exact relaxation has joined a scene's start and goal (nothing to
prove), later plans of the scene in the process do not run it again
(:func:`~pivot_ompl.scene.shared.keep_shared`).
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from collections.abc import Callable
from dataclasses import dataclass

import shapely

from pivot_ompl.analysis.bound_cache import cached_bound
from pivot_ompl.analysis.bound_levels import CELLS, exhaustive_estimate
from pivot_ompl.analysis.passage import Passage, PassageOnce, assembly_width
from pivot_ompl.analysis.pose_estimate import held_estimate
from pivot_ompl.analysis.pose_explain import explained
from pivot_ompl.analysis.pose_floor import HeldFloor
from pivot_ompl.analysis.pose_inner import joined_at_every_yaw
from pivot_ompl.analysis.pose_proof import MOTION_CLEARANCE, proof_estimate, prove_no_plan
from pivot_ompl.analysis.turning import TurningPlace, turning_place, widest_circle
from pivot_ompl.analysis.turning_raster import raster_turning_place
from pivot_ompl.analysis.wall_frame import wall_frame
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import keep_shared, shared_value

log = logging.getLogger(__name__)

#: What :func:`~pivot_ompl.scene.shared.keep_shared` keeps for a scene whose exact
#: relaxation joined start and goal: nothing to prove for it.
NOTHING_TO_PROVE = ("late proof: the relaxation joins start and goal",)


@dataclass(frozen=True)
class NoPlan:
    """A proof that no plan exists, with why.

    Attributes:
        reason: one line a person can act on (where, how wide, what needs what).
        passage: the passage that blocks every plan, if one does.
        turn: the place where the held box cannot turn, if that is why.
    """

    reason: str
    passage: Passage | None = None
    turn: TurningPlace | None = None

    def fields(self) -> dict[str, object]:
        """The plan file's fields: ``no_plan`` and, when known, ``passage`` or ``turn``."""
        out: dict[str, object] = {"no_plan": self.reason}
        if self.passage is not None:
            out["passage"] = self.passage.as_dict()
        if self.turn is not None:
            out["turn"] = self.turn.as_dict()
        return out


#: What :func:`~pivot_ompl.scene.shared.keep_shared` keeps for a scene whose held poses'
#: relaxation was run to its end: its :class:`NoPlan`, or ``False`` (nothing proven).
HELD_POSES = ("late proof: the held poses' relaxation",)
#: Share of the held poses' window the gate may take (seconds of CPU):
#: :func:`~pivot_ompl.analysis.pose_inner.joined_at_every_yaw` stopped then tells nothing and
#: lets the proof run (a gate dearer than that saves the proof little: it took 9.3 s of CPU
#: on the 1506 boxes of the lab, whose proof takes 8-9 s).
GATE_SHARE = 0.25


#: Share of the held window (``held_begin`` to ``held_end``) a scene gets whose start and goal
#: the passage search found joined clear of every gap narrower than the held assembly
#: (:attr:`~pivot_ompl.analysis.passage.PassageOnce.clear`: room all the way, most often a
#: plan); the others, where every way passes such a gap (the lab's door, 0.85 m for 0.88 m),
#: get the whole window. At :func:`pivot_ompl.api.plan`'s 4 % to 25 % of the limit: to 14.5 %.
CLEAR_SHARE = 0.5


def generic(scene: Scene) -> NoPlan:
    """The line of a proof whose place was not found in time: what the held assembly needs."""
    need = assembly_width(scene.model)
    return NoPlan(f"no plan: the box and the robot holding it cannot get from the start to the "
                  f"goal; every passage is as wide as they need ({need:.2f} m), so room to "
                  f"turn or to regrasp is missing on the way")


class LateProof:
    """Polled by the search while it has no path: ``True`` once no plan is proven.

    Args:
        scene: the scene planned.
        begin: clock time from which the proof is tried (once).
        end: clock time at which the bound is stopped (nothing proven then).
        explain_end: clock time at which the explanation is stopped (default ``end``); a
            proof found later still gives its passage search ``explain_end - begin``.
        clock: the clock of those times (``time.monotonic``).
        passages: the scene's passage search, shared with the check before the search
            (:class:`~pivot_ompl.analysis.passage.PassageOnce`); default: its own.
        held_begin: clock time from which the held poses' relaxation is tried, whether or
            not the poses' relaxation joins start and goal (default ``begin``; asked before,
            it is tried when asked again after it: a search that plans by then never pays it).
        work_begin: the process's CPU time (``work``) before which the proof is not tried
            either, but from ``held_begin`` on: "slow to find a path" is then the search's
            own work, not the clock's seconds other processes took on a loaded machine
            (``None``: the clock alone; an OMPL planner's solve asks only once).
        work: the clock of ``work_begin`` (``time.process_time``).
        held_end: clock time by which the held poses' relaxation is stopped (tried where
            half its estimate fits before it, and no chain of poses valid at every yaw joins
            start and goal: :func:`~pivot_ompl.analysis.pose_inner.joined_at_every_yaw`, the
            proof could not end apart); where ``passages`` found the start's and the
            goal's regions joined clear of every gap narrower than the held assembly, the
            held window ends at :data:`CLEAR_SHARE` of the way from ``held_begin`` to it,
            and where they found every way passing such a gap, the proof's estimate is
            its passages' try's (:func:`~pivot_ompl.analysis.pose_estimate.held_estimate`);
            ``None``: tried where its every-piece estimate fits before ``explain_end``,
            stopped there.
        should_stop: polled by every relaxation besides its own end (a prover's parent
            that has a plan, :mod:`~pivot_ompl.analysis.prover`).
        exact_seconds: the exact polygons run only where estimated at most this (s) too,
            else the coarse raster, then the held poses whatever the windows (a prover's
            choice: the cheaper proof first); ``None``: where they fit before ``end``.
        gate_share: share of the held poses' window the gate may take (0: no gate, the
            proof at once: a prover's where every way passes a gap narrower than the held
            assembly, most often no plan).

    Attributes:
        proof: the proof, once found; ``None`` before, or when nothing was proven.
        tried: whether the bound was asked.
    """

    def __init__(self, scene: Scene, *, begin: float, end: float,
                 explain_end: float | None = None,
                 clock: Callable[[], float] = time.monotonic,
                 passages: PassageOnce | None = None, held_begin: float | None = None,
                 work_begin: float | None = None,
                 work: Callable[[], float] = time.process_time,
                 held_end: float | None = None,
                 should_stop: Callable[[], bool] | None = None,
                 exact_seconds: float | None = None, gate_share: float = GATE_SHARE) -> None:
        """Nothing tried yet."""
        self.scene, self.begin, self.end = scene, begin, end
        self.held_end = held_end
        self.work_begin, self.work = work_begin, work
        self.held_begin = begin if held_begin is None else held_begin
        self._held_pending = False
        self.passages = passages if passages is not None else PassageOnce(scene)
        self.explain_end = end if explain_end is None else explain_end
        self.clock = clock
        self.should_stop = should_stop
        self.exact_seconds = exact_seconds
        self.gate_share = gate_share
        self.proof: NoPlan | None = None
        self.tried = False

    def __call__(self) -> bool:
        """Whether no plan is proven (tries the proof once, the first time after ``begin``)."""
        if self.tried:
            if self._held_pending and self.clock() >= self.held_begin:
                self._held_pending = False
                return self._held_poses(self.clock())
            return self.proof is not None
        now = self.clock()
        if now < self.begin or (self.work_begin is not None and now < self.held_begin
                                and self.work() < self.work_begin):
            return False
        self.tried = True
        known = cached_bound(self.scene)
        if known is not None and known.solvable:
            return self._held_later(now)
        if known is None and shared_value(self.scene, NOTHING_TO_PROVE):
            return self._held_later(now)
        stop = self._stop(self.end if known is None else self.explain_end)
        polygons = exhaustive_estimate(self.scene)
        exact = polygons <= min(self.end - now, math.inf if self.exact_seconds is None
                                else self.exact_seconds)
        if exact:  # proof and place at once (its polygons kept for the bound: joined)
            place = turning_place(self.scene, should_stop=stop, keep=True)
        else:
            place = framed_turning_place(self.scene, should_stop=stop)
        if place is None and known is None:
            if exact and not stop():  # run to its end: the relaxation joins start and goal
                keep_shared(self.scene, NOTHING_TO_PROVE, True)
                return self._held_later(now)
            held = self.explain_end if self.held_end is None else self.held_end
            if polygons > held - self.begin or self.exact_seconds is not None:
                # a map too large for the exact polygons, or a prover's cheaper proof next
                return self._held_later(now)  # the held poses need no other relaxation's word
            log.debug("late proof: nothing proven in %.2f s", self.clock() - now)
            return False
        # the proof holds: the passage (milliseconds) gets its window even past explain_end,
        # which a loaded machine's clock may have passed while the proof ran
        passage = self.passages(should_stop=self._stop(
            max(self.explain_end, self.clock() + self.explain_end - self.begin)))
        if passage is not None:  # a narrow passage says more than where to turn
            self.proof = NoPlan(passage.reason, passage=passage)
        else:
            self.proof = generic(self.scene) if place is None else NoPlan(place.reason,
                                                                          turn=place)
        log.info("no plan exists (proven in %.2f s): %s", self.clock() - now,
                 self.proof.reason)
        return True

    def _held_later(self, now: float) -> bool:
        """:meth:`_held_poses` now, or when asked again after ``held_begin``."""
        if self.clock() >= self.held_begin:
            return self._held_poses(now)
        self._held_pending = True
        return False

    def _held_poses(self, now: float) -> bool:
        """The held poses' relaxation, whatever the turning place's relaxation said.

        Not tried where a chain of poses valid at every yaw joins start and goal
        (:func:`~pivot_ompl.analysis.pose_inner.joined_at_every_yaw`, the gate: it could not
        prove; asked with at most :data:`GATE_SHARE` of the proof's window in seconds of
        ``work``: a gate dearer than that saves the proof little); else tried when half its
        estimate fits before ``held_end`` (then stopped at ``held_end`` once it has had as
        many seconds of ``work`` as the clock's from now to then, as a loaded machine's
        clock runs ahead of the work, and at twice that window at the latest), or without
        ``held_end`` when the estimate fits before ``explain_end`` (stopped there). The
        estimate: with ``held_end``, where
        every way from start to goal passes a gap narrower than the held assembly (most
        often no plan: the proof's passages' try most often ends it), its try's
        (:func:`~pivot_ompl.analysis.pose_estimate.held_estimate`, on the floor then built
        for the gate and the proof); else every piece's
        (:func:`~pivot_ompl.analysis.pose_proof.proof_estimate`: a feasible scene's try
        joins start and goal and the proof goes on with every piece). Its answer is kept
        for the scene's geometry (a later plan of the scene reads it, and does not try
        again what found nothing).
        """
        kept = shared_value(self.scene, HELD_POSES)
        if kept is None:
            floor: HeldFloor | None = None
            guess = proof_estimate(self.scene)
            if (self.held_end is not None and self.passages.clear is False
                    and self._held_window(0.0)[0] is not None):
                try:  # most often no plan: the passages' try most often ends the proof
                    floor = HeldFloor(self.scene, MOTION_CLEARANCE, self._floor_stop())
                except Interrupted:
                    return False  # stopped: nothing known, may be tried again with more time
                guess = held_estimate(floor)
            stop, window = self._held_window(guess)
            log.debug("late proof: held poses estimated at %.2f s, window %.2f s%s", guess,
                      window, "" if stop is not None else ": not tried")
            if stop is None:
                return False
            spent = self.work() + self.gate_share * window
            try:  # one floor for the estimate, the gate and the proof
                if floor is None:
                    floor = HeldFloor(self.scene, MOTION_CLEARANCE, stop)
            except Interrupted:
                return False  # stopped: nothing known, may be tried again with more time
            joined = joined_at_every_yaw(
                self.scene, should_stop=lambda: stop() or self.work() >= spent, floor=floor)
            log.debug("late proof: joined at every yaw: %s (%.2f s)", joined,
                      self.clock() - now)
            if joined:
                keep_shared(self.scene, HELD_POSES, False)  # nothing it could prove
                return False
            proof = held_pose_proof(self.scene, should_stop=stop, floor=floor)
            if proof is None and stop():
                return False  # stopped: nothing known, may be tried again with more time
            kept = proof if proof is not None else False
            keep_shared(self.scene, HELD_POSES, kept)
        if not isinstance(kept, NoPlan):
            return False
        self.proof = kept
        log.info("no plan exists (proven in %.2f s): %s", self.clock() - now, kept.reason)
        return True

    def _held_window(self, guess: float) -> tuple[Callable[[], bool] | None, float]:
        """The held poses' stop for a proof estimated at ``guess`` s, and its window (s).

        With ``held_end``: its stop (:meth:`_held_stop`) where half of ``guess`` fits before
        it (the estimate only admits: the bins a proof computes vary fourfold between maps
        of one cost a bin), or before :data:`CLEAR_SHARE` of the held window where the
        scene's passage search found the start's and the goal's regions joined clear of
        every gap narrower than the held assembly (``passages.clear``); else the stop at
        ``explain_end`` where ``guess`` fits before it.
        ``None`` and 0: no window fits it.
        """
        now = self.clock()
        end = self.held_end
        if end is not None and self.passages.clear:  # room all the way: most often a plan
            end = self.held_begin + CLEAR_SHARE * (end - self.held_begin)
        if end is not None and end > now + 0.5 * guess:
            return self._held_stop(end), end - now
        if self.held_end is None and guess <= self.explain_end - now:
            return self._stop(self.explain_end), self.explain_end - now
        return None, 0.0

    def _held_stop(self, at: float) -> Callable[[], bool]:
        """A stop at clock time ``at``, once the work has had the clock's seconds till then.

        At twice the clock's window from now at the latest.
        """
        window = at - self.clock()
        cap, spent = at + window, self.work() + window

        def stop() -> bool:
            now = self.clock()
            return now >= cap or (now >= at and self.work() >= spent) or self._told()

        return stop

    def _floor_stop(self) -> Callable[[], bool]:
        """The stop of the floor built for the estimate: where no window is left for it."""
        return lambda: self._held_window(0.0)[0] is None or self._told()

    def _stop(self, at: float) -> Callable[[], bool]:
        return lambda: self.clock() >= at or self._told()

    def _told(self) -> bool:
        return self.should_stop is not None and self.should_stop()


def held_pose_proof(scene: Scene, *, should_stop: Callable[[], bool] | None = None,
                    floor: HeldFloor | None = None) -> NoPlan | None:
    """The held poses' relaxation's proof (:func:`~pivot_ompl.analysis.pose_proof.prove_no_plan`).

    Tried where the poses' relaxation joins start and goal: it refines the yaw where that
    relaxation's rooms join. ``None`` when it proves nothing before ``should_stop``.
    ``floor``: the scene's floor at the proof's clearance, shared with its gate.
    """
    proof = prove_no_plan(scene, should_stop=should_stop, floor=floor)
    if not proof.apart:
        return None
    line, passage = explained(scene, proof, should_stop=should_stop)
    return NoPlan(line, passage=passage)


def framed_turning_place(scene: Scene, *, cell: float = CELLS[0],
                         should_stop: Callable[[], bool] | None = None) -> TurningPlace | None:
    """:func:`~pivot_ompl.analysis.turning_raster.raster_turning_place`, in the walls' frame.

    (:func:`~pivot_ompl.analysis.wall_frame.wall_frame`; the scene as it is where no frame is
    worth it.) The place is turned back to the scene and its room to turn measured there.
    """
    frame = wall_frame(scene, should_stop=should_stop)
    if frame is None:  # the scene's own raster: kept for its bound when it joins the ends
        return raster_turning_place(scene, cell=cell, should_stop=should_stop, keep=True)
    place = raster_turning_place(frame.scene, cell=cell, should_stop=should_stop)
    if place is None:
        return None
    centre = frame.point_out(place.center)
    width = widest_circle(scene, shapely.Point(centre), 0.5 * place.assembly_length,
                          should_stop)
    return dataclasses.replace(place, center=centre, width=width,
                               from_start=frame.arc_out(place.from_start),
                               to_goal=frame.arc_out(place.to_goal))
