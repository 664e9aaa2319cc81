"""Obstacle clearance of every link and the box over a motion, against brute force."""

from __future__ import annotations

import math

import coal
import numpy as np
import pinocchio as pin
import pytest
from factories import make_scene

from pivot_ompl import hrp2
from pivot_ompl.motionfile import Motion
from pivot_ompl.validity.collision import obstacle_objects
from pivot_ompl.wholebody.box import matrix_from_quat
from pivot_ompl.wholebody.checks_box import obstacles_result as _obstacles
from pivot_ompl.wholebody.clearance import BOX, obstacle_clearance

BOX_SIZE = (0.8, 0.6, 1.3)


def synthetic_motion(seed: int, n: int = 120) -> Motion:
    """HRP-2 walking its base from x = 0 to 0.6 m while its arms and chest wave (seeded)."""
    rng = np.random.default_rng(seed)
    model = hrp2.load_pinocchio_model()
    q0 = hrp2.half_sitting_configuration(model)
    t = np.arange(n) * 0.01
    q = np.tile(q0, (n, 1))
    q[:, 0] = np.linspace(0.0, 0.6, n)
    yaw = np.linspace(0.0, rng.uniform(-0.5, 0.5), n)
    q[:, 3:7] = [[0, 0, math.sin(a / 2), math.cos(a / 2)] for a in yaw]
    for name in ("RARM_JOINT0", "LARM_JOINT0", "RARM_JOINT3", "LARM_JOINT3", "CHEST_JOINT0"):
        j = model.joints[model.getJointId(name)].idx_q
        q[:, j] += rng.uniform(0.2, 0.8) * np.sin(np.linspace(0, rng.uniform(2, 6), n))
    box = np.zeros((n, 7))
    box[:, 0] = np.linspace(1.0, 1.6, n)
    box[:, 2] = 0.5 * BOX_SIZE[2]
    box[:, 6] = 1.0
    names = tuple(str(s) for s in model.names[2:])
    return Motion(t, q, names, hrp2.URDF_RELPATH, box, box_size=BOX_SIZE, scene="test")


def wall_scene(x: float, y: float = 0.0, size: tuple[float, float] = (0.2, 3.0)):
    return make_scene(bounds=[-3.0, -3.0, 8.0, 6.0], obstacles=[
        {"type": "box", "center": [x, y], "size": list(size), "yaw": 0.0, "height": 2.0},
        {"type": "cylinder", "center": [0.3, -1.2], "radius": 0.3, "height": 0.8}])


def brute_force(motion: Motion, scene) -> dict[str, float]:
    """Every body against every obstacle object at every sample."""
    path = hrp2.urdf_path()
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    geom = pin.buildGeomFromUrdf(model, str(path), pin.GeometryType.COLLISION)
    data, gdata = model.createData(), geom.createData()
    objs = [o for ob in scene.obstacles for o in obstacle_objects(ob)]
    req, res = coal.DistanceRequest(), coal.DistanceResult()
    box = coal.Box(*BOX_SIZE)
    out: dict[str, float] = {}
    for i in range(len(motion.t)):
        pin.updateGeometryPlacements(model, data, geom, gdata, motion.q[i])
        bodies = [(g.name, g.geometry, coal.Transform3s(M.rotation, M.translation))
                  for g, M in zip(geom.geometryObjects, gdata.oMg, strict=True)]
        bodies.append((BOX, box, coal.Transform3s(matrix_from_quat(motion.box[i, 3:]),
                                                  motion.box[i, :3])))
        for name, shape, T in bodies:
            for o in objs:
                res.clear()
                d = coal.distance(shape, T, o.collisionGeometry(), o.getTransform(), req, res)
                out[name] = min(out.get(name, math.inf), d)
    return out


@pytest.mark.parametrize("seed", [0, 1])
def test_clearance_matches_brute_force_below_the_exact_bound(seed):
    motion = synthetic_motion(seed)
    scene = wall_scene(0.75)
    rep = obstacle_clearance(motion, scene, exact_below=0.05)
    truth = brute_force(motion, scene)
    assert {b.body for b in rep.bodies} == set(truth)
    assert rep.queries < 0.5 * len(motion.t) * len(truth)  # the bound skips most samples
    for b in rep.bodies:
        if truth[b.body] < 0.05:
            assert b.exact and b.clearance == pytest.approx(truth[b.body], abs=1e-5), b
        else:  # a proven lower bound above the exact range
            assert 0.05 <= b.clearance <= truth[b.body] + 1e-9, b
    assert rep.worst.clearance < 0  # the arms wave into the wall
    assert rep.worst.obstacle == "obstacles[0] (box)"


def test_failure_names_link_time_obstacle_and_depth():
    motion = synthetic_motion(0)
    rep = obstacle_clearance(motion, wall_scene(0.75))
    res = _obstacles(rep, 0.01)
    w = rep.worst
    assert not res.passed and res.value == w.clearance < 0
    assert w.link in res.detail and "depth" in res.detail and "obstacles[0] (box)" in res.detail
    assert f"t = {w.time:.3f} s" in res.detail
    clear = obstacle_clearance(motion, wall_scene(2.5))  # the box stops at 1.9 m
    assert _obstacles(clear, 0.01).passed
    assert {b.link for b in clear.bodies} >= {"box", "LARM_LINK5", "RLEG_LINK5", "BODY"}
    assert "LARM_LINK5" in clear.table()
