"""The route repair's parameters (:mod:`pivot_ompl.planners.repair`), a group of the config.

``RegraspConfig().repair``: how a replanning session joins the observed box back to the
route it was executing, and how much it polishes the joined route. Listed with every other
parameter by ``pivot-ompl bench --param help`` (``repair.join_step``...).
"""

from __future__ import annotations

from dataclasses import dataclass

from pivot_ompl.params import knob

__all__ = ["RepairConfig"]


@dataclass(frozen=True)
class RepairConfig:
    """The route repair of a replanning session.

    Attributes:
        join_step: spacing (m) of the join points along a route's transfer edges (the car's
            Reeds-Shepp path).
        detour_spacing: spacing (m along the route) of the join points a short search is
            tried to when no direct join holds.
        detour_targets: how many such join points get a short search.
        detour_checks: motion checks of each short search (RRT-Connect at one grasp).
        polish_checks_per_state: motion checks (cache hits free) the polish of a repaired
            route may compute per state of it, for the lattice re-routing and then the
            optimiser each (at least the optimiser's ``min_checks``).
        polish_kept: old route states after the repair's own that the polish reworks (the
            rest of the route was polished when it was planned).
    """

    join_step: float = knob(0.25, low_open=True)
    detour_spacing: float = knob(0.75, low_open=True)
    detour_targets: int = knob(3)
    detour_checks: int = knob(60)
    polish_checks_per_state: int = knob(4)
    polish_kept: int = knob(4)
