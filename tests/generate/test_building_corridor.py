"""The building family's ``corridor`` layout: box-only slots, the robot round by a corridor."""

from __future__ import annotations

import math

import pytest
import shapely

from pivot_ompl.cli.main import main
from pivot_ompl.generate import GeneratorParams, generate
from pivot_ompl.generate.building import ROOM, ROOM_DEPTH, WALL, room_origin
from pivot_ompl.generate.layout import BOX
from pivot_ompl.planfile import TransitPhase
from pivot_ompl.validity.footprints import obstacle_pieces
from pivot_ompl.validity.plan_check import check_plan


def _gaps(walls: shapely.Geometry, a: tuple[float, float], b: tuple[float, float]
          ) -> list[float]:
    """Lengths of the free stretches of the segment ``a -> b``."""
    free = shapely.LineString([a, b]).difference(walls)
    parts = getattr(free, "geoms", [free])
    return sorted(p.length for p in parts if p.length > 1e-6)


@pytest.mark.parametrize("seed", [0, 1])
def test_every_wall_is_a_slot_and_the_robot_walks_round_by_the_corridor(seed):
    """Unturned: each wall between rooms has one gap, the box's slot; a corridor of a width
    in the range runs north of the rooms, a door of the given width from each room; every
    witness walk that leaves a room side-steps along the corridor, square to it."""
    rooms = 3
    gen = generate("building", seed, params=GeneratorParams(
        rooms=rooms, layout="corridor", rotate=False, side_corridor=(0.87, 0.89),
        side_door=(1.0, 1.0)))
    assert check_plan(gen.witness, gen.scene).ok
    assert gen.witness.regrasps == 2 * (rooms - 1)
    walls = shapely.union_all([shapely.Polygon(p) for p in obstacle_pieces(gen.scene.obstacles)])
    for i in range(1, rooms):
        x = room_origin(i, 0)[0] - 0.5 * WALL
        (slot,) = _gaps(walls, (x, 0.0), (x, WALL + ROOM_DEPTH))
        assert BOX[1] + 2 * 0.1 - 1e-9 <= slot <= BOX[1] + 2 * 0.12 + 1e-9
    y_in = WALL + ROOM_DEPTH + WALL  # the corridor's south side
    for i in range(rooms):
        x0, _ = room_origin(i, 0)
        (width,) = _gaps(walls, (x0 + 0.5 * ROOM, y_in), (x0 + 0.5 * ROOM, gen.scene.bounds[3]))
        assert 0.87 - 1e-9 <= width <= 0.89 + 1e-9
        (door,) = _gaps(walls, (x0, y_in - 0.5 * WALL), (x0 + ROOM, y_in - 0.5 * WALL))
        assert door == pytest.approx(1.0)
    through = 0
    for ph in gen.witness.phases:
        if not isinstance(ph, TransitPhase):
            continue
        moves = [(a, b) for a, b in zip(ph.robot_path, ph.robot_path[1:], strict=False)
                 if min(a[1], b[1]) > y_in + 0.3]  # in the corridor
        through += bool(moves)
        along = sum(abs(b[0] - a[0]) for a, b in moves)
        # square to the corridor (walking along it the 0.86 m body would not fit) but
        # where it turns into a door
        square = sum(abs(b[0] - a[0]) for a, b in moves
                     if max(abs(math.cos(a[2])), abs(math.cos(b[2]))) < 0.05)
        assert square >= 0.8 * along
    assert through == rooms - 1


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_turned_corridor_buildings_have_a_checked_witness(seed):
    """Turned by a random angle (the default): the walks side-step along the turned corridor."""
    gen = generate("building", seed, params=GeneratorParams(rooms=4, layout="corridor"))
    rep = check_plan(gen.witness, gen.scene)
    assert rep.ok, rep.problems
    assert gen.witness.regrasps == 6


def test_cli_makes_a_corridor_building_and_refuses_bad_widths(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["generate", "--family", "building", "--layout", "corridor", "--rooms", "2",
                 "--side-corridor", "0.88", "0.88", "--side-door", "1.0", "1.1",
                 "--out", str(out)]) == 0
    assert len(list(out.glob("*.yaml"))) == 1
    for flag, values in (("--side-corridor", ["0.9", "0.8"]), ("--side-door", ["1.0", "9"])):
        code = main(["generate", "--family", "building", "--layout", "corridor", flag, *values,
                     "--out", str(tmp_path / "bad")])
        assert code == 2
        assert flag.lstrip("-").replace("-", "_") in capsys.readouterr().err.replace("-", "_")
    assert not (tmp_path / "bad").exists()


@pytest.mark.parametrize("angle", [0.2, -0.9])
def test_the_planner_solves_a_turned_corridor_building(angle):
    """The regrasp planner on 3 rooms turned by ``angle``, off the lattice's 16 headings
    (11.5 and 51.6 deg): solved, the plan checked (its walks side-step along the turned
    corridor). Without the walls' frame no walk passes the corridor at these angles."""
    from pivot_ompl.api import plan
    from pivot_ompl.generate import rotate_scene

    gen = generate("building", 1, params=GeneratorParams(rooms=3, layout="corridor",
                                                        rotate=False))
    scene = rotate_scene(gen.scene, angle)
    res = plan(scene, time_limit=20.0, seed=0, bound=False)
    assert res.solved
    rep = check_plan(res.plan, scene)
    assert rep.ok, rep.problems
    assert res.plan.regrasps >= 2
