"""Issue 28, class 6: one contract everywhere. One time-limit rule for every verb and API call
(``inf`` is the largest limit), and wrong types are InputErrors naming the argument."""

from __future__ import annotations

import math

import pytest
from factories import scene_file
from hypothesis import given
from hypothesis import strategies as st

from pivot_ompl.api import MAX_TIME_LIMIT, check_time_limit
from pivot_ompl.bench.sweep import make_jobs
from pivot_ompl.cli.args import time_limit
from pivot_ompl.errors import InputError


@given(st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.integers(-10, 10**9)))
def test_the_cli_parser_and_the_api_agree_on_every_time_limit(value):
    """Accepted by one, accepted by the other, with the same limit."""
    try:
        expected = check_time_limit(value)
    except InputError:
        expected = None
    try:
        got = time_limit("--time")(repr(float(value)) if isinstance(value, float) else str(value))
    except Exception:  # argparse.ArgumentTypeError
        got = None
    assert got == expected
    if expected is not None:
        assert 0 < expected <= MAX_TIME_LIMIT


def test_bench_takes_inf_as_plan_does():
    jobs = make_jobs([scene_file("open")], ["rrtconnect"], runs=1, time_limit=math.inf)
    assert jobs[0].time_limit == MAX_TIME_LIMIT
    with pytest.raises(InputError) as e:
        make_jobs([scene_file("open")], ["rrtconnect"], runs=1, time_limit=math.nan)
    assert e.value.field == "--time"


def _generate(**kw):
    from pivot_ompl.generate import generate

    return generate(**{"family": "walls", "seed": 0, **kw})


def _viz(name, *args, **kw):
    from pivot_ompl import viz

    return getattr(viz, name)(*args, **kw)


def _vis():
    from pivot_ompl.viz import recording_visualizer

    return recording_visualizer()


def _plan():
    from pivot_ompl.viz.samples import sample_plan

    return sample_plan()


WRONG = {
    "generate family a list": (lambda: _generate(family=["walls"]), "family"),
    "generate params a dict": (lambda: _generate(params={"rooms": 3}), "params"),
    "show_plan scene a name": (lambda: _viz("show_plan", _vis(), "open", _plan()), "scene"),
    "show_plan plan None": (lambda: _viz("show_plan", _vis(), None, None), "plan"),
    "show_plan vis None": (lambda: _viz("show_plan", None, None, _plan()), "vis"),
    "show_scene scene a name": (lambda: _viz("show_scene", _vis(), "open"), "scene"),
    "show_motion motion a path": (lambda: _viz("show_motion", _vis(), "m.npz"), "motion"),
    "motion_guide motion a path": (lambda: _viz("motion_guide", "m.npz"), "motion"),
    "narrowest_steps a name": (lambda: _viz("narrowest_steps", _plan(), "open"), "scene"),
    "write_html vis None": (lambda: _viz("write_html", None, "x.html"), "vis"),
    "write_html path an int": (lambda: _viz("write_html", _vis(), 3), "path"),
    "load_motion an int": (lambda: _viz("load_motion", 3), "motion"),
    "load_plan an int": (lambda: __import__("pivot_ompl").load_plan(3), "path"),
}


@pytest.mark.parametrize("case", sorted(WRONG))
def test_wrong_types_are_input_errors_naming_the_argument(case):
    call, field = WRONG[case]
    with pytest.raises(InputError) as e:
        call()
    assert e.value.field == field
