"""The regrasp bound's graph of free pieces: the fewest regrasps between them, level by level.

Used by :func:`~pivot_ompl.analysis.regrasp_bound.regrasp_lower_bound`: its nodes are the
free pieces of the yaw bins, joined by transfers (free) and regrasps (cost 1, each checked
only when it could reach a piece not reached yet).
"""

from __future__ import annotations

from collections.abc import Callable

from pivot_ompl.errors import Interrupted

#: A regrasp edge as the bound names it (its bins, grasps and pieces).
Regrasp = tuple[int, int, int, int, int]


class PieceGraph:
    """Pieces joined by transfers (free) and regrasps (cost 1, checked lazily).

    Args:
        areas: each piece's area (m^2): the regrasps into the largest are checked first.
    """

    def __init__(self, areas: list[float]) -> None:
        """No joins yet."""
        self.areas = areas
        self.zero: list[list[int]] = [[] for _ in areas]
        self.one: list[list[tuple[int, Regrasp]]] = [
            [] for _ in areas]

    def add(self, u: int, v: int, regrasp: Regrasp | None) -> None:
        """Join pieces ``u`` and ``v``: by a transfer (``regrasp`` ``None``) or a regrasp."""
        if regrasp is None:
            self.zero[u].append(v)
            self.zero[v].append(u)
        else:
            self.one[u].append((v, regrasp))
            self.one[v].append((u, regrasp))

    def add_transfers(self, us: list[int], vs: list[int]) -> None:
        """:meth:`add` of the transfers ``(us[i], vs[i])``, in turn."""
        zero = self.zero
        for u, v in zip(us, vs, strict=True):
            zero[u].append(v)
            zero[v].append(u)

    def add_regrasps(self, us: list[int], vs: list[int], regrasps: list[Regrasp]) -> None:
        """:meth:`add` of the regrasps ``(us[i], vs[i], regrasps[i])``, in turn."""
        one = self.one
        for u, v, e in zip(us, vs, regrasps, strict=True):
            one[u].append((v, e))
            one[v].append((u, e))

    def fewest_regrasps(self, starts: list[int], goals: set[int],
                        allowed: Callable[[Regrasp], bool],
                        should_stop: Callable[[], bool] | None, *,
                        check_beyond: bool = True) -> tuple[int | None, set[int]]:
        """Fewest allowed regrasps from a start to a goal, and every piece reachable at all.

        Level by level: the pieces reachable with ``d`` regrasps are the free closure of the
        starts (``d = 0``) or of the regrasps out of level ``d - 1``. A regrasp is checked
        (``allowed``, the costly part) only when its far piece is not reached yet, the
        regrasps out of the largest pieces first (the cheapest to allow). ``should_stop``
        raises :class:`~pivot_ompl.errors.Interrupted`. ``check_beyond`` ``False``: once a
        goal is reached, later regrasps are taken as allowed unchecked (the reached set then
        holds more pieces: a route through them is still a lower bound, found sooner).
        """
        level: dict[int, int] = {}
        best: int | None = None
        frontier = list(starts)
        d = 0
        while frontier:
            grown = self._closure(frontier, d, level)
            if best is None and any(u in goals for u in grown):
                best = d
            pending = [(v, e) for u in grown for v, e in self.one[u] if v not in level]
            pending.sort(key=lambda ve: -self.areas[ve[0]])
            frontier = []
            for v, e in pending:
                if should_stop is not None and should_stop():
                    raise Interrupted("regrasp bound")
                if v in level:
                    continue
                if (best is not None and not check_beyond) or allowed(e):
                    frontier.extend(self._closure([v], d + 1, level))
            d += 1
        return best, set(level)

    def _closure(self, seeds: list[int], d: int, level: dict[int, int]) -> list[int]:
        """Mark every piece reachable from ``seeds`` by transfers with level ``d``."""
        out = []
        stack = [s for s in seeds if s not in level or level[s] == d]
        for s in stack:
            level[s] = d
        while stack:
            u = stack.pop()
            out.append(u)
            for v in self.zero[u]:
                if v not in level:
                    level[v] = d
                    stack.append(v)
        return out
