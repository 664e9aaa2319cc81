"""The one exception family of pivot_ompl.

Every error raised on purpose by the library is a :class:`PivotError`. Subclasses carry the
offending data as attributes so that callers (the CLI, a notebook, a benchmark) can report it
without parsing messages.
"""

from __future__ import annotations

import reprlib
import unicodedata
from typing import Any

_REPR = reprlib.Repr()
_REPR.maxstring, _REPR.maxother, _REPR.maxlong = 80, 80, 40
_REPR.maxlist = _REPR.maxtuple = _REPR.maxdict = _REPR.maxset = 6
_REPR.maxlevel = 3


def _escape(ch: str) -> str:
    code = ord(ch)
    if ch == "\n":
        return "\\n"
    if ch == "\t":
        return "\\t"
    if ch == "\r":
        return "\\r"
    return f"\\x{code:02x}" if code < 0x100 else (
        f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}")


def printable(text: object, *, keep: str = "") -> str:
    r"""``text`` (``str()`` of it) safe for a terminal or a log line: one line, no control codes.

    Every character of Unicode's "other" categories (controls such as ESC, BEL, NUL,
    newline; format characters such as bidirectional overrides; surrogates, unassigned) and
    the line and paragraph separators is shown as its Python escape (``\x1b``, ``\n``,
    ``\u202e``); a backslash stays as it is; any other text is unchanged. Every print or log
    of a user's string (a scene's name, a key, a path) goes through it. Characters in
    ``keep`` (``"\n"`` for a whole text of several lines) are left as they are.
    """
    s = text if isinstance(text, str) else str(text)
    if s.isprintable():
        return s
    return "".join(_escape(c) if c not in keep and (unicodedata.category(c)[0] == "C"
                                                   or unicodedata.category(c) in ("Zl", "Zp"))
                   else c for c in s)


def counted(n: int, noun: str, plural: str = "") -> str:
    """``"1 regrasp"``, ``"2 regrasps"``: ``n`` and ``noun``, plural (``noun + "s"``) unless 1."""
    return f"{n} {noun if n == 1 else plural or noun + 's'}"


def abridge(value: Any) -> str:
    """A short ``repr`` of ``value`` for a message (long numbers, strings, lists abridged)."""
    try:
        return _REPR.repr(value)
    except (ValueError, RecursionError):  # e.g. an int beyond Python's digit limit
        if isinstance(value, int):
            return f"<integer of {value.bit_length()} bits>"
        return f"<{type(value).__name__}>"


def require_type(value: Any, kinds: type | tuple[type, ...], field: str, what: str) -> None:
    """Raise :class:`InputError` naming ``field`` unless ``value`` is one of ``kinds``.

    ``what`` says what is expected (``"a Scene"``); ``bool`` never passes for a number.
    """
    numbers = kinds in (int, float) or (isinstance(kinds, tuple) and set(kinds) <= {int, float})
    if not isinstance(value, kinds) or (numbers and isinstance(value, bool)):
        raise InputError(field, type(value).__name__, f"must be {what}")


class PivotError(Exception):
    """Base class of every error raised by pivot_ompl."""


class InputError(PivotError, ValueError):
    """Bad input: a field has a wrong value or type.

    Attributes:
        field: dotted name of the offending field (``"object.size[1]"``).
        value: the offending value as given.
        source: where the input came from (a file path, ``"--start"``, ...), or ``""``.
    """

    def __init__(self, field: str, value: Any, reason: str, *, source: str = "") -> None:
        self.field = field
        self.value = value
        self.reason = reason
        self.source = source
        where = f"{printable(source)}: " if source else ""
        super().__init__(f"{where}{printable(field)} = {printable(abridge(value))}: "
                         f"{printable(reason)}")


class SceneError(InputError):
    """A scene file is invalid (unknown key, missing field, wrong type, bad value)."""


class MapError(InputError):
    """A ROS ``map_server`` map (its YAML or its image) cannot be imported as a scene."""


class PlanFileError(InputError):
    """A ``pivot-plan/1`` file is malformed (not a validity verdict: see ``PlanCheckReport``)."""


class UnreachableError(PivotError):
    """Two poses cannot be joined by three bounded pivot rotations.

    Attributes:
        start: car pose (x, y, heading) the rotations start from.
        goal: car pose to reach.
        alpha_max: bound on each rotation (rad).
    """

    def __init__(self, start: tuple[float, float, float], goal: tuple[float, float, float],
                 alpha_max: float) -> None:
        self.start = start
        self.goal = goal
        self.alpha_max = alpha_max
        super().__init__(
            f"goal {goal} not reachable from {start} by three rotations of at most "
            f"{alpha_max:.6g} rad")


class Interrupted(PivotError):
    """A computation was stopped by its termination condition (a planner's time limit).

    Attributes:
        what: what was stopped.
    """

    def __init__(self, what: str) -> None:
        self.what = what
        super().__init__(f"{what}: stopped by the termination condition")


class SteeringError(PivotError):
    """The Reeds-Shepp-to-pivot conversion did not converge (a piece shorter than the minimum).

    Attributes:
        start, goal: the car poses of the path being converted.
        reason: what failed.
    """

    def __init__(self, start: Any, goal: Any, reason: str) -> None:
        self.start = start
        self.goal = goal
        self.reason = reason
        super().__init__(f"steering {start} -> {goal}: {reason}")


class PlanningError(PivotError):
    """Planning could not start (invalid start or goal, bad planner parameters).

    Attributes:
        status: the OMPL status name (``"INVALID_START"``, ``"INVALID_GOAL"``, ...).
        reason: a human-readable explanation.
    """

    def __init__(self, status: str, reason: str) -> None:
        self.status = status
        self.reason = reason
        super().__init__(f"{status}: {reason}")


class WholeBodyError(PivotError):
    """Whole-body motion generation failed at a given plan step.

    Attributes:
        phase: index of the plan phase.
        step: index of the step inside the phase (-1 for the whole phase).
        reason: what failed (infeasible QP, unreachable grip...).
    """

    def __init__(self, phase: int, step: int, reason: str) -> None:
        self.phase = phase
        self.step = step
        self.reason = reason
        super().__init__(f"phase {phase}, step {step}: {reason}")
