"""A walk planned in windows of supports is the walk planned in one QP (receding horizon)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("placo")

import placo  # noqa: E402

from pivot_ompl.errors import InputError  # noqa: E402
from pivot_ompl.wholebody.settings import WalkSettings  # noqa: E402
from pivot_ompl.wholebody.walk_windows import WindowedWalk  # noqa: E402
from pivot_ompl.wholebody.walker import PlacoWalker  # noqa: E402


@pytest.fixture(scope="module")
def walk():
    """A turning walk of about 40 steps (80 supports) and its one-QP trajectory."""
    walker = PlacoWalker(WalkSettings(), (0.0, 0.0, 0.0))
    targets = [(0.2 * i, 0.05 * np.sin(i), 0.05 * i) for i in range(1, 14)]
    footsteps = walker.plan_footsteps(targets)
    wpg = placo.WalkPatternGenerator(walker.robot, walker.params)

    def supports():
        return placo.FootstepsPlanner.make_supports(footsteps, 0.0, True,
                                                    walker.params.has_double_support(), True)

    one = wpg.plan(supports(), walker.com(), 0.0)
    return wpg, supports, walker.com(), one


@pytest.mark.parametrize("window,commit", [(17, 8), (9, 4), (13, 6)])
def test_a_windowed_walk_is_the_one_qp_walk(walk, window, commit):
    wpg, supports, com, one = walk
    ww = WindowedWalk(wpg, supports(), com, 0.0, window=window, commit=commit)
    assert len(ww.pieces) > 3
    assert ww.t_start == 0.0 and ww.t_end == pytest.approx(one.t_end, abs=1e-9)
    assert [s.t_start for s in ww.get_supports()] == pytest.approx(
        [s.t_start for s in one.get_supports()], abs=1e-9)
    starts = [s.t_start for s in one.get_supports()]
    for t in np.arange(0.0, one.t_end, 0.005):
        piece = ww.at(t)
        assert np.linalg.norm(np.subtract(piece.get_p_world_CoM(t), one.get_p_world_CoM(t))) \
            < 1e-4, t  # 0.1 mm
        assert np.linalg.norm(np.subtract(piece.get_v_world_CoM(t), one.get_v_world_CoM(t))) \
            < 1e-3, t
        for side in ("left", "right"):
            a = getattr(piece, f"get_T_world_{side}")(t)
            b = getattr(one, f"get_T_world_{side}")(t)
            assert np.abs(np.subtract(a, b)).max() < 1e-6, (t, side)
        if min(abs(t - b) for b in starts) > 1e-6:  # at a boundary either part is right
            assert piece.support_is_both(t) == one.support_is_both(t), t


def test_each_piece_takes_over_at_a_double_support(walk):
    wpg, supports, com, one = walk
    ww = WindowedWalk(wpg, supports(), com, 0.0)
    for k, t in enumerate(ww.switches):
        assert ww.at(t) is ww.pieces[k + 1] and ww.at(t - 1e-6) is ww.pieces[k]
        assert one.support_is_both(t + 1e-6)
        assert one.get_part_t_start(t + 1e-6) == pytest.approx(t, abs=1e-9)


def test_a_short_walk_is_one_piece(walk):
    wpg, supports, com, one = walk
    few = supports()[:7]  # start, three steps, ends on a double support
    ww = WindowedWalk(wpg, few, com, 0.0)
    assert len(ww.pieces) == 1 and ww.switches == []


@pytest.mark.parametrize("window,commit,field", [(16, 8, "window"), (7, 2, "window"),
                                                 (17, 3, "commit"), (17, 10, "commit"),
                                                 (17, 0, "commit")])
def test_bad_window_sizes_are_refused(walk, window, commit, field):
    wpg, supports, com, _ = walk
    with pytest.raises(InputError) as e:
        WindowedWalk(wpg, supports(), com, 0.0, window=window, commit=commit)
    assert e.value.field == field


class _FailingReplans:
    """PlaCo's pattern generator whose replans answer as to a failed QP (the old rest)."""

    def __init__(self, wpg):
        self.wpg, self.plans = wpg, 0

    def plan(self, supports, com, t0):
        self.plans += 1
        return self.wpg.plan(supports, com, t0)

    def replan(self, supports, old, t):
        return self.wpg.replan(supports[:len(supports) - 2], old, t)


def test_a_failed_window_plans_the_walk_in_one_qp(walk):
    wpg, supports, com, one = walk
    failing = _FailingReplans(wpg)
    ww = WindowedWalk(failing, supports(), com, 0.0)
    assert failing.plans == 2 and len(ww.pieces) == 1 and ww.switches == []
    assert len(ww.get_supports()) == len(one.get_supports())
    for t in np.arange(0.0, one.t_end, 0.05):
        assert np.subtract(ww.get_p_world_CoM(t), one.get_p_world_CoM(t)) == pytest.approx(0)
