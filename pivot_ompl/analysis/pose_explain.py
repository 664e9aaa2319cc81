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

from pivot_ompl.analysis.passage import Passage, assembly_width, blocking_passage, hull_extents
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
    passage = blocking_passage(scene, should_stop=should_stop,
                               gaps_below=assembly_length(scene) + 2.0 * KEEP_CLEARANCE)
    if passage is None or passage.center is None:
        return f"no plan: the start's room and the goal's are joined only where {tail}", None
    x, y = passage.center
    line = (f"no plan: every way from the start to the goal passes a gap of at most "
            f"{passage.width:.2f} m (the widest such gap is at ({x:.2f}, {y:.2f})); {tail}")
    return line, dataclasses.replace(passage, note=line)
