"""What the plans of one scene share: values computed once per scene, and its motion checks.

Every plan builds a checker, fields and lattices of its own, but much of what they compute
depends only on the scene (its geometry, pivoting and walking:
:func:`~pivot_ompl.scene.scene_digest`), never on the plan asking. :func:`scene_shared` keeps
such a value for later plans of the scene (the assembly fields of
:mod:`pivot_ompl.planners.routes.shared_fields`, the route bound's free field of
:mod:`pivot_ompl.planners.follow_route`, the motion checks below), one memo for all, the
least recently used dropped first beyond :data:`KEPT` values.

:func:`shared_results` is the scene's checked transfers and walks (by the checker's tolerance
and kept clearance): a later plan of a scene checks again only what no plan checked before.
A result a checker takes from there counts as computed by it
(:class:`~.pivot_checker.MotionCounters`): the improvement's budgets, which count checks,
and so the plans are the same whatever the process planned before. A checker offered stored
motions (:meth:`~.pivot_checker.PivotChecker.offer`), whose results may differ, keeps its own.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from dataclasses import dataclass, field
from typing import Any, TypeVar, cast

from pivot_ompl.cache import BoundedCache
from pivot_ompl.scene import Scene, scene_digest

__all__ = ["KEPT", "RESULTS_KEPT", "SharedResults", "scene_shared", "shared_results"]

T = TypeVar("T")

#: Values kept, all scenes and kinds together (a scene has its checks, a free field and an
#: assembly field or a few: a few recent scenes).
KEPT = 24
#: Most results kept per scene, transfers and walks together (then forgotten all at once:
#: a later plan computes them again).
RESULTS_KEPT = 20_000

_memo: BoundedCache[tuple[Hashable, ...], Any] = BoundedCache(KEPT)


def scene_shared(scene: Scene, what: tuple[Hashable, ...], compute: Callable[[], T | None]
                 ) -> T | None:
    """The value ``compute()`` gives for ``scene``'s geometry and ``what``, computed once.

    ``what`` names the kind of value and whatever else it depends on (a resolution, a
    region, ...). ``None`` (e.g. stopped) is returned and not kept.
    """
    key = (scene_digest(scene), *what)
    hit = _memo.get(key)
    if hit is None:
        hit = compute()
        if hit is not None:
            _memo.put(key, hit)
    return cast("T | None", hit)


@dataclass
class SharedResults:
    """One scene's checked motions.

    Attributes:
        edges: transfers by ``(a, b, grasp, with_robot)``.
        walks: walks by ``(pose, from_grasp, to_grasp)``.
    """

    edges: dict[tuple, object] = field(default_factory=dict)
    walks: dict[tuple, object] = field(default_factory=dict)

    def room(self) -> None:
        """Forget everything once :data:`RESULTS_KEPT` are held."""
        if len(self.edges) + len(self.walks) >= RESULTS_KEPT:
            self.edges.clear()
            self.walks.clear()


def shared_results(scene: Scene, *, tolerance: float, clearance: float) -> SharedResults:
    """The results shared by the checkers of ``scene`` at ``tolerance`` and ``clearance`` (m)."""
    res = scene_shared(scene, ("checks", float(tolerance), float(clearance)), SharedResults)
    assert res is not None
    return res
