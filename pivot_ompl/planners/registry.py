"""Planner names: ours (``regrasp``, ``visprm``) and OMPL's baselines on the same space.

A *planner spec* is a name, optionally with parameters of a configurable planner in brackets:
``regrasp[search.weight=1.5;cost.regrasp=60]`` (dotted names of
:meth:`~pivot_ompl.planners.config.RegraspConfig.flat`, ``;`` between them). Each spec is one
planner configuration, under its own name in OMPL (``RegraspPlanner[search.weight=1.5]``):
what ``pivot-ompl bench --param`` sweeps.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ompl import base as ob
from ompl import geometric as og

from pivot_ompl.base.problem import PivotProblem
from pivot_ompl.errors import InputError
from pivot_ompl.planners.config import RegraspConfig
from pivot_ompl.planners.regrasp import RegraspPlanner, Resume
from pivot_ompl.planners.visprm import VisibilityPRM

#: An allocator: ``(problem, seed) -> planner`` on ``problem.si``.
Allocator = Callable[[PivotProblem, int], ob.Planner]


def _ompl(cls: Any) -> Allocator:
    def make(problem: PivotProblem, seed: int) -> ob.Planner:
        return cls(problem.si)
    return make


#: Planner name -> allocator.
PLANNERS: dict[str, Allocator] = {
    "regrasp": lambda problem, seed: RegraspPlanner(problem.si, problem.checker, seed=seed),
    "visprm": lambda problem, seed: VisibilityPRM(problem.si, seed=seed),
    "rrtconnect": _ompl(og.RRTConnect),
    "rrt": _ompl(og.RRT),
    "rrtstar": _ompl(og.RRTstar),
    "kpiece1": _ompl(og.KPIECE1),
    "bkpiece1": _ompl(og.BKPIECE1),
}

#: OMPL planners refused, with the reason (``make_planner`` raises ``InputError``: exit 2).
REFUSED: dict[str, str] = {
    name: ("OMPL's PRM grows its roadmap on a C++ thread that calls our Python validators "
           "while the calling thread holds the GIL: in the ompl 2.0.1 wheel it deadlocks. "
           "Use 'visprm' (a visibility PRM) or 'regrasp'.")
    for name in ("prm", "prmstar")}

#: Planners whose randomness comes from OMPL's global seed (``ompl.util.RNG.setSeed``).
OMPL_PLANNERS = frozenset(PLANNERS) - {"regrasp", "visprm"}


#: Planners whose parameters a spec may set (their configuration's dotted names).
CONFIGURABLE = frozenset({"regrasp"})


def parse_spec(spec: str) -> tuple[str, dict[str, str]]:
    """``"regrasp[a.b=1;c=2]"`` -> ``("regrasp", {"a.b": "1", "c": "2"})``.

    Raises:
        InputError: a malformed spec, or parameters for a planner that takes none.
    """
    if not isinstance(spec, str):
        raise InputError("planner", spec, f"must be a planner name (known: {sorted(PLANNERS)})")
    name, bracket, rest = spec.partition("[")
    if not bracket:
        return spec, {}
    if not rest.endswith("]") or "[" in rest[:-1]:
        raise InputError("planner", spec, "write parameters as name[key=value;key=value]")
    if name not in CONFIGURABLE:
        raise InputError("planner", spec, f"only {sorted(CONFIGURABLE)} take parameters")
    values: dict[str, str] = {}
    for item in filter(None, rest[:-1].split(";")):
        key, eq, value = item.partition("=")
        if not eq or not key.strip():
            raise InputError("planner", spec, f"parameter {item!r} is not key=value")
        values[key.strip()] = value.strip()
    return name, values


def planner_spec(name: str, values: dict[str, object]) -> str:
    """The spec of planner ``name`` with ``values`` (the inverse of :func:`parse_spec`).

    Raises:
        InputError: ``name`` is not a string or ``values`` not a mapping of names.
    """
    if not isinstance(name, str):
        raise InputError("name", name, "must be a planner name")
    if not isinstance(values, dict) or not all(isinstance(k, str) for k in values):
        raise InputError("values", values, "must map parameter names to values")
    if not values:
        return name
    return name + "[" + ";".join(f"{k}={v}" for k, v in values.items()) + "]"


def make_planner(name: str, problem: PivotProblem, *, seed: int = 0,
                 config: RegraspConfig | None = None, resume: Resume | None = None
                 ) -> ob.Planner:
    """Allocate planner ``name`` (a spec, see the module docstring) on ``problem``.

    ``config``: the regrasp planner's base configuration, which a spec's values override;
    ``resume``: the held grasp and the earlier search the regrasp planner starts from.

    Raises:
        InputError: unknown or refused planner name, bad parameters (the message says why).
    """
    base, values = parse_spec(check_planner_name(name))
    if base == "regrasp":
        cfg = (config or RegraspConfig()).with_values(values)
        label = "RegraspPlanner" + (name[len(base):] if values else "")
        return RegraspPlanner(problem.si, problem.checker, seed=seed, config=cfg, name=label,
                              resume=resume)
    return PLANNERS[base](problem, seed)


def check_planner_name(name: str) -> str:
    """Return ``name`` if it is a usable planner spec, else raise :class:`InputError`."""
    base, values = parse_spec(name)
    if base in REFUSED:
        raise InputError("planner", name, f"refused: {REFUSED[base]}")
    if base not in PLANNERS:
        raise InputError("planner", name, f"unknown planner (known: {sorted(PLANNERS)})")
    if values:
        RegraspConfig().with_values(values)  # names and values checked now
    return name
