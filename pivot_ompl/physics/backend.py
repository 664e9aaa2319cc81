"""MuJoCo, imported on first use: the ``physics`` extra (``pip install pivot_ompl[physics]``)."""

from __future__ import annotations

import importlib
from types import ModuleType

from pivot_ompl.errors import InputError

#: The versions of MuJoCo the physics package is written for (its 4.x API).
REQUIREMENT = "mujoco>=4,<5"


def mujoco() -> ModuleType:
    """The ``mujoco`` module.

    Raises:
        InputError: MuJoCo is not installed, or not a 4.x version (the message says how to
            install it).
    """
    try:
        mod = importlib.import_module("mujoco")
    except ImportError as e:
        raise InputError("physics", "mujoco", "is not installed: pip install "
                         f"'pivot_ompl[physics]' (or '{REQUIREMENT}')") from e
    major = str(getattr(mod, "__version__", "0")).split(".")[0]
    if major != "4":
        raise InputError("physics", f"mujoco {getattr(mod, '__version__', '?')}",
                         f"is not supported: {REQUIREMENT} is needed")
    return mod
