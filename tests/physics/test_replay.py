"""The replay of a simulated run: its joined motion and the simulated box."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco")

from pivot_ompl.errors import InputError  # noqa: E402
from pivot_ompl.physics import simulate  # noqa: E402
from pivot_ompl.physics.replay import run_motion, sim_box_poses  # noqa: E402


@pytest.fixture(scope="module")
def replanned(short_run):
    scene, plan_file, motion_file = short_run
    return simulate(plan_file, motion_file, scene=scene, perturb=["slip@1:0.06,0"],
                    replan=True)


def test_the_joined_motion_follows_the_run(replanned):
    m = run_motion(replanned)
    assert len(m.t) == len(replanned.trace["t"])
    assert np.all(np.diff(m.t) > 0)
    np.testing.assert_allclose(m.box[:, :3], replanned.trace["plan_pos"])
    assert len(replanned.segments) >= 2
    # each plan's phases are numbered on: the replanned motion's first phase is a new one
    switch = len(replanned.segments[0][0].t[replanned.segments[0][1]:
                                            replanned.segments[0][2] + 1])
    assert m.phase[switch] > m.phase[switch - 1]


def test_the_simulated_box_poses(replanned):
    p = sim_box_poses(replanned)
    assert p.shape == (len(replanned.trace["t"]), 7)
    np.testing.assert_allclose(np.linalg.norm(p[:, 3:], axis=1), 1.0, atol=1e-6)
    np.testing.assert_allclose(p[:, :3], replanned.trace["sim_pos"])


def test_an_empty_run_has_no_replay(replanned):
    import dataclasses

    with pytest.raises(InputError):
        run_motion(dataclasses.replace(replanned, segments=[]))


def test_show_motion_refuses_a_simulated_box_of_another_length(replanned):
    from pivot_ompl.viz.motion_view import show_motion
    from pivot_ompl.viz.recorder import recording_visualizer

    m = run_motion(replanned)
    with pytest.raises(InputError) as e:
        show_motion(recording_visualizer(), m, sim_box=sim_box_poses(replanned)[:-1])
    assert e.value.field == "sim_box"
