"""Humanoid profiles, looked up by name: every fact about a robot lives here.

* :mod:`.profile` -- :class:`HumanoidProfile`, the fields every layer reads;
* :mod:`.hrp2` -- HRP-2 (our primitive model shipped in ``robots/hrp2``), the default;
* :mod:`.talos` and :mod:`.talos_data` -- Talos, from the ``example-robot-data`` package
  (the ``talos`` extra), located in the installed package.

No module outside this package names a robot: they take a profile, or a model name and
:func:`profile_of`.
"""

from __future__ import annotations

from pathlib import Path

from pivot_ompl.errors import InputError
from pivot_ompl.humanoids import hrp2, talos, talos_data
from pivot_ompl.humanoids.profile import FRAMES, HumanoidProfile
from pivot_ompl.resources import data_path

__all__ = ["DEFAULT_MODEL", "FRAMES", "PROFILES", "HumanoidProfile", "hrp2", "model_of_urdf",
           "profile_of", "talos", "talos_data", "urdf_file"]

#: Every profile by name.
PROFILES: dict[str, HumanoidProfile] = {p.name: p for p in (hrp2.PROFILE, talos.PROFILE)}
#: The model of a scene, plan or motion that names none.
DEFAULT_MODEL = hrp2.PROFILE.name


def profile_of(name: str | None, *, field: str = "robot.model") -> HumanoidProfile:
    """The profile called ``name`` (``None``: the default model's).

    Raises:
        InputError: no profile has that name (``field`` names where it was given).
    """
    if name is None:
        name = DEFAULT_MODEL
    try:
        return PROFILES[name]
    except (KeyError, TypeError):
        raise InputError(field, name, f"unknown robot model (known: {sorted(PROFILES)})"
                         ) from None


def model_of_urdf(urdf: str) -> str | None:
    """The model whose motion files name their URDF ``urdf``, if any."""
    for p in PROFILES.values():
        if p.urdf_name == urdf:
            return p.name
    return None


def urdf_file(urdf: str, *, field: str = "motion.urdf") -> Path:
    """The file a motion's ``urdf`` names: a profile's URDF, or a shipped file.

    Raises:
        InputError: neither (``field`` names where it was given), or the profile's robot data
            is not installed.
    """
    if not isinstance(urdf, str):
        raise InputError(field, urdf, "must be a URDF file name")
    model = model_of_urdf(urdf)
    if model is not None:
        return PROFILES[model].urdf_path()
    return data_path(urdf, field=field)
