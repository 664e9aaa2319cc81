"""``plan --time T`` ends within ``T + 5 %`` on large floors, the plan written (issue 41/43).

A 200 x 200 m hall at ``--time 1`` ended at 1.25-1.41 s: after the search's stop came steps
that did not look at the clock (the lattice's whole-floor components, the disk route's graph
search, writing the plan). The search now stops early enough for them
(``pivot_ompl.api.FINISH_SHARE``), the components are computed in polled chunks, and the
route bound's graph search is not started when its estimate exceeds the time left.
"""

from __future__ import annotations

import math
import subprocess
import sys
import time

import numpy as np
import pytest
from factories import make_scene

from pivot_ompl.analysis.plan_bounds import disk_route
from pivot_ompl.analysis.raster import FloorRaster
from pivot_ompl.analysis.route_bound import route_on
from pivot_ompl.checking.pivot_checker import PivotChecker
from pivot_ompl.cost import CostModel
from pivot_ompl.errors import Interrupted
from pivot_ompl.generate.sceneio import write_scene
from pivot_ompl.planners.routes.lattice import TransferLattice

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

#: Scheduling slack (s) on a shared machine, on top of the 5 %.
SLACK = 0.05


def _hall(size: float, boxes: int, seed: int):
    """A ``size`` m square floor with ``boxes`` scattered boxes, start and goal at corners."""
    rng = np.random.default_rng(seed)
    start, goal = (3.0, 3.0, 0.0), (size - 3.0, size - 3.0, 0.0)
    obstacles: list[dict] = []
    while len(obstacles) < boxes:
        x, y = rng.uniform(1.0, size - 1.0, 2)
        if min(math.dist((x, y), start[:2]), math.dist((x, y), goal[:2])) < 4.0:
            continue
        obstacles.append({"type": "box", "center": [float(x), float(y)],
                          "size": [float(v) for v in rng.uniform(0.5, 2.0, 2)],
                          "yaw": float(rng.uniform(-math.pi, math.pi)), "height": 1.5})
    return make_scene(bounds=[0.0, 0.0, size, size], start=list(start), goal=list(goal),
                      obstacles=obstacles, object={"size": [0.8, 0.6, 1.3]})


@pytest.fixture(scope="module")
def hall_200():
    return _hall(200.0, 60, 0)


#: The timed run, in a fresh interpreter as ``pivot-ompl plan`` runs it (a test process late
#: in a long run carries a large heap whose collections slowed the same plan by ~25 %).
_TIMED = """
import sys, time
from pivot_ompl.api import plan
from pivot_ompl.scene import load_scene
warm, hall, limit, out = sys.argv[1:5]
plan(load_scene(warm), time_limit=0.5)  # the first plan of a process imports lazily
scene = load_scene(hall)
t0 = time.monotonic()
res = plan(scene, time_limit=float(limit), seed=0)
if res.solved:
    res.to_json(out)
print(res.status, time.monotonic() - t0)
"""


@pytest.fixture(scope="module")
def hall_files(hall_200, tmp_path_factory):
    folder = tmp_path_factory.mktemp("halls")
    return (write_scene(_hall(20.0, 5, 1), folder / "warm.yaml"),
            write_scene(hall_200, folder / "hall.yaml"))


@pytest.mark.parametrize("limit", [1.0, 2.0])
def test_a_200_m_hall_is_planned_and_written_within_the_limit(hall_files, limit, tmp_path):
    walls = []
    for _ in range(2):  # wall-clock time: the better of two runs (a loaded machine delays
        done = subprocess.run(  # one run; code that overruns overruns every time)
            [sys.executable, "-c", _TIMED, *map(str, hall_files), str(limit),
             str(tmp_path / "plan.json")], capture_output=True, text=True, timeout=120)
        assert done.returncode == 0, done.stderr[-2000:]
        status, wall = done.stdout.split()[-2:]
        assert status in ("EXACT_SOLUTION", "TIMEOUT")
        walls.append(float(wall))
        if walls[-1] <= 1.05 * limit + SLACK:
            break
    assert min(walls) <= 1.05 * limit + SLACK, walls


def test_the_route_bounds_graph_search_is_not_started_without_the_time_for_it(hall_200):
    raster = FloorRaster(hall_200.bounds, min_cell=0.05, max_cells=400_000)
    mask = np.ones(raster.shape, dtype=bool)
    with pytest.raises(Interrupted):
        route_on(raster, mask, hall_200.start, hall_200.goal, time_left=lambda: 0.01)
    assert disk_route(hall_200, time_left=lambda: 0.01) is None
    # with the time for it, the same answer as without an estimate
    assert disk_route(hall_200, time_left=lambda: math.inf) == disk_route(hall_200)


def test_a_lattice_route_across_a_200_m_hall_polls_the_stop_all_along(hall_200):
    """No step between two polls is long: the whole-floor components come in chunks.

    One ``connected_components`` call over the whole floor left 0.3-0.6 s unpolled. The gaps
    are this process's CPU seconds, so other work on the machine does not widen them.
    """
    checker = PivotChecker(hall_200)
    grasp = next(g for g in range(4) if checker.state_valid(hall_200.start, g)
                 and checker.state_valid(hall_200.goal, g))
    lattice = TransferLattice(checker, CostModel())
    stamps: list[float] = []

    def stop() -> bool:
        stamps.append(time.process_time())
        return False

    route, cost = lattice.route(hall_200.start, hall_200.goal, grasp, should_stop=stop)
    assert route and math.isfinite(cost)
    gaps = [b - a for a, b in zip(stamps, stamps[1:], strict=False)]
    assert max(gaps) < 0.3, max(gaps)
