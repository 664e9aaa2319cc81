"""A URDF robot for the viewer: link visuals (primitives or meshes) and vectorised kinematics.

Read with yourdfpy (no scene graph, no mesh loading by yourdfpy). The meshcat tree mirrors
the kinematic tree: node ``<prefix>/<root>/<child>/.../<link>`` per link, so a revolute
joint animates only its child's rotation. Visual geometry is sent as geometry (boxes,
cylinders, spheres, or triangle meshes read from the URDF's mesh files), never as file refs;
a mesh of more than :data:`MAX_MESH_FACES` triangles is decimated to that many
(:mod:`pivot_ompl.viz.decimate`: Talos's 159 k triangles become 59 k, its fig10 replay 1.3 MB
smaller).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import cast

import meshcat
import meshcat.geometry as g
import numpy as np
import yourdfpy

from pivot_ompl.errors import InputError
from pivot_ompl.viz.decimate import decimate
from pivot_ompl.viz.shapes import axis_angle

log = logging.getLogger(__name__)

LINK_COLOR = 0xa0a8b8
#: Most triangles of one link mesh in a replay.
MAX_MESH_FACES = 2000


@dataclass(frozen=True)
class JointInfo:
    """One URDF joint: ``T_parent_child(q) = origin @ motion(axis, q)``."""

    name: str
    type: str
    parent: str
    child: str
    origin: np.ndarray
    axis: np.ndarray
    mimic: tuple[str, float, float] | None = None  # (master, multiplier, offset)


@dataclass
class RobotModel:
    """Links, joints and visuals of a URDF (see the module docstring).

    Attributes:
        path: the URDF file.
        root: the root link's name.
        joints: joints keyed by child link name.
        children: child link names keyed by parent link name.
        urdf: the yourdfpy object.
    """

    path: Path
    root: str
    joints: dict[str, JointInfo]
    children: dict[str, list[str]]
    urdf: yourdfpy.URDF
    node_paths: dict[str, str] = field(default_factory=dict)

    @property
    def links(self) -> list[str]:
        """Every link name, parents before children."""
        out, stack = [], [self.root]
        while stack:
            name = stack.pop()
            out.append(name)
            stack.extend(reversed(self.children.get(name, [])))
        return out

    def node_path(self, link: str) -> str:
        """The meshcat node path of ``link`` relative to the robot's node."""
        if not self.node_paths:
            for name in self.links:
                j = self.joints.get(name)
                self.node_paths[name] = (name if j is None
                                         else f"{self.node_paths[j.parent]}/{name}")
        return self.node_paths[link]

    def joint_values(self, q_joints: np.ndarray, names: tuple[str, ...]) -> dict[str, np.ndarray]:
        """Per-joint value arrays ``(K,)`` from configuration columns (mimic joints follow)."""
        k = q_joints.shape[0]
        vals = {n: q_joints[:, i] for i, n in enumerate(names)}
        out: dict[str, np.ndarray] = {}
        for j in self.joints.values():
            if j.type in ("fixed", "floating", "planar"):
                continue
            if j.name in vals:
                out[j.name] = vals[j.name]
            elif j.mimic is not None and j.mimic[0] in vals:
                out[j.name] = vals[j.mimic[0]] * j.mimic[1] + j.mimic[2]
            else:
                out[j.name] = np.zeros(k)
        return out

    def local_transforms(self, link: str, value: np.ndarray | None) -> np.ndarray:
        """``T_parent_link`` ``(K, 4, 4)`` for joint values ``(K,)`` (``(1,4,4)`` if fixed)."""
        j = self.joints[link]
        if value is None or j.type == "fixed":
            return j.origin[None]
        k = len(value)
        m = np.repeat(np.eye(4)[None], k, axis=0)
        if j.type == "prismatic":
            m[:, :3, 3] = value[:, None] * j.axis[None]
        else:  # revolute, continuous
            a = j.axis
            kx = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
            s, c = np.sin(value)[:, None, None], np.cos(value)[:, None, None]
            m[:, :3, :3] = np.eye(3) + s * kx + (1 - c) * (kx @ kx)
        return j.origin[None] @ m

    def world_transforms(self, root: np.ndarray, values: dict[str, np.ndarray],
                         links: list[str]) -> dict[str, np.ndarray]:
        """``T_world_link`` ``(K, 4, 4)`` of ``links`` given ``T_world_root`` ``(K, 4, 4)``."""
        cache: dict[str, np.ndarray] = {self.root: root}

        def get(name: str) -> np.ndarray:
            if name not in cache:
                j = self.joints[name]
                cache[name] = get(j.parent) @ self.local_transforms(name, values.get(j.name))
            return cache[name]

        return {n: get(n) for n in links}


def load_robot(path: str | Path) -> RobotModel:
    """Read a URDF (primitives and meshes are only read when drawn).

    Raises:
        InputError: the file is missing or not a valid URDF.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError("urdf", str(path), "file not found")
    try:
        u = yourdfpy.URDF.load(str(path), build_scene_graph=False, load_meshes=False)
    except Exception as e:  # yourdfpy raises many kinds (lxml, its own errors)
        raise InputError("urdf", str(path), f"is not a readable URDF ({e})") from e
    joints: dict[str, JointInfo] = {}
    children: dict[str, list[str]] = {}
    for j in u.robot.joints:
        origin = np.eye(4) if j.origin is None else np.asarray(j.origin, dtype=float)
        axis = np.array([1.0, 0.0, 0.0]) if j.axis is None else np.asarray(j.axis, dtype=float)
        axis = axis / (np.linalg.norm(axis) or 1.0)
        mimic = None
        if j.mimic is not None:
            mimic = (j.mimic.joint, float(j.mimic.multiplier or 1.0),
                     float(j.mimic.offset or 0.0))
        joints[j.child] = JointInfo(j.name, j.type, j.parent, j.child, origin, axis, mimic)
        children.setdefault(j.parent, []).append(j.child)
    roots = [lk.name for lk in u.robot.links if lk.name not in joints]
    if len(roots) != 1:
        raise InputError("urdf", str(path), f"must have exactly one root link (found {roots})")
    return RobotModel(path, roots[0], joints, children, u)


def _material(visual: yourdfpy.Visual, u: yourdfpy.URDF) -> g.MeshLambertMaterial:
    rgba = None
    mat = visual.material
    if mat is not None:
        if mat.color is not None:
            rgba = mat.color.rgba
        elif mat.name and mat.name in getattr(u, "_material_map", {}):
            c = u._material_map[mat.name].color
            rgba = c.rgba if c is not None else None
    if rgba is None:
        return g.MeshLambertMaterial(color=LINK_COLOR)
    r, gg, b, a = (float(x) for x in rgba)
    color = (int(r * 255) << 16) | (int(gg * 255) << 8) | int(b * 255)
    return g.MeshLambertMaterial(color=color, opacity=a)


def _mesh_geometry(model: RobotModel, mesh: yourdfpy.Mesh) -> tuple[g.Geometry, np.ndarray]:
    import trimesh  # a yourdfpy dependency

    name = mesh.filename
    for prefix in ("package://", "file://"):
        if name.startswith(prefix):
            name = name[len(prefix):]
    candidates = [model.path.parent / name, model.path.parent.parent / name, Path(name)]
    parts = Path(name).parts
    candidates += [model.path.parent / Path(*parts[i:]) for i in range(1, len(parts))]
    file = next((c for c in candidates if c.is_file()), None)
    if file is None:
        raise FileNotFoundError(mesh.filename)
    tm = cast("trimesh.Trimesh", trimesh.load(str(file), force="mesh"))
    scale = np.eye(4)
    if mesh.scale is not None:
        s = np.broadcast_to(np.asarray(mesh.scale, dtype=float), (3,))
        scale[:3, :3] = np.diag(s)
    vertices, faces = decimate(np.asarray(tm.vertices), np.asarray(tm.faces), MAX_MESH_FACES)
    return g.TriangularMeshGeometry(vertices, faces), scale


def visual_geometry(model: RobotModel, visual: yourdfpy.Visual) -> tuple[g.Geometry, np.ndarray]:
    """Meshcat geometry of one URDF visual and the fixed transform to put it at."""
    geo = visual.geometry
    origin = np.eye(4) if visual.origin is None else np.asarray(visual.origin, dtype=float)
    if geo.box is not None:
        return g.Box(list(np.asarray(geo.box.size, dtype=float))), origin
    if geo.cylinder is not None:  # URDF cylinders run along z, three.js ones along y
        return (g.Cylinder(float(geo.cylinder.length), float(geo.cylinder.radius)),
                origin @ axis_angle((1.0, 0.0, 0.0), 0.5 * math.pi))
    if geo.sphere is not None:
        return g.Sphere(float(geo.sphere.radius)), origin
    if geo.mesh is not None:
        mg, scale = _mesh_geometry(model, geo.mesh)
        return mg, origin @ scale
    raise ValueError("empty geometry")


def draw_robot(vis: meshcat.Visualizer, model: RobotModel) -> int:
    """Send every link's visuals under ``vis`` (tree mirrors the URDF); returns the count.

    Link nodes get their zero-configuration transform; visuals are children
    ``visual_<i>`` of their link node.
    """
    n = 0
    links = {lk.name: lk for lk in model.urdf.robot.links}
    for name in model.links:
        node = vis[model.node_path(name)]
        j = model.joints.get(name)
        node.set_transform(np.eye(4) if j is None else model.local_transforms(name, None)[0])
        for i, visual in enumerate(links[name].visuals):
            try:
                geo, tf = visual_geometry(model, visual)
            except (FileNotFoundError, ValueError) as e:
                log.warning("link %s visual %d not drawn: %s", name, i, e)
                continue
            # Fixed transforms (possibly mirrored scales) live on the child node.
            vis_node = node[f"visual_{i}"]
            vis_node.set_object(geo, _material(visual, model.urdf))
            vis_node.set_transform(tf)
            n += 1
    return n
