"""A short scene planned and animated once for the physics tests (a few seconds)."""

from __future__ import annotations

import importlib.util
import os

import pytest

#: Set (CI does) to make a missing MuJoCo fail the physics tests instead of skipping them.
REQUIRE_ENV = "PIVOT_OMPL_REQUIRE_PHYSICS"


def pytest_collection_modifyitems(config, items):
    if importlib.util.find_spec("mujoco") is not None:
        return
    if os.environ.get(REQUIRE_ENV) == "1":
        raise pytest.UsageError(f"{REQUIRE_ENV}=1 but mujoco is not installed: "
                                "pip install -e '.[physics]'")

SCENE = {"name": "physics_short", "bounds": [-2.0, -2.0, 3.0, 2.0],
         "object": {"size": [0.8, 0.6, 1.3]}, "start": [0.0, 0.0, 0.0],
         "goal": [0.45, 0.05, 0.0],
         "obstacles": [{"type": "box", "center": [1.0, -1.5], "size": [0.4, 0.4], "yaw": 0.3,
                        "height": 1.0},
                       {"type": "cylinder", "center": [-1.0, 1.5], "radius": 0.2,
                        "height": 1.0},
                       {"type": "polygon", "points": [[1.5, 1.0], [2.5, 1.0], [2.5, 1.8],
                                                      [2.0, 1.3], [1.5, 1.8]], "height": 0.8}]}


@pytest.fixture(scope="session")
def short_run(tmp_path_factory):
    """(scene, plan file, motion file) of a short pivoting plan."""
    pytest.importorskip("mujoco")
    from pivot_ompl import plan
    from pivot_ompl.scene import scene_from_dict
    from pivot_ompl.wholebody import generate_motion

    scene = scene_from_dict(SCENE, source="<physics test>")
    res = plan(scene, time_limit=10.0, seed=0)
    assert res.solved
    folder = tmp_path_factory.mktemp("physics")
    plan_file = res.plan.to_json(folder / "plan.json")
    motion, _ = generate_motion(res.plan, walk=scene.walk)
    motion_file = motion.save(folder / "motion.npz")
    return scene, plan_file, motion_file
