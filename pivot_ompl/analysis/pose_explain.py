"""The line that explains a proof of the held poses' relaxation: which gap, how wide, why.

:func:`~pivot_ompl.analysis.pose_proof.prove_no_plan` proves that no plan exists where every
passage is as wide as the box and the robot holding it (so
:func:`~pivot_ompl.analysis.passage.blocking_passage` names none): they fit it, but at no
heading from which they can turn into it and out again. The passage named is the narrowest
gap of the widest way from start to goal among the gaps narrower than the assembly is long
(its extent along its length, the longest way it can face a gap).
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
import shapely

from pivot_ompl.analysis.passage import (
    Passage,
    assembly_width,
    blocking_passage,
    gap_at,
    hull_extents,
)
from pivot_ompl.analysis.pose_cells import held_bodies
from pivot_ompl.analysis.pose_proof import PoseProof
from pivot_ompl.scene import Scene
from pivot_ompl.validity.collision import KEEP_CLEARANCE


def assembly_length(scene: Scene) -> float:
    """The held assembly's least length over the grasps (m: its convex outline's extent)."""
    out = []
    for bodies in held_bodies(scene.model):
        ext = hull_extents(np.vstack(bodies))
        out.append(max(length for _, length in ext))
    return min(out)


def explained(scene: Scene, proof: PoseProof, *,
              should_stop: Callable[[], bool] | None = None) -> tuple[str, Passage | None]:
    """The proof's one line and the passage it names (``None`` when none is found)."""
    need = assembly_width(scene.model, clearance=KEEP_CLEARANCE)
    steps = math.degrees(proof.finest)
    tail = (f"the box and the robot holding it ({need:.2f} m across) fit no pose, turning or "
            f"regrasping with the robot walking round the resting box, that takes them through "
            f"(held poses checked in yaw steps down to "
            f"{steps:.2f} degrees)")
    if proof.refused:
        found = _refused_gap(scene, proof)
        if found is not None:
            return found
    passage = blocking_passage(scene, should_stop=should_stop,
                               gaps_below=assembly_length(scene) + 2.0 * KEEP_CLEARANCE)
    if passage is None or passage.center is None:
        return f"no plan: the start's room and the goal's are joined only where {tail}", None
    x, y = passage.center
    line = (f"no plan: every way from the start to the goal passes a gap of at most "
            f"{passage.width:.2f} m (the widest such gap is at ({x:.2f}, {y:.2f})); {tail}")
    return line, dataclasses.replace(passage, note=line)


def _refused_gap(scene: Scene, proof: PoseProof) -> tuple[str, Passage] | None:
    """The line and the gap where the proof's last round refused regrasps (the widest).

    Every chain of that round from start to goal needed a regrasp the robot cannot walk
    round; the gap is the narrowest one across each place (``None``: none found).
    """
    places = shapely.union_all(list(proof.refused))
    widest = assembly_length(scene) + 2.0 * KEEP_CLEARANCE
    reach = 0.5 * max(scene.model.object_size[:2])
    gaps = [g for p in getattr(places, "geoms", [places]) if not p.is_empty
            and (g := gap_at(scene, (p.centroid.x, p.centroid.y), reach=reach,
                             widest=widest)) is not None]
    if not gaps:
        return None
    gap = max(gaps, key=lambda g: g.width)
    x, y = gap.center  # type: ignore[misc]
    where = (f"the gap at ({x:.2f}, {y:.2f}), {gap.width:.2f} m wide" if len(gaps) == 1 else
             f"one of {len(gaps)} gaps (the widest at ({x:.2f}, {y:.2f}), {gap.width:.2f} m "
             f"wide)")
    line = (f"no plan: every way of the held box from the start to the goal needs a regrasp "
            f"with the box resting in {where}, where the robot cannot walk round the box to "
            f"its other side (the box alone needs {gap.box_needs:.2f} m, with the robot "
            f"holding it {gap.assembly_needs:.2f} m; held poses checked in yaw steps down to "
            f"{math.degrees(proof.finest):.2f} degrees)")
    return line, dataclasses.replace(gap, note=line)
