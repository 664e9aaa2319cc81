"""The prover's regrasp bound aims at what the search expects and refines its places first."""

from __future__ import annotations

import logging
import socket
import threading
import time
from multiprocessing.connection import Connection

import pytest
from factories import shipped

from pivot_ompl.analysis import prover
from pivot_ompl.analysis.regrasp_bound import RegraspBound

pytestmark = pytest.mark.timed  # a thread serving, polled against a clock

PLACES = ((1.0, 2.0), (3.0, 4.0))


class _Spy:
    """``lower_bound`` recorded: each call's target and places; blocks while told to."""

    def __init__(self, *, block_first: bool = False, until_hint: tuple | None = None) -> None:
        self.calls: list[tuple[int | None, tuple]] = []
        self.running = threading.Event()
        self.block_first = block_first
        self.until_hint = until_hint
        self.hints: list[tuple] = []

    def __call__(self, scene, *, target, should_stop, guided_seconds, places,  # noqa: ANN001
                 hint):  # noqa: ANN001
        self.calls.append((target, places))
        self.running.set()
        while self.until_hint is not None and not should_stop():  # rounds asking the hint
            self.hints.append(hint())
            if self.hints[-1] == self.until_hint:
                return RegraspBound(self.until_hint[0], True, 8, 0, 0.0)
            time.sleep(0.01)
        if self.block_first and len(self.calls) == 1:
            while not should_stop():  # a long refinement, stopped
                time.sleep(0.01)
            return RegraspBound(None, True, 8, 0, 0.0, complete=False)
        return RegraspBound(target, True, 8, 0, 0.0)


def _serve(scene, spy: _Spy, monkeypatch, *words):  # noqa: ANN001, ANN002, ANN202
    """The prover's messages for ``scene`` after ``words`` (each sent once the previous
    message it waits for has come: ``(wait_for, (kind, value))``)."""
    monkeypatch.setattr(prover, "lower_bound", spy)
    ours, theirs = socket.socketpair()
    conn, child = Connection(ours.detach()), Connection(theirs.detach())
    conn.send(("job", (scene, time.monotonic() + 60.0, None, logging.WARNING, None)))
    todo = list(words)
    while todo and todo[0][0] is None:  # sent with the job: there before the prover asks
        conn.send(todo.pop(0)[1])
    worker = threading.Thread(target=prover.serve, args=(child,))
    worker.start()
    kinds: list[str] = []
    values: dict[str, object] = {}
    while not kinds or kinds[-1] not in ("done", "failed"):
        while todo and (todo[0][0] in kinds or
                        (todo[0][0] == "running" and spy.running.is_set())):
            conn.send(todo.pop(0)[1])
        if conn.poll(0.02):
            kind, value = conn.recv()
            kinds.append(kind)
            values[kind] = value
    conn.send(("stop", None))
    worker.join(30.0)
    conn.close()
    child.close()
    return kinds, values


def test_the_bound_aims_at_the_expected_regrasps_and_refines_their_places_first(monkeypatch):
    spy = _Spy()
    kinds, values = _serve(shipped("fig10"), spy, monkeypatch,
                           (None, ("expect", (2, PLACES))), ("bound", ("solved", (2, ()))))
    assert spy.calls == [(2, PLACES)]
    assert kinds[-1] == "done" and values["bound"].regrasps == 2


def test_a_plan_expected_without_regrasps_gets_no_regrasp_bound(monkeypatch):
    spy = _Spy()
    kinds, _ = _serve(shipped("fig10"), spy, monkeypatch,
                      (None, ("expect", (0, ()))), ("route", ("solved", (0, ()))))
    assert spy.calls == [] and "bound" not in kinds and kinds[-1] == "done"


def test_what_is_told_while_the_bound_runs_reaches_its_rounds(monkeypatch):
    spy = _Spy(until_hint=(2, PLACES))  # nothing told yet: the bound runs, asking every round
    _, values = _serve(shipped("fig10"), spy, monkeypatch, ("running", ("expect", (2, PLACES))),
                       ("bound", ("solved", (2, ()))))
    assert spy.calls == [(None, ())] and spy.hints[0] is None
    assert spy.hints[-1] == (2, PLACES) and values["bound"].regrasps == 2
    spy = _Spy(until_hint=(1, PLACES[:1]))  # then the plan's count and places
    _serve(shipped("fig10"), spy, monkeypatch, ("running", ("expect", (2, PLACES))),
           ("running", ("solved", (1, PLACES[:1]))))
    assert spy.hints[-1] == (1, PLACES[:1])


@pytest.mark.parametrize("plan_count", [1, 0])
def test_a_bound_aiming_above_the_plan_s_count_aims_again(monkeypatch, plan_count):
    spy = _Spy(block_first=True)
    kinds, values = _serve(shipped("fig10"), spy, monkeypatch, (None, ("expect", (3, PLACES))),
                           ("running", ("solved", (plan_count, ()))))
    assert spy.calls[0] == (3, PLACES)
    if plan_count == 0:  # a plan without regrasps: none wanted any more
        assert len(spy.calls) == 1 and "bound" not in kinds
    else:
        assert spy.calls[1] == (plan_count, PLACES)
        assert values["bound"].regrasps == plan_count and values["bound"].complete


def test_the_refinement_waits_a_little_after_its_coarse_round_for_the_search_s_word(
        monkeypatch):
    from pivot_ompl.analysis import guided_refine
    from pivot_ompl.analysis.guided_refine import GuidedRound, guided_lower_bound, place_window
    from pivot_ompl.analysis.raster_bound import CELL
    from pivot_ompl.analysis.raster_cover import raster_cover

    scene = shipped("fig10")
    cover = raster_cover(scene, cell=CELL)
    x0, y0, x1, y1 = scene.bounds
    places = ((0.5 * (x0 + x1), 0.5 * (y0 + y1)),)
    told_at = time.monotonic() + 0.3

    def later():  # noqa: ANN202 - the search's word comes 0.3 s after the start
        return (None, places) if time.monotonic() >= told_at else None

    trace: list[GuidedRound] = []
    guided_lower_bound(scene, cover=cover, trace=trace, hint=later)
    assert len(trace) >= 2 and trace[1].window >= int(place_window(cover, places).sum())
    monkeypatch.setattr(guided_refine, "HINT_WAIT", 0.2)  # a word that never comes
    begun, trace = time.monotonic(), []
    found = guided_lower_bound(scene, cover=cover, trace=trace, hint=lambda: None)
    assert found is not None and found.solvable and time.monotonic() - begun >= 0.2
