"""Tunable parameters declared with their ranges, next to the dataclass field they bound.

The counterpart of OMPL's ``Planner::declareParam(name, ..., "8:1:1000")``: a configuration
dataclass declares each numeric field with :func:`knob`, whose :class:`Range` sits in the
field's ``metadata``; validation (:func:`check_fields`) and listings (``pivot-ompl bench
--param help``) read it from there, so a range is written once, beside its default.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from pivot_ompl.errors import InputError

#: The key of a field's :class:`Range` in its ``metadata``.
RANGE_KEY = "range"
#: What every numeric parameter must be, whatever its range.
FLOOR = "must be finite and >= 0"


@dataclass(frozen=True)
class Range:
    """The values a numeric parameter (or each item of a tuple parameter) may take.

    Attributes:
        low: the smallest value (or the bound it must exceed, with ``low_open``).
        high: the largest value (``inf``: none).
        low_open: the value must be strictly greater than ``low``.
        integer: the value is a count (an ``int``).
    """

    low: float = 0.0
    high: float = math.inf
    low_open: bool = False
    integer: bool = False

    def __post_init__(self) -> None:
        """Every range lies within ``[0, inf)``, the floor :func:`check_value` tests first."""
        if not self.low >= 0.0 or self.high < self.low:
            raise ValueError(f"a parameter's range must lie in [0, inf): {self}")

    def problem(self, value: float) -> str | None:
        """Why ``value`` is out of the range (``"must be >= 1"``...), or ``None``."""
        if not (math.isfinite(value) and value >= 0):
            return FLOOR
        if self.low_open and not value > self.low:
            return f"must be {self._low_text()}"
        if value < self.low:
            return f"must be {self._low_text()}"
        if value > self.high:
            return f"must be <= {self.high:g}"
        return None

    def _low_text(self) -> str:
        return f"{'>' if self.low_open else '>='} {self.low:g}"

    def __str__(self) -> str:
        """Interval notation: ``[1, inf) integer``, ``(0, inf)``, ``[0, 1]``."""
        text = (f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}"
                f"{')' if math.isinf(self.high) else ']'}")
        return f"{text} integer" if self.integer else text


def knob(default: Any, *, low: float = 0.0, high: float = math.inf, low_open: bool = False,
         integer: bool | None = None) -> Any:
    """A dataclass field of default ``default`` whose values lie in a :class:`Range`.

    ``integer`` defaults to whether ``default`` (or its first item) is an ``int``.
    """
    first = default[0] if isinstance(default, tuple) and default else default
    whole = isinstance(first, int) and not isinstance(first, bool) if integer is None \
        else integer
    rng = Range(low=low, high=high, low_open=low_open, integer=whole)
    return field(default=default, metadata={RANGE_KEY: rng})


def range_of(metadata: Any) -> Range:
    """The :class:`Range` a field's ``metadata`` declares (the default: ``[0, inf)``)."""
    return metadata.get(RANGE_KEY, Range()) if metadata else Range()


def check_value(name: str, value: Any, rng: Range, *, floor_only: bool = False) -> None:
    """Raise :class:`InputError` naming ``name`` and ``value`` when out of ``rng``.

    Flags are not checked; a tuple's items are checked one by one (the error names the
    whole tuple). ``floor_only``: only that the value is finite and ``>= 0`` (the floor of
    every range: a configuration checks it for every field before their own ranges).
    """
    if isinstance(value, bool):
        return
    for x in value if isinstance(value, tuple) else (value,):
        if isinstance(x, int | float) and not isinstance(x, bool):
            why = Range().problem(x) if floor_only else rng.problem(x)
            if why is not None:
                raise InputError(name, value, why)
