"""Regrasps read from where the held assembly's lattice components meet."""

from __future__ import annotations

import math

import pytest
from corner_factories import open_corner

from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator, Status
from pivot_ompl.planners.routes.lattice import TransferLattice
from pivot_ompl.planners.routes.regrasp_lattice import (
    RegraspLatticeStats,
    component_steps,
    regrasp_lattice_path,
)


def _valid_grasps(ck: PivotChecker, pose) -> list[int]:
    return [g for g in range(4) if ck.state_valid(pose, g)]


@pytest.fixture(scope="module")
def corner():
    scene = open_corner()
    ck = PivotChecker(scene, seed=0)
    return scene, ck, TransferLattice(ck, CostModel())


def test_ends_held_at_grasps_of_either_parity_need_one_change(corner):
    scene, ck, lattice = corner
    starts, goals = _valid_grasps(ck, scene.start), _valid_grasps(ck, scene.goal)
    assert {g % 2 for g in starts} == {0} and {g % 2 for g in goals} == {1}
    steps = component_steps(lattice, scene.start, scene.goal, start_grasps=starts,
                            goal_grasps=goals, cell=0.2, yaw_bins=8, max_changes=4)
    assert steps is not None
    assert len(steps.components) == 2 and len(steps.meetings) == 1
    assert [c[0] for c in steps.components] == [0, 1]
    assert steps.meetings[0]
    # allowed no change, there is none to make
    assert component_steps(lattice, scene.start, scene.goal, start_grasps=starts,
                           goal_grasps=goals, cell=0.2, yaw_bins=8, max_changes=0) is None


def test_each_meeting_offers_one_pose_per_bin_before_a_second_of_one(corner):
    scene, ck, lattice = corner
    cell, yaw_bins = 0.2, 8
    steps = component_steps(lattice, scene.start, scene.goal,
                            start_grasps=_valid_grasps(ck, scene.start),
                            goal_grasps=_valid_grasps(ck, scene.goal), cell=cell,
                            yaw_bins=yaw_bins, max_changes=4)
    assert steps is not None
    x0, y0 = ck.world.bounds[:2]

    def bin_of(q):
        yaw = math.floor(math.fmod(q[2] % math.pi, math.pi) / math.pi * yaw_bins) % yaw_bins
        return math.floor((q[0] - x0) / cell), math.floor((q[1] - y0) / cell), yaw

    for meeting, n in zip(steps.meetings, steps.bins, strict=True):
        bins = [bin_of(q) for q in meeting]
        assert n >= 1 and len(set(bins[:n])) == n  # the first n: one per bin
        assert set(bins) == set(bins[:n])  # and every bin the meeting holds among them


def test_one_grasp_that_suffices_gives_no_coarse_plan(corner):
    scene, ck, lattice = corner
    assert component_steps(lattice, scene.start, scene.start, start_grasps=[0],
                           goal_grasps=[0], cell=0.2, yaw_bins=8, max_changes=4) is None


def test_the_path_regrasps_once_per_change_and_every_step_passes_its_check(corner):
    scene, ck, lattice = corner
    stats = RegraspLatticeStats()
    found = regrasp_lattice_path(ck, lattice, CostModel(), scene.start, scene.goal,
                                 start_grasps=_valid_grasps(ck, scene.start),
                                 goal_grasps=_valid_grasps(ck, scene.goal), grasps=(0, 1, 2, 3),
                                 run_spacing=8, should_stop=lambda: False, stats=stats)
    assert found.status is Status.VALID and found.path
    states = found.path
    assert states[0][0] == scene.start and states[-1][0] == scene.goal
    regrasps = [(a, b) for a, b in zip(states, states[1:], strict=False) if a[1] != b[1]]
    assert len(regrasps) == stats.changes == 1
    assert all(a[0] == b[0] for a, b in regrasps)  # a regrasp keeps the box where it is
    evaluate = Evaluator(ck, CostModel())
    for a, b in zip(states, states[1:], strict=False):
        e = evaluate.step(a, b)
        assert e.valid and math.isfinite(e.cost), (a, b, e)


def test_a_stop_is_reported_as_such(corner):
    scene, ck, lattice = corner
    found = regrasp_lattice_path(ck, lattice, CostModel(), scene.start, scene.goal,
                                 start_grasps=[0, 2], goal_grasps=[1, 3], grasps=(0, 1, 2, 3),
                                 run_spacing=8, should_stop=lambda: True)
    assert found.status is Status.STOPPED


def test_the_regrasp_planner_takes_it_before_any_roadmap_where_the_band_applies():
    from pivot_ompl.api import plan

    scene = open_corner()
    spec = ("regrasp[sampling.band_area=0;sampling.band_boxes=0;"
            "single_grasp.lattice_area=0]")
    result = plan(scene, planner=spec, time_limit=30.0, seed=0)
    assert result.status == "EXACT_SOLUTION"
    assert result.roadmap["object_nodes"] == 0  # no roadmap grown: the lattice's regrasps
    assert result.plan.regrasps == 1
    # the figures say where the path came from (serialised in the plan's ``roadmap``)
    assert result.roadmap["regrasp_lattice_solved"] is True
    assert result.roadmap["regrasp_lattice_changes"] == 1
    assert result.roadmap["single_grasp_solved"] is False
    assert result.plan.extra["roadmap"]["regrasp_lattice_solved"] is True
    off = plan(scene, planner=spec.replace("]", ";sampling.regrasp_lattice=false]"),
               time_limit=30.0, seed=0)
    assert off.roadmap["object_nodes"] > 0
    assert off.roadmap["regrasp_lattice_solved"] is False
    assert off.roadmap["regrasp_lattice_changes"] == -1  # not tried


class _RefusingLattice(TransferLattice):
    """A lattice whose first meeting poses asked join no component; its routes recorded.

    The plan's ends (``spare``) join as the lattice says.
    """

    def __init__(self, *args, refused: int, spare: tuple, **kwargs) -> None:
        super().__init__(*args, **kwargs)
        self.refused: list = []
        self.routed: list = []
        self._left, self._spare = refused, spare

    def joined_components(self, obj, grasp, should_stop=None):
        if obj not in self._spare and (obj in self.refused or self._left > 0):
            if obj not in self.refused:
                self.refused.append(obj)
                self._left -= 1
            return set()
        return super().joined_components(obj, grasp, should_stop)

    def route(self, start, goal, grasp, **kwargs):
        self.routed.append(goal)
        return super().route(start, goal, grasp, **kwargs)


def test_a_meeting_pose_joining_no_next_component_costs_no_leg():
    scene = open_corner()
    ck = PivotChecker(scene, seed=0)
    lattice = _RefusingLattice(ck, CostModel(), refused=1, spare=(scene.start, scene.goal))
    stats = RegraspLatticeStats()
    found = regrasp_lattice_path(ck, lattice, CostModel(), scene.start, scene.goal,
                                 start_grasps=_valid_grasps(ck, scene.start),
                                 goal_grasps=_valid_grasps(ck, scene.goal), grasps=(0, 1, 2, 3),
                                 run_spacing=8, should_stop=lambda: False, stats=stats)
    assert found.status is not Status.STOPPED and len(lattice.refused) == 1
    assert not set(lattice.refused) & set(lattice.routed)  # no route to the refused pose
    assert stats.legs >= 1 and lattice.routed  # the next pose was routed to instead
