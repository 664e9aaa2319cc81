"""What the plans of one scene share: values computed once per scene geometry.

Every plan builds a checker, fields and lattices of its own, but much of what they compute
depends only on the scene (its geometry, pivoting, walking, start and goal:
:func:`~pivot_ompl.scene.scene_digest`), never on the plan asking. :func:`scene_shared` keeps
such a value for later plans of the scene in the process: the motion checks
(:mod:`pivot_ompl.checking.shared_results`), the assembly fields
(:mod:`pivot_ompl.planners.routes.shared_fields`), the route bound's free field
(:mod:`pivot_ompl.planners.route_field`), the disk route bound
(:func:`pivot_ompl.analysis.plan_bounds.plan_bounds`) and whether the late proof has nothing
to prove (:mod:`pivot_ompl.analysis.late_proof`), and its relaxations until the plan's
bound takes them (:mod:`pivot_ompl.analysis.relaxation_handoff`): one memo for all, the
least recently used value dropped first beyond :data:`KEPT`.
"""

from __future__ import annotations

from collections.abc import Callable, Hashable
from typing import Any, TypeVar, cast

from pivot_ompl.cache import BoundedCache
from pivot_ompl.scene.files import scene_digest
from pivot_ompl.scene.model import Scene

__all__ = ["KEPT", "drop_shared", "keep_shared", "scene_shared", "shared_value"]

T = TypeVar("T")

#: Values kept, all scenes and kinds together (a scene has its checks, a free field, a
#: route bound and an assembly field or a few: a few recent scenes).
KEPT = 32

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


def shared_value(scene: Scene, what: tuple[Hashable, ...]) -> Any | None:
    """The value kept for ``scene``'s geometry and ``what``, or ``None``; nothing computed."""
    return _memo.get((scene_digest(scene), *what))


def keep_shared(scene: Scene, what: tuple[Hashable, ...], value: object) -> None:
    """Keep ``value`` (not ``None``) for ``scene``'s geometry and ``what``."""
    _memo.put((scene_digest(scene), *what), value)


def drop_shared(scene: Scene, what: tuple[Hashable, ...]) -> None:
    """Forget the value kept for ``scene``'s geometry and ``what`` (nothing when none is)."""
    _memo.discard((scene_digest(scene), *what))
