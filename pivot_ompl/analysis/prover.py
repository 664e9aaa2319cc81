"""The proofs a plan needs, on a second core while the search runs.

On a floor where proving takes seconds (a building of hundreds of wall pieces) the search and
the proofs compete for one core: :func:`pivot_ompl.api.plan` runs the regrasp and route
bounds its quality block carries after the search, and tries the relaxations that may prove
"no plan" in windows of the search's own time. A :class:`Prover` runs them instead in a
process of its own, from the search's start, beside it:

* **"no plan"**: :class:`~pivot_ompl.analysis.late_proof.LateProof` with its windows open at
  once, to the end of the prover's time: the relaxation that proves and places (the exact
  polygons only where estimated cheaper than the held poses' proof, else the coarse raster),
  then the held poses' relaxation behind its gate;
* **the bounds**: the disk route every plan's quality block carries
  (:func:`~pivot_ompl.analysis.plan_bounds.route_bound`), then the regrasp bound
  (:func:`~pivot_ompl.analysis.bound_cache.lower_bound`, the guided refinement given the
  prover's time), which only a plan with regrasps needs.

The process starts with :class:`Prover` (its interpreter's imports overlap the plan's passage
search) and gets its job from :meth:`Prover.start`, which ``plan`` calls once that search
(:class:`~pivot_ompl.analysis.passage.PassageOnce`) has answered, before its own set-up: the
prover takes the answer instead of searching again.

The order is the scene's: "no plan" first where every way from start to goal passes a gap
narrower than the held assembly (:attr:`~pivot_ompl.analysis.passage.PassageOnce.clear`
``False``: the lab's door, most often no plan; the held poses' proof then without its gate,
which only spares a scene with a plan), the bounds first elsewhere (most often a plan,
whose quality block waits for them). The regrasp bound takes the search's expectation
(:meth:`Prover.expect`: the regrasps and places of its lattice's coarse plan, told once its
regrasp-free tries have ended, seconds before its plan is made real): it aims at that count
and refines those places first (cost only: the bound is a proof whatever it is told), and is
not computed at all where the search found a plan without regrasps. Told while the bound
runs, its guided refinement takes it from its next round on (its ``hint``; after its coarse
round it waits a little for a word not yet come). Once the search has a plan, the parent
says so (:meth:`Prover.solved`): "no plan" is abandoned, and the regrasp bound aims at the
plan's count (a bound aiming higher is stopped and aims again).

Every answer is a proof computed by the same functions as in one process, sent back through
a pipe and kept by the parent as its own (:func:`~pivot_ompl.analysis.bound_cache.keep_bound`,
:func:`~pivot_ompl.analysis.plan_bounds.keep_route_bound`): the plan and its quality block are
those of a plan made in one process; only the clock's seconds differ. The process is stopped
when the plan ends (:meth:`Prover.close`), by its own end time, or when its parent is gone.
"""

from __future__ import annotations

import logging
import math
import os
import queue
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Callable
from multiprocessing.connection import Connection
from typing import Any

from pivot_ompl.analysis.bound_cache import keep_bound, lower_bound
from pivot_ompl.analysis.bound_levels import guided_estimate
from pivot_ompl.analysis.late_proof import GATE_SHARE, LateProof, NoPlan
from pivot_ompl.analysis.passage import PassageOnce
from pivot_ompl.analysis.plan_bounds import keep_route_bound, route_bound
from pivot_ompl.analysis.pose_proof import proof_estimate
from pivot_ompl.analysis.regrasp_bound import RegraspBound
from pivot_ompl.scene import Scene

log = logging.getLogger(__name__)

#: A scene gets a prover where its held poses' proof or its guided bound is estimated at
#: this many seconds or more (a process's start costs about a second of the other core).
MIN_SECONDS = 1.0
#: Shortest time limit (s) a prover is started for by default: its process takes about a
#: second to start, a shorter plan would only pay for it.
MIN_LIMIT = 5.0
#: Seconds between two looks at the parent's messages by the prover's stop condition.
POLL_PERIOD = 0.05
#: Seconds :meth:`Prover.close` waits for the process to end before terminating it (a
#: stopped computation stands: nothing it kept is lost but its own cache writes, atomic).
CLOSE_WAIT = 0.2


def cores() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not Linux
        return os.cpu_count() or 1


def wanted(scene: Scene, choice: bool | None, *, time_limit: float = math.inf) -> bool:
    """Whether a plan of ``scene`` within ``time_limit`` s runs a :class:`Prover`.

    ``choice`` ``True``/``False``: as said; ``None``: on two cores or more, with a limit of
    :data:`MIN_LIMIT` or more, where the held poses' proof or the guided bound is estimated
    at :data:`MIN_SECONDS` or more.
    """
    if choice is not None:
        return choice
    if cores() < 2 or time_limit < MIN_LIMIT:
        return False
    return max(proof_estimate(scene), guided_estimate(scene)) >= MIN_SECONDS


class Prover:
    """A process proving "no plan" and the lower bounds of ``scene`` until ``end``.

    Polled like :class:`~pivot_ompl.analysis.late_proof.LateProof` by the search: calling
    it says whether "no plan" is proven (then :attr:`proof` holds it). The process starts
    here and waits for its job (:meth:`start`).

    Args:
        scene: the scene planned.
        end: clock time (``time.monotonic``, shared by the processes) at which the prover
            stops.
        prove: :func:`pivot_ompl.api.plan`'s: the guided refinement of the regrasp bound
            given the prover's time (``None``: where its estimate fits it), until its end
            (``True``) or never (``False``).

    Attributes:
        proof: the proof that no plan exists, once received.
        bound: the regrasp bound, once received (also kept in the bound cache).
        route: the disk route (m), once received (also kept for the plans' quality block).
        fallback: the late proof polled instead, in the plan's own process, should the
            prover's process end without a word before its work is done (an interpreter
            that cannot import this package, a crash); ``None``: none. Not where the
            prover reports an error of the proofs themselves (they would meet it again).
    """

    def __init__(self, scene: Scene, *, end: float, prove: bool | None = None) -> None:
        """The process started (its job: :meth:`start`)."""
        self.scene = scene
        self._next = 0.0
        self.proof: NoPlan | None = None
        self.bound: RegraspBound | None = None
        self.route: float | None = None
        self._done = False
        self._failed = False
        self._ready = False
        self.fallback: LateProof | None = None
        ours, theirs = socket.socketpair()
        self._conn = Connection(ours.detach())
        # a new interpreter (no fork of a process with OMPL's threads; unlike multiprocessing's
        # spawn, it never imports the caller's main script again)
        self._process = subprocess.Popen(
            [sys.executable, "-m", "pivot_ompl.analysis.prover_main", str(theirs.fileno())],
            pass_fds=(theirs.fileno(),), stdin=subprocess.DEVNULL)
        theirs.close()
        # sent in order by a thread of their own: the job (the scene, hundreds of kB on a
        # large floor) waits for the process to start reading, the plan does not
        self._outbox: queue.SimpleQueue[tuple[str, Any] | None] = queue.SimpleQueue()
        self._job = (scene, end, prove, logging.getLogger().getEffectiveLevel())
        threading.Thread(target=self._post, name="prover's outbox", daemon=True).start()
        log.debug("prover started for %s", scene.name)

    def start(self, passages: PassageOnce | None = None) -> None:
        """Send the job: prove from now on.

        ``passages``: the scene's passage search, if made (its :attr:`~PassageOnce.answer`
        is taken: the prover does not search again).
        """
        self._outbox.put(("job", (*self._job, None if passages is None else passages.answer)))

    @property
    def pid(self) -> int:
        """The process's id."""
        return self._process.pid

    @property
    def running(self) -> bool:
        """Whether the process is still running."""
        return self._process.poll() is None

    def __call__(self) -> bool:
        """Whether no plan is proven (reads what has arrived, every :data:`POLL_PERIOD` s)."""
        now = time.monotonic()
        if now >= self._next:
            self._next = now + POLL_PERIOD
            self._receive(0.0)
        if self.proof is None and self._failed and self.fallback is not None \
                and self.fallback():
            self.proof = self.fallback.proof
        return self.proof is not None

    def expect(self, regrasps: int | None, places: tuple[tuple[float, float], ...]) -> None:
        """Tell the prover the regrasps the search expects (``None``: unknown) and where.

        The search's :class:`~pivot_ompl.planners.expectation.Expectation` listener.
        """
        self._outbox.put(("expect", (regrasps, tuple(places))))

    def solved(self, regrasps: int, places: tuple[tuple[float, float], ...] = ()) -> None:
        """Tell the prover that the search has a plan of ``regrasps`` regrasps, at ``places``."""
        self._outbox.put(("solved", (regrasps, tuple(places))))

    def wait_bounds(self, *, until: float, regrasps: int) -> None:
        """Receive until the bounds a plan of ``regrasps`` regrasps needs have come, or ``until``.

        A plan without regrasps waits for nothing (its regrasp bound is 0; the route is
        taken if it has come).
        """
        while not self._done and (regrasps > 0 and self.bound is None or self.route is None):
            left = until - time.monotonic()
            if regrasps == 0 or left <= 0:
                self._receive(0.0)
                return
            self._receive(min(left, POLL_PERIOD * 4))

    def close(self) -> None:
        """Stop the process: told to (it polls the pipe), terminated if still running.

        Terminated after :data:`CLOSE_WAIT` s (between two polls), or at once while it is
        still starting (it has not read its job).
        """
        self._outbox.put(("stop", None))
        self._receive(0.0)  # its "ready", if sent
        try:
            self._process.wait(CLOSE_WAIT if self._ready else 0.0)  # still starting: at once
        except subprocess.TimeoutExpired:
            self._process.terminate()
            self._process.wait()
        self._outbox.put(None)  # the outbox's thread ends
        self._conn.close()

    def __enter__(self) -> Prover:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def _post(self) -> None:
        """The outbox's thread: every message sent in order, until ``None`` or a closed pipe."""
        while (message := self._outbox.get()) is not None:
            try:
                self._conn.send(message)
            except (BrokenPipeError, OSError):  # the process has ended, or the plan closed
                return

    def _receive(self, wait: float) -> None:
        """Take every message that has arrived (waiting at most ``wait`` s for the first)."""
        try:
            while not self._done and self._conn.poll(wait):
                kind, value = self._conn.recv()
                wait = 0.0
                self._take(kind, value)
        except (EOFError, OSError):  # the process ended without a word: nothing more comes
            self._failed = self._failed or not self._done
            self._done = True

    def _take(self, kind: str, value: Any) -> None:
        if kind == "ready":
            self._ready = True
        elif kind == "no plan":
            log.debug("prover: no plan exists: %s", value.reason)
            self.proof = value
        elif kind == "bound" and keep_bound(self.scene, value):
            self.bound = value
        elif kind == "route" and keep_route_bound(self.scene, value):
            self.route = value
        elif kind == "done":
            self._done = True
        elif kind == "failed":
            # an error of the proofs' own code: the fallback would meet it again
            log.warning("the prover failed (the plan goes on without it): %s", value)
            self._done = True


class _ParentWord:
    """The prover's stop condition: its end, the parent's "stop", or the parent gone.

    Also records the parent's "solved" (:attr:`solved`: the plan's regrasps; :attr:`places`:
    where it regrasps) and the search's "expect" (:attr:`expected`: ``(regrasps, places)``).
    """

    def __init__(self, conn: Connection, end: float) -> None:
        self.conn, self.end = conn, end
        self.solved: int | None = None
        self.places: tuple[tuple[float, float], ...] = ()
        self.expected: tuple[int | None, tuple[tuple[float, float], ...]] | None = None
        self.aim: int | None = None  # the regrasp bound's target while it runs
        self.stopped = False
        self._next = 0.0

    def __call__(self) -> bool:
        now = time.monotonic()
        if self.stopped or now >= self.end:
            return True
        if now >= self._next:
            self._read(now)
        return self.stopped

    def _read(self, now: float) -> None:
        """Take every message that has come."""
        self._next = now + POLL_PERIOD
        try:
            while self.conn.poll():
                kind, value = self.conn.recv()
                if kind == "solved":
                    self.solved, self.places = value
                elif kind == "expect":
                    self.expected = value
                else:
                    self.stopped = True
        except (EOFError, OSError):  # the parent is gone
            self.stopped = True

    def aims_too_high(self) -> bool:
        """Whether the regrasp bound running aims above the plan's count, now known."""
        return self.aim is not None and self.solved is not None and self.solved < self.aim

    def bound_wanted(self) -> Callable[[], bool]:
        """A stop for the regrasp bound: also once it aims above the plan's count."""
        return lambda: self() or self.aims_too_high()

    def hint(self) -> tuple[int | None, tuple[tuple[float, float], ...]] | None:
        """The plan's regrasps and places if made, else the search's expectation, if told."""
        self._read(time.monotonic())
        if self.solved is not None:
            return self.solved, self.places or (self.expected or (None, ()))[1]
        return self.expected

    def no_plan_wanted(self) -> Callable[[], bool]:
        """A stop for the "no plan" proof: also once the search has a plan."""
        return lambda: self() or self.solved is not None


def serve(conn: Connection) -> None:
    """The prover's process: its job read from ``conn``, then its proofs (module docstring).

    Each answer is sent as soon as found; :mod:`~pivot_ompl.analysis.prover_main` runs it.
    """
    try:
        _, (scene, end, prove, level, answer) = conn.recv()
    except (EOFError, OSError):  # the parent is gone
        return
    logging.basicConfig(level=level, format="%(levelname)s %(name)s (prover): %(message)s")
    word = _ParentWord(conn, end)
    try:
        conn.send(("ready", None))
        passages = PassageOnce(scene)  # the order (module docstring), and the proof's passage
        passages.share(answer)
        passages(should_stop=word)  # searched here if the plan did not
        jobs = (_no_plan, _bounds) if _narrow(passages) else (_bounds, _no_plan)
        for job in jobs:
            if word():
                break
            job(scene, end, prove, passages, word, conn)
        conn.send(("done", None))
    except (BrokenPipeError, EOFError, OSError):  # the parent is gone
        pass
    except Exception as e:  # noqa: BLE001 - reported to the parent, which plans on without it
        try:
            conn.send(("failed", f"{type(e).__name__}: {e}"))
        except OSError:
            pass


def _no_plan(scene: Scene, end: float, prove: bool | None, passages: PassageOnce,
             word: _ParentWord, conn: Connection) -> None:
    """"No plan", tried at once to ``end`` unless the search has a plan."""
    if word.solved is not None:
        return
    now = time.monotonic()
    late = LateProof(scene, begin=now, end=end, explain_end=end, held_begin=now,
                     passages=passages, should_stop=word.no_plan_wanted(),
                     exact_seconds=proof_estimate(scene),  # the cheaper proof first
                     gate_share=0.0 if _narrow(passages) else GATE_SHARE)
    if late():
        conn.send(("no plan", late.proof))


def _narrow(passages: PassageOnce) -> bool:
    """Whether every way from start to goal passes a gap narrower than the held assembly."""
    return passages.clear is False


def _bounds(scene: Scene, end: float, prove: bool | None, passages: PassageOnce,
            word: _ParentWord, conn: Connection) -> None:
    """The disk route (every plan's), then the regrasp bound unless the plan has no regrasp.

    Only what ran to its end is sent (a stopped route may be weaker than the scene's, which
    the parent would keep for its later plans); the parent keeps a bound only where
    :func:`~pivot_ompl.analysis.bound_cache.keep_bound` would keep its own.
    """
    route = route_bound(scene, should_stop=word)
    if word():
        return
    conn.send(("route", route))
    while not word():
        word.aim, places = word.hint() or (None, ())
        if word.aim == 0:
            return  # a plan without regrasps needs no regrasp bound
        guided = (0.0 if prove is False else math.inf if prove is True
                  else max(0.0, end - time.monotonic()))
        log.debug("regrasp bound aiming at %s, %d places first", word.aim, len(places))
        bound = lower_bound(scene, target=word.aim, should_stop=word.bound_wanted(),
                            guided_seconds=guided, places=places, hint=word.hint)
        if not word.aims_too_high():
            conn.send(("bound", bound))
            return
        log.debug("regrasp bound aimed at %s, the plan has %s: aimed again", word.aim,
                  word.solved)
