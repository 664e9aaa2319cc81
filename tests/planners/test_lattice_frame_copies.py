"""A turned copy of a floor with walls at two angles routes as the floor itself.

``gen:walls:1`` has its inner walls at 40 and 37.5 degrees inside an axis-aligned floor. Turned
by 0.6 rad, its old floor kept as walls ran at 34.4 degrees and set the lattice's frame: the
copy's route was 1.79 times the shortest against the original's 1.27.
"""

from __future__ import annotations

from pivot_ompl import plan
from pivot_ompl.generate import generate, rotate_scene


def test_gen_walls_1_turned_by_0_6_rad_gets_a_route_as_short_as_the_original_s():
    original = generate("walls", 1).scene
    ratios = []
    for scene in (original, rotate_scene(original, 0.6)):
        res = plan(scene, seed=0, time_limit=15.0)
        q = res.plan.extra["quality"]
        assert res.solved and q["regrasps"] == q["regrasps_lower_bound"] == 1
        ratios.append(q["route_ratio"])
    assert ratios[1] <= 1.05 * ratios[0], ratios
