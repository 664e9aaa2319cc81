"""Fixtures shared by the whole suite (the factories live in ``factories.py``)."""

from __future__ import annotations

import pytest
from factories import PAPER_BOX
from ompl import util as ou

from pivot_ompl.grasp import BoxGraspModel

ou.setLogLevel(ou.LogLevel.LOG_ERROR)


@pytest.fixture
def paper_model() -> BoxGraspModel:
    return BoxGraspModel(PAPER_BOX)
