"""Every public entry point validates its arguments (issue 43, class 8).

Each call below is made with valid arguments but one, replaced by a wrong type or value; the
only exceptions allowed are the project's own (:class:`~pivot_ompl.errors.PivotError`),
naming the argument.
"""

from __future__ import annotations

import inspect
import math
from typing import Any

import pytest
from factories import shipped
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import pivot_ompl
import pivot_ompl.generate
from pivot_ompl.analysis.bound_cache import lower_bound
from pivot_ompl.errors import InputError, PivotError
from pivot_ompl.generate.transform import mirror_scene, rotate_scene
from pivot_ompl.motionfile import load_motion
from pivot_ompl.planfile import load_plan
from pivot_ompl.session import PlanningSession
from pivot_ompl.viz.samples import sample_plan

OPEN = shipped("open")
STEERING = pivot_ompl.PivotSteering(turning_radius=2.0, alpha_max=0.39)


class _Odd:
    """An object of no expected type."""

    def __repr__(self) -> str:
        return "<odd>"


JUNK = st.one_of(
    st.none(), st.booleans(), st.integers(-2**70, 2**70), st.sampled_from(
        [math.nan, math.inf, -math.inf, 1e300, -1e300, -1.0, 0.0, 1e-320]),
    st.floats(), st.text(max_size=8), st.binary(max_size=4), st.just("fig10"),
    st.lists(st.floats(), max_size=4), st.lists(st.text(max_size=2), max_size=3),
    st.dictionaries(st.text(max_size=3), st.integers(), max_size=2), st.just(_Odd()),
    st.just(()), st.just((1e300, 0.0, 0.0)), st.just([0.0, 0.0]), st.just(object),
)


def _session() -> PlanningSession:
    return PlanningSession(OPEN, planner="rrtconnect")


#: Entry points: a call taking keyword arguments, and valid values of each.
CALLS: dict[str, tuple[Any, dict[str, Any]]] = {
    "load_scene": (pivot_ompl.load_scene, {"path": "open"}),
    "load_plan": (lambda path: load_plan(path), {"path": "/nonexistent/plan.json"}),
    "plan": (pivot_ompl.plan, {"scene": OPEN, "planner": "rrtconnect", "time_limit": 0.3,
                               "seed": 0, "simplify": False, "bound": False}),
    "make_setup": (pivot_ompl.make_setup, {"scene": OPEN, "seed": 0, "grasp_weight": 1.0,
                                           "start_grasp": None, "goal_grasp": None,
                                           "checker": None, "should_stop": None}),
    "PivotSteering": (pivot_ompl.PivotSteering, {"turning_radius": 2.0, "alpha_max": 0.39,
                                                 "merge": True}),
    "PivotSteering.convert": (
        lambda start, goal, half_length, should_stop: STEERING.convert(
            start, goal, half_length=half_length, should_stop=should_stop),
        {"start": (0.0, 0.0, 0.0), "goal": (1.0, 0.2, 0.1), "half_length": 0.4,
         "should_stop": None}),
    "PivotSteering.iter_rotations": (
        lambda start, goal, half_length: list(STEERING.iter_rotations(
            start, goal, half_length=half_length)),
        {"start": (0.0, 0.0, 0.0), "goal": (1.0, 0.2, 0.1), "half_length": 0.4}),
    "BoxGraspModel": (pivot_ompl.BoxGraspModel, {"object_size": (0.8, 0.6, 1.3),
                                                 "robot_footprint": (0.3, 0.6),
                                                 "standoff": 0.1, "robot_height": 1.5}),
    "PlanningSession": (PlanningSession, {"scene": OPEN, "planner": "rrtconnect",
                                          "config": None, "seed": 0, "bound": False,
                                          "executing": None, "repair": True}),
    "PlanningSession.plan": (lambda time_limit, seed: _session().plan(
        time_limit=time_limit, seed=seed), {"time_limit": 0.3, "seed": 0}),
    "PlanningSession.replan": (
        lambda **kw: _session().replan(**kw),
        {"box": OPEN.start, "grasp": None, "robot": None, "add_obstacles": [],
         "remove_obstacles": [], "time_limit": 0.3, "seed": 0}),
    "lower_bound": (lower_bound, {"scene": OPEN, "use_cache": True, "should_stop": None}),
    "rotate_scene": (rotate_scene, {"scene": OPEN, "angle": 0.3, "about": None,
                                    "name": None}),
    "mirror_scene": (mirror_scene, {"scene": OPEN, "axis_angle": 0.3, "about": None,
                                    "name": None}),
}


@pytest.mark.parametrize("entry", sorted(CALLS))
@settings(max_examples=25, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_a_wrong_argument_raises_only_the_projects_errors(entry, data):
    call, good = CALLS[entry]
    name = data.draw(st.sampled_from(sorted(good)), label="argument")
    value = data.draw(JUNK, label="value")
    try:
        call(**{**good, name: value})
    except PivotError:
        pass


ISSUE_CASES = [
    ("replan without a box", lambda: _session().replan(), "box"),
    ("replan with a negative time limit", lambda: _session().replan(box=OPEN.start,
                                                                     time_limit=-1), "time_limit"),
    ("replan with an int obstacle", lambda: _session().replan(box=OPEN.start,
                                                               add_obstacles=[3]),
     "add_obstacles[0]"),
    ("replan with a text of obstacles", lambda: _session().replan(box=OPEN.start,
                                                                   add_obstacles="box"),
     "add_obstacles"),
    ("a path string as executing", lambda: PlanningSession(OPEN, executing="plan.json"),
     "executing"),
    ("lower_bound of a name", lambda: lower_bound("fig10"), "scene"),
    ("make_setup of a name", lambda: pivot_ompl.make_setup("fig10"), "scene"),
    ("convert of strings", lambda: STEERING.convert("a", "b", half_length=0.4), "start"),
    ("rotate_scene by nan", lambda: rotate_scene(OPEN, math.nan), "angle"),
]


@pytest.mark.parametrize("what, call, field", ISSUE_CASES, ids=[c[0] for c in ISSUE_CASES])
def test_the_issues_cases_name_their_argument(what, call, field):
    with pytest.raises(InputError) as e:
        call()
    assert e.value.field == field


@pytest.mark.parametrize("route_state", [[1e300, 0.0, 0.0, 0], [1.0, 1.0, 0.0, 7],
                                         [1.0, 1.0, 0.0], ["a", 1.0, 0.0, 0]])
def test_a_plan_whose_route_is_out_of_range_is_refused_as_executing(route_state):
    plan = sample_plan()
    plan.extra["route"] = [[1.0, 1.0, 0.0, 0], route_state]
    with pytest.raises(InputError) as e:
        PlanningSession(OPEN, executing=plan)
    assert e.value.field.startswith("executing.route[1]")


def test_bench_seed0_beyond_the_seeds_is_bad_input(tmp_path, capsys):
    from pivot_ompl.cli.main import main

    assert main(["bench", "open", "--runs", "1", "--seed0", str(2**33), "--out",
                 str(tmp_path / "b"), "--planners", "regrasp"]) == 2
    assert "--seed0" in capsys.readouterr().err


# --- the geometry model's methods and the plan's dataclasses (the planners' inner loop and
# the plan in memory: checked at their boundary, at no cost on the planners' path) ---------

MODEL = pivot_ompl.BoxGraspModel(object_size=(0.8, 0.6, 1.3))
POSE = (1.0, 2.0, 0.3)

#: Each public method of BoxGraspModel that takes arguments, with valid values of them.
MODEL_METHODS: dict[str, dict[str, Any]] = {
    "half_extent": {"grasp": 1}, "edge_half_length": {"grasp": 1},
    "robot_offset": {"grasp": 1}, "heading": {"obj": POSE, "grasp": 1},
    "robot_pose": {"obj": POSE, "grasp": 1}, "car_pose": {"obj": POSE, "grasp": 1},
    "object_from_car": {"car": POSE, "grasp": 1}, "robot_from_car": {"car": POSE, "grasp": 1},
    "pivots": {"car": POSE, "grasp": 1}, "object_corners": {"obj": POSE},
    "robot_corners": {"robot": POSE}, "grip_lateral": {"grasp": 1},
    "held_polygons": {"grasp": 1}, "held_outline": {"grasp": 1},
    "held_corners": {"robot": POSE, "grasp": 1},
}


def test_every_method_of_the_model_with_arguments_is_listed():
    public = {n for n, v in vars(pivot_ompl.BoxGraspModel).items()
              if callable(v) and not n.startswith("_")
              and len(inspect.signature(v).parameters) > 1}
    assert public == set(MODEL_METHODS)


@pytest.mark.parametrize("method", sorted(MODEL_METHODS))
@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_a_wrong_argument_to_the_model_raises_only_the_projects_errors(method, data):
    good = MODEL_METHODS[method]
    name = data.draw(st.sampled_from(sorted(good)), label="argument")
    value = data.draw(JUNK, label="value")
    try:
        getattr(MODEL, method)(**{**good, name: value})
    except InputError as e:
        assert e.field == name


@pytest.mark.parametrize("call, field", [
    (lambda: MODEL.robot_pose("abc", 0), "obj"), (lambda: MODEL.car_pose(POSE, 7), "grasp"),
    (lambda: MODEL.object_from_car((0.0, 0.0), 1), "car"),
    (lambda: MODEL.held_corners(POSE, -1), "grasp"), (lambda: MODEL.pivots(POSE, "a"), "grasp"),
    (lambda: MODEL.object_corners(None), "obj")])
def test_the_model_names_its_wrong_argument(call, field):
    with pytest.raises(InputError) as e:
        call()
    assert e.value.field == field


STEP = pivot_ompl.TransferStep((0.0, 0.0), 0.1, POSE, POSE)

#: The plan's dataclasses, with valid values of each field.
PLAN_PARTS: dict[str, tuple[Any, dict[str, Any]]] = {
    "TransferStep": (pivot_ompl.TransferStep, {"pivot": (0.0, 0.0), "angle": 0.1,
                                               "object": POSE, "robot": POSE}),
    "TransferPhase": (pivot_ompl.TransferPhase, {"grasp": 0, "robot_start": POSE,
                                                 "steps": (STEP,), "object_start": POSE,
                                                 "rs_path": (POSE,)}),
    "TransitPhase": (pivot_ompl.TransitPhase, {"from_grasp": 0, "to_grasp": 1,
                                               "robot_path": (POSE, POSE), "object_pose": POSE}),
    "Plan": (pivot_ompl.Plan, {"scene": "s", "status": "exact", "object_size": (0.8, 0.6, 1.3),
                               "robot_footprint": (0.4, 0.7), "standoff": 0.25,
                               "alpha_max": 0.39, "start": POSE, "phases": [],
                               "extra": {}, "robot_model": "hrp2"}),
}


@pytest.mark.parametrize("part", sorted(PLAN_PARTS))
@settings(max_examples=40, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_a_wrong_field_of_a_plan_part_is_refused_by_name(part, data):
    """A part built with one wrong field raises InputError naming it; one built is usable:
    written and read back."""
    cls, good = PLAN_PARTS[part]
    name = data.draw(st.sampled_from(sorted(good)), label="field")
    value = data.draw(JUNK, label="value")
    try:
        made = cls(**{**good, name: value})
    except InputError as e:
        assert e.field.startswith(f"{part}.{name}")
        return
    plan = made if isinstance(made, pivot_ompl.Plan) else pivot_ompl.Plan(
        **{**PLAN_PARTS["Plan"][1], "phases": [made]} if not isinstance(
            made, pivot_ompl.TransferStep) else PLAN_PARTS["Plan"][1])
    plan.to_dict()
    _ = plan.pivots, plan.regrasps, plan.object_end


def test_a_step_of_a_string_angle_names_the_field():
    with pytest.raises(InputError) as e:
        pivot_ompl.TransferStep((0.0, 0.0), "0.1", POSE, POSE)  # type: ignore[arg-type]
    assert e.value.field == "TransferStep.angle"


# --- every public entry point, every required argument junk --------------------------------

#: Packages whose ``__all__`` is swept. Not yet: ``bench``, ``viz``, ``wholebody``,
#: ``physics`` beyond what the top level exports.
SWEPT = ["pivot_ompl", "pivot_ompl.scene", "pivot_ompl.planners", "pivot_ompl.maps",
         "pivot_ompl.humanoids", "pivot_ompl.generate"]


def _entry_points() -> list[tuple[str, Any]]:
    import importlib

    out = []
    for package in SWEPT:
        module = importlib.import_module(package)
        for name in module.__all__:
            obj = getattr(module, name)
            if not callable(obj) or inspect.isclass(obj) and issubclass(obj, BaseException):
                continue
            try:
                inspect.signature(obj)
            except (TypeError, ValueError):  # a type alias (planners.Allocator)
                continue
            out.append((f"{package}.{name}", obj))
    return out


ENTRY_POINTS = _entry_points()
#: Junk without a shipped scene's name (a valid name would plan it for 30 s).
ANY_JUNK = JUNK.filter(lambda v: v != "fig10")


@pytest.mark.parametrize("name, call", ENTRY_POINTS, ids=[n for n, _ in ENTRY_POINTS])
@settings(max_examples=15, deadline=None, suppress_health_check=list(HealthCheck))
@given(data=st.data())
def test_every_public_entry_point_raises_only_the_projects_errors(name, call, data,
                                                                  tmp_path_factory,
                                                                  monkeypatch):
    """Every required argument junk (a writer would write into a folder of the test's)."""
    monkeypatch.chdir(tmp_path_factory.mktemp("cwd"))
    params = inspect.signature(call).parameters.values()
    args, kwargs = [], {}
    for p in params:
        if p.default is not p.empty or p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
            continue
        value = data.draw(ANY_JUNK, label=p.name)
        if p.kind is p.KEYWORD_ONLY:
            kwargs[p.name] = value
        else:
            args.append(value)
    try:
        call(*args, **kwargs)
    except PivotError:
        pass


@pytest.mark.parametrize("call, field", [
    (lambda tmp: pivot_ompl.generate.scene_to_dict("open"), "scene"),
    (lambda tmp: pivot_ompl.generate.write_scene(OPEN, b"x.yaml"), "path"),
    (lambda tmp: pivot_ompl.generate.write_scene(OPEN, tmp / "x.yaml", comment=3), "comment"),
    (lambda tmp: pivot_ompl.generate.transform_scene(OPEN, (0.1, (0.0, 0.0)), name="x"), "f"),
    (lambda tmp: pivot_ompl.generate.transform_scene(
        OPEN, pivot_ompl.generate.RigidMap(0.1, (0.0, 0.0)), name=""), "name"),
    (lambda tmp: pivot_ompl.generate.RigidMap(math.nan, (0.0, 0.0)), "RigidMap.angle"),
    (lambda tmp: pivot_ompl.generate.RigidMap(0.1, (0.0,)), "RigidMap.about"),
    (lambda tmp: pivot_ompl.generate.build_witness(OPEN, [(OPEN.start, 4)]),
     "states[0].grasp"),
    (lambda tmp: pivot_ompl.generate.build_witness(OPEN, [((0.0, "1", 0.0), 0)]),
     "states[0].pose"),
    (lambda tmp: pivot_ompl.generate.build_witness(OPEN, [OPEN.start]), "states[0]"),
    (lambda tmp: pivot_ompl.generate.build_witness(OPEN, [(OPEN.start, 0)], checker=1),
     "checker"),
    (lambda tmp: pivot_ompl.generate.write_generated(OPEN, tmp), "gen"),
    (lambda tmp: pivot_ompl.generate.write_all_generated("walls", tmp), "gens"),
    (lambda tmp: pivot_ompl.generate.write_all_generated([None], tmp), "gens[0]"),
    (lambda tmp: pivot_ompl.generate.write_all_generated([], None), "out_dir"),
])
def test_the_generators_entry_points_name_their_wrong_argument(call, field, tmp_path):
    """Junk to ``pivot_ompl.generate`` is the project's InputError naming the argument."""
    with pytest.raises(InputError) as e:
        call(tmp_path)
    assert e.value.field == field
    assert not list(tmp_path.iterdir())  # nothing written


@pytest.mark.parametrize("read", [
    lambda p: pivot_ompl.simulate(p, p),
    lambda p: load_plan(p),
    lambda p: load_motion(p),
    lambda p: pivot_ompl.load_scene(p),
], ids=["simulate", "load_plan", "load_motion", "load_scene"])
def test_a_path_holding_a_nul_character_is_refused_as_a_path(read):
    """Found by the entry-point test: ``simulate("\\x00", ...)`` raised the system's
    ValueError (embedded null byte) from the file's stat, not the project's error."""
    with pytest.raises(InputError, match="NUL"):
        read("plan\x00.json")
