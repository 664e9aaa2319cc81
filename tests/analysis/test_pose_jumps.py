"""The held poses' parts across the sweep's jumps: at 1 cm within the motions' 8 mm room."""

from __future__ import annotations

import math

from corner_factories import corner_slot

from pivot_ompl.analysis import pose_floor, pose_jumps
from pivot_ompl.analysis.pose_bins import BinRegions
from pivot_ompl.analysis.pose_jumps import JumpParts
from pivot_ompl.analysis.pose_proof import MOTION_CLEARANCE, HeldParts


def test_the_parts_keep_a_centimetre_within_the_motions_room():
    # the room is the 8 mm relaxation's; each bin's regions (before the jumps' growth) lie
    # within that relaxation's and are smaller where obstacles are near (1 cm kept)
    scene = corner_slot(3.0, 0.95)
    jumps, motions = JumpParts(scene, None), HeldParts(scene, MOTION_CLEARANCE, None)
    assert jumps.room is not None and jumps.room.equals(motions.room)
    smaller = 0
    for i in range(8):
        a, b = 2.0 * math.pi * i / 8, 2.0 * math.pi * (i + 1) / 8
        for kept, loose in zip(jumps.bins.regions(a, b), motions.bins.regions(a, b),
                               strict=True):
            assert kept.difference(loose).area < 1e-9
            smaller += kept.area < loose.area - 1e-6
    assert smaller


def test_the_parts_build_one_region_index_and_merge_the_boxes_once(monkeypatch):
    built, merged = [], []
    init = BinRegions.__init__

    def counted_init(self, *args, **kwargs) -> None:  # noqa: ANN001, ANN002, ANN003
        built.append(None)
        init(self, *args, **kwargs)

    def counted_merge(obstacles, **kwargs):  # noqa: ANN001, ANN003, ANN202
        merged.append(None)
        return merge(obstacles, **kwargs)

    merge = pose_floor.merge_boxes
    monkeypatch.setattr(BinRegions, "__init__", counted_init)
    monkeypatch.setattr(pose_floor, "merge_boxes", counted_merge)
    monkeypatch.setattr(pose_jumps, "merge_boxes", counted_merge, raising=False)
    JumpParts(corner_slot(3.0, 0.95), None)
    assert (len(built), len(merged)) == (1, 1)
