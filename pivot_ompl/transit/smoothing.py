"""A lattice walk shortened: certified straight motions and forward Dubins walks, when cheaper.

Greedy shortcuts from each pose to the farthest later pose they reach (the far end first,
then ends at halving distances): a straight motion (any direction, linear yaw) if it costs
less than the stretch it replaces and is certified free, else a forward walk along a Dubins
curve (OMPL's, turning radius ``step_forward / step_turn``). A Dubins shortcut is refused
cheaply when it can be: its cost bounded from its length
(:func:`~pivot_ompl.transit.lattice.forward_chain_cost_bound`), then its poses at 1/2, 1/4
and 3/4 of the way (a blocked curve nearly always is at one of them), before it is sampled
whole and costed (:func:`~pivot_ompl.transit.lattice.chain_cost`). Two passes share what
they learn (:class:`SmoothMemo`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from pivot_ompl.errors import Interrupted
from pivot_ompl.pivoting.dubins import Dubins
from pivot_ompl.scene import WalkParameters
from pivot_ompl.se2 import Pose
from pivot_ompl.transit.clearance import WalkClearance
from pivot_ompl.transit.lattice import chain_cost, forward_chain_cost_bound, motion_cost

#: Certified shortcut attempts per smoothing pass.
MAX_SHORTCUT_CHECKS = 400


@dataclass
class SmoothMemo:
    """What the smoothing passes over one walk learn, shared between them.

    Attributes:
        clearances: the two clearance parts of each pose met
            (:meth:`~pivot_ompl.transit.clearance.WalkClearance.exact_parts`).
        segments: straight motions (linear yaw) certified free or refused.
        curves: Dubins walks sampled: their poses (ends included) and cost; ``None``: blocked.
    """

    clearances: dict[Pose, tuple[float, float]] = field(default_factory=dict)
    segments: dict[tuple[Pose, Pose], bool] = field(default_factory=dict)
    curves: dict[tuple[Pose, Pose], tuple[np.ndarray, float] | None] = field(
        default_factory=dict)


class WalkSmoother:
    """Shortens walks (see the module docstring).

    Args:
        clearance: the walking robot's clearances and certified motions.
        walk: step limits and walking costs.
        resolution: spacing (m) of the poses sampled along a Dubins walk.
    """

    def __init__(self, clearance: WalkClearance, walk: WalkParameters, *,
                 resolution: float) -> None:
        """A smoother with these parts."""
        self.clearance, self.walk, self.resolution = clearance, walk, resolution
        self.dubins = Dubins(turning_radius=walk.turning_radius)

    def dubins_walk(self, a: Pose, b: Pose, length: float) -> np.ndarray:
        """Poses every ~``resolution`` along the Dubins curve ``a -> b`` (``length`` long).

        Ends included, as an ``(n, 3)`` array; yaws continuous from ``a``'s.
        """
        n = max(1, math.ceil(length / self.resolution))
        pts = np.array([a, *self.dubins.sample(a, b, [k / n for k in range(1, n)]), b])
        pts[1:-1, 2] = a[2] + (pts[1:-1, 2] - a[2] + math.pi) % (2.0 * math.pi) - math.pi
        return pts

    def dubins_probes(self, a: Pose, b: Pose, pieces: int) -> list[Pose]:
        """The poses of :meth:`dubins_walk` (``pieces`` pieces) at 1/2, 1/4 and 3/4 of the way.

        In that order; the same poses, to the bit (their clearances are shared).
        """
        ks = dict.fromkeys(k for k in (pieces // 2, pieces // 4, 3 * pieces // 4)
                           if 0 < k < pieces)
        out = []
        for k in ks:
            x, y, yaw = self.dubins.interpolate(a, b, k / pieces)
            out.append((x, y, a[2] + (yaw - a[2] + math.pi) % (2.0 * math.pi) - math.pi))
        return out

    def smooth(self, poses: list[Pose], obj: Pose, *, memo: SmoothMemo | None = None,
               should_stop: Callable[[], bool] | None = None) -> list[Pose]:
        """One greedy pass of shortcuts over ``poses`` with the box resting at ``obj``.

        ``memo``: what an earlier pass over the same walk learnt, reused and completed.

        Raises:
            Interrupted: ``should_stop()`` became true (polled before each shortcut).
        """
        walk = self.walk
        memo = SmoothMemo() if memo is None else memo
        costs = [motion_cost(a, b, walk) for a, b in zip(poses, poses[1:], strict=False)]
        prefix = [0.0]
        for c in costs:
            prefix.append(prefix[-1] + c)
        out = [poses[0]]
        checks = 0
        i, n = 0, len(poses)
        while i < n - 1:
            nxt, piece = i + 1, []
            # the far end first, then ends at halving distances: long shortcuts are tried
            # without spending the budget on every pose of a long walk
            ends = sorted({min(n - 1, i + step) for step in (n, 64, 32, 16, 8, 4, 2)},
                          reverse=True)
            for j in ends:
                if j <= i + 1:
                    continue
                if checks >= MAX_SHORTCUT_CHECKS:
                    break
                if should_stop is not None and should_stop():
                    raise Interrupted("walk smoothing")
                found, tried = self._shortcut(poses[i], poses[j], prefix[j] - prefix[i], obj,
                                              memo)
                checks += tried
                if found is not None:
                    nxt, piece = j, found
                    break
            out.extend(piece)
            out.append(poses[nxt])
            i = nxt
        return out

    def _shortcut(self, a: Pose, b: Pose, old: float, obj: Pose, memo: SmoothMemo
                  ) -> tuple[list[Pose] | None, int]:
        """The poses between ``a`` and ``b`` of a free shortcut cheaper than ``old``.

        ``[]`` for a straight motion, the Dubins walk's inner poses, or ``None``; and the
        number of certified attempts made (0 to 2).
        """
        walk, tried = self.walk, 0
        if motion_cost(a, b, walk) < old - 1e-9:
            tried += 1
            if self._chain_free([a, b], obj, memo):
                return [], tried
        curve = self._curve(a, b, old, obj, memo)
        if curve is None:
            return None, tried
        pts, dc = curve
        if dc < old - 1e-9:
            tried += 1
            mids: list[Pose] = [(x, y, t) for x, y, t in pts[1:-1].tolist()]
            if self._chain_free([a, *mids, b], obj, memo):
                return mids, tried
        return None, tried

    def _curve(self, a: Pose, b: Pose, old: float, obj: Pose, memo: SmoothMemo
               ) -> tuple[np.ndarray, float] | None:
        """The Dubins walk ``a -> b`` sampled and costed, or ``None`` (refused or blocked)."""
        if (a, b) in memo.curves:
            return memo.curves[(a, b)]
        length = self.dubins.distance(a, b)
        pieces = max(1, math.ceil(length / self.resolution))
        if length >= old - 1e-9 or forward_chain_cost_bound(
                length, pieces, b[2] - a[2], self.walk.turning_radius, self.walk) >= old - 1e-9:
            return None  # too costly whatever the obstacles: not remembered
        curve = None
        if all(min(self._clear(p, obj, memo)) > 0.0 for p in self.dubins_probes(a, b, pieces)):
            pts = self.dubins_walk(a, b, length)
            curve = (pts, chain_cost(pts, self.walk))
        memo.curves[(a, b)] = curve
        return curve

    def _clear(self, p: Pose, obj: Pose, memo: SmoothMemo) -> tuple[float, float]:
        """Each pose's clearances, queried once."""
        d = memo.clearances.get(p)
        if d is None:
            d = memo.clearances[p] = self.clearance.exact_parts(p, obj)
        return d

    def _chain_free(self, chain: list[Pose], obj: Pose, memo: SmoothMemo) -> bool:
        cp = self._clear(chain[0], obj, memo)
        for p, q in zip(chain, chain[1:], strict=False):
            cq = self._clear(q, obj, memo)
            if min(cq) <= 0.0:
                return False
            ok = memo.segments.get((p, q))
            if ok is None:
                ok = memo.segments[(p, q)] = self.clearance.free_between(p, q, obj, cp, cq)
            if not ok:
                return False
            cp = cq
        return True
