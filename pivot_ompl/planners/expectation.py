"""What the search expects of its plan, told once, as soon as known, to a listener.

A plan's prover (:class:`~pivot_ompl.analysis.prover.Prover`) proves the regrasp bound on a
second core while the search runs. The bound's refinement costs least where it knows the
plan's count (its target) and where the plan regrasps (the places it refines first): the
search knows both long before its plan is made real, once its regrasp-free tries have ended
or its lattice has found the coarse plan over rooms and passages
(:func:`~.routes.regrasp_lattice.component_steps`). :class:`Expectation` tells the listener
that once: ``(regrasps, places)``, with ``regrasps`` ``None`` when the search has no coarse
plan (it then learns the count only with the plan). What is told is cost only: the bound is a
proof whatever it is told.
"""

from __future__ import annotations

from collections.abc import Callable

from pivot_ompl.planners.routes.regrasp_lattice import ComponentSteps, meeting_places

#: A listener: the regrasps expected (``None``: unknown) and where (m, the scene's frame).
Listener = Callable[[int | None, tuple[tuple[float, float], ...]], None]


class Expectation:
    """Tells :attr:`listener` (if any) the search's first expectation, once.

    Attributes:
        listener: told ``(regrasps, places)``; ``None``: nobody listens.
        told: whether it has been told (later expectations are not told).
    """

    def __init__(self, listener: Listener | None = None) -> None:
        """Nothing told yet."""
        self.listener = listener
        self.told = False

    def tell(self, regrasps: int | None,
             places: tuple[tuple[float, float], ...] = ()) -> None:
        """Tell ``(regrasps, places)`` unless told already."""
        if self.told:
            return
        self.told = True
        if self.listener is not None:
            self.listener(regrasps, places)

    def steps(self, steps: ComponentSteps) -> None:
        """Tell the lattice's coarse plan: its changes, at its meetings' first poses."""
        self.tell(len(steps.meetings), meeting_places(steps))
