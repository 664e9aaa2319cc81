"""Fuzz (hypothesis, derandomized): the scene and plan readers and the CLI's argument parsing.

Whatever the input: the readers return or raise their own InputError kind; the CLI returns
0, 1 or 2, never raises, never prints a traceback, and each example ends quickly.
"""

from __future__ import annotations

import contextlib
import io
import json
import math
import time
from pathlib import Path

import numpy as np
import pytest
import yaml
from factories import scene_file
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pivot_ompl.cli.main import main
from pivot_ompl.errors import PlanFileError, SceneError
from pivot_ompl.planfile import Plan, load_plan, plan_from_dict
from pivot_ompl.scene import Scene, load_scene, scene_from_dict
from pivot_ompl.viz.samples import sample_plan

pytestmark = pytest.mark.timed  # a time budget or a clock stop: run alone

FUZZ = settings(derandomize=True, deadline=None, max_examples=150,
                suppress_health_check=[HealthCheck.too_slow])

SCENE_DOC = {"name": "t", "bounds": [0.0, 0.0, 8.0, 6.0], "object": {"size": [0.8, 0.6, 1.3]},
             "robot": {"standoff": 0.25}, "pivot": {"alpha_max": 0.39},
             "obstacles": [{"type": "box", "center": [4.0, 1.0], "size": [0.5, 0.5],
                            "height": 1.0},
                           {"type": "polygon", "points": [[5, 4], [6, 4], [6, 5]],
                            "height": 1.0}],
             "start": [1.5, 3.0, 0.0], "goal": [6.0, 3.0, 0.0]}
PLAN_DOC = sample_plan().to_dict()

scalars = st.one_of(
    st.none(), st.booleans(), st.integers(), st.integers(min_value=10**300, max_value=10**400),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=20),
    st.sampled_from([0, -1, 1e-9, 1e300, -1e308, 2 * math.pi, 7.0, 1e4, 1e5, "", "box"]))
values = st.recursive(scalars, lambda c: st.one_of(
    st.lists(c, max_size=5), st.dictionaries(st.text(max_size=8), c, max_size=4)), max_leaves=12)


def paths(doc, prefix=()):
    """Every path into a JSON-like document."""
    yield prefix
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from paths(v, (*prefix, i))


def mutate(doc, path, value):
    doc = json.loads(json.dumps(doc))
    if not path:
        return value
    d = doc
    for k in path[:-1]:
        d = d[k]
    d[path[-1]] = value
    return doc


def mutate_all(doc, changes):
    """``doc`` with every applicable ``(path, value)`` change (an inapplicable one is skipped)."""
    for path, value in changes:
        try:
            doc = mutate(doc, path, value)
        except (KeyError, IndexError, TypeError):
            continue
    return doc


SCENE_PATHS = list(paths(SCENE_DOC))
PLAN_PATHS = list(paths(PLAN_DOC))


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(SCENE_PATHS), values), min_size=1, max_size=3))
def test_scene_reader_mutations(changes):
    doc = mutate_all(SCENE_DOC, changes)
    t0 = time.perf_counter()
    try:
        assert isinstance(scene_from_dict(doc, source="<fuzz>"), Scene)
    except SceneError as e:
        assert len(str(e)) < 600
    assert time.perf_counter() - t0 < 2.0


@FUZZ
@given(st.one_of(st.binary(max_size=300), st.text(max_size=300).map(str.encode),
                 values.map(lambda v: yaml.safe_dump(v).encode())))
def test_scene_reader_raw_files(tmp_path_factory, data):
    _read_raw_file(tmp_path_factory, data, "s.yaml", load_scene, SceneError)


@FUZZ
@given(st.lists(st.tuples(st.sampled_from(PLAN_PATHS), values), min_size=1, max_size=3))
def test_plan_reader_mutations(changes):
    doc = mutate_all(PLAN_DOC, changes)
    try:
        assert isinstance(plan_from_dict(doc, source="<fuzz>"), Plan)
    except PlanFileError as e:
        assert len(str(e)) < 600


@FUZZ
@given(st.one_of(st.binary(max_size=300),
                 values.map(lambda v: json.dumps(v, allow_nan=True).encode())))
def test_plan_reader_raw_files(tmp_path_factory, data):
    _read_raw_file(tmp_path_factory, data, "p.json", load_plan, PlanFileError)


def _read_raw_file(tmp_path_factory, data: bytes, name: str, load, error) -> None:
    """A file of arbitrary bytes is read, or refused with a short ``error``."""
    p = tmp_path_factory.mktemp("fz") / name
    p.write_bytes(data)
    try:
        load(p)
    except error as e:
        assert len(str(e)) < 800


# --- the command line ----------------------------------------------------------------------

@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, str]:
    d = tmp_path_factory.mktemp("cli")
    garbage = d / "garbage.yaml"
    garbage.write_bytes(b"\x00\xff{[")
    plan = sample_plan().to_json(d / "plan.json")
    motion = d / "motion.npz"
    np.savez(motion, t=np.zeros(3))
    return {"dir": str(d), "garbage": str(garbage), "plan": str(plan), "motion": str(motion),
            "missing": str(d / "missing.yaml"), "out_json": str(d / "out" / "o.json"),
            "out_png": str(d / "o.png"), "out_xyz": str(d / "o.xyz"),
            "out_html": str(d / "o.html"), "open": str(scene_file("open"))}


NUMBERS = ["0", "-1", "1", "0.5", "1e-9", "1e10", "1e308", "1e400", "inf", "-inf", "nan",
           "abc", "", "3" * 400, str(2**64), "6.2831853", "1e-320"]


def argv_for(verb: str, f: dict[str, str]) -> st.SearchStrategy[list[str]]:
    inputs = [f["garbage"], f["missing"], f["dir"], f["plan"], f["motion"], "open", "nosuch"]
    outputs = [f["dir"], f["out_json"], f["out_png"], f["out_xyz"], f["out_html"], f["plan"],
               f["open"]]
    opts = {
        "plan": ["--planner", "--seed", "--out", "--plot"],
        "steer": ["--grasp", "--out", "--plot", "--scene"],
        "check": ["--no-collisions"],
        "check-motion": ["--plan"],
        "replay": ["--scene", "--plan", "--html", "--urdf", "--fps"],
        "animate": ["--out", "--tilt-deg", "--tick", "--substeps", "--no-check",
                    "--no-progress"],
        "bench": ["--planners", "--runs", "--workers", "--seed0", "--out", "--memory"],
    }[verb]
    token = st.one_of(st.sampled_from(opts), st.sampled_from(inputs), st.sampled_from(outputs),
                      st.sampled_from(NUMBERS),
                      st.sampled_from(["regrasp", "rrtconnect", "prm", "-h", "--", "-x"]))
    fixed: list[str] = []
    if verb == "plan":
        fixed = ["--time", "0.5"]
    elif verb == "steer":
        fixed = ["--time", "0.5", "--start", "0", "0", "0", "--goal", "1", "0", "0"]
    scenes = st.sampled_from(["open", f["garbage"], f["missing"]])
    plans = st.sampled_from([f["plan"], f["motion"], f["dir"]])
    positional = {"plan": [scenes], "check": [scenes, plans], "check-motion": [plans],
                  "replay": [plans], "animate": [plans], "bench": [scenes]}.get(verb, [])
    return st.tuples(st.tuples(*positional), st.lists(token, max_size=5)).map(
        lambda a: [verb, *a[0], *a[1], *fixed])


CODES: list[int] = []
VERBS = ["plan", "steer", "check", "check-motion", "replay", "animate", "bench"]


@settings(derandomize=True, deadline=None, max_examples=60,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_cli_argument_fuzz(files, data):
    verb = data.draw(st.sampled_from(VERBS))
    argv = data.draw(argv_for(verb, files))
    if verb in ("animate", "bench") and files["plan"] in argv or \
            (verb == "bench" and "open" in argv) or (verb == "replay" and "--plan" in argv):
        argv = [a for a in argv if a not in (files["plan"], "open")]  # real work: not fuzzed
    before = {p: Path(p).read_bytes() for p in (files["plan"], files["open"])}
    err = io.StringIO()
    t0 = time.monotonic()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        code = main(argv)
    assert code in (0, 1, 2), (argv, err.getvalue()[-500:])
    CODES.append(code)
    assert "Traceback" not in err.getvalue()
    assert time.monotonic() - t0 < 20, argv
    assert all(Path(p).read_bytes() == b for p, b in before.items()), argv  # inputs untouched


def test_cli_fuzz_reached_every_exit_code():
    """The argument fuzz is not only usage errors: it reached success and failure as well."""
    if not CODES:
        pytest.skip("run with test_cli_argument_fuzz")
    assert set(CODES) == {0, 1, 2}
