"""Planners as ``ompl.base.Planner`` subclasses, and the registry of planner names.

``RegraspPlanner`` (roadmap multiplexing with regrasps) and ``VisibilityPRM`` are ours;
OMPL's planners run on the same space as baselines (:data:`PLANNERS`).
"""

from __future__ import annotations

from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.registry import (
    OMPL_PLANNERS,
    PLANNERS,
    REFUSED,
    Allocator,
    check_planner_name,
    make_planner,
    parse_spec,
    planner_spec,
)
from pivot_ompl.planners.regrasp import RegraspPlanner, Resume
from pivot_ompl.planners.visprm import VisibilityPRM

__all__ = ["OMPL_PLANNERS", "PLANNERS", "REFUSED", "Allocator", "RegraspConfig",
           "RegraspPlanner", "Resume", "VisibilityPRM", "check_planner_name", "make_planner",
           "parse_spec", "planner_spec"]
