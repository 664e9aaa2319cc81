"""The figures of a regrasp planner's run (:class:`~.regrasp_search.RegraspSearch`'s stats).

Serialised as they are (``dataclasses.asdict``) into a plan's ``roadmap`` and a benchmark's
``planner_*`` columns: fields are added, never renamed or removed.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pivot_ompl.planners.improve import ImproveStats
    from pivot_ompl.planners.multiplex.graph import MultiplexedGraph
    from pivot_ompl.planners.multiplex.search import PathSearch
    from pivot_ompl.planners.objects.roadmap import Roadmap


@dataclass
class RegraspStats:
    """Figures of one run (roadmap sizes, counts, seconds per stage).

    Attributes:
        single_grasp_solved, single_grasp_by: whether a regrasp-free try
            (:mod:`~.direct`) gave the path, and which (``"rrt"``, ``"lattice"``, ``""``).
        regrasp_lattice_solved: whether the path came from the regrasp lattice
            (:mod:`~.routes.regrasp_lattice`: regrasps where the held assembly's lattice
            components meet), before any object roadmap was grown (then
            ``object_nodes`` is 0).
        regrasp_lattice_changes: component changes (regrasps) of the regrasp lattice's
            coarse plan; ``-1`` when it found none or was not tried.
        time_regrasp_lattice: seconds spent in the regrasp lattice's try.
    """

    object_nodes: int = 0
    guards: int = 0
    connectors: int = 0
    critical: int = 0
    diffusion_nodes: int = 0
    passage_nodes: int = 0
    slots: int = 0
    slot_nodes: int = 0
    doors: int = 0
    door_nodes: int = 0
    manipulation_nodes: dict[int, int] = field(default_factory=dict)
    regrasp_edges: int = 0
    turn_edges: int = 0
    searches: int = 0
    edges_checked: int = 0
    plausibility_tests: int = 0
    edges_invalid: int = 0
    single_grasp_checks: int = 0
    single_grasp_solved: bool = False
    single_grasp_by: str = ""
    time_single_grasp: float = 0.0
    time_visibility: float = 0.0
    time_search: float = 0.0
    time_optimise: float = 0.0
    time_routes: float = 0.0
    refined: int = 0
    regrasps_turned: int = 0
    regrasp_lattice_solved: bool = False
    regrasp_lattice_changes: int = -1
    time_regrasp_lattice: float = 0.0

    def count(self, roadmap: Roadmap, graph: MultiplexedGraph, paths: PathSearch,
              improved: ImproveStats) -> None:
        """Take the roadmap's, graph's, search's and improvement's figures as they are now."""
        kinds = roadmap.kinds
        self.object_nodes = len(roadmap)
        self.guards = kinds.count("guard") + 2
        self.connectors = kinds.count("connector")
        self.critical = kinds.count("critical")
        self.manipulation_nodes = {g: len(v) for g, v in graph.by_grasp.items()}
        self.regrasp_edges = graph.regrasp_edges
        self.turn_edges = graph.turn_edges
        self.plausibility_tests = graph.plausibility_tests
        self.searches = paths.searches
        self.edges_checked = paths.edges_checked
        self.edges_invalid = paths.edges_invalid
        self.time_search = paths.seconds
        self.refined = improved.refine.applied
        self.regrasps_turned = improved.refine.regrasps_removed
