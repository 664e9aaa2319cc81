"""Where the shipped data lives: the robot model (``robots/``) and the scenes (``scenes/``).

In a source checkout they are the top-level folders ``robots/`` and ``scenes/``; in a wheel the
build maps them into the package as ``pivot_ompl/data/robots`` and ``pivot_ompl/data/scenes``
(``pyproject.toml``), so one relative name such as ``robots/hrp2/hrp2.urdf`` (the name written
into motion files) means the same file in both.
"""

from __future__ import annotations

from pathlib import Path

from pivot_ompl.errors import InputError

_PACKAGE = Path(__file__).resolve().parent


def data_root() -> Path:
    """The folder holding ``robots/`` and ``scenes/`` (the wheel's copy first)."""
    packaged = _PACKAGE / "data"
    if (packaged / "robots").is_dir():
        return packaged
    return _PACKAGE.parent


#: The URDF of HRP-2, relative to :func:`data_root` (written into motion files).
URDF_RELPATH = "robots/hrp2/hrp2.urdf"


def data_path(relpath: str, *, field: str = "path") -> Path:
    """The shipped file ``relpath`` (relative to :func:`data_root`).

    Raises:
        InputError: ``relpath`` is absolute, leaves the data folders, or does not exist.
    """
    root = data_root()
    rel = Path(relpath)
    if rel.is_absolute() or ".." in rel.parts or rel.parts[:1] not in (("robots",), ("scenes",)):
        raise InputError(field, relpath, "must name a shipped file such as "
                         f"{URDF_RELPATH!r} (relative, under robots/ or scenes/)")
    path = root / rel
    if not path.is_file():
        raise InputError(field, relpath, f"no such shipped file under {root}")
    return path


def urdf_path() -> Path:
    """Absolute path of HRP-2's URDF."""
    return data_root() / URDF_RELPATH


def shipped_scenes() -> dict[str, Path]:
    """Shipped scene name -> file (``scenes/<name>.yaml``)."""
    return {p.stem: p for p in sorted((data_root() / "scenes").glob("*.yaml"))}
