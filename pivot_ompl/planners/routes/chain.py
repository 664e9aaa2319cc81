"""A lattice route made real: the cheapest chain of certified transfers between its poses.

The transfer lattice (:mod:`.lattice`) routes the held assembly by pushes, pulls and turns in
place; its many short motions would each cost a pivot sequence of their own. :func:`corners`
keeps the route's poses worth joining, and :func:`shortened` joins them by the cheapest chain
of transfers that pass their checks (:class:`~pivot_ompl.planners.evaluation.Evaluator`).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from pivot_ompl.cost import CostModel
from pivot_ompl.planners.evaluation import Evaluator, Found, Status, lazy_search
from pivot_ompl.se2 import Pose, wrap_angle

Stop = Callable[[], bool]

#: :func:`shortened`'s answer when no chain along the route can cost less than its ceiling
#: (``INVALID``; tell it from "no chain at all" by identity: ``found is TOO_DEAR``)
TOO_DEAR: Found = Found(Status.INVALID)


def corners(route: list[Pose], *, spacing: int, end_turns: bool = False,
            leads: bool = False) -> list[Pose]:
    """The route's poses worth joining by transfers.

    Its ends, the poses where it starts or stops turning, and every ``spacing`` th pose of a
    long straight run (lattice motions;
    :attr:`~pivot_ompl.planners.config.OptimiserConfig.run_spacing`). ``end_turns``: also
    every pose of a turn in place the route starts or ends with (one transfer turning the
    whole way at a tight end may graze what the lattice's small turns pass); with ``leads``
    (a route asked with leads, :mod:`.lattice_ends`), also of the turn it makes right after
    (before) a first (last) straight motion, an end's lead.
    """
    if len(route) < 3:
        return route
    last = len(route) - 1

    def turning(k: int) -> bool:  # the motion from pose k to pose k + 1 turns
        return abs(route[k + 1][2] - route[k][2]) > 1e-9

    head = tail = 0
    if end_turns:
        if leads:  # after a first (last) straight motion: an end's lead
            head = int(last > 1 and not turning(0))
            tail = int(last > 1 and not turning(last - 1))
        while head < last and turning(head):
            head += 1
        while tail < last and turning(last - 1 - tail):
            tail += 1
    keep = [0]
    for k in range(1, last):
        if turning(k - 1) != turning(k) or k - keep[-1] >= spacing or k < head \
                or k > last - tail:
            keep.append(k)
    keep.append(last)
    return [route[k] for k in keep]


def end_rotations(costs: CostModel) -> float:
    """Seconds a transfer spends beyond its length at the push rate: one rotation's part.

    A transfer starts and ends with the supporting edge on its path, so its first and last
    rotations are part rotations (about half a full one each, see
    :mod:`~pivot_ompl.pivoting.steering`): it takes about one rotation more than its length
    at the push rate (:meth:`~pivot_ompl.cost.CostModel.push_rate`, full rotations).
    :func:`shortened` adds it to each transfer's estimate, so a chain of many short
    transfers is estimated dearer than one of few long ones, as checked it is (the
    hospital's one-grasp route of 64 poses: 188 transfers checked for a chain of 7 without
    it, 95 with it, the same chain).
    """
    return costs.durations.per_pivot


def made_real(evaluate: Evaluator, route: list[Pose], grasp: int, should_stop: Stop, *,
              spacing: int, ceiling: float = math.inf,
              cache: dict[tuple, tuple[list[Pose], float] | None] | None = None,
              leads: bool = False) -> Found[tuple[list[Pose], float]]:
    """The route's cheapest chain of certified transfers, its end turns split if need be.

    :func:`shortened` over the route's :func:`corners`, then again over them with every pose
    of the turns in place it starts or ends with (the first try's checks are cached: only
    the new transfers are checked), below the first chain's cost: the cheaper chain is
    kept. A turn in place joined as one transfer is a Reeds-Shepp manoeuvre that may cost
    much more than the turn (a 1.65 rad end turn: 120 s as one transfer, 78 s as five).
    A route whose first try is stopped is not tried again; one whose first try is
    :data:`TOO_DEAR` is answered by the second only with a chain.

    ``cache``: the answers found before, by route, grasp and spacing (e.g. the lattice's
    :attr:`~.lattice.TransferLattice.chains`; ``None`` for a route with no chain at all):
    a route made real once is answered from it, :data:`TOO_DEAR` where its chain does not
    cost less than ``ceiling`` (the lazy search with a ceiling returns the same chain
    whenever one below it exists). ``leads``: the route was asked with leads
    (:meth:`~.lattice.TransferLattice.route`; :func:`corners`).
    """
    key = (tuple(route), grasp, spacing, leads)
    if cache is not None and key in cache:
        hit = cache[key]
        if hit is None:
            return Found(Status.INVALID)
        return Found(Status.VALID, hit) if hit[1] < ceiling + 1e-6 else TOO_DEAR
    coarse = corners(route, spacing=spacing)
    tested: dict[tuple[Pose, Pose], bool] = {}  # the cheap tests, shared by both tries
    found = shortened(evaluate, coarse, grasp, should_stop, ceiling=ceiling, tested=tested)
    fine = corners(route, spacing=spacing, end_turns=True, leads=leads)
    if found.status is not Status.STOPPED and len(fine) > len(coarse):
        below = min(ceiling, found.path[1]) if found.path is not None else ceiling
        finer = shortened(evaluate, fine, grasp, should_stop, ceiling=below, tested=tested)
        if finer.path is not None or (found.path is None and found is not TOO_DEAR):
            found = finer
    if cache is not None and found is not TOO_DEAR and found.status is not Status.STOPPED:
        cache[key] = found.path  # a chain, or None: none at all
    return found


def shortened(evaluate: Evaluator, route: list[Pose], grasp: int,
              should_stop: Stop, *, ceiling: float = math.inf,
              tested: dict[tuple[Pose, Pose], bool] | None = None
              ) -> Found[tuple[list[Pose], float]]:
    """The cheapest chain of certified transfers along the route, with its cost (s).

    ``VALID`` with the chain, ``INVALID`` when there is none, ``STOPPED``. Candidate
    transfers join route pose ``i`` to ``i + 1, i + 2, i + 4, ...`` and to the end. Lazily
    (:func:`~pivot_ompl.planners.evaluation.lazy_search`): the cheapest chain by estimated
    costs (a transfer's reference path length at the push rate,
    :meth:`~pivot_ompl.cost.CostModel.transfer_estimate`, plus :func:`end_rotations`; a
    turn's :meth:`~pivot_ompl.cost.CostModel.spin_estimate`, until it is checked), its unchecked
    transfers checked (the cheap test of every one before the full check of any: a chain
    one of whose transfers crosses an obstacle costs no full check), again until every
    transfer of it is checked.
    ``should_stop`` is polled before every check. ``ceiling`` (s): :data:`TOO_DEAR` as
    soon as no chain can cost less (checked transfers at their cost, the others at the
    admissible :meth:`~pivot_ompl.cost.CostModel.transfer_bound`): a chain the caller would
    refuse for its cost is not checked to the end. ``tested``: the cheap tests' answers by
    pair of poses (at ``grasp``), read and filled: calls over routes sharing poses (the
    corners with and without their end turns) test each pair once.
    """
    checker, costs = evaluate.checker, evaluate.costs
    tested = {} if tested is None else tested

    def cheap_free(a: Pose, b: Pose) -> bool:
        free = tested.get((a, b))
        if free is None:
            free = tested[(a, b)] = checker.path_free(a, b, grasp)
        return free

    n = len(route)
    m, alpha = checker.model, checker.scene.alpha_max
    ell = m.edge_half_length(grasp)
    cars = [m.car_pose(q, grasp) for q in route]
    paths = checker.steering.paths
    ends = {i: sorted({min(n - 1, i + (1 << k)) for k in range(n.bit_length() + 1)} - {i})
            for i in range(n - 1)}
    extra = end_rotations(costs)
    checked: dict[tuple[int, int], float] = {}
    estimates: dict[tuple[int, int], float] = {}  # each search round asks them all again

    def estimate(i: int, j: int) -> float:
        e = estimates.get((i, j))
        if e is None:
            a, b = cars[i], cars[j]
            e = estimates[(i, j)] = costs.spin_estimate(wrap_angle(b[2] - a[2]), alpha) \
                if paths.is_spin(a, b) else costs.transfer_estimate(paths.distance(a, b), ell,
                                                                    alpha) + extra
        return e

    lows: dict[tuple[int, int], float] = {}

    def low(i: int, j: int) -> float:
        b = lows.get((i, j))
        if b is None:
            a, c = cars[i], cars[j]
            b = lows[(i, j)] = costs.transfer_bound(math.hypot(c[0] - a[0], c[1] - a[1]),
                                                    wrap_angle(c[2] - a[2]), ell, alpha)
        return b

    def too_dear() -> bool:
        """A chain is left, none costing less than ``ceiling`` (checked costs and bounds)."""
        least = [math.inf] * n
        least[0] = 0.0
        for i in range(n - 1):
            if math.isfinite(least[i]):
                for j in ends[i]:
                    c = checked.get((i, j))
                    least[j] = min(least[j], least[i] + (low(i, j) if c is None else c))
        return ceiling + 1e-6 <= least[-1] < math.inf

    dear = [False]

    def cheapest() -> Found[tuple[list[int], float]]:
        if math.isfinite(ceiling) and too_dear():
            dear[0] = True
            return Found(Status.INVALID)
        best = [math.inf] * n
        back = [-1] * n
        best[0] = 0.0
        for i in range(n - 1):  # a DAG: the route's order
            if not math.isfinite(best[i]):
                continue
            for j in ends[i]:
                c = checked.get((i, j))
                v = best[i] + (estimate(i, j) if c is None else c)
                if v < best[j]:
                    best[j], back[j] = v, i
        if not math.isfinite(best[-1]):
            return Found(Status.INVALID)
        chain = [n - 1]
        while chain[-1] != 0:
            chain.append(back[chain[-1]])
        return Found(Status.VALID, (chain[::-1], best[-1]))

    def check(found: tuple[list[int], float]) -> Status:
        chain = found[0]
        pending = [(i, j) for i, j in zip(chain, chain[1:], strict=False)
                   if (i, j) not in checked]
        if should_stop():
            return Status.STOPPED
        # the cheap tests first: the hospital's one-grasp route, 95 full checks -> 50
        refused = [(i, j) for i, j in pending
                   if j != i + 1 and not cheap_free(route[i], route[j])]
        for key in refused:
            checked[key] = math.inf
        if refused:
            return Status.INVALID
        for i, j in pending:
            if should_stop():
                return Status.STOPPED
            e = evaluate.transfer(route[i], route[j], grasp, should_stop=should_stop)
            if e.status is Status.STOPPED:
                return e.status
            checked[(i, j)] = e.cost
            if not math.isfinite(e.cost):
                break
        return Status.INVALID if pending else Status.VALID

    # the checks poll ``should_stop``: a chain whose every transfer is checked is returned
    # even when the time is up
    found = lazy_search(cheapest, check, lambda: False)
    if found.path is None:
        return TOO_DEAR if dear[0] else Found(found.status)
    chain, cost = found.path
    if cost >= ceiling + 1e-6:
        return TOO_DEAR
    return Found(Status.VALID, ([route[i] for i in chain], cost))
