"""Shared factories of the test suite: scenes, problems and paths of shipped files."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path
from types import ModuleType

import numpy as np

from pivot_ompl.resources import data_root
from pivot_ompl.scene import Scene, load_scene, scene_from_dict

ROOT = Path(__file__).resolve().parents[1]


def benchmark_script(name: str) -> ModuleType:
    """``benchmarks/<name>.py`` imported as module ``bench_<name>`` (registered in
    ``sys.modules``: its dataclasses look their module up)."""
    spec = importlib.util.spec_from_file_location(f"bench_{name}",
                                                  ROOT / "benchmarks" / f"{name}.py")
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod
    spec.loader.exec_module(mod)
    return mod
SCENES = data_root() / "scenes"
#: Scenes kept for tests only (e.g. the first fig10, whose exact poses regression tests use).
TEST_SCENES = Path(__file__).resolve().parent / "data" / "scenes"
PAPER_BOX = (0.8, 0.6, 1.3)
ALPHA_MAX = math.pi / 8


def scene_file(name: str) -> Path:
    """A shipped scene's file, else one of the test scenes."""
    path = SCENES / f"{name}.yaml"
    return path if path.exists() else TEST_SCENES / f"{name}.yaml"


def shipped(name: str) -> Scene:
    return load_scene(scene_file(name))


def make_scene(**overrides) -> Scene:
    """A small scene dict (8 x 6 m, paper box) with overrides, parsed."""
    doc = {"name": "test", "bounds": [0.0, 0.0, 8.0, 6.0], "object": {"size": list(PAPER_BOX)},
           "start": [1.5, 3.0, 0.0], "goal": [6.0, 3.0, 0.0], "obstacles": []}
    doc.update(overrides)
    return scene_from_dict(doc, source="<test>")


def sliced(obstacles, pieces: int) -> list:  # noqa: ANN001
    """Every box of ``obstacles`` cut across its long side into ``pieces`` boxes (one floor)."""
    import dataclasses

    out = []
    for o in obstacles:
        (cx, cy), (sx, sy), yaw = o.center, o.size, o.yaw
        long_x = sx >= sy
        ux, uy = (math.cos(yaw), math.sin(yaw)) if long_x else (-math.sin(yaw), math.cos(yaw))
        for k in range(pieces):
            t = ((k + 0.5) / pieces - 0.5) * (sx if long_x else sy)
            size = (sx / pieces, sy) if long_x else (sx, sy / pieces)
            out.append(dataclasses.replace(o, center=(cx + t * ux, cy + t * uy), size=size))
    return out


def rotated_scene_doc(doc: dict, angle: float, about: tuple[float, float] = (0.0, 0.0)) -> dict:
    """A scene document with every coordinate rotated by ``angle`` (rad) about ``about``.

    The bounds become the axis-aligned box round the rotated bounds (scenes of this kind are
    closed by their own walls, so the extra floor is outside them).
    """
    import copy

    c, s = math.cos(angle), math.sin(angle)

    def pt(p):
        x, y = p[0] - about[0], p[1] - about[1]
        return [about[0] + c * x - s * y, about[1] + s * x + c * y]

    out = copy.deepcopy(doc)
    x0, y0, x1, y1 = doc["bounds"]
    corners = [pt(p) for p in ((x0, y0), (x1, y0), (x1, y1), (x0, y1))]
    out["bounds"] = [min(p[0] for p in corners), min(p[1] for p in corners),
                     max(p[0] for p in corners), max(p[1] for p in corners)]
    out["name"] = f"{doc['name']}_rot{angle:.2f}"
    for o in out.get("obstacles") or []:
        if o["type"] in ("box", "cylinder"):
            o["center"] = pt(o["center"])
        if o["type"] == "box":
            o["yaw"] = o.get("yaw", 0.0) + angle
        if o["type"] == "polygon":
            o["points"] = [pt(p) for p in o["points"]]
    for k in ("start", "goal"):
        out[k] = pt(doc[k]) + [doc[k][2] + angle]
    return out


def shipped_doc(name: str) -> dict:
    """The parsed YAML document of a shipped scene."""
    import yaml

    return yaml.safe_load(scene_file(name).read_text())


def walk_problems(scene: Scene, obj, g1: int, g2: int, walk) -> list[str]:  # noqa: ANN001
    """What the independent check finds in a walk from grasp ``g1`` to ``g2`` round ``obj``.

    The walk is checked as a plan of its own (a transfer-less grasp at each end) of the
    scene with its start and goal at ``obj``; problems that only say the plan's status or
    sizes differ from the scene's are left out.
    """
    from pivot_ompl.planfile import Plan, TransferPhase, TransitPhase
    from pivot_ompl.validity.plan_check import check_plan

    m = scene.model
    plan = Plan(scene.name, "exact", m.object_size, m.robot_footprint, m.standoff,
                scene.alpha_max, obj,
                [TransferPhase(g1, m.robot_pose(obj, g1), (), obj),
                 TransitPhase(g1, g2, walk.robot_path, obj),
                 TransferPhase(g2, m.robot_pose(obj, g2), (), obj)])
    import dataclasses

    here = dataclasses.replace(scene, start=obj, goal=obj)  # the check starts at the scene's
    return [p for p in check_plan(plan, here).problems if "scene" not in p]


def two_rooms(door: float) -> Scene:
    """Two 4 x 4.5 m rooms joined by one door ``door`` m wide in the 0.3 m wall between them
    (its west face at x = 4.3, the door centred at y = 2.55)."""
    from pivot_ompl.generate.layout import free_complement
    from pivot_ompl.generate.layout import make_scene as layout_scene

    bounds = (0.0, 0.0, 8.9, 5.1)
    free = [(0.3, 0.3, 4.3, 4.8), (4.6, 0.3, 8.6, 4.8),
            (4.3, 2.55 - 0.5 * door, 4.6, 2.55 + 0.5 * door)]
    return layout_scene("two_rooms", bounds, free_complement(bounds, free), (2.0, 2.55, 0.0),
                        (7.0, 2.55, 0.0))


def turned_generated(seed: int) -> Scene:
    """A generated walls, corridor or building scene (by ``seed``), turned by a random angle."""
    import numpy as np

    from pivot_ompl.generate import generate, rotate_scene

    rng = np.random.default_rng(seed)
    family = ("walls", "corridor", "building")[seed % 3]
    scene = generate(family, seed=int(rng.integers(0, 50))).scene
    return rotate_scene(scene, float(rng.uniform(-math.pi, math.pi)))


def open_floor_checker(start: tuple[float, float, float], goal: tuple[float, float, float],
                       **extra):  # noqa: ANN201
    """The checker of a 10 x 8 m floor from ``start`` to ``goal`` (``extra``: scene fields)."""
    from pivot_ompl.base.problem import make_problem

    scene = make_scene(start=list(start), goal=list(goal), bounds=[-1.0, -1.0, 9.0, 7.0], **extra)
    return make_problem(scene).checker


class DeadlineWatch:
    """Times a call against its limit in this process's CPU seconds past the deadline.

    A call that honours its limit stops at the first poll after the deadline; the work done
    after it is what a test bounds. Read as CPU seconds of this process (a timer thread notes
    the process clock when the deadline passes), it does not grow when other work on the
    machine slows the call down, as the wall clock does. ``wall`` is kept for gross checks.
    """

    def __init__(self, limit: float) -> None:
        self.limit = limit
        self.wall = math.nan
        self._cpu_at_deadline: float | None = None
        self._cpu_at_end = math.nan

    def __enter__(self) -> DeadlineWatch:
        import gc
        import threading
        import time

        gc.collect()  # earlier tests' garbage: a full collection is not the call's own work
        self._timer = threading.Timer(self.limit, self._note_deadline)
        self._t0 = time.perf_counter()
        self._timer.start()
        return self

    def _note_deadline(self) -> None:
        import time

        self._cpu_at_deadline = time.process_time()

    def __exit__(self, *exc: object) -> None:
        import time

        self._cpu_at_end = time.process_time()
        self.wall = time.perf_counter() - self._t0
        self._timer.cancel()

    @property
    def cpu_past_deadline(self) -> float:
        """CPU seconds spent after the deadline (0 when the call ended before it)."""
        if self._cpu_at_deadline is None:
            return 0.0
        return max(0.0, self._cpu_at_end - self._cpu_at_deadline)


def clear_lane_boxes(max_size: int):  # noqa: ANN201
    """A hypothesis strategy: up to ``max_size`` boxes ``(x, offset, above, w, h, yaw)`` that
    :func:`floor_with_clear_lane` places beside a clear lane."""
    from hypothesis import strategies as st

    return st.lists(st.tuples(st.floats(0.5, 7.5), st.floats(0.2, 1.6), st.booleans(),
                              st.floats(0.1, 0.8), st.floats(0.1, 0.8), st.floats(0, 3.1)),
                    min_size=1, max_size=max_size)


def floor_with_clear_lane(boxes) -> Scene:  # noqa: ANN001
    """The default floor with ``boxes`` anywhere but a lane 1.8 m wide round y = 3 (the held
    assembly is 0.88 m across): the box pivots straight from start to goal at one grasp."""
    doc = [{"type": "box", "center": [x, 3.0 + (1.0 if up else -1.0) * (1.0 + d + 0.6)],
            "size": [w, h], "yaw": yaw, "height": 1.0}
           for x, d, up, w, h, yaw in boxes]
    return make_scene(obstacles=doc)


#: fig10's middle phase: its regrasp poses (box) and the grasp held between them
FIG10_MIDDLE = ((3.55, 1.5, 0.0), (8.95, 5.5, math.pi), 2)


def about_centre(scene: Scene, angle: float, *, reflect: bool):  # noqa: ANN201
    """The rigid map of a copy of ``scene`` turned (or reflected in the line at ``angle``)
    about its bounds' centre, as :func:`pivot_ompl.generate.rotate_scene` and
    :func:`~pivot_ompl.generate.mirror_scene` make it."""
    from pivot_ompl.generate import RigidMap

    b = scene.bounds
    return RigidMap(angle, (0.5 * (b[0] + b[2]), 0.5 * (b[1] + b[3])), reflect)


def ragged_wall(door: float, seed: int = 0) -> Scene:
    """The default floor cut at x = 4 by a wall of 5 cm strips, each 0.2-0.4 m thick at random
    (a mapped wall: no two strips merge), with a door ``door`` m wide round y = 3."""
    rng = np.random.default_rng(seed)
    walls = []
    for k in range(120):
        y = 0.05 * k + 0.025
        lo, hi = 4.0 - rng.uniform(0.1, 0.2), 4.0 + rng.uniform(0.1, 0.2)
        if abs(y - 3.0) >= 0.5 * door:
            walls.append({"type": "box", "center": [0.5 * (lo + hi), y], "size": [hi - lo, 0.05],
                          "yaw": 0.0, "height": 2.0})
    return make_scene(obstacles=walls)
