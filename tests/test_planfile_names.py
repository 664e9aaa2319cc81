"""The plan file's names: one package, every name importable where outside code imports it."""

from __future__ import annotations

import importlib

import pytest

import pivot_ompl
from pivot_ompl import planfile

#: Each public name and the module that defines it.
HOMES = {"TransferStep": "phases", "TransferPhase": "phases", "TransitPhase": "phases",
         "Phase": "phases", "Plan": "plan", "FORMAT": "plan", "STATUSES": "plan",
         "MAX_VALUE": "reading", "plan_from_dict": "reading", "load_plan": "reading"}


def test_the_package_lists_every_public_name():
    assert sorted(planfile.__all__) == sorted(HOMES)


@pytest.mark.parametrize("name", sorted(HOMES))
def test_a_name_from_the_package_is_its_modules_own(name):
    home = importlib.import_module(f"pivot_ompl.planfile.{HOMES[name]}")
    assert getattr(planfile, name) is getattr(home, name)


@pytest.mark.parametrize("name", ["Plan", "TransferPhase", "TransferStep", "TransitPhase",
                                  "load_plan"])
def test_the_top_level_names_are_the_plan_files(name):
    assert getattr(pivot_ompl, name) is getattr(planfile, name)
