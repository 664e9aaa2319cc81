"""The relaxation's proof that no plan exists, tried late: only when the search is slow to plan.

Before the search, :func:`pivot_ompl.api.plan` proves only what a narrow passage explains
(:func:`~pivot_ompl.analysis.passage.explain_no_plan`: milliseconds when there is none). A
scene without a plan for want of room to turn has no such passage, and its search would run
the whole limit. Running the relaxation before every search costs easy scenes its time
(about 0.1 s of the coarse raster on fig10, a fifth of its solve), so :class:`LateProof` is
polled by the search *while it has no path* and does nothing before ``begin``; then, once,
it asks the relaxation, stopped at ``end``: where the exact polygons are estimated to fit,
:func:`~pivot_ompl.analysis.turning.turning_place` (the relaxation itself: it proves and
places at once); elsewhere the regrasp bound coarse to fine
(:func:`~pivot_ompl.analysis.bound_cache.lower_bound`; a result kept by the cache serves the
plan's quality block later). When no plan exists it says why, stopped at ``explain_end``:
the passage that blocks every plan (:func:`~pivot_ompl.analysis.passage.blocking_passage`),
else the place where the held box cannot turn, else a line naming the width the held
assembly needs; and the search stops. Its cost to a scene that has a plan is at most
``end - begin``, and only when the search is slow to find a path.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass

from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.analysis.bound_levels import exhaustive_estimate
from pivot_ompl.analysis.passage import Passage, assembly_width, blocking_passage
from pivot_ompl.analysis.turning import TurningPlace, turning_place
from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)

#: Margin on the polygons' time (measured by the proof, else estimated) before the turning
#: place is looked for (it runs them once more, and searches from both ends).
EXPLAIN_MARGIN = 1.0


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


def explain_proven(scene: Scene, *, should_stop: Callable[[], bool] | None = None,
                   time_left: Callable[[], float] | None = None,
                   polygons: float | None = None) -> NoPlan:
    """Why ``scene``, which the relaxation proved has no plan, has none (module docstring).

    The turning place is looked for when ``time_left()`` (s, if known) holds
    :data:`EXPLAIN_MARGIN` times the polygons' time: ``polygons`` (s, measured) or estimated.
    """
    passage = blocking_passage(scene, should_stop=should_stop)
    if passage is not None:
        return NoPlan(passage.reason, passage=passage)
    left = None if time_left is None else time_left()
    cost = exhaustive_estimate(scene) if polygons is None else polygons
    if left is None or EXPLAIN_MARGIN * cost <= left:
        place = turning_place(scene, should_stop=should_stop)
        if place is not None:
            return NoPlan(place.reason, turn=place)
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
        explain_end: clock time at which the explanation is stopped (default ``end``).
        clock: the clock of those times (``time.monotonic``).

    Attributes:
        proof: the proof, once found; ``None`` before, or when nothing was proven.
        tried: whether the bound was asked.
    """

    def __init__(self, scene: Scene, *, begin: float, end: float,
                 explain_end: float | None = None,
                 clock: Callable[[], float] = time.monotonic) -> None:
        """Nothing tried yet."""
        self.scene, self.begin, self.end = scene, begin, end
        self.explain_end = end if explain_end is None else explain_end
        self.clock = clock
        self.proof: NoPlan | None = None
        self.tried = False

    def __call__(self) -> bool:
        """Whether no plan is proven (tries the proof once, the first time after ``begin``)."""
        if self.tried:
            return self.proof is not None
        now = self.clock()
        if now < self.begin:
            return False
        self.tried = True
        budget = self.end - now
        if exhaustive_estimate(self.scene) <= budget:  # the polygons: proof and place at once
            place = turning_place(self.scene, should_stop=lambda: self.clock() >= self.end)
            if place is None:
                log.debug("late proof: nothing proven in %.2f s", self.clock() - now)
                return False
            passage = blocking_passage(self.scene,
                                       should_stop=lambda: self.clock() >= self.explain_end)
            self.proof = (NoPlan(passage.reason, passage=passage) if passage is not None
                          else NoPlan(place.reason, turn=place))
        else:
            bound = lower_bound(self.scene, refine_seconds=budget,
                                should_stop=lambda: self.clock() >= self.end)
            if bound.solvable is not False:
                log.debug("late proof: nothing proven (%s) in %.2f s", bound.solvable,
                          self.clock() - now)
                return False
            self.proof = explain_proven(
                self.scene, should_stop=lambda: self.clock() >= self.explain_end,
                time_left=lambda: self.explain_end - self.clock(),
                polygons=bound.seconds if bound.exhaustive else None)
        log.info("no plan exists (proven in %.2f s): %s", self.clock() - now,
                 self.proof.reason)
        return True
