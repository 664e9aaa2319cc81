"""Write ``hrp2.urdf`` from the HRP-2 fact tables (``hrp2_joints.csv``, ``hrp2_links.csv``).

Our own model: every number comes from the fact sheet (../shared/hrp2/HRP2-FACTS.md); the
geometry is primitive (boxes and cylinders sized from the link bounding boxes). Run::

    python robots/hrp2/make_urdf.py [FACTS_DIR]

FACTS_DIR defaults to ``../shared/hrp2`` next to the repository.
"""

from __future__ import annotations

import csv
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent

#: Sole centre in the ankle frame (*LEG_LINK5), fact sheet section 6 (y sign per side).
SOLE = (0.015, 0.010, -0.105)
#: Sole plate size (length x width x thickness) and its centre height above the sole.
SOLE_PLATE = (0.241, 0.138, 0.030)
#: Grip point in the *ARM_LINK5 frame, fact sheet section 7.
GRIP = (0.0, 0.0, -0.15)
#: Links drawn as a cylinder along their z axis (long limb segments).
CYLINDERS = {"RLEG_LINK2", "RLEG_LINK3", "LLEG_LINK2", "LLEG_LINK3",
             "RARM_LINK2", "RARM_LINK3", "LARM_LINK2", "LARM_LINK3"}


def f(x: float) -> str:
    """Format a number compactly."""
    return f"{x:.6g}"


def geometry(link: dict[str, str]) -> tuple[str, tuple[float, float, float]]:
    """Primitive geometry XML and its centre for one link row."""
    lo = [float(link[f"bbox_min_{a}_m"]) for a in "xyz"]
    hi = [float(link[f"bbox_max_{a}_m"]) for a in "xyz"]
    size = [b - a for a, b in zip(lo, hi, strict=True)]
    centre = tuple((b + a) / 2 for a, b in zip(lo, hi, strict=True))
    if link["link"] in CYLINDERS:
        r = 0.5 * min(size[0], size[1])
        return f'<cylinder radius="{f(r)}" length="{f(size[2])}"/>', centre
    return f'<box size="{f(size[0])} {f(size[1])} {f(size[2])}"/>', centre


def shape(name: str, geom: str, xyz: tuple[float, float, float], material: str) -> str:
    """Visual and collision elements of one primitive."""
    origin = f'<origin xyz="{f(xyz[0])} {f(xyz[1])} {f(xyz[2])}" rpy="0 0 0"/>'
    return (f'    <visual name="{name}">{origin}<geometry>{geom}</geometry>'
            f'<material name="{material}"/></visual>\n'
            f'    <collision name="{name}">{origin}<geometry>{geom}</geometry></collision>\n')


def link_xml(link: dict[str, str]) -> str:
    """One ``<link>`` with inertial and primitive geometry."""
    name = link["link"]
    m = float(link["mass_kg"])
    com = [float(link[f"com_{a}_m"]) for a in "xyz"]
    inertia = " ".join(f'{k}="{f(float(link[k + "_kgm2"]))}"'
                       for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
    out = [f'  <link name="{name}">\n',
           f'    <inertial><origin xyz="{f(com[0])} {f(com[1])} {f(com[2])}" rpy="0 0 0"/>'
           f'<mass value="{f(m)}"/><inertia {inertia}/></inertial>\n']
    material = "grey" if "ARM" in name or "LEG" in name else "white"
    if name.endswith("LEG_LINK5"):  # foot: sole plate + ankle block
        sy = -1.0 if name.startswith("R") else 1.0
        z = SOLE[2] + SOLE_PLATE[2] / 2
        out.append(shape(f"{name}_sole", '<box size="{} {} {}"/>'.format(*map(f, SOLE_PLATE)),
                         (SOLE[0], sy * SOLE[1], z), "grey"))
        out.append(shape(f"{name}_ankle", '<box size="0.1 0.09 0.11"/>',
                         (0.0, sy * 0.005, -0.02), "grey"))
    else:
        geom, centre = geometry(link)
        out.append(shape(f"{name}_geom", geom, centre, material))
    out.append("  </link>\n")
    return "".join(out)


def joint_xml(j: dict[str, str]) -> str:
    """One revolute ``<joint>``."""
    name = j["joint"]
    xyz = [float(j[f"origin_{a}_m"]) for a in "xyz"]
    if name == "LARM_JOINT6":  # mirror the right gripper hinge (fact sheet section 4)
        xyz[2] = -0.08525
    axis = " ".join(f(float(j[f"axis_{a}"])) for a in "xyz")
    return (f'  <joint name="{name}" type="revolute">\n'
            f'    <parent link="{j["parent_link"]}"/><child link="{j["child_link"]}"/>\n'
            f'    <origin xyz="{f(xyz[0])} {f(xyz[1])} {f(xyz[2])}" rpy="0 0 0"/>'
            f'<axis xyz="{axis}"/>\n'
            f'    <limit lower="{f(float(j["lower_rad"]))}" upper="{f(float(j["upper_rad"]))}" '
            f'effort="{f(float(j["effort_limit_Nm"]))}" '
            f'velocity="{f(float(j["velocity_limit_rad_s"]))}"/>\n'
            f'  </joint>\n')


def frame_xml(name: str, parent: str, xyz: tuple[float, float, float]) -> str:
    """A massless fixed link ``name`` (an operational frame) on ``parent``."""
    return (f'  <link name="{name}"/>\n'
            f'  <joint name="{name}_fixed" type="fixed"><parent link="{parent}"/>'
            f'<child link="{name}"/><origin xyz="{f(xyz[0])} {f(xyz[1])} {f(xyz[2])}" '
            f'rpy="0 0 0"/></joint>\n')


def build(facts: Path) -> str:
    """The URDF text."""
    joints = list(csv.DictReader((facts / "hrp2_joints.csv").open()))
    links = list(csv.DictReader((facts / "hrp2_links.csv").open()))
    parts = ['<?xml version="1.0"?>\n',
             "<!-- HRP-2-like humanoid, primitive geometry. Written by pivot_ompl from the\n"
             "     published kinematic and inertial facts (see README.md); generated by\n"
             "     make_urdf.py. Frames: left_foot/right_foot (sole centres), trunk (waist),\n"
             "     left_hand/right_hand (grip points). -->\n",
             '<robot name="hrp2">\n',
             '  <material name="grey"><color rgba="0.55 0.57 0.6 1"/></material>\n',
             '  <material name="white"><color rgba="0.9 0.9 0.92 1"/></material>\n']
    parts += [link_xml(row) for row in links]
    parts += [joint_xml(row) for row in joints]
    parts.append(frame_xml("trunk", "BODY", (0.0, 0.0, 0.0)))
    parts.append(frame_xml("right_foot", "RLEG_LINK5", (SOLE[0], -SOLE[1], SOLE[2])))
    parts.append(frame_xml("left_foot", "LLEG_LINK5", SOLE))
    parts.append(frame_xml("right_hand", "RARM_LINK5", GRIP))
    parts.append(frame_xml("left_hand", "LARM_LINK5", GRIP))
    parts.append("</robot>\n")
    return "".join(parts)


def main() -> None:
    """Write hrp2.urdf next to this script."""
    facts = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE.parents[2] / "shared" / "hrp2"
    (HERE / "hrp2.urdf").write_text(build(facts))


if __name__ == "__main__":
    main()
