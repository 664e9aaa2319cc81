"""Argument checks of the public dataclasses: finite numbers, poses and grasp indices.

The constructors of the plan's dataclasses (:mod:`pivot_ompl.planfile`) call these at the
boundary, so a wrong value is an :class:`~pivot_ompl.errors.InputError` naming the field
(``TransferStep.angle``), never a ``TypeError`` deep inside a later computation.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np

from pivot_ompl.errors import InputError

__all__ = ["finite_real", "guard", "guard_all"]


def finite_real(x: Any) -> bool:
    """Whether ``x`` is a finite real number (not a bool)."""
    if type(x) is float:
        return math.isfinite(x)
    try:
        return isinstance(x, numbers.Real) and not isinstance(x, bool) and math.isfinite(x)
    except OverflowError:  # an int beyond the floats
        return False


def guard(owner: str, **values: tuple[Any, int | None]) -> None:
    """Raise :class:`InputError` naming ``owner.name`` for the first wrong value.

    Each keyword is ``name=(value, n)``: ``value`` must be a finite number (``n`` None),
    ``n`` of them (a pose: 3), or (``n`` -1) a grasp index 0..3.
    """
    for name, (v, n) in values.items():
        if n == -1:
            ok = (isinstance(v, numbers.Integral) and not isinstance(v, bool)
                  and 0 <= int(v) <= 3)
        elif n is None:
            ok = finite_real(v)
        elif type(v) is tuple and len(v) == n and all(type(x) is float for x in v):
            ok = all(map(math.isfinite, v))  # the common case, without a call per number
        else:
            ok = (not isinstance(v, str | bytes) and isinstance(v, Sequence | np.ndarray)
                  and len(v) == n and all(finite_real(x) for x in v))
        if not ok:
            raise InputError(f"{owner}.{name}", v, "must be a grasp index 0..3" if n == -1
                             else "must be a finite number" if n is None
                             else f"must be {n} finite numbers")


def guard_all(owner: str, name: str, items: Any, kind: Any = None) -> None:
    """InputError unless ``items`` is a sequence of ``kind`` (``None``: of poses)."""
    if isinstance(items, str | bytes) or not isinstance(items, Sequence):
        raise InputError(f"{owner}.{name}", items, "must be a sequence")
    for i, x in enumerate(items):
        if kind is None:
            guard(owner, **{f"{name}[{i}]": (x, 3)})
        elif not isinstance(x, kind):
            raise InputError(f"{owner}.{name}[{i}]", x,
                             f"must be a {getattr(kind, '__name__', kind)}")
