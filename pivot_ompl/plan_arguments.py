"""The arguments of :func:`pivot_ompl.api.plan` and of every verb's time limit and seed, checked."""

from __future__ import annotations

import math
import os
from typing import Any

from pivot_ompl.errors import InputError
from pivot_ompl.grasp import check_grasp
from pivot_ompl.planners import PLANNERS, RegraspConfig, check_planner_name
from pivot_ompl.scene import Scene

#: Largest effective time limit (s, 11.6 days): a larger one (or ``inf``) means "until solved"
#: in practice and is clamped to this, which OMPL's clock still represents.
MAX_TIME_LIMIT = 1.0e6
#: Largest seed (OMPL's global seed is ``seed + 1``, a 32-bit value on every platform).
MAX_SEED = 2**32 - 2

__all__ = ["MAX_SEED", "MAX_TIME_LIMIT", "check_config", "check_plan_arguments",
           "check_time_limit"]


def check_plan_arguments(scene: Any, planner: Any, time_limit: Any, seed: Any,
                     simplify: Any, bound: Any, start_grasp: Any,
                     late_proof: Any = None, prove: Any = None, parallel: Any = None) -> float:
    """Validate :func:`plan`'s arguments; return the effective time limit (s)."""
    if not isinstance(scene, Scene | str | os.PathLike):
        raise InputError("scene", type(scene).__name__,
                         "must be a Scene, a scene file path or a shipped scene name")
    if not isinstance(planner, str):
        raise InputError("planner", planner, f"unknown planner (known: {sorted(PLANNERS)})")
    check_planner_name(planner)  # unknown or refused planners (prm) say why
    limit = check_time_limit(time_limit)
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
        raise InputError("seed", seed, f"must be an integer in [0, {MAX_SEED}]")
    if not isinstance(simplify, bool):
        raise InputError("simplify", simplify, "must be True or False")
    if not isinstance(bound, bool):
        raise InputError("bound", bound, "must be True or False")
    if prove is not None and not isinstance(prove, bool):
        raise InputError("prove", prove, "must be True, False or None")
    if prove is True and not bound:
        raise InputError("prove", prove, "needs the bounds (bound=True, no --no-bound)")
    if parallel is not None and not isinstance(parallel, bool):
        raise InputError("parallel", parallel, "must be True, False or None")
    if parallel is True and not bound:
        raise InputError("parallel", parallel, "needs the bounds (bound=True, no --no-bound)")
    if late_proof is not None and not isinstance(late_proof, bool):
        raise InputError("late_proof", late_proof, "must be True, False or None")
    if start_grasp is not None:
        check_grasp(start_grasp, field="start_grasp")
    return limit


def check_time_limit(value: Any, field: str = "time_limit") -> float:
    """The one time-limit contract of every verb and API call: the limit (s) to use.

    A number > 0; ``math.inf`` and anything above :data:`MAX_TIME_LIMIT` is
    :data:`MAX_TIME_LIMIT`.

    Raises:
        InputError: not a number, NaN, or not > 0 (naming ``field``).
    """
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise InputError(field, value, "must be a number of seconds")
    if math.isnan(value) or value <= 0:
        raise InputError(field, value, "must be > 0 s")
    return float(min(value, MAX_TIME_LIMIT))


def check_config(config: Any, regrasp_cost: Any) -> RegraspConfig:
    """The regrasp planner's configuration with ``regrasp_cost`` applied."""
    if config is None:
        config = RegraspConfig()
    elif not isinstance(config, RegraspConfig):
        raise InputError("config", type(config).__name__, "must be a RegraspConfig")
    if regrasp_cost is None:
        return config
    if isinstance(regrasp_cost, bool) or not isinstance(regrasp_cost, int | float) or \
            not math.isfinite(regrasp_cost) or regrasp_cost < 0:
        raise InputError("regrasp_cost", regrasp_cost, "must be a number of seconds >= 0")
    return config.with_values({"cost.regrasp": float(regrasp_cost)})

