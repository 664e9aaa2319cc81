"""The object roadmap's parameters (:mod:`pivot_ompl.planners.objects`), a group of the config.

``RegraspConfig().sampling``: how the roadmap of the box alone grows (visibility, critical
configurations, slots and doors, bridge tests, diffusion). Listed with every other parameter
by ``pivot-ompl bench --param help`` (``sampling.goal_bias``...).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from pivot_ompl.params import knob

__all__ = ["SamplingConfig"]


@dataclass(frozen=True)
class SamplingConfig:
    """How the object roadmap (the box alone) grows.

    Attributes:
        guard_failures: consecutive discarded samples that end the Visibility PRM.
        max_visibility_samples: samples of the Visibility PRM phase at most, before the
            passage and diffusion phases, on a floor of up to ``visibility_area`` times as
            many square metres that the box can reach; a larger floor gets one more sample
            per ``visibility_area`` (its rooms need guards of their own).
        visibility_area: reachable floor (m^2) per visibility sample beyond
            ``max_visibility_samples``.
        guard_radius: a sample is tested for visibility only from guards this near (m,
            pose metric).
        critical_spacing: a critical configuration closer than this (m, pose metric) to a
            recorded one is not recorded again.
        slots: seed the roadmap with box poses along the scene's slots (gaps wide enough
            for the box but narrower than the walking robot, where it must let go of the box:
            :mod:`pivot_ompl.planners.objects.slots`).
        slot_play: the play (m) beyond which a gap no longer counts as a slot.
        slot_spacing: spacing (m) of the seeded poses along a slot.
        slot_approach: distances (m) beyond the slot's ends (and the box's length) of the
            seeded poses from which the box is pushed in or pulled out.
        doors: seed the roadmap with box poses along the scene's doors (gaps the held
            assembly passes but cannot turn in: :func:`~pivot_ompl.planners.objects.slots.doors`).
        door_play: the play (m) beyond the assembly's turning disk up to which a gap counts
            as a door.
        band_area: on a floor of at least this many square metres (its bounds) and
            ``band_boxes`` obstacles the slots and doors are seeded along the box's cheapest
            coarse routes only, widened level by level when the search fails, and the
            roadmap's samples drawn in that band
            (:mod:`~pivot_ompl.planners.objects.passage_band`).
        band_boxes: least number of obstacles (touching boxes merged) for the band.
        band_slacks: the levels' slacks: a level's band holds the routes at most that share
            dearer than the cheapest; the level after the last is the whole floor; ``()``:
            every passage seeded whatever the floor.
        band_cell: least cell side (m) of the floor's raster for the coarse routes.
        band_max_cells: most cells of that raster (a larger floor gets larger cells).
        band_penalty: extra cost (m) of a coarse route's step into a place too narrow for
            the held assembly (where a plan regrasps).
        band_margin: how far (m) the band reaches beyond its routes.
        band_reach: a passage the held assembly goes round within this (m) is not seeded.
        band_spacing: of passages whose centres lie this near (m), with near axes, only the
            narrowest is seeded.
        band_passages: most slots, and most doors, seeded per level (times the level's
            number), those on the cheapest routes first; a smaller floor where more slots,
            or more doors, than this are found gets the band too (a crowded floor).
        band_patience: diffusion steps without a path before the band is widened.
        regrasp_lattice: on a floor where the band applies, and before the object roadmap,
            try the regrasps where the held assembly's lattice components meet
            (:mod:`~pivot_ompl.planners.routes.regrasp_lattice`).
        bridge_rounds: rounds of (up to 100) bridge tests before the diffusion.
        bridge_bias: probability that a diffusion iteration is a bridge test instead.
        bridge_sigma: standard deviation (m) of the bridge test's second sample.
        passage_steps: distances (m) of the extensions from a passage node.
        epsilon: diffusion extension step (m, Reeds-Shepp length of the box's path).
        extend_step: spacing (m along the box's Reeds-Shepp path) of the poses tested along a
            diffusion extension.
        critical_bias: probability that a diffusion sample is drawn near a critical
            configuration.
        goal_bias: probability that a diffusion sample is the goal pose.
        yaw_range: sampled yaws lie in ``[-yaw_range, yaw_range)`` (neighbours are found with
            yaw modulo pi whatever the range: the box's half-turn symmetry).
        max_rejects: draws of a pose the box may reach (the region of box centres reachable
            from the start) rejected in a row before a uniform pose over the floor's bounds
            is drawn instead (a sliver of a region).
    """

    guard_failures: int = knob(25, low=1)
    max_visibility_samples: int = knob(30)
    visibility_area: float = knob(4.0, low_open=True)
    guard_radius: float = knob(3.0)
    critical_spacing: float = knob(0.4)
    slots: bool = True
    slot_play: float = knob(0.1)
    slot_spacing: float = knob(0.2, low_open=True)
    slot_approach: tuple[float, ...] = knob((0.4, 0.7, 1.2))
    doors: bool = True
    door_play: float = knob(0.5)
    band_area: float = knob(1000.0)
    band_boxes: int = knob(2000)
    band_slacks: tuple[float, ...] = knob((0.2, 1.0))
    band_cell: float = knob(0.1, low_open=True)
    band_max_cells: int = knob(1_000_000, low=1)
    band_penalty: float = knob(20.0)
    band_margin: float = knob(1.5)
    band_reach: float = knob(2.5)
    band_spacing: float = knob(0.5, low_open=True)
    band_passages: int = knob(300, low=1)
    band_patience: int = knob(400, low=1)
    regrasp_lattice: bool = True
    bridge_rounds: int = knob(60)
    bridge_bias: float = knob(0.3, high=1.0)
    bridge_sigma: float = knob(0.5)
    passage_steps: tuple[float, ...] = knob((0.5, 1.0, 1.5, 2.0))
    epsilon: float = knob(1.0)
    extend_step: float = knob(0.05, low_open=True)
    critical_bias: float = knob(0.25, high=1.0)
    goal_bias: float = knob(0.05, high=1.0)
    yaw_range: float = knob(math.pi)
    max_rejects: int = knob(200)
