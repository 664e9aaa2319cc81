"""The MuJoCo model of a scene: floor and obstacles static, the box free, two mocap hands.

* the floor: a plane over the scene's bounds (a margin around them);
* each obstacle a static geom: a box, a cylinder, or a polygon prism cut into triangular
  prisms (convex meshes: MuJoCo collides meshes by their convex hulls);
* the box: a free body of the plan's size, ``mass`` kg spread evenly (its inertia a solid
  box's), the centre of mass moved by ``com_offset`` (m, box frame), friction ``friction``
  on every face;
* the hands: two mocap bodies (kinematic, driven by :mod:`.drive`), each carrying a hand body
  on a free vertical slide, joined to the box by a soft ``weld`` that is on only while the
  motion holds the box (:mod:`.loop`): the hands push, pull and turn the box, the floor
  carries its weight (as when the robot pivots it on its supporting edge).

The floor's and the obstacles' friction is tiny: MuJoCo takes the larger of the two geoms'
values, so the box's own value (changed at run time over friction patches) is the pair's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from pivot_ompl.errors import InputError
from pivot_ompl.physics.backend import mujoco
from pivot_ompl.scene import BoxObstacle, CylinderObstacle, PolygonObstacle, Scene

#: Simulation time step (s): the motion's samples are split into steps of at most this.
MAX_TIMESTEP = 0.0025
#: Time constant (s) and damping ratio of the hands' welds (MuJoCo ``solref``).
WELD_SOLREF = (0.02, 1.0)
#: ``solref`` of the box's contacts: stiffer than the hands, the floor carries the box.
CONTACT_SOLREF = (0.005, 1.0)
#: Mass (kg) of each hand body and damping (N s/m) of its vertical slide: the hands guide the
#: box but leave its weight to the floor (each hand hangs from its mocap body on a free
#: vertical slide, its own weight compensated).
HAND_MASS, LIFT_DAMPING = 0.5, 20.0
#: Friction of the floor and obstacles (the box's value wins: see the module docstring).
STATIC_FRICTION = 1e-3
#: Largest box mass (kg) and centre-of-mass offset (share of the half size) accepted.
MAX_MASS, MAX_COM_SHARE = 1000.0, 0.9
#: Names of the bodies and geoms the loop looks up.
BOX, FLOOR, HANDS = "box", "floor", ("hand_left", "hand_right")


@dataclass
class PhysicsModel:
    """A compiled model and the indices the loop uses.

    Attributes:
        model, data: MuJoCo's ``MjModel`` and ``MjData``.
        box_body, box_geom, floor_geom: indices of the box body, its geom and the floor.
        obstacle_geoms: geom index -> index of the scene obstacle it belongs to.
        welds: the equality indices of the left and right hand's weld.
        mass: the box's mass (kg).
        friction: the box's nominal friction coefficient.
        size: the box's size (m).
    """

    model: Any
    data: Any
    box_body: int
    box_geom: int
    floor_geom: int
    obstacle_geoms: dict[int, int]
    welds: tuple[int, int]
    mass: float
    friction: float
    size: tuple[float, float, float]


def _f(*v: float) -> str:
    return " ".join(f"{x:.9g}" for x in v)


def _obstacle_xml(i: int, o: object, assets: list[str]) -> list[str]:
    fr = _f(STATIC_FRICTION, 0.0, 0.0)
    if isinstance(o, BoxObstacle):
        h = o.height
        half = _f(o.size[0] / 2, o.size[1] / 2, h / 2)
        return [f'<geom name="obstacle{i}" type="box" size="{half}"'
                f' pos="{_f(o.center[0], o.center[1], h / 2)}" euler="0 0 {o.yaw:.9g}"'
                f' friction="{fr}"/>']
    if isinstance(o, CylinderObstacle):
        return [f'<geom name="obstacle{i}" type="cylinder" size="{_f(o.radius, o.height / 2)}"'
                f' pos="{_f(o.center[0], o.center[1], o.height / 2)}" friction="{fr}"/>']
    if isinstance(o, PolygonObstacle):
        import shapely

        tris = shapely.constrained_delaunay_triangles(shapely.Polygon(o.points))
        out = []
        for j, tri in enumerate(shapely.get_parts(tris)):
            pts = np.asarray(tri.exterior.coords)[:3]
            verts = [(*p, 0.0) for p in pts] + [(*p, o.height) for p in pts]
            assets.append(f'<mesh name="obstacle{i}_{j}" vertex="'
                          f'{_f(*np.ravel(verts))}"/>')
            out.append(f'<geom name="obstacle{i}_{j}" type="mesh" mesh="obstacle{i}_{j}"'
                       f' friction="{fr}"/>')
        return out
    raise InputError("scene.obstacles", i, f"has an unknown kind {type(o).__name__}")


def model_xml(scene: Scene, *, size: tuple[float, float, float], mass: float,
              friction: float, com_offset: tuple[float, float, float] = (0.0, 0.0, 0.0),
              timestep: float = MAX_TIMESTEP) -> str:
    """The MJCF text of the scene (see the module docstring); the box starts at the origin."""
    w, d, h = size
    inertia = (mass / 12.0 * (d * d + h * h), mass / 12.0 * (w * w + h * h),
               mass / 12.0 * (w * w + d * d))
    x0, y0, x1, y1 = scene.bounds
    margin = 2.0 + max(size)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    hx, hy = 0.5 * (x1 - x0) + margin, 0.5 * (y1 - y0) + margin
    assets: list[str] = []
    obstacles = [line for i, o in enumerate(scene.obstacles)
                 for line in _obstacle_xml(i, o, assets)]
    hands = "".join(f'<body name="{n}_mocap" mocap="true"><body name="{n}" gravcomp="1">'
                    f'<joint name="{n}_lift" type="slide" axis="0 0 1" damping="{LIFT_DAMPING}"/>'
                    f'<inertial pos="0 0 0" mass="{HAND_MASS}" diaginertia="1e-3 1e-3 1e-3"/>'
                    '</body></body>' for n in HANDS)
    welds = "".join(f'<weld name="{n}" body1="{n}" body2="{BOX}" active="false"'
                    f' solref="{_f(*WELD_SOLREF)}"/>' for n in HANDS)
    return f"""<mujoco model="pivot_ompl {scene.name}">
  <option timestep="{timestep:.9g}" cone="elliptic" integrator="implicitfast"/>
  <asset>{''.join(assets)}</asset>
  <worldbody>
    <geom name="{FLOOR}" type="plane" size="{_f(hx, hy, 0.1)}" pos="{_f(cx, cy, 0.0)}"
          friction="{_f(STATIC_FRICTION, 0.0, 0.0)}"/>
    {''.join(obstacles)}
    <body name="{BOX}" pos="0 0 {h / 2:.9g}">
      <freejoint/>
      <inertial pos="{_f(*com_offset)}" mass="{mass:.9g}" diaginertia="{_f(*inertia)}"/>
      <geom name="{BOX}" type="box" size="{_f(w / 2, d / 2, h / 2)}" condim="3"
            solref="{_f(*CONTACT_SOLREF)}" friction="{_f(friction, 0.005, 0.0001)}" mass="0"/>
    </body>
    {hands}
  </worldbody>
  <equality>{welds}</equality>
</mujoco>"""


def check_physical(*, mass: float, friction: float, size: tuple[float, float, float],
                   com_offset: tuple[float, float, float]) -> None:
    """Raise :class:`InputError` naming a box mass, friction or COM offset out of range."""
    if not (math.isfinite(mass) and 0.0 < mass <= MAX_MASS):
        raise InputError("box_mass", mass, f"must be in (0, {MAX_MASS:g}] kg")
    if not (math.isfinite(friction) and 0.0 < friction <= 5.0):
        raise InputError("friction", friction, "must be in (0, 5]")
    for k in range(3):
        if not (math.isfinite(com_offset[k])
                and abs(com_offset[k]) <= MAX_COM_SHARE * 0.5 * size[k]):
            raise InputError(f"com_offset[{k}]", com_offset[k], "must be within "
                             f"{MAX_COM_SHARE:g} of the box's half size ({0.5 * size[k]:g} m)")


def build_model(scene: Scene, *, size: tuple[float, float, float], mass: float,
                friction: float, com_offset: tuple[float, float, float] = (0.0, 0.0, 0.0),
                timestep: float = MAX_TIMESTEP) -> PhysicsModel:
    """Compile the scene's model (see the module docstring).

    Raises:
        InputError: a mass, friction or COM offset out of range (naming it), or MuJoCo
            missing.
    """
    check_physical(mass=mass, friction=friction, size=size, com_offset=com_offset)
    mj = mujoco()
    xml = model_xml(scene, size=size, mass=mass, friction=friction, com_offset=com_offset,
                    timestep=timestep)
    model = mj.MjModel.from_xml_string(xml)
    data = mj.MjData(model)
    geom = {model.geom(i).name: i for i in range(model.ngeom)}
    obstacles = {g: int(name[8:].split("_")[0]) for name, g in geom.items()
                 if name.startswith("obstacle")}
    welds = (mj.mj_name2id(model, mj.mjtObj.mjOBJ_EQUALITY, HANDS[0]),
             mj.mj_name2id(model, mj.mjtObj.mjOBJ_EQUALITY, HANDS[1]))
    return PhysicsModel(model, data, mj.mj_name2id(model, mj.mjtObj.mjOBJ_BODY, BOX),
                        geom[BOX], geom[FLOOR], obstacles, welds, float(mass), float(friction),
                        size)
