"""The ``building`` family: rooms in a row or in a grid, joined by doors and box-only slots.

Rooms are ``ROOM`` (x) by ``ROOM_DEPTH`` (y) rectangles on a grid, separated by walls
``WALL`` thick. The route visits every room: along the row, or snaking through the grid (east
along the first row, north, west along the next, ...). Each wall the route crosses has:

* going along a row, with probability ``1 - WIDE_SHARE``, a **slot** only the box fits through
  (the box's 0.4 m side plus ``slot_clearance`` a side, or ``slot_gap``'s range) and a robot
  **door** narrower than the holding robot (``ROBOT_DOOR``: the robot walks through it sideways
  alone), else a **wide door** in the middle where robot and box pass together; with
  ``wide_doors`` (a range of widths) every such wall has a wide door of a width in that range,
  its centre up to ``WIDE_SHIFT`` from the middle (doors narrower than the disk the held
  assembly sweeps turning: it must line up with each one);
* going north, a wide door.

Layout ``"corridor"`` (rooms in a row): every wall between rooms is a box-only slot and none
has a robot door; the robot's way round is a **corridor** along the row's north side
(``side_corridor``: a range of widths, e.g. 0.87-0.89 m, 1-3 cm wider than the 0.86 m
walking body, which side-steps along it with its 0.6 m depth across), entered from each room
by a **door** in its north wall (``side_door``: a range of widths, e.g. 1.0 m), its centre
up to ``SIDE_DOOR_SHIFT`` from the room's middle.

Every other wall is solid. The witness pushes the box from room to room: through a wide door
in one push; into a slot, then the robot walks round through the door and pulls the box out
(a regrasp), then walks round the box again to push on (a second one); a regrasp turns the
push at the grid's corners. So the floor grows with ``rooms`` (16 in a row: a 73 m floor).
"""

from __future__ import annotations

import math

import numpy as np

from pivot_ompl.generate.layout import BOX, HELD_FACE_BACK, Retry, free_complement, make_scene
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose

State = tuple[Pose, int]
Rect = tuple[float, float, float, float]

#: A room's size (m) along x and y, and the walls' thickness (m).
ROOM, ROOM_DEPTH, WALL = 4.25, 4.5, 0.3
#: Width (m) of a robot door (the walking body, 0.6 m deep, passes it sideways; the holding
#: robot, 0.86 m wide, does not) and of a wide door (robot and box pass together).
ROBOT_DOOR, WIDE_DOOR = 0.82, 1.7
#: Share of the row walls with a wide door instead of a slot.
WIDE_SHARE = 0.3
#: With ``wide_doors`` given: the largest offset (m) of a door's centre from its wall's middle,
#: and the widest door (m) that leaves 0.3 m of wall at either end.
WIDE_SHIFT = 0.6
MAX_WIDE_DOOR = ROOM_DEPTH - 2.0 * (WIDE_SHIFT + 0.3)
#: Distances (m) of the slot's and the robot door's axes from a room's near side.
SLOT_Y, DOOR_Y = 1.2, ROOM_DEPTH - 1.0
#: Layout ``"corridor"``: the largest offset (m) of a door's centre from its room's middle,
#: and the widest door (m) that leaves 0.3 m of wall at either end.
SIDE_DOOR_SHIFT = 0.5
MAX_SIDE_DOOR = ROOM - 2.0 * (SIDE_DOOR_SHIFT + 0.3)
#: Least distance (m) of the start's centre from the first room's west wall (layout
#: ``"corridor"``: far enough that the holding robot behind the box clears it at any start yaw).
START_BACK, START_BACK_CORRIDOR = 1.0, 1.5
#: Layouts of the family.
BUILDING_LAYOUTS = ("row", "grid", "corridor")


def room_origin(i: int, j: int) -> tuple[float, float]:
    """The lower-left inner corner (m) of the room in column ``i`` and row ``j``."""
    return (WALL + i * (ROOM + WALL), WALL + j * (ROOM_DEPTH + WALL))


def _cells(rooms: int, layout: str) -> list[tuple[int, int]]:
    """The rooms in route order: a row, or a snake through a near-square grid."""
    if layout != "grid":
        return [(i, 0) for i in range(rooms)]
    cols = max(1, math.ceil(math.sqrt(rooms)))
    out = []
    for k in range(rooms):
        j, i = divmod(k, cols)
        out.append((i if j % 2 == 0 else cols - 1 - i, j))
    return out


def building_layout(rng: np.random.Generator, *, rooms: int, layout: str,
                    slot_gap: tuple[float, float], slot_clearance: float | None,
                    seed: int, wide_doors: tuple[float, float] | None = None,
                    side_corridor: tuple[float, float] = (0.87, 0.89),
                    side_door: tuple[float, float] = (1.0, 1.0)
                    ) -> tuple[Scene, list[State]]:
    """A building floor and the witness's chain of ``(object pose, grasp)`` states.

    ``side_corridor`` and ``side_door``: ranges of the corridor's and its doors' widths (m),
    layout ``"corridor"`` only.
    """
    cells = _cells(rooms, layout)
    nx = max(i for i, _ in cells) + 1
    ny = max(j for _, j in cells) + 1
    bounds = (0.0, 0.0, WALL + nx * (ROOM + WALL), WALL + ny * (ROOM_DEPTH + WALL))
    free: list[Rect] = []
    corridor = layout == "corridor"
    if corridor:
        bounds = _side_corridor(rng, nx, bounds, free, side_corridor, side_door)
    for i, j in cells:
        x0, y0 = room_origin(i, j)
        free.append((x0, y0, x0 + ROOM, y0 + ROOM_DEPTH))
    x0, y0 = room_origin(*cells[0])
    back = START_BACK_CORRIDOR if corridor else START_BACK
    start = (x0 + back + float(rng.uniform(0.0, 0.4)), y0 + SLOT_Y + float(rng.uniform(-0.2, 0.6)),
             float(rng.uniform(-0.3, 0.3)))
    states: list[State] = [(start, 0)]
    for a, b in zip(cells, cells[1:], strict=False):
        if b[1] != a[1]:
            states += _north(a, b, states[-1], free)
        else:
            east = b[0] > a[0]
            door = (WIDE_DOOR, 0.0)
            if corridor:
                slot, gap = True, slot_clearance if slot_clearance is not None else \
                    float(rng.uniform(*slot_gap))
            elif wide_doors is None:
                slot = rng.uniform() >= WIDE_SHARE
                gap = slot_clearance if slot_clearance is not None else \
                    float(rng.uniform(*slot_gap))
            else:
                slot, gap = False, 0.0
                door = (float(rng.uniform(*wide_doors)), float(rng.uniform(-1.0, 1.0)) * WIDE_SHIFT)
            states += _along_row(a, b, east, slot, gap, states[-1], free, door=door,
                                 robot_door=not corridor)
    xl, yl = room_origin(*cells[-1])
    east = len(cells) < 2 or cells[-1][0] >= cells[-2][0]
    g = states[-1][1]
    goal_x = xl + ROOM - 1.2 if east else xl + 1.2
    goal = (goal_x, yl + ROOM_DEPTH / 2 + float(rng.uniform(-0.5, 0.5)),
            float(rng.uniform(-0.3, 0.3)))
    states.append((goal, g))
    obstacles = free_complement(bounds, free)
    name = f"building_{layout}{rooms}_{seed}"
    return make_scene(name, bounds, obstacles, start, goal), states


def _side_corridor(rng: np.random.Generator, rooms: int, bounds: Rect, free: list[Rect],
                   width: tuple[float, float], door: tuple[float, float]) -> Rect:
    """Lay the robot's corridor north of a row of ``rooms``; return the grown bounds.

    The corridor runs the row's length; each room opens into it by a door in its north wall,
    of a width in ``door``, its centre within :data:`SIDE_DOOR_SHIFT` of the room's middle.
    """
    w = float(rng.uniform(*width))
    y0 = bounds[3]  # the corridor's south side: the rooms' north wall's north face
    free.append((WALL, y0, bounds[2] - WALL, y0 + w))
    for i in range(rooms):
        x0, _ = room_origin(i, 0)
        dw = float(rng.uniform(*door))
        xc = x0 + ROOM / 2 + float(rng.uniform(-1.0, 1.0)) * SIDE_DOOR_SHIFT
        free.append((xc - dw / 2, y0 - WALL, xc + dw / 2, y0))
    return (bounds[0], bounds[1], bounds[2], y0 + w + WALL)


def _north(a: tuple[int, int], b: tuple[int, int], last: State, free: list[Rect]) -> list[State]:
    """From the corner room ``a`` north into ``b`` through a wide door (grasp 1 pushes +y).

    The box is pushed straight along the row to the door's axis (at the height it entered
    the room by), the robot walks round to its south face, and pushes it straight north
    through the door.
    """
    x0, y0 = room_origin(*a)
    xc = x0 + ROOM / 2
    yw = y0 + ROOM_DEPTH
    free.append((xc - WIDE_DOOR / 2, yw, xc + WIDE_DOOR / 2, yw + WALL))
    turn = (xc, last[0][1], 0.0)
    return [(turn, last[1]), (turn, 1), ((xc, yw + WALL + ROOM_DEPTH / 2, 0.0), 1)]


def _along_row(a: tuple[int, int], b: tuple[int, int], east: bool, slot: bool, gap: float,
               last: State, free: list[Rect], *,
               door: tuple[float, float] = (WIDE_DOOR, 0.0), robot_door: bool = True
               ) -> list[State]:
    """From room ``a`` into its neighbour ``b`` along the row.

    ``door``: the wide door's width and its centre's offset from the wall's middle (m);
    ``robot_door``: a slot's wall also has a robot door (else the robot walks round by a
    way of its own).
    """
    x0, y0 = room_origin(*a)
    xw = x0 + ROOM if east else x0 - WALL  # the wall's west face
    s = 1.0 if east else -1.0
    push_g, pull_g = (0, 2) if east else (2, 0)
    near = xw if east else xw + WALL  # the face the box enters by
    far = xw + WALL if east else xw  # the face it leaves by
    out: list[State] = []
    if last[1] != push_g:  # turn the push: regrasp at the last pose
        out.append((last[0], push_g))
    if not slot:
        width, shift = door
        yc = y0 + ROOM_DEPTH / 2 + shift
        free.append((xw, yc - width / 2, xw + WALL, yc + width / 2))
        out += [((near - s * 1.3, yc, 0.0), push_g), ((far + s * 1.3, yc, 0.0), push_g)]
        return out
    ys, yd = y0 + SLOT_Y, y0 + DOOR_Y
    half = BOX[1] / 2 + gap
    free.append((xw, ys - half, xw + WALL, ys + half))
    if robot_door:
        free.append((xw, yd - ROBOT_DOOR / 2, xw + WALL, yd + ROBOT_DOOR / 2))
    if gap < 0.005:
        raise Retry("slot clearance below the kept 1 cm")
    before = (near - s * 1.4, ys, 0.0)
    # pushed in until the held face is HELD_FACE_BACK short of the wall: the arms stay out
    push = (near + s * (BOX[0] / 2 - HELD_FACE_BACK), ys, 0.0)
    after = (far + s * 1.5, ys, 0.0)
    out += [(before, push_g), (push, push_g), (push, pull_g), (after, pull_g),
            (after, push_g)]
    return out
