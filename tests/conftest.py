"""Fixtures shared by the whole suite (the factories live in ``factories.py``)."""

from __future__ import annotations

import pytest
from factories import PAPER_BOX
from hypothesis import settings
from ompl import util as ou

from pivot_ompl.grasp import BoxGraspModel

ou.setLogLevel(ou.LogLevel.LOG_ERROR)

# no per-example deadline: a property's examples are checked, not timed (a test beside it on a
# busy machine would stretch the clock); examples and seeds stay as each test sets them
settings.register_profile("pivot_ompl", deadline=None)
settings.load_profile("pivot_ompl")


@pytest.fixture(scope="session", autouse=True)
def _private_cache(tmp_path_factory: pytest.TempPathFactory):
    """The suite's caches (the regrasp bounds) live in a folder of its own, never in ~/.cache."""
    mp = pytest.MonkeyPatch()
    mp.setenv("XDG_CACHE_HOME", str(tmp_path_factory.mktemp("cache")))
    yield
    mp.undo()


@pytest.fixture
def paper_model() -> BoxGraspModel:
    return BoxGraspModel(PAPER_BOX)
