"""The generator's parameters and their checks."""

from __future__ import annotations

import math
from dataclasses import dataclass

from pivot_ompl.errors import InputError
from pivot_ompl.generate.building import BUILDING_LAYOUTS, MAX_SIDE_DOOR, MAX_WIDE_DOOR

__all__ = ["BUILDING_LAYOUTS", "GeneratorParams", "check_params"]


@dataclass(frozen=True)
class GeneratorParams:
    """Parameters of the generator (lengths in m, angles in rad).

    Attributes:
        door_width: range of robot door widths (``walls``).
        slot_gap: range of the gap on each side of the box in a slot.
        corridor_width: range of corridor widths (``corridor``).
        bend_size: range of the side of the square at a bend (``corridor``).
        max_tilt: largest tilt of a wall from the room's cross direction (``walls``).
        rotate: turn the scene by a random angle (``walls``, ``corridor``).
        attempts: layouts drawn at most before giving up.
        walls: number of walls (``walls``; default 1 to 3 at random).
        slot_clearance: the gap (m) on each side of the box in every slot (``walls`` and
            ``building``; default ``slot_gap``'s range).
        rooms: number of rooms (``building``).
        layout: ``"row"`` (rooms in a row), ``"grid"`` (rooms in a grid, the route
            snaking through them) or ``"corridor"`` (rooms in a row, every wall a box-only
            slot, the robot's way round a corridor along the row), ``building``.
        wide_doors: range of widths (m) of the doors robot and box pass together
            (``building``): every wall along a row gets one, its centre at random within
            :data:`~pivot_ompl.generate.building.WIDE_SHIFT` of the wall's middle; ``None``:
            30 % of those walls get a 1.7 m door in the middle, the others a slot.
        side_corridor: range of the robot's corridor's widths (m), ``building`` layout
            ``"corridor"`` (default 1-3 cm wider than the 0.86 m walking body).
        side_door: range of the widths (m) of the doors into that corridor.
    """

    door_width: tuple[float, float] = (0.76, 0.84)
    slot_gap: tuple[float, float] = (0.1, 0.12)
    corridor_width: tuple[float, float] = (1.2, 1.4)
    bend_size: tuple[float, float] = (3.0, 3.4)
    max_tilt: float = 0.3
    rotate: bool = True
    attempts: int = 60
    walls: int | None = None
    slot_clearance: float | None = None
    rooms: int = 4
    layout: str = "row"
    wide_doors: tuple[float, float] | None = None
    side_corridor: tuple[float, float] = (0.87, 0.89)
    side_door: tuple[float, float] = (1.0, 1.0)

    def __post_init__(self) -> None:
        check_params(self)


def check_params(p: GeneratorParams) -> None:
    """Raise :class:`InputError` for parameters no layout can honour (run when they are made)."""
    if p.walls is not None and (isinstance(p.walls, bool) or not isinstance(p.walls, int)
                                or not 1 <= p.walls <= 64):
        raise InputError("walls", p.walls, "must be a whole number from 1 to 64")
    if p.slot_clearance is not None and (
            isinstance(p.slot_clearance, bool) or not isinstance(p.slot_clearance, int | float)
            or not 0.005 <= p.slot_clearance <= 0.5):
        raise InputError("slot_clearance", p.slot_clearance,
                         "must be from 0.005 m (the kept 1 cm over both sides) to 0.5 m")
    if isinstance(p.rooms, bool) or not isinstance(p.rooms, int) or not 1 <= p.rooms <= 256:
        raise InputError("rooms", p.rooms, "must be a whole number from 1 to 256")
    ranges = ("door_width", "slot_gap", "corridor_width", "bend_size", "side_corridor",
              "side_door")
    for name in ranges + (("wide_doors",) if p.wide_doors is not None else ()):
        r = getattr(p, name)
        if (not isinstance(r, tuple | list) or len(r) != 2
                or not all(isinstance(v, int | float) and not isinstance(v, bool)
                           and math.isfinite(v) and v > 0 for v in r) or r[0] > r[1]):
            raise InputError(name, r, "must be a range (min, max) of lengths > 0 m")
    if p.wide_doors is not None and p.wide_doors[1] > MAX_WIDE_DOOR:
        raise InputError("wide_doors", p.wide_doors,
                         f"must be widths of at most {MAX_WIDE_DOOR:g} m")
    if p.side_door[1] > MAX_SIDE_DOOR:
        raise InputError("side_door", p.side_door, f"must be widths of at most {MAX_SIDE_DOOR:g} m")
    if isinstance(p.max_tilt, bool) or not isinstance(p.max_tilt, int | float) or \
            not 0 <= p.max_tilt < math.pi / 2:
        raise InputError("max_tilt", p.max_tilt, "must be an angle in [0, pi/2) rad")
    if not isinstance(p.rotate, bool):
        raise InputError("rotate", p.rotate, "must be True or False")
    if isinstance(p.attempts, bool) or not isinstance(p.attempts, int) or \
            not 1 <= p.attempts <= 100_000:
        raise InputError("attempts", p.attempts, "must be a whole number from 1 to 100000")
    if not isinstance(p.layout, str) or p.layout not in BUILDING_LAYOUTS:
        raise InputError("layout", p.layout, f"must be one of {list(BUILDING_LAYOUTS)}")
