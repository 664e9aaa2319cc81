"""Where a lattice route meets its exact ends: the lattice states a car pose joins.

A route of the transfer lattice (:mod:`.lattice`) runs between lattice states; its two ends
are exact poses, joined to the free states of the two nearest lattice headings within 1.5
grid cells (:func:`end_joins`). An end whose heading is a lattice heading needs no turn to
join. An end *between* two lattice headings (a scene whose walls run at another angle: a
turned or reflected building, a real map) must turn to one of them, and a turn needs more
room than a push: where the end lies along a wall, as every regrasp pose in a passage does,
the near states are free at the lattice headings but the joining turn grazes the wall, and
the checks refuse the whole route (a reflected fig10's middle phase: every lattice route
refused, the plan 1.31 times the shortest route against the original's 1.14).

So an end between headings joins only states where the lattice could turn across its
heading (free at both headings either side and at the yaw half-way: the lattice's own test
of a turn, :func:`~.lattice_components.turn_room`), and it may first be pushed or
pulled straight along its own heading, up to :data:`LEAD_REACH`, to reach such a state (a
*lead*: the car's heading kept, the floor along it free at the field yaw nearest to it).
The lead's pose then becomes the route's second (or last but one) pose, and the chain made
of the route certifies it like every other transfer. Where no such state is found, the end
joins as before (the near states, a turn wherever it is).
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from pivot_ompl.planners.routes.lattice_components import turn_room
from pivot_ompl.se2 import Pose, wrap_angle
from pivot_ompl.transit.lattice import HEADING_YAWS, N_HEADINGS
from pivot_ompl.validity.assembly_field import FIELD_YAWS, AssemblyField

__all__ = ["LEAD_REACH", "between_headings", "end_joins"]

State = tuple[int, int, int]
Stop = Callable[[], bool]

#: Longest straight push or pull (m) along an end's own heading before it joins the lattice.
LEAD_REACH = 1.5
#: Radius (grid cells) round a point within which lattice states are joined to it.
JOIN_CELLS = 1.5
#: A heading closer than this (rad) to a lattice heading is on the lattice.
ON_LATTICE = 1e-9
#: Lead lengths shorter than this (grid cells) are tested by the end's own joins, not the
#: field: the end pose itself is valid, and the raster is inside the true free space.
NEAR_CELLS = 2.0


def _near(field: AssemblyField, x: float, y: float) -> list[tuple[int, int, float]]:
    """Grid positions within :data:`JOIN_CELLS` of a floor point, with their distance (m)."""
    fx, fy = field.cell(x, y)
    out = []
    for ix in range(math.floor(fx - JOIN_CELLS), math.ceil(fx + JOIN_CELLS) + 1):
        for iy in range(math.floor(fy - JOIN_CELLS), math.ceil(fy + JOIN_CELLS) + 1):
            if math.hypot(ix - fx, iy - fy) <= JOIN_CELLS:
                px, py = field.position(ix, iy)
                out.append((ix, iy, math.hypot(px - x, py - y)))
    return out


def between_headings(yaw: float) -> bool:
    """Whether a car's heading ``yaw`` (rad) lies between two lattice headings."""
    return min(abs(wrap_angle(y - yaw)) for y in HEADING_YAWS) > ON_LATTICE


def end_joins(field: AssemblyField, car: Pose, parity: int, *, push: float, spin: float,
              region: np.ndarray, leads: bool = True, should_stop: Stop | None = None,
              turns: Callable[[int], np.ndarray] | None = None
              ) -> tuple[dict[State, float], dict[State, Pose]]:
    """The lattice states a car pose joins, with the joins' costs (s), and their leads.

    Args:
        field: the lattice's assembly field.
        car: the end's car pose.
        parity: the grasp's parity.
        push: seconds per metre pushed.
        spin: seconds per radian turned in place.
        region: the grid positions the lattice holds (``(nx, ny)`` booleans).
        leads: join an end between headings as the module docstring says; ``False``: the
            near states, a turn wherever it is.
        should_stop: polled while a yaw's grid is computed.
        turns: ``turns(h)``, the grid positions where the lattice turns between heading
            ``h`` and the next within ``region`` (:func:`~.lattice_components.turn_room`,
            e.g. the lattice's kept :meth:`~.lattice.TransferLattice.turn_room`); default:
            computed here.

    Returns:
        ``(joins, leads)``: the states and their join costs, and for the states joined
        through a lead, the lead's car pose (the end pushed or pulled along its heading).

    Raises:
        Interrupted: ``should_stop()`` said stop while a yaw's grid was computed.
    """
    def fits(ix: int, iy: int, k: int) -> bool:
        return field.state_fits(ix, iy, k, parity, should_stop) and bool(region[ix, iy])

    yaw = car[2]
    off = [abs(wrap_angle(HEADING_YAWS[h] - yaw)) for h in range(N_HEADINGS)]
    near = sorted(range(N_HEADINGS), key=off.__getitem__)[:2]
    plain: dict[State, float] = {}
    for ix, iy, d in _near(field, car[0], car[1]):
        for h in near:
            if fits(ix, iy, 2 * h):
                plain[(ix, iy, h)] = d * push + off[h] * spin
    if not leads or off[near[0]] <= ON_LATTICE:
        return plain, {}
    low = near[0] if wrap_angle(yaw - HEADING_YAWS[near[0]]) > 0 else near[1]
    high = (low + 1) % N_HEADINGS  # the end's heading lies between these two
    k_own = min(range(len(FIELD_YAWS)), key=lambda k: abs(wrap_angle(FIELD_YAWS[k] - yaw)))
    if turns is None:
        room = turn_room(lambda k: field.fits(parity, k, should_stop=should_stop) & region, low)
    else:
        room = turns(low)
    joins: dict[State, float] = {}
    through: dict[State, Pose] = {}  # the leads' cars
    step = field.resolution
    for sign in (1.0, -1.0):
        for n in range(int(LEAD_REACH / step) + 1):
            if n == 0 and sign < 0:
                continue
            t = sign * n * step
            x, y = car[0] + t * math.cos(yaw), car[1] + t * math.sin(yaw)
            if n >= NEAR_CELLS:
                fx, fy = field.cell(x, y)
                if not fits(round(fx), round(fy), k_own):
                    break  # the lead runs into a wall
            for ix, iy, d in _near(field, x, y):
                if not (0 <= ix < field.nx and 0 <= iy < field.ny and room[ix, iy]):
                    continue  # no room to turn across the end's heading here
                for h in (low, high):
                    c = (abs(t) + d) * push + off[h] * spin
                    if c < joins.get((ix, iy, h), math.inf):
                        joins[(ix, iy, h)] = c
                        if n:
                            through[(ix, iy, h)] = (x, y, yaw)
                        else:
                            through.pop((ix, iy, h), None)
    if not joins:
        return plain, {}
    return joins, through
