"""Visibility PRM (Simeon, Laumond and Nissoux 2000), as used in the regrasp paper, Section III.

A sample that sees no guard becomes a guard; one that sees guards of two or more connected
components becomes a connector linked to one guard of each; other samples are discarded.
Construction ends after ``max_failures`` consecutive discarded samples (the roadmap then
covers the free space with high probability) or at the caller's termination condition.

:class:`VisibilityRoadmap` is the one implementation, on any configurations held in any
:class:`RoadmapStore`: the regrasp planner runs it on box poses (the object roadmap), and
:class:`~pivot_ompl.planners.visprm.VisibilityPRM` on compound states ``(pose, grasp)``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from typing import Generic, Protocol, TypeVar

from pivot_ompl.planners.evaluation import Status

C = TypeVar("C")
Stop = Callable[[], bool]


class RoadmapStore(Protocol[C]):
    """Where a visibility roadmap keeps its nodes: configurations, edges, components."""

    def add(self, c: C, kind: str) -> int:
        """Add a node; return its index."""
        ...

    def connect(self, i: int, j: int) -> None:
        """Add the edge ``i - j``."""
        ...

    def component(self, i: int) -> int:
        """Representative of ``i``'s connected component."""
        ...

    def __getitem__(self, i: int) -> C:
        """The configuration of node ``i``."""
        ...


class VisibilityRoadmap(Generic[C]):
    """Guards and connectors grown one sample at a time (see the module docstring).

    Args:
        store: where the nodes go (other nodes may live there too).
        sample: ``should_stop -> configuration`` (a valid random one), or ``None`` when
            stopped.
        visible: ``(a, b, should_stop) -> Status``: whether the local path between two
            configurations is valid (:class:`~pivot_ompl.planners.evaluation.Status`).
        candidates: ``(q, guards) -> guard indices`` to test for visibility from ``q``, in the
            order they are tested (e.g. the nearest within a radius, or those of ``q``'s grasp).
        max_failures: consecutive discarded samples that end the construction.

    Attributes:
        guards: indices (in ``store``) of the guards, start and goal included.
        failures: consecutive discarded samples so far.
    """

    guards: list[int]
    failures: int

    def __init__(self, store: RoadmapStore[C], *, sample: Callable[[Stop], C | None],
                 visible: Callable[[C, C, Stop], Status],
                 candidates: Callable[[C, list[int]], Iterable[int]],
                 max_failures: int) -> None:
        """An empty roadmap over ``store``."""
        self.store = store
        self.sample = sample
        self.visible = visible
        self.candidates = candidates
        self.max_failures = max_failures
        self.guards = []
        self.failures = 0

    @property
    def done(self) -> bool:
        """``max_failures`` consecutive samples were discarded."""
        return self.failures >= self.max_failures

    def add_guard(self, c: C, kind: str = "guard") -> int:
        """Add a node that always becomes a guard (start, goal); return its index."""
        i = self.store.add(c, kind)
        self.guards.append(i)
        return i

    def adopt_guard(self, i: int) -> None:
        """Make node ``i``, already in the store, a guard."""
        self.guards.append(i)

    def step(self, should_stop: Stop) -> tuple[str, int]:
        """One sample: ``("guard" | "connector", index)``, ``("discarded" | "stopped", -1)``."""
        q = self.sample(should_stop)
        if q is None:
            return "stopped", -1
        store = self.store
        seen: dict[int, int] = {}  # component -> the guard seen in it
        for g in self.candidates(q, self.guards):
            if should_stop():
                return "stopped", -1
            comp = store.component(g)
            if comp in seen:
                continue
            status = self.visible(store[g], q, should_stop)
            if status is Status.STOPPED:  # not known: the sample is neither guard nor connector
                return "stopped", -1
            if status is Status.VALID:
                seen[comp] = g
        if not seen:
            self.failures = 0
            return "guard", self.add_guard(q)
        if len(seen) >= 2:
            i = store.add(q, "connector")
            for g in seen.values():
                store.connect(g, i)
            self.failures = 0
            return "connector", i
        self.failures += 1
        return "discarded", -1
