"""The held poses' parts at the checkers' full clearance, joined across the sweep's jumps.

A checked transfer keeps the checkers' clearance (:data:`KEEP` = 1 cm) at every *sampled*
pose, and every pose between two samples is within the sweep's tolerance (:data:`JUMP`,
2 mm) of one of them (:mod:`~pivot_ompl.validity.certify`: an interval is accepted either
because the clearances at its ends leave no point able to reach an obstacle, and then
every pose of it keeps the full clearance, or because no point moves more than twice the
tolerance over it, both ends sampled). So a transfer is a chain of poses that keep the full
clearance, each at most ``2 * JUMP`` of any point's displacement from the next (the box
centre among those points); the ends of every transfer are sampled, so a regrasp, where the
box rests, keeps the full clearance at both grasps.

:class:`JumpParts` gives, per yaw bin and grasp, the parts of the positions where the held
assembly may keep the full clearance at some yaw of the bin, each grown by ``JUMP`` and the
grown parts that meet merged: two parts ``2 * JUMP`` apart or nearer are one. Grown parts of
neighbouring bins meet wherever a jump may cross between them (a jump turns the box by at
most ``2 * JUMP`` over its reach from the pivot, under a bin of
:data:`~pivot_ompl.analysis.pose_proof.FINEST`, so it never skips a bin). Against the
relaxation at the motions' 8 mm (:data:`~pivot_ompl.analysis.pose_proof.MOTION_CLEARANCE`):
a passage that holds the assembly at 8 mm but not at 1 cm is open there and closed here,
unless it is under ``2 * JUMP`` long.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import shapely
from shapely.geometry.base import BaseGeometry

from pivot_ompl.analysis.pose_proof import MOTION_CLEARANCE, HeldParts
from pivot_ompl.scene import Scene
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

#: Clearance (m) every sampled pose keeps.
KEEP = KEEP_CLEARANCE
#: Growth (m) of every part: half the largest displacement between two samples.
JUMP = SWEEP_TOLERANCE
#: Added to the growth (m): round-off never separates parts that meet.
ROUND_OFF = 1e-6
#: Segments per quarter circle of the growth's rounded corners.
QUAD_SEGS = 2
#: The growth's offset (m): its polygon's chords lie outside the round offset by ``JUMP``.
GROWTH = (JUMP + ROUND_OFF) / math.cos(math.pi / (4 * QUAD_SEGS))


class JumpParts(HeldParts):
    """The held poses' parts at :data:`KEEP`, grown by :data:`JUMP` (module docstring).

    A :class:`~pivot_ompl.analysis.pose_proof.HeldParts` whose box centre's room is the
    motions' (8 mm).
    """

    def __init__(self, scene: Scene, should_stop: Callable[[], bool] | None) -> None:
        super().__init__(scene, MOTION_CLEARANCE, should_stop, parts_clearance=KEEP)

    def of(self, a: float, b: float) -> list[list[BaseGeometry]]:
        """Per grasp, the grown parts of the bin ``[a, b]``."""
        key = (a, b)
        if key not in self.known:
            out = []
            for region in self.bins.regions(a, b):
                grown = shapely.buffer(region, GROWTH, quad_segs=QUAD_SEGS) \
                    if not region.is_empty else region
                out.append([g for g in getattr(grown, "geoms", [grown]) if not g.is_empty])
            self.known[key] = out
        return self.known[key]
