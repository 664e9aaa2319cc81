"""Talos's files, located in the installed ``example-robot-data`` package (the ``talos`` extra).

The package (PAL Robotics' model, Apache-2.0) installs its files under
``<site-packages>/cmeel.prefix/share/example-robot-data/robots/talos_data/``; nothing of it is
copied into this repository. :func:`talos_urdf` writes, once per process, a copy of
``talos_reduced.urdf`` with

* the mesh URIs (``package://example-robot-data/...``) made absolute file paths, so that
  pinocchio, PlaCo and the replay read the meshes without a package path;
* the fixed frames :data:`~pivot_ompl.humanoids.profile.FRAMES`: ``left_foot`` /
  ``right_foot`` at the sole centres (the middle of the foot's collision mesh, on its
  underside), ``trunk`` at the pelvis (``base_link``, as HRP-2's waist), ``left_hand`` /
  ``right_hand`` at the grip points between the gripper's fingers (:data:`GRIP_DEPTH` below
  the gripper base, x along the fingers' closing axis).
"""

from __future__ import annotations

import functools
import logging
import math
import re
import tempfile
from importlib import metadata
from pathlib import Path

from pivot_ompl.errors import InputError

log = logging.getLogger(__name__)

__all__ = ["DISTRIBUTION", "GRIP_DEPTH", "SOLE_CENTRE", "half_sitting_from_srdf", "talos_dir",
           "talos_solver_urdf", "talos_urdf"]

#: The package that ships Talos.
DISTRIBUTION = "example-robot-data"
#: Its data folder, relative to the distribution's install root.
_RELDIR = "cmeel.prefix/share/example-robot-data/robots/talos_data"
#: Sole centre in the ankle link ``leg_*_6_link`` (m): the middle of the foot collision
#: mesh ``ankle_X_collision.stl`` (x from -0.1163 to 0.1046, y +/-0.0672) on the sole
#: frame's plane (``*_sole_link``, 0.107 m under the ankle).
SOLE_CENTRE = (-0.00587, 0.0, -0.107)
#: Grip point below the gripper base (m): between the fingers (the fingertips' joints are
#: 0.056 m below the base, the fingertips 0.04 m further).
GRIP_DEPTH = 0.09
#: Yaw of the hand frames about the gripper's axis (rad): the hand's x axis, which the grips
#: hold up the box face (:mod:`pivot_ompl.wholebody.box`), is the gripper's -y axis. Of the
#: quarter turns it is the one whose wrists stay within their limits while the hands hold
#: the box: at +pi/2 the forearm roll ``arm_*_7_joint`` sits on its limit and the elbows
#: flare 3 cm further out (measured on the open scene's motion).
HAND_YAW = -0.5 * math.pi


def talos_dir() -> Path:
    """``.../robots/talos_data`` of the installed ``example-robot-data``.

    Raises:
        InputError: the package is not installed (``pip install "pivot-ompl[talos]"``).
    """
    try:
        dist = metadata.distribution(DISTRIBUTION)
    except metadata.PackageNotFoundError:
        raise InputError("robot.model", "talos", f"needs the {DISTRIBUTION!r} package: "
                         'pip install "pivot-ompl[talos]"') from None
    folder = Path(str(dist.locate_file(_RELDIR)))
    if not (folder / "robots" / "talos_reduced.urdf").is_file():
        raise InputError("robot.model", "talos", f"{DISTRIBUTION} is installed but "
                         f"{folder}/robots/talos_reduced.urdf is missing (version 6 expected)")
    return folder


def _frames_xml() -> str:
    cx, cy, cz = SOLE_CENTRE
    out = ['  <link name="trunk"/>\n  <joint name="trunk_fixed" type="fixed"><parent '
           'link="base_link"/><child link="trunk"/><origin xyz="0 0 0" rpy="0 0 0"/></joint>']
    for side in ("left", "right"):
        out.append(f'  <link name="{side}_foot"/>\n  <joint name="{side}_foot_fixed" '
                   f'type="fixed"><parent link="leg_{side}_6_link"/><child link="{side}_foot"/>'
                   f'<origin xyz="{cx} {cy} {cz}" rpy="0 0 0"/></joint>')
        out.append(f'  <link name="{side}_hand"/>\n  <joint name="{side}_hand_fixed" '
                   f'type="fixed"><parent link="gripper_{side}_base_link"/><child '
                   f'link="{side}_hand"/><origin xyz="0 0 {-GRIP_DEPTH}" '
                   f'rpy="0 0 {HAND_YAW}"/></joint>')
    return "\n".join(out) + "\n"


def urdf_text(folder: Path) -> str:
    """``talos_reduced.urdf`` with absolute mesh paths and the added frames."""
    text = (folder / "robots" / "talos_reduced.urdf").read_text()
    text = text.replace("package://example-robot-data/robots/talos_data/", f"{folder}/")
    end = text.rfind("</robot>")
    return text[:end] + _frames_xml() + text[end:]


@functools.lru_cache(maxsize=1)
def talos_urdf() -> Path:
    """The URDF with the added frames, written once per process into a temporary folder."""
    folder = talos_dir()
    out = Path(tempfile.mkdtemp(prefix="pivot-talos-")) / "talos_reduced_frames.urdf"
    out.write_text(urdf_text(folder))
    log.debug("wrote Talos's URDF with frames to %s", out)
    return out


@functools.lru_cache(maxsize=1)
def talos_solver_urdf() -> Path:
    """The same URDF without its visual and collision geometry (kinematics and inertias).

    PlaCo loads it in 0.13 s against 4.3 s with the meshes, which it does not use.
    """
    text = re.sub(r"<(visual|collision)>.*?</\1>", "", talos_urdf().read_text(), flags=re.S)
    out = talos_urdf().parent / "talos_reduced_frames_kinematics.urdf"
    out.write_text(text)
    return out


def half_sitting_from_srdf(folder: Path | None = None) -> dict[str, float]:
    """The SRDF's ``half_sitting`` group state, joint name -> angle (the root excluded)."""
    text = ((folder or talos_dir()) / "srdf" / "talos.srdf").read_text()
    block = re.search(r'<group_state name="half_sitting".*?</group_state>', text, re.S)
    if block is None:  # pragma: no cover - the package's file has it
        raise InputError("talos.srdf", "half_sitting", "group state not found")
    return {m.group(1): float(m.group(2)) for m in
            re.finditer(r'<joint name="([^"]+)" value="([-0-9.eE]+)"\s*/>', block.group(0))}
