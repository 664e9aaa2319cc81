"""The raster regrasp bound refined where its best path cheats: counterexample-guided windows.

The coarse raster relaxation (:mod:`~pivot_ompl.analysis.raster_bound`) may join start and goal
with fewer regrasps than any plan needs, through places its cells and yaw bins make look wider
than they are. :func:`guided_lower_bound` asks the relaxation for its *counterexample* (a path of
fewest regrasps through its graph, :func:`~pivot_ompl.analysis.guided_paths.best_path`), refines
a window round the places where that path passes narrow parts of a layer (:func:`path_window`),
reads the relaxation again on
the mixed cover (:func:`~pivot_ompl.analysis.refined_bound.refined_graph`: fine voxels inside
the window, coarse pieces outside), and repeats while the path still needs fewer regrasps than
``target``, a round adds cells to the window, and the budget lasts (:data:`MAX_ROUNDS`
rounds, :data:`PATIENCE` rounds in a row without a rise, :data:`FIRST_PATIENCE` before the
first, :data:`MAX_WINDOW` cells: counts,
not clocks, so that a result is the same on any load and may be kept by the bound cache;
``should_stop`` ends it sooner, its rounds done standing; a ``hint``, below, makes the windows
depend on when its words come, its result a proof all the same).

**Soundness.** Every round's count is the fewest regrasps on the mixed graph of *some* window,
and :mod:`~pivot_ompl.analysis.refined_bound` proves that every plan's path is a path of that
graph whatever the window (a coarse cell's claim outside, the fine voxels' claim inside, the
joins at the window's edge): so each round's count is a lower bound of every plan's regrasps,
and so is their maximum, the result. The window only grows (each round only refines), and how
it is chosen is a matter of cost, never of soundness. "No plan" is said only when a round's
graph joins no path at all (the same proof as the coarse relaxation's).

**Where the path cheats.** The path is a sequence of nodes: coarse pieces of a ``(bin,
grasp)`` layer and fine components. A coarse piece it passes is refined

* whole, when it is small (at most :data:`SMALL` cells: a place where the held box turns
  within a few cells, which the finer bins often close);
* else in its *thin parts* on the way through: the piece's cells outside its opening by
  :data:`THIN` cells (necks at most about ``2 THIN`` cells wide) that lie on a fewest-step
  chain of its thick and thin parts from the cells where the path enters the piece to those
  where it leaves (shared with the path's previous and next pieces, the start's or goal's
  cell, or the window's edge);

and a transfer between two coarse pieces sharing at most :data:`SMALL` cells (a turn neck) has
those cells refined. The whole is grown by :data:`GROW` cells. When that adds nothing new,
every thin part of the path's large pieces is taken, then those of a wider opening
(:data:`ESCALATION`).

**A plan's places.** Inside ``plan`` the bound judges a plan, and a plan regrasps where it
must: its regrasp places (``places``) are where the relaxation's paths are likely to cheat.
The cells within :data:`PLACE_RADIUS` of them join the first refined window
(:func:`place_window`), while the window stays within :data:`MAX_WINDOW` cells: on the Willow
Garage office its 2 comes in two refined rounds instead of five (about 40 % of the
refinement's CPU). Like any window choice this is cost only. Beside the search (a plan's
prover) the plan is not made yet: a ``hint``, asked every round, gives what the search
expects so far (its coarse plan's regrasps and places, then the plan's), its places joining
the next window and its count aimed at where no ``target`` is given. Where the search has
told nothing yet when the coarse round ends, the refinement waits for its word up to
:data:`HINT_WAIT` seconds (the search tells it within a second or two of its start, once its
regrasp-free tries have ended; a round refined without the places is seconds of work that
the places would mostly make needless).
"""

from __future__ import annotations

import logging
import math
import time
from collections import deque
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from pivot_ompl.analysis.guided_paths import best_path
from pivot_ompl.analysis.piece_graph import Regrasp
from pivot_ompl.analysis.raster_bound import CELL, RasterGraph, raster_graph
from pivot_ompl.analysis.raster_cover import RasterCover, raster_cover
from pivot_ompl.analysis.refined_bound import refined_graph
from pivot_ompl.analysis.regrasp_bound import RegraspBound
from pivot_ompl.analysis.regrasp_walk import WalkRelaxation
from pivot_ompl.errors import Interrupted
from pivot_ompl.scene import Scene
from pivot_ompl.se2 import Pose
from pivot_ompl.validity.certify import SWEEP_TOLERANCE
from pivot_ompl.validity.collision import KEEP_CLEARANCE

log = logging.getLogger(__name__)

#: A coarse piece (or two pieces' shared cells) of at most this many cells is refined whole.
SMALL = 400
#: Opening radius (cells) below which a part of a large piece is thin.
THIN = 2
#: Cells the path's places are grown by to make the window.
GROW = 2
#: ``(thin, chain)`` of :func:`path_window`, tried in turn until one adds cells.
ESCALATION = ((THIN, True), (THIN, False), (THIN + 1, False))
#: Rounds at most (the first reads the coarse graph alone).
MAX_ROUNDS = 8
#: Rounds in a row without the count rising after which the refinement stops (the Willow
#: Garage office rises from 1 to 2 on the fourth such round).
PATIENCE = 4
#: The same before any rise above the coarse count (where the coarse raster already has the
#: relaxation's answer, as on the corridor buildings, rounds cost without changing it).
FIRST_PATIENCE = 3
#: Radius (m) round a plan's regrasp places refined from the first refined round on (the
#: Willow Garage office's 2 in two refined rounds instead of five: the plan regrasps where
#: the relaxation's paths cheat).
PLACE_RADIUS = 1.0
#: Coarse cells at most in the window (past it the refinement stops: cost only; the Willow
#: Garage office's 2 needs about 4500).
MAX_WINDOW = 6_000

_EIGHT = np.ones((3, 3), dtype=bool)

#: What a search expects so far: a plan's regrasps (``None``: unknown) and where (m);
#: ``None``: it has told nothing yet.
Hint = Callable[[], tuple[int | None, tuple[tuple[float, float], ...]] | None]
#: Seconds the refinement waits after its coarse round for a ``hint`` that has told nothing
#: yet (cost only).
HINT_WAIT = 2.0
#: Seconds between two looks at a ``hint`` while waiting.
HINT_POLL = 0.05


@dataclass
class GuidedRound:
    """One round of the refinement.

    Attributes:
        regrasps: fewest regrasps on this round's graph (``None``: it joins no path).
        window: coarse cells refined in this round.
        path: nodes on the round's best path.
        seconds: the round's time (graph and path).
    """

    regrasps: int | None
    window: int
    path: int
    seconds: float


def _node_cells(joined: RasterGraph, cover: RasterCover, u: int,
                keys: list[tuple[tuple[int, int], int]], firsts: np.ndarray
                ) -> tuple[np.ndarray, int] | None:
    """The labels of coarse node ``u``'s layer and its label (``None`` for a fine node)."""
    if u >= joined.total:
        return None
    (b, k), first = keys[int(np.searchsorted(firsts, u, side="right")) - 1]
    return cover.layers[joined.layer(b, k)][0], u - first + 1


def _cell_of(cover: RasterCover, pose: Pose) -> np.ndarray:
    """A mask of the coarse cell holding ``pose``'s position."""
    out = np.zeros(cover.raster.shape, dtype=bool)
    out[cover.raster.index(pose[0], pose[1])] = True
    return out


def thin_crossing(piece: np.ndarray, enter: np.ndarray, leave: np.ndarray, *,
                  thin: int = THIN) -> np.ndarray:
    """The thin parts of ``piece`` on a fewest-step chain from ``enter`` to ``leave``.

    ``piece``, ``enter``, ``leave``: boolean masks of one block of cells. Thin: the cells
    outside the piece's opening by ``thin`` cells. The chain alternates the thick and
    thin parts (8-connected components) that touch; when ``enter`` or ``leave`` is empty, or
    no chain joins them, every thin part of the piece is returned.
    """
    thick = ndimage.binary_opening(piece, structure=_EIGHT, iterations=thin) & piece
    narrow = piece & ~thick
    if not narrow.any():
        return narrow
    a, na = ndimage.label(thick, structure=_EIGHT)
    t, _ = ndimage.label(narrow, structure=_EIGHT)
    parts = np.where(thick, a, np.where(narrow, t + na, 0))
    if not (enter & piece).any() or not (leave & piece).any():
        return narrow
    pairs: set[tuple[int, int]] = set()
    nx, ny = parts.shape
    for di, dj in ((1, 0), (0, 1), (1, 1), (1, -1)):
        p = parts[max(0, -di):nx - max(0, di), max(0, -dj):ny - max(0, dj)]
        q = parts[max(0, di):, max(0, dj):][:p.shape[0], :p.shape[1]]
        both = (p > 0) & (q > 0) & (p != q)
        pairs.update(zip(p[both].tolist(), q[both].tolist(), strict=True))
    near: dict[int, list[int]] = {}
    for x, y in pairs:
        near.setdefault(x, []).append(y)
        near.setdefault(y, []).append(x)
    goal = set(np.unique(parts[leave & piece]).tolist()) - {0}
    prev = {s: -1 for s in set(np.unique(parts[enter & piece]).tolist()) - {0}}
    queue = deque(prev)
    while queue:
        x = queue.popleft()
        if x in goal:
            chain = []
            while x >= 0:
                chain.append(x)
                x = prev[x]
            wanted = np.array([c for c in chain if c > na], dtype=parts.dtype)
            return np.isin(parts, wanted) if len(wanted) else np.zeros_like(narrow)
        for y in near.get(x, []):
            if y not in prev:
                prev[y] = x
                queue.append(y)
    return narrow


def path_window(scene: Scene, joined: RasterGraph, cover: RasterCover, path: list[int],
                window: np.ndarray, *, thin: int = THIN, chain: bool = True) -> np.ndarray:
    """The coarse cells round the places where ``path`` passes narrow parts (module docstring).

    ``joined``, ``cover``: the round's coarse graph and cover (the coarse cells off
    ``window``, the cells refined so far). ``thin``: the opening radius (cells) of the thin
    parts; ``chain`` ``False``: every thin part of a large piece on the path, not only those
    on its way through. Returns the cells to add (none of ``window``).
    """
    keys = sorted(joined.base.items(), key=lambda kv: kv[1])
    firsts = np.array([v for _, v in keys], dtype=np.int64)
    nodes = [_node_cells(joined, cover, u, keys, firsts) for u in path]
    edge = ndimage.binary_dilation(window, structure=_EIGHT) & ~window
    add = np.zeros(cover.raster.shape, dtype=bool)
    for i, node in enumerate(nodes):
        if node is None:
            continue
        lab, c = node
        box = cover.extent(_layer_of(joined, path[i], keys, firsts), c)
        piece = lab[box] == c
        if piece.sum() <= SMALL:
            add[box] |= piece
        else:
            enter = _side(scene, cover, nodes, i, -1, box, edge, scene.start)
            leave = _side(scene, cover, nodes, i, 1, box, edge, scene.goal)
            if not chain:
                enter = leave = np.zeros_like(piece)
            add[box] |= thin_crossing(piece, enter, leave, thin=thin)
        if i + 1 < len(nodes) and nodes[i + 1] is not None:
            lab2, c2 = nodes[i + 1]  # type: ignore[misc]
            shared = piece & (lab2[box] == c2)
            if 0 < shared.sum() <= SMALL:
                add[box] |= shared
    if GROW and add.any():
        add = ndimage.binary_dilation(add, structure=_EIGHT, iterations=GROW)
    return add & ~window


def _layer_of(joined: RasterGraph, u: int, keys: list[tuple[tuple[int, int], int]],
              firsts: np.ndarray) -> tuple[int, int]:
    (b, k), _ = keys[int(np.searchsorted(firsts, u, side="right")) - 1]
    return joined.layer(b, k)


def _side(scene: Scene, cover: RasterCover, nodes: list, i: int, step: int,
          box: tuple[slice, slice], edge: np.ndarray, end: Pose) -> np.ndarray:
    """Where the path enters (``step`` -1) or leaves (+1) node ``i``'s piece, in ``box``."""
    j = i + step
    if 0 <= j < len(nodes):
        if nodes[j] is None:
            return edge[box]
        lab, c = nodes[j]
        return lab[box] == c
    return _cell_of(cover, end)[box]


def guided_lower_bound(scene: Scene, *, cover: RasterCover | None = None,
                       target: int | None = None, rounds: int = MAX_ROUNDS,
                       patience: int = PATIENCE, max_window: int = MAX_WINDOW,
                       tolerance: float = SWEEP_TOLERANCE, clearance: float = KEEP_CLEARANCE,
                       walks: bool = True, coarse: RasterGraph | None = None,
                       should_stop: Callable[[], bool] | None = None,
                       trace: list[GuidedRound] | None = None,
                       places: tuple[tuple[float, float], ...] = (),
                       hint: Hint | None = None) -> RegraspBound | None:
    """The fewest regrasps on the relaxation refined where its best path cheats.

    Args:
        scene: the scene (in the frame its cover was built in).
        cover: the scene's coarse :func:`~pivot_ompl.analysis.raster_cover.raster_cover`
            (the same tolerance and clearance; built at :data:`~pivot_ompl.analysis.
            raster_bound.CELL` when ``None``).
        target: stop once the count reaches it (the regrasps of a plan to judge).
        rounds: rounds at most (the first reads the coarse graph alone).
        patience: rounds in a row without the count rising after which it stops
            (:data:`FIRST_PATIENCE` at most before its first rise).
        max_window: coarse cells at most in the window.
        tolerance: the swept checks' tolerance (m; the cover's).
        clearance: distance (m) the checkers keep every body from the obstacles (the
            cover's).
        walks: allow a regrasp only where the walk relaxation may get round the box.
        coarse: the cover's graph when already built (the first round's, then let go:
            freed if the caller keeps no other reference; its walk relaxation serves
            every round).
        should_stop: polled in every round; stopped, the rounds done stand.
        trace: appended one :class:`GuidedRound` per round when given.
        places: positions (m, in ``scene``'s frame) where a plan regrasps: the cells within
            :data:`PLACE_RADIUS` of them join the first refined window (:func:`place_window`;
            cost only: any window gives a lower bound).
        hint: asked every round (module docstring): places not seen before join the next
            window as ``places`` do, and its count is aimed at when ``target`` is ``None``.

    Returns:
        A :class:`~pivot_ompl.analysis.regrasp_bound.RegraspBound` (``exhaustive`` False, no
        route: the coarse relaxation's route stands; ``complete`` and ``guided`` False when
        stopped: the rounds done stand), or ``None`` when stopped before the first round
        ended.
    """
    t0 = time.perf_counter()
    if cover is None:
        cover = raster_cover(scene, cell=CELL, tolerance=tolerance, clearance=clearance,
                             should_stop=should_stop)
        if cover is None:
            return None
    if should_stop is not None and should_stop():
        return None
    window = np.zeros(cover.raster.shape, dtype=bool)
    placed = place_window(cover, places)
    seen = set(places)
    walk = None if not walks else coarse.walk() if coarse is not None else WalkRelaxation(
        scene, width=2.0 * math.pi / cover.bins, tolerance=tolerance, clearance=clearance)
    memo: dict = {}
    best: int | None = None
    first: int | None = None  # the coarse graph's count
    pieces, stopped, stale = 0, False, 0
    for _ in range(max(1, rounds)):
        t1 = time.perf_counter()
        try:
            count, length, total, add = _round(scene, cover, window, walk, memo, tolerance,
                                               clearance, walks, should_stop, coarse)
            coarse = None  # later rounds read their mixed graphs: this one may be freed
        except Interrupted:
            stopped = True
            break
        if trace is not None:
            trace.append(GuidedRound(count, int(window.sum()), length,
                                     time.perf_counter() - t1))
        pieces = max(pieces, total)
        if count is None:
            return RegraspBound(None, False, cover.bins, pieces, time.perf_counter() - t0,
                                None, True, exhaustive=False, guided=True)
        stale = 0 if best is None or count > best else stale + 1
        best = count if best is None else max(best, count)
        first = count if first is None else first
        aim, told = (target, ()) if hint is None else _told(hint, not window.any(), should_stop)
        aim = target if target is not None else aim
        if (aim is not None and best >= aim) or stale >= patience or (
                best == first and stale >= min(patience, FIRST_PATIENCE)):
            break
        if new := tuple(p for p in told if p not in seen):
            seen.update(new)
            placed |= place_window(cover, new)
        if placed.any():  # the plan's places, once, while the window stays in its budget
            if (window | add | placed).sum() <= max_window:
                add = add | placed
            placed = np.zeros_like(window)
        if not add.any() or window.sum() + add.sum() > max_window:
            break
        window |= add
    if best is None:
        return None
    log.debug("guided regrasp bound %d: window of %d cells, %.2f s", best, int(window.sum()),
              time.perf_counter() - t0)
    return RegraspBound(best, True, cover.bins, pieces, time.perf_counter() - t0, None,
                        complete=not stopped, exhaustive=False, guided=not stopped)


def _told(hint: Hint, coarse: bool, should_stop: Callable[[], bool] | None
          ) -> tuple[int | None, tuple[tuple[float, float], ...]]:
    """What ``hint`` tells now (``(None, ())``: nothing).

    After the coarse round (``coarse``) it is waited for up to :data:`HINT_WAIT` s if it has
    told nothing yet.
    """
    said = hint()
    end = time.monotonic() + (HINT_WAIT if coarse else 0.0)
    while said is None and time.monotonic() < end and not (should_stop and should_stop()):
        time.sleep(HINT_POLL)
        said = hint()
    return said if said is not None else (None, ())


def place_window(cover: RasterCover, places: tuple[tuple[float, float], ...], *,
                 radius: float = PLACE_RADIUS) -> np.ndarray:
    """The coarse cells whose centres lie within ``radius`` (m) of one of ``places``.

    Each place's cells are found in the block round it only (no floor-sized temporary).
    """
    r = cover.raster
    window = np.zeros(r.shape, dtype=bool)
    for x, y in places:
        i0, j0 = r.index(x - radius, y - radius)
        i1, j1 = r.index(x + radius, y + radius)
        box = (slice(i0, i1 + 1), slice(j0, j1 + 1))
        window[box] |= np.hypot(r.gx[box] - x, r.gy[box] - y) <= radius
    return window


def _round(scene: Scene, cover: RasterCover, window: np.ndarray,
           walk: WalkRelaxation | None, memo: dict, tolerance: float, clearance: float,
           walks: bool, should_stop: Callable[[], bool] | None,
           coarse: RasterGraph | None) -> tuple[int | None, int, int, np.ndarray]:
    """One round: ``(count, path nodes, graph nodes, cells to add)`` (its graph then freed).

    Raises:
        Interrupted: ``should_stop`` said stop.
    """
    holding: Callable[[Pose], list[int]]
    allowed: Callable[[Regrasp], bool]
    if window.any():
        mixed = refined_graph(scene, cover, tolerance=tolerance, clearance=clearance,
                              walks=walks, window=window, should_stop=should_stop,
                              relaxation=walk, memo=memo)
        assert mixed is not None
        joined, outside = mixed.coarse, mixed.cover
        holding, allowed = mixed.holding, mixed.allowed
        total = mixed.fine_base[3] + mixed.fine.count[1]
    else:
        joined = coarse if coarse is not None else raster_graph(
            scene, cover, tolerance=tolerance, clearance=clearance, walks=walks,
            should_stop=should_stop, relaxation=walk)
        outside, holding, allowed, total = cover, joined.holding, joined.allowed, joined.total
    count, path = best_path(joined.graph, holding(scene.start), set(holding(scene.goal)),
                            allowed, should_stop)
    add = np.zeros_like(window)
    if count is not None:
        for thin, chain in ESCALATION:  # wider nets only when the narrower adds nothing
            add = path_window(scene, joined, outside, path, window, thin=thin, chain=chain)
            if add.any():
                break
    return count, len(path), total, add
