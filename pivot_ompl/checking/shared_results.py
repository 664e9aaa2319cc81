"""The motion checks of recent scenes, shared by the checkers of their plans.

A transfer's pivot sequence and a walk between two grasps depend only on the scene (its
geometry, pivoting and walking: :func:`~pivot_ompl.scene.scene_digest`) and the checker's
tolerance and kept clearance, never on the plan asking. Every plan builds a checker of its
own; :func:`shared_results` (kept by :func:`~pivot_ompl.scene.shared.scene_shared`) hands a
later plan of the same scene the results an earlier one computed, so a second plan of a
scene checks again only what no plan checked before.

A result a checker takes from here counts as computed by it
(:class:`~.pivot_checker.MotionCounters`): the improvement's budgets, which count checks,
and so the plans are the same whatever the process planned before. A checker offered
stored motions (:meth:`~.pivot_checker.PivotChecker.offer`), whose results may differ,
keeps its own.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from pivot_ompl.scene import Scene
from pivot_ompl.scene.shared import scene_shared

__all__ = ["RESULTS_KEPT", "SharedResults", "shared_results"]

#: Most results kept per scene, transfers and walks together (1-3 KB each, pickled: three
#: plans of the hall layout keep 865), then forgotten all at once (a later plan computes
#: them again).
RESULTS_KEPT = 10_000


@dataclass
class SharedResults:
    """One scene's checked motions.

    Attributes:
        edges: transfers by ``(a, b, grasp, with_robot)``.
        walks: walks by ``(pose, from_grasp, to_grasp)``.
        shortened: transfer phases' rotations shortened, by ``(start, rotations, grasp)``
            (:func:`~.rotation_shortcut.shorten`).
    """

    edges: dict[tuple, object] = field(default_factory=dict)
    walks: dict[tuple, object] = field(default_factory=dict)
    shortened: dict[tuple, object] = field(default_factory=dict)

    def room(self) -> None:
        """Forget everything once :data:`RESULTS_KEPT` are held."""
        if len(self.edges) + len(self.walks) + len(self.shortened) >= RESULTS_KEPT:
            self.edges.clear()
            self.walks.clear()
            self.shortened.clear()


def shared_results(scene: Scene, *, tolerance: float, clearance: float) -> SharedResults:
    """The results shared by the checkers of ``scene`` at ``tolerance`` and ``clearance`` (m)."""
    res = scene_shared(scene, ("checks", float(tolerance), float(clearance)), SharedResults)
    assert res is not None
    return res
