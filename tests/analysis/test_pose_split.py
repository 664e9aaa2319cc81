"""Which bins of a chain of held-pose parts are halved first (pose_split)."""

from __future__ import annotations

import math

from pivot_ompl.analysis.pose_split import SPANS, regrasp_bins, spanning_bins

WIDTHS = [2.0 * math.pi / 8] * 8
FINEST = 2.0 * math.pi / 512


def test_a_part_spanning_more_than_both_chain_neighbours_has_its_bin_halved():
    # a box turning through bins 0-4, at bin 2 one part joining two rooms
    path = [(0, 0, 0), (1, 0, 0), (2, 0, 1), (3, 0, 0), (4, 0, 0)]
    areas = [12.0, 12.5, 30.0, 12.4, 12.1]
    assert spanning_bins(path, areas, WIDTHS, FINEST) == {2}


def test_parts_of_about_one_size_leave_the_choice_to_the_widest_bins():
    path = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)]
    step = 0.5 * (SPANS - 1.0)  # each part a little larger than the one before
    areas = [10.0 * (1.0 + step) ** n for n in range(4)]
    assert spanning_bins(path, areas, WIDTHS, FINEST) == set()


def test_a_part_larger_than_only_one_neighbour_is_not_spanning():
    # growing into a larger room is not a false step: the next part is as large
    path = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (3, 0, 0)]
    assert spanning_bins(path, [10.0, 20.0, 20.0, 20.0], WIDTHS, FINEST) == set()


def test_the_chain_ends_and_bins_at_the_finest_width_are_never_chosen():
    path = [(0, 0, 0), (1, 0, 0), (2, 1, 0), (2, 2, 0), (3, 0, 0)]
    # the ends are largest; bin 2 (a regrasp within it) is already at the finest width
    widths = [*WIDTHS[:2], FINEST, *WIDTHS[3:]]
    areas = [40.0, 10.0, 30.0, 10.0, 40.0]
    assert spanning_bins(path, areas, widths, FINEST) == set()
    assert spanning_bins(path, areas, WIDTHS, FINEST) == {2}  # bin 2 coarser: chosen


def test_the_bins_where_a_chain_changes_grasp_are_its_regrasps():
    # turning through bins 0-2 at grasp 0, regrasping to 1 in bin 2, turning on, regrasping
    # back to 0 in bin 4; moving at one grasp from a bin to the next is no regrasp
    path = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (2, 1, 3), (3, 1, 0), (4, 1, 2), (4, 0, 1)]
    assert regrasp_bins(path, WIDTHS, FINEST) == {2, 4}
    assert regrasp_bins(path[:3], WIDTHS, FINEST) == set()


def test_a_regrasp_in_a_bin_at_the_finest_width_is_not_halved_again():
    path = [(0, 0, 0), (1, 0, 0), (1, 2, 0), (2, 2, 0), (2, 3, 1)]
    widths = [WIDTHS[0], FINEST, *WIDTHS[2:]]
    assert regrasp_bins(path, widths, FINEST) == {2}
