"""The result of a simulated run: :class:`SimulationReport` (written as the report JSON)."""

from __future__ import annotations

import json
import math
from dataclasses import asdict, dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from pivot_ompl.fileio import atomic_output
from pivot_ompl.motionfile import Motion
from pivot_ompl.physics.loop import PivotRecord

FORMAT = "pivot-physics/1"
#: Statuses of a run: the goal reached, missed at the end, the time limit, a replan that found
#: no plan (or no whole-body motion), or the replans' budget spent.
STATUSES = ("done", "goal_missed", "time_limit", "replan_failed", "replans_exhausted")
#: A pivot whose corner moved more than this (m) slipped.
SLIP_LIMIT = 0.005


@dataclass(frozen=True)
class ReplanRecord:
    """One replan of the closed loop.

    Attributes:
        time: run time (s) at which it was decided.
        observed: the box's observed pose ``(x, y, yaw)``.
        error_m, yaw_error_rad: its departure from the plan being executed.
        plan_time_s: the planner's wall time (s).
        motion_time_s: the whole-body generation's wall time (s).
        pivots, regrasps: the new plan's.
        status: the planner's status.
    """

    time: float
    observed: tuple[float, float, float]
    error_m: float
    yaw_error_rad: float
    plan_time_s: float
    motion_time_s: float
    pivots: int
    regrasps: int
    status: str


@dataclass
class SimulationReport:
    """What a simulated run of a plan's whole-body motion showed (``pivot-physics/1``).

    Attributes:
        status: one of :data:`STATUSES`.
        reached_goal: the box ended within the goal tolerance of the scene's goal.
        box_error_max_m, box_error_final_m: the largest and the last distance (m) between the
            simulated and the planned box centre over the whole run.
        box_yaw_error_max_rad, box_yaw_error_final_rad: the same for the heading (rad).
        goal_error_m, goal_yaw_error_rad: the final box pose against the scene's goal.
        friction: the floor's friction coefficient (mu).
        box_mass: the box mass (kg).
        friction_needed_max: the largest median force ratio of a pivot corner (the friction
            the pivots need); ``pivots_at_limit``: the rotations whose corner spent more than
            half its loaded time at the friction limit; ``slipping_pivots``: those whose
            corner moved more than :data:`SLIP_LIMIT`.
        hand_force_peak_n: the largest force of each hand (left, right; N).
        obstacle_contacts: each touch of an obstacle by the box: ``{start, end, obstacle,
            depth_m}`` (times in s, the obstacle's index in the scene, deepest penetration).
        replans: the closed loop's replans, in order.
        pivots: every simulated rotation.
        simulated_s, wall_s: the run's simulated and wall time (s); ``real_time_factor``
            their ratio (replanning and whole-body generation excluded from ``wall_s``).
        seed, perturbations: the run's seed and perturbation texts.
        scene, plan, motion: where the run came from.
        trace: the per-sample arrays (not written to JSON): ``t``, ``sim_pos``,
            ``sim_yaw``, ``sim_quat`` (w x y z), ``plan_pos``, ``plan_yaw``.
        segments: ``(motion, first, last)`` of each stretch of motion simulated, in order
            (not written to JSON; :func:`pivot_ompl.physics.replay.run_motion` joins them).
    """

    status: str
    reached_goal: bool
    box_error_max_m: float
    box_error_final_m: float
    box_yaw_error_max_rad: float
    box_yaw_error_final_rad: float
    goal_error_m: float
    goal_yaw_error_rad: float
    friction: float
    box_mass: float
    friction_needed_max: float
    pivots_at_limit: int
    slipping_pivots: int
    hand_force_peak_n: tuple[float, float]
    obstacle_contacts: list[dict[str, Any]]
    replans: list[ReplanRecord]
    pivots: list[PivotRecord]
    simulated_s: float
    wall_s: float
    seed: int
    perturbations: tuple[str, ...] = ()
    scene: str = ""
    plan: str = ""
    motion: str = ""
    trace: dict[str, np.ndarray] = field(default_factory=dict, repr=False)
    segments: list[tuple[Motion, int, int]] = field(default_factory=list, repr=False)

    @property
    def real_time_factor(self) -> float:
        """Simulated seconds per wall-clock second of simulation."""
        return self.simulated_s / self.wall_s if self.wall_s > 0 else math.inf

    def to_dict(self) -> dict[str, Any]:
        """The report as JSON-ready data (no trace)."""
        doc: dict[str, Any] = {"format": FORMAT}
        for f in fields(self):
            if f.name not in ("trace", "segments"):
                doc[f.name] = getattr(self, f.name)
        doc["replans"] = [asdict(r) for r in self.replans]
        doc["replan_count"] = len(self.replans)
        doc["real_time_factor"] = self.real_time_factor
        doc["pivots"] = [_pivot(p) for p in self.pivots]
        return _clean(doc)

    def to_json(self, path: str | Path) -> Path:
        """Write the report (replaced only once completely written)."""
        path = Path(path)
        with atomic_output(path) as tmp:
            tmp.write_text(json.dumps(self.to_dict(), indent=1) + "\n", encoding="utf-8")
        return path

    def summary(self) -> str:
        """One line: status, errors, friction, forces, replans, speed."""
        return (f"{self.status}: box error max {100 * self.box_error_max_m:.1f} cm / "
                f"{math.degrees(self.box_yaw_error_max_rad):.2f} deg, final "
                f"{100 * self.box_error_final_m:.1f} cm, goal {100 * self.goal_error_m:.1f} cm; "
                f"{len(self.pivots)} pivots (friction needed <= "
                f"{self.friction_needed_max:.2f} of mu {self.friction:g}, "
                f"{self.slipping_pivots} slipped > {1000 * SLIP_LIMIT:.0f} mm); hands <= "
                f"{max(self.hand_force_peak_n):.0f} N; {len(self.obstacle_contacts)} obstacle "
                f"contacts; {len(self.replans)} replans; {self.simulated_s:.0f} s simulated at "
                f"{self.real_time_factor:.0f}x real time")


def _pivot(p: PivotRecord) -> dict[str, Any]:
    d = asdict(p)
    d["slipped"] = p.corner_slip > SLIP_LIMIT
    return d


def _clean(v: Any) -> Any:
    """JSON-safe: tuples as lists, numpy scalars as numbers, non-finite floats as None."""
    if isinstance(v, dict):
        return {str(k): _clean(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_clean(x) for x in v]
    if isinstance(v, np.generic):
        v = v.item()
    if isinstance(v, float) and not math.isfinite(v):
        return None
    return v
