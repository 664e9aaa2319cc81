"""A walk's CoM trajectory planned in overlapping windows of supports (receding horizon).

PlaCo's pattern generator plans a walk's LIPM trajectory as one dense QP over all of its
timesteps, so its cost grows with the cube of the walk's length (a 25-step pivot walk, about
430 timesteps: 0.15 s, and the demo has 37 such walks). A
:class:`WindowedWalk` plans the first ``window`` supports, keeps the first ``commit`` of
them, and plans the next window from that trajectory's CoM position, velocity and
acceleration at the start of the first support not kept (PlaCo's ``replan``), until the
window reaches the walk's last support. Each piece switches to the next at the start of a
double support, so no swing spans two pieces, and the supports' times are those of the
one-piece plan: the walk's timeline is unchanged. The ZMP preview of every kept support is
at least ``window - commit`` supports long (``commit`` ≤ ``window / 2``: several seconds,
against the LIPM's time constant of about 0.3 s for HRP-2), so the CoM differs from the
one-piece plan's by a fraction of a millimetre (``tests/wholebody/test_walk_windows.py``).
Should a window's QP fail, the walk is planned in one QP, as without windows.
"""

from __future__ import annotations

import bisect
import logging
from typing import Any

import numpy as np

from pivot_ompl.errors import InputError, PivotError

log = logging.getLogger(__name__)

#: Supports planned in one QP and supports kept of each. A walk's supports alternate
#: double (even indices) and single (odd): a window starts and ends with a double support
#: (an odd count), 9 supports being 4 steps, about 3.5 s at HRP-2's step timing; each kept
#: support has at least 5 supports of preview, 2 steps and 3 double supports (1.8 s, six
#: times the LIPM's time constant). The smallest window is the cheapest: a window's QP
#: costs the cube of its length, and there are ``1 / commit`` as many.
WINDOW = 9
COMMIT = 4


class WindowedWalk:
    """The pieces of one walk's trajectory and the times they take over.

    Args:
        wpg: PlaCo's ``WalkPatternGenerator``.
        supports: the walk's supports (``FootstepsPlanner.make_supports``).
        com: initial CoM position (world, 3).
        t0: the walk's start time (s).
        window: supports planned in one QP (odd: it ends with a double support; ≥ 9:
            with less preview, a window's CoM can leave no feasible QP after it).
        commit: supports kept of each window before the next (even, from 2 to
            ``window / 2``: the next window starts with a double support).

    Raises:
        InputError: ``window`` or ``commit`` out of range.
    """

    def __init__(self, wpg: Any, supports: list, com: np.ndarray, t0: float, *,
                 window: int = WINDOW, commit: int = COMMIT) -> None:
        if window < 9 or window % 2 == 0:
            raise InputError("window", window, "an odd number of supports, at least 9")
        if commit < 2 or commit % 2 or 2 * commit > window:
            raise InputError("commit", commit, f"an even number from 2 to {window // 2}")
        self.pieces: list[Any] = []
        self.switches: list[float] = []  # piece k + 1 takes over at switches[k]
        self._kept: list[list] = []  # the supports each piece keeps
        try:
            self._plan_windows(wpg, supports, com, t0, window, commit)
        except _WindowFailed as e:  # what the one QP plans, at its cost
            log.debug("%s: the walk of %d supports in one QP", e, len(supports))
            self.pieces, self.switches = [wpg.plan(supports, com, t0)], []
            self._kept = [self.pieces[0].get_supports()]
        self.t_start: float = self.pieces[0].t_start
        self.t_end: float = self.pieces[-1].t_end
        if len(self.pieces) > 1:
            log.debug("walk of %d supports planned in %d windows", len(supports),
                      len(self.pieces))

    def _plan_windows(self, wpg: Any, supports: list, com: np.ndarray, t0: float,
                      window: int, commit: int) -> None:
        first = supports[:window] if len(supports) > window else supports
        self.pieces = [wpg.plan(first, com, t0)]
        start, end = 0, len(first)  # the last piece's supports: start, ..., end - 1
        while end < len(supports):
            prev = self.pieces[-1]
            planned = prev.get_supports()
            t_switch = planned[commit].t_start
            self._kept.append(planned[:commit])
            start += commit
            part = supports[start:start + window]
            piece = wpg.replan(part, prev, t_switch)
            if len(piece.get_supports()) != len(part):  # PlaCo's answer to a failed QP: the
                raise _WindowFailed(f"supports {start}-{start + len(part) - 1}")  # old rest
            self.pieces.append(piece)
            self.switches.append(t_switch)
            end = start + len(part)
        self._kept.append(self.pieces[-1].get_supports())

    def at(self, t: float) -> Any:
        """The PlaCo trajectory in force at time ``t``."""
        return self.pieces[bisect.bisect_right(self.switches, t)]

    def get_supports(self) -> list:
        """The walk's supports as planned (their ``t_start`` set), in order."""
        return [s for kept in self._kept for s in kept]

    def get_T_world_left(self, t: float) -> Any:
        """Left sole frame at ``t``."""
        return self.at(t).get_T_world_left(t)

    def get_T_world_right(self, t: float) -> Any:
        """Right sole frame at ``t``."""
        return self.at(t).get_T_world_right(t)

    def get_p_world_CoM(self, t: float) -> Any:
        """CoM position at ``t``."""
        return self.at(t).get_p_world_CoM(t)


class _WindowFailed(PivotError):
    """A window's QP failed (the walk is then planned in one)."""
