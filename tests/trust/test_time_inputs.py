"""Counts, sizes and reading inside the limit (issue 43, class 5).

Each run is watched by :func:`_within`: code that ignores its limit makes the test fail
after a few seconds instead of hanging the suite (a count of 1e9 or an unpolled read runs
for minutes).
"""

from __future__ import annotations

import contextlib
import json
import signal
import threading
import time
from collections.abc import Iterator

import pytest
from factories import DeadlineWatch

from pivot_ompl.cli.main import main

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone


class Overran(BaseException):  # noqa: N818 - not an Exception: no ``except Exception`` eats it
    """The watched call ran past its watchdog."""


@contextlib.contextmanager
def _within(seconds: float) -> Iterator[None]:
    """Fail the test (raise :class:`Overran` in it, again every second) once ``seconds``
    have passed; SIGUSR1 from a timer thread (the code under test may use SIGALRM)."""
    main_thread = threading.get_ident()
    done = threading.Event()

    def watch() -> None:
        wait = seconds
        while not done.wait(wait):
            signal.pthread_kill(main_thread, signal.SIGUSR1)
            wait = 1.0

    def overran(signum: int, frame: object) -> None:
        raise Overran(f"still running after {seconds} s")

    old = signal.signal(signal.SIGUSR1, overran)
    timer = threading.Thread(target=watch, daemon=True)
    timer.start()
    try:
        yield
    finally:
        done.set()
        timer.join()
        signal.signal(signal.SIGUSR1, old)


def test_generate_refuses_a_huge_count_before_any_work(tmp_path, capsys):
    t0 = time.monotonic()
    with _within(10.0):
        assert main(["generate", "--family", "walls", "--count", "1e9", "--out",
                     str(tmp_path / "g")]) == 2
    assert time.monotonic() - t0 < 2.0
    assert "--count" in capsys.readouterr().err
    assert not (tmp_path / "g").exists()


def test_generate_honours_its_time_limit_and_writes_nothing(tmp_path, capsys):
    t0 = time.monotonic()
    with _within(10.0):
        code = main(["generate", "--family", "building", "--rooms", "64", "--layout", "grid",
                     "--time", "1", "--out", str(tmp_path / "g")])
    took = time.monotonic() - t0
    assert code == 1 and "stopped" in capsys.readouterr().err
    assert took < 1.0 + 1.0
    assert not (tmp_path / "g").exists() or list((tmp_path / "g").iterdir()) == []


@pytest.fixture(scope="module")
def long_route_plan(tmp_path_factory):
    """A plan of ``open`` whose route holds 200 000 states."""
    d = tmp_path_factory.mktemp("route")
    assert main(["plan", "open", "--out", str(d / "p.json"), "--time", "5", "--no-bound"]) == 0
    doc = json.loads((d / "p.json").read_text())
    a, b = doc["route"][0], doc["route"][-1]
    n = 200_000
    doc["route"] = [[a[0] + (b[0] - a[0]) * i / (n - 1), a[1] + (b[1] - a[1]) * i / (n - 1),
                     a[2], a[3]] for i in range(n)]
    (d / "big.json").write_text(json.dumps(doc))
    return d


def test_replan_of_a_long_route_keeps_its_time_limit(long_route_plan, tmp_path, capsys):
    """Reading and checking the route count: the goal walled in, the search uses what is
    left of the limit (before, it had the whole limit after a second of reading)."""
    import yaml

    gx, gy, h = 0.5, 3.0, 1.7  # a closed square round open's goal
    ring = [{"type": "box", "center": c, "size": s, "height": 1.0} for c, s in (
        ([gx, gy - h], [2 * h + 0.1, 0.1]), ([gx, gy + h], [2 * h + 0.1, 0.1]),
        ([gx - h, gy], [0.1, 2 * h + 0.1]), ([gx + h, gy], [0.1, 2 * h + 0.1]))]
    extra = tmp_path / "ring.yaml"
    extra.write_text(yaml.safe_dump({"obstacles": ring}))
    d = long_route_plan
    with _within(10.0), DeadlineWatch(2.0) as watch:
        code = main(["replan", "open", str(d / "big.json"), "--box", "0", "0", "0", "--time",
                     "2", "--add-obstacles", str(extra), "--out", str(tmp_path / "n.json"),
                     "--scene-out", str(tmp_path / "n.yaml")])
    assert code == 1, capsys.readouterr().err[-500:]
    # the limit, not seconds more: little work after the deadline (CPU seconds of this
    # process, which a loaded machine does not stretch), and no gross overrun of the clock
    assert watch.cpu_past_deadline < 0.05 * 2.0 + 0.1, watch.cpu_past_deadline
    assert watch.wall < 3 * 2.0, watch.wall
    assert not (tmp_path / "n.json").exists()


def test_replan_reads_its_inputs_inside_the_limit(long_route_plan, tmp_path, capsys):
    obstacles = [{"type": "box", "center": [5.0 + 0.001 * i, 6.5], "size": [0.0005, 0.1],
                  "height": 1.0} for i in range(100_000)]
    extra = tmp_path / "add.yaml"
    import yaml

    extra.write_text(yaml.safe_dump({"obstacles": obstacles}))
    d = long_route_plan
    t0 = time.monotonic()
    with _within(10.0):
        code = main(["replan", "open", str(d / "p.json"), "--box", "0", "0", "0", "--time",
                     "1", "--add-obstacles", str(extra), "--out", str(tmp_path / "n.json"),
                     "--scene-out", str(tmp_path / "n.yaml")])
    took = time.monotonic() - t0
    assert code == 1, capsys.readouterr().err[-500:]
    assert took < 1.0 + 1.0, took
    assert not (tmp_path / "n.json").exists()
