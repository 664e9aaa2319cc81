"""The regrasp planner's configuration: nested frozen dataclasses, one per stage.

:class:`RegraspConfig` holds the grasps the robot may use, one block per stage of the planner
(:class:`~.sampling_config.SamplingConfig`: the object roadmap's visibility, critical
configurations, slots, bridge tests and diffusion; :class:`SearchConfig`: the multiplexed
graph and its lazy search; :class:`SingleGraspConfig`: the regrasp-free try;
:class:`OptimiserConfig`) and the cost both the search and the optimiser minimise
(:class:`~pivot_ompl.cost.CostModel`). Units are metres, radians and seconds; lengths "in
the pose metric" add ``YAW_WEIGHT`` m per radian.

Every leaf has a dotted name (``search.weight``, ``cost.regrasp``,
``sampling.slot_spacing``...), listed by :meth:`RegraspConfig.flat` and set by
:meth:`RegraspConfig.with_values`: what ``pivot-ompl bench --param NAME=V1,V2`` sweeps (OMPL
2.0.1's Python binding cannot declare planner parameters: ``Planner.params()`` raises a
conversion error). Each numeric leaf declares its range beside its default, as OMPL's
``declareParam`` does (:func:`~pivot_ompl.params.knob`: the range in the field's
``metadata``); :meth:`RegraspConfig.validate` reads it there, and :func:`parameters` lists
every leaf with its default, range and description (``pivot-ompl bench --param help``).
"""

from __future__ import annotations

import inspect
from collections.abc import Iterator
from dataclasses import dataclass, field, fields, is_dataclass, replace
from typing import Any

from pivot_ompl.cost import CostModel
from pivot_ompl.errors import InputError
from pivot_ompl.params import Range, check_value, knob, range_of
from pivot_ompl.planners.repair_config import RepairConfig
from pivot_ompl.planners.sampling_config import SamplingConfig

#: The grasp indices (one per side of the box).
GRASPS = (0, 1, 2, 3)


@dataclass(frozen=True)
class SearchConfig:
    """The multiplexed graph and its search.

    Attributes:
        neighbours: candidate transfer edges per new manipulation node.
        connect_radius: candidate edges are not longer than this (m, Reeds-Shepp length).
        weight: inflation of the search's heuristic, the exact cost to go over the graph's
            plausible edges (weighted A*: a path at most this factor costlier than the
            graph's cheapest; 1.1 breaks the ties of equal-cost plateaus, which 1.0 expands).
        every: the roadmap's growth searches after this many new object nodes gave
            manipulation nodes (a search is skipped at no cost while the candidate graph
            cannot join start and goal).
        turns: give every manipulation node whose assembly has room to turn round in place
            a candidate *turn* edge: the box swung round by pi with the robot (the car spins
            about its position: backward and forward manipulation), which puts the robot on
            the box's other side without a regrasp.
        turn_margin: room (m) a turn needs beyond the disk the assembly sweeps.
    """

    neighbours: int = knob(10, low=1)
    connect_radius: float = knob(3.5)
    weight: float = knob(1.1, low=1.0)
    every: int = knob(16, low=1)
    turns: bool = True
    turn_margin: float = knob(0.05)


@dataclass(frozen=True)
class SingleGraspConfig:
    """The regrasp-free tries before the multiplexed search (:mod:`~.direct`).

    Attributes:
        checks: motion checks (transfer edges) the single-grasp RRT-Connect may make, shared
            by the grasps valid at both start and goal; ``0``: not tried.
        step: its longest extension (m of the car's Reeds-Shepp path).
        lattice: where the RRT-Connect found nothing, follow the held assembly's lattice
            route at each grasp, certified transfer by transfer (found at once on floors of
            many rooms, where the random trees get lost).
        lattice_weight: inflation of that route search's heuristic, the floor's way to the
            goal (a route at most this factor costlier than the lattice's cheapest, found
            expanding far fewer states; the improve step refines it).
        lattice_detour: a lattice route costing more than this factor times the pushes
            along the floor's way (headings forgotten) is not taken: the lattice turns only
            in place, and where that forces a detour the multiplexed search's curves do
            better (the AWS bookstore: 2.4 times, 1.8 times the search's plan).
        lattice_area: the lattice try is made only where the box may reach at least this
            floor (m^2): on a room's floor the RRT-Connect and the multiplexed search are
            quick, and the lattice's fields would cost more than they save (fig10, 60 m^2:
            0.3 s of a 0.5 s plan).
        corridor: where the lattice try is made, its lattice and the re-routing of a
            one-grasp path first hold only the box centres within this many m of the floor's
            shortest way from start to goal (:mod:`~.corridor`: the field pays for the wall
            pieces round that band, not the whole floor's); ``0``: the whole floor.
    """

    checks: int = knob(80)
    step: float = knob(1.5)
    lattice: bool = True
    lattice_weight: float = knob(1.2, low=1.0)
    lattice_detour: float = knob(1.5, low=1.0)
    lattice_area: float = knob(100.0)
    corridor: float = knob(1.0)


#: The default ``optimiser.quality_share``: the stages' own shares as they are.
QUALITY_SHARE = 0.6


def quality_scale(share: float) -> float:
    """Factor on every improvement stage's share of checks at ``quality_share = share``.

    ``share / (1 - share)`` improvement checks per check of the search, relative to the
    default :data:`QUALITY_SHARE` (1 there; 0 at 0; 12.7 at the largest, 0.95).
    """
    def ratio(q: float) -> float:
        return q / (1.0 - q)
    return ratio(share) / ratio(QUALITY_SHARE)


@dataclass(frozen=True)
class OptimiserConfig:
    """The path optimiser run once on the path found.

    Attributes:
        enabled: run it (shortcuts, useless regrasps removed, grasps chosen by the cost).
        check_share: it may compute at most this share of the motion checks planning made
            (a budget of work, not of seconds: a seed gives the same plan on any machine).
        min_checks: the smallest budget (motion checks).
        shortcut_reach: longest shortcut the optimiser tries (m, between the box's centres;
            :data:`~pivot_ompl.planners.optimiser.SHORTCUT_REACH`).
        routes: re-route each transfer phase along the held assembly's cheapest lattice
            route where that is cheaper (:mod:`pivot_ompl.planners.routes.refine`), then
            optimise again.
        route_share: the re-routing may compute at most this share of the motion checks
            planning made.
        eliminate: try every regrasp of the optimised path for removal
            (:mod:`pivot_ompl.planners.eliminate`); a regrasp stays only if it saves cost.
        eliminate_share: the elimination may compute at most this share of the motion checks
            planning made (at least ``eliminate_checks``).
        eliminate_checks: motion checks of each single-grasp re-planning of a stretch, and
            the elimination's smallest budget.
        choose_grasps: route each phase at every other grasp on the lattice and keep the
            cheapest (:mod:`pivot_ompl.planners.grasp_choice`; needs ``routes``), within
            ``eliminate_share`` too; off by default until its time is measured.
        run_spacing: along a straight run of a lattice route made real (re-routing,
            elimination, and the single-grasp try's lattice route), a pose is kept to join
            every this many lattice motions (:func:`~pivot_ompl.planners.routes.chain.corners`).
        route_min_saving: the re-routing
            (:func:`~pivot_ompl.planners.routes.refine.refine`) leaves a run of phases whose
            lattice estimate saves at most this share of the path's cost: the estimates are
            optimistic, on the shipped scenes, the layouts and the one-grasp maps no run
            estimated under 5 % made a path cheaper, and checking one costs as much as
            checking a run that does; 0: every run that may save.
        whole_min_saving: the same for a run of every phase of the path (the whole path
            re-planned as one phase, at each grasp), when larger: its lattice estimate is
            the least accurate (its chain meets every tight place of the route), and it
            saves only if its chain costs less than ``1 / (1 - share)`` times that estimate;
            made real, such chains cost at least 1.118 x their estimate on the shipped
            scenes, both layouts, the one-grasp maps and generated scenes (none estimated
            under 12.6 % made a path cheaper), so one estimated under 10 % is not checked
            (cluttered_room and corridor: 0.05 s of a first plan's 0.1-0.3 s re-routing).
        converge_checks: every improvement stage (re-routing, optimiser, elimination) may
            compute at least this many motion checks (times :func:`quality_scale`), however
            few the search made: a seed whose search ended early (a direct single-grasp
            path) is improved as far as one whose search took long. Each stage stops
            earlier once it has nothing more to gain (no cheaper route, shortcut or removal).
        quality_share: the share of the solve's time limit that improving the path found may
            take at most (re-routing, optimiser, elimination together, from the first path
            found), and the scale of their budgets of motion checks: every stage's share
            above and ``converge_checks`` are scaled by :func:`quality_scale` (1 at the
            default :data:`QUALITY_SHARE`). See ``docs/quality.md``.
        straighten: after the optimiser, replace stretches of each phase by a turn in place,
            a straight push and a turn where that is cheaper
            (:mod:`pivot_ompl.planners.straighten`), within the optimiser's budget.
        follow_route: after the optimiser, re-plan each transfer phase along the route
            bound's shortest route (kept off the walls where that is cheaper) where that is
            cheaper (:mod:`pivot_ompl.planners.follow_route`), within the optimiser's budget.
        slide_regrasps: after the optimiser, let each regrasp move to a pose of the
            transfers beside it where that is cheaper
            (:mod:`pivot_ompl.planners.regrasp_slide`), within the optimiser's budget.
    """

    enabled: bool = True
    check_share: float = knob(0.2)
    min_checks: int = knob(10)
    shortcut_reach: float = knob(8.0, low_open=True)
    routes: bool = True
    route_share: float = knob(1.0)
    eliminate: bool = True
    eliminate_share: float = knob(0.3)
    eliminate_checks: int = knob(60)
    choose_grasps: bool = False
    run_spacing: int = knob(6, low=1)
    route_min_saving: float = knob(0.05, high=1.0)
    whole_min_saving: float = knob(0.1, high=1.0)
    converge_checks: int = knob(500)
    quality_share: float = knob(QUALITY_SHARE, high=0.95)
    straighten: bool = True
    follow_route: bool = True
    slide_regrasps: bool = True


@dataclass(frozen=True)
class RegraspConfig:
    """Everything the regrasp planner can be told (see the module docstring).

    Attributes:
        grasps: the grasps the robot may use.
        sampling: the object roadmap's growth.
        search: the multiplexed graph and its search.
        single_grasp: the regrasp-free try.
        optimiser: the path optimiser.
        repair: the route repair of a replanning session.
        cost: what the search and the optimiser minimise: seconds of whole-body execution
            plus a price per regrasp (``cost.regrasp``, s).
    """

    grasps: tuple[int, ...] = GRASPS
    sampling: SamplingConfig = field(default_factory=SamplingConfig)
    search: SearchConfig = field(default_factory=SearchConfig)
    single_grasp: SingleGraspConfig = field(default_factory=SingleGraspConfig)
    optimiser: OptimiserConfig = field(default_factory=OptimiserConfig)
    repair: RepairConfig = field(default_factory=RepairConfig)
    cost: CostModel = field(default_factory=CostModel)

    def flat(self) -> dict[str, Any]:
        """Every leaf by dotted name (``"search.weight": 2.0``...), in declaration order."""
        return {name: v for name, v, _ in _leaves(self, "")}

    def with_values(self, values: dict[str, Any]) -> RegraspConfig:
        """A copy with the leaves named in ``values`` replaced (dotted names).

        Values are converted to the leaf's type (a string ``"1.5"`` for a float, ``"0,1"`` or
        ``"0 1"`` for a tuple, ``"true"``/``"false"`` for a flag), so they may come from a
        command line.

        Raises:
            InputError: unknown name, or a value of the wrong type or out of range.
        """
        out: Any = self
        for name, value in values.items():
            out = _replace_leaf(out, name.split("."), value, name)
        out.validate()
        return out

    def validate(self) -> None:
        """Raise :class:`InputError` naming the first leaf whose value is out of its range.

        The ranges are the fields' own (:func:`~pivot_ompl.params.knob` metadata; a field
        declared without one: finite and ``>= 0``); every leaf is first checked to be finite
        and ``>= 0``, then the grasps, then each leaf against its range.
        """
        leaves = list(_leaves(self, ""))
        for name, v, rng in leaves:
            check_value(name, v, rng, floor_only=True)
        if not self.grasps or any(g not in GRASPS for g in self.grasps):
            raise InputError("grasps", self.grasps, "must be grasp indices 0, 1, 2 or 3")
        for name, v, rng in leaves:
            check_value(name, v, rng)


@dataclass(frozen=True)
class Parameter:
    """One leaf of :class:`RegraspConfig`, as ``pivot-ompl bench --param help`` lists it.

    Attributes:
        name: the dotted name (``search.weight``).
        default: the default value.
        range: the values it may take (``None``: a flag, true or false; for ``grasps``, the
            grasp indices).
        doc: what it is (from its class's docstring).
    """

    name: str
    default: Any
    range: Range | None
    doc: str


def parameters() -> list[Parameter]:
    """Every parameter of :class:`RegraspConfig` with its default and range, in order."""
    out = []
    for name, v, rng in _leaves(RegraspConfig(), ""):
        owner, leaf = _owner(name)
        doc = _attribute_docs(type(owner)).get(leaf, "")
        out.append(Parameter(name, v, None if isinstance(v, bool) or name == "grasps"
                             else rng, doc))
    return out


def _owner(name: str) -> tuple[Any, str]:
    """The default dataclass holding the leaf ``name``, and the leaf's own name."""
    obj: Any = RegraspConfig()
    *groups, leaf = name.split(".")
    for g in groups:
        obj = getattr(obj, g)
    return obj, leaf


def _attribute_docs(cls: type) -> dict[str, str]:
    """The ``Attributes:`` entries of ``cls``'s docstring, one line each."""
    docs: dict[str, str] = {}
    lines = (inspect.getdoc(cls) or "").splitlines()
    if "Attributes:" not in lines:
        return docs
    current = None
    for line in lines[lines.index("Attributes:") + 1:]:
        if not line.strip():
            break
        if line.startswith("    ") and not line.startswith("     ") and ":" in line:
            names, text = line.strip().split(":", 1)
            current = [n.strip() for n in names.split(",")]
            for n in current:
                docs[n] = text.strip()
        elif current:
            for n in current:
                docs[n] += " " + line.strip()
    return docs


def _leaves(obj: Any, prefix: str) -> Iterator[tuple[str, Any, Range]]:
    """Every leaf of ``obj`` by dotted name, with its value and range, in declaration order."""
    for f in fields(obj):
        v = getattr(obj, f.name)
        if is_dataclass(v):
            yield from _leaves(v, f"{prefix}{f.name}.")
        else:
            yield f"{prefix}{f.name}", v, range_of(f.metadata)


def _replace_leaf(obj: Any, path: list[str], value: Any, name: str) -> Any:
    known = {f.name: f for f in fields(obj)}
    if path[0] not in known:
        groups = sorted({n.split(".")[0] for n in _leaf_names()})
        raise InputError("param", name, "unknown parameter: the names are those of "
                         f"RegraspConfig().flat(), in the groups {', '.join(groups)}")
    current = getattr(obj, path[0])
    if len(path) > 1:
        if not is_dataclass(current):
            raise InputError("param", name, "unknown parameter")
        return replace(obj, **{path[0]: _replace_leaf(current, path[1:], value, name)})
    if is_dataclass(current):
        raise InputError("param", name, "names a group, not a parameter")
    return replace(obj, **{path[0]: _convert(value, current, name)})


def _convert(value: Any, like: Any, name: str) -> Any:
    """``value`` as the type of ``like`` (strings parsed)."""
    try:
        if isinstance(like, bool):
            if isinstance(value, str):
                if value.lower() not in ("true", "false", "1", "0"):
                    raise ValueError(value)
                return value.lower() in ("true", "1")
            if not isinstance(value, bool):
                raise ValueError(value)
            return value
        if isinstance(like, tuple):
            items = value.replace(",", " ").split() if isinstance(value, str) else list(value)
            kind = type(like[0]) if like else float
            return tuple(kind(x) for x in items)
        if isinstance(like, int):
            if isinstance(value, float) and not value.is_integer():
                raise ValueError(value)
            return int(value)
        return float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, f"must be of type {type(like).__name__}") from None


def _leaf_names() -> list[str]:
    return list(RegraspConfig().flat())


__all__ = ["OptimiserConfig", "Parameter", "RegraspConfig", "RepairConfig", "SamplingConfig",
           "SearchConfig", "SingleGraspConfig", "parameters"]
