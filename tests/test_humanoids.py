"""Humanoid profiles: the registry, Talos from its URDF and SRDF, and the model in scenes,
plans and motions."""

from __future__ import annotations

import dataclasses
import json
from importlib import metadata

import numpy as np
import pinocchio as pin
import pytest

from pivot_ompl.errors import InputError, PlanFileError, SceneError
from pivot_ompl.grasp import BoxGraspModel
from pivot_ompl.humanoids import (
    DEFAULT_MODEL,
    FRAMES,
    PROFILES,
    model_of_urdf,
    profile_of,
    talos_data,
    urdf_file,
)
from pivot_ompl.planfile import Plan, load_plan, plan_from_dict
from pivot_ompl.scene import scene_from_dict

TALOS = PROFILES["talos"]
HRP2 = PROFILES["hrp2"]

SCENE = {"name": "t", "bounds": [-4, -4, 6, 7], "object": {"size": [0.8, 0.6, 1.3]},
         "start": [0, 0, 0], "goal": [0.5, 3, 0]}


def test_the_registry_names_both_robots_and_refuses_others():
    assert set(PROFILES) == {"hrp2", "talos"} and DEFAULT_MODEL == "hrp2"
    assert profile_of(None) is HRP2
    with pytest.raises(InputError) as e:
        profile_of("asimo", field="robot.model")
    assert e.value.field == "robot.model" and "talos" in e.value.reason
    for p in PROFILES.values():
        assert model_of_urdf(p.urdf_name) == p.name


@pytest.fixture(scope="module")
def talos():
    path = TALOS.urdf_path()
    model = pin.buildModelFromUrdf(str(path), pin.JointModelFreeFlyer())
    geom = pin.buildGeomFromUrdf(model, str(path), pin.GeometryType.COLLISION)
    return model, geom


def _half_sitting(model, profile) -> np.ndarray:
    q = pin.neutral(model)
    for name, v in profile.half_sitting.items():
        q[model.joints[model.getJointId(name)].idx_q] = v
    return q


def test_talos_urdf_has_the_frames_and_its_half_sitting_is_the_srdfs(talos):
    model, _ = talos
    for name in FRAMES:
        assert model.existFrame(name), name
    hs = dict(TALOS.half_sitting)
    assert len(hs) == 30 and hs["leg_left_4_joint"] == pytest.approx(0.859395)
    q = _half_sitting(model, TALOS)
    assert np.all(q[7:] >= model.lowerPositionLimit[7:] - 1e-9)
    assert np.all(q[7:] <= model.upperPositionLimit[7:] + 1e-9)
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    # the foot frame lies on the sole link's plane, under the ankle
    for side in ("left", "right"):
        foot = data.oMf[model.getFrameId(f"{side}_foot")].translation
        sole = data.oMf[model.getFrameId(f"{side}_sole_link")].translation
        assert foot[2] == pytest.approx(sole[2], abs=1e-9)
        assert np.linalg.norm(foot[:2] - sole[:2]) == pytest.approx(0.00587, abs=1e-4)


def test_talos_sole_is_its_foot_collision_mesh(talos):
    model, geom = talos
    data, gdata = model.createData(), geom.createData()
    q = pin.neutral(model)
    pin.updateGeometryPlacements(model, data, geom, gdata, q)
    pin.framesForwardKinematics(model, data, q)
    i = next(k for k, g in enumerate(geom.geometryObjects) if g.name.startswith("leg_left_6"))
    pts = np.asarray(geom.geometryObjects[i].geometry.vertices())
    world = (gdata.oMg[i].rotation @ pts.T).T + gdata.oMg[i].translation
    foot = data.oMf[model.getFrameId("left_foot")]
    local = (foot.rotation.T @ (world - foot.translation).T).T
    length, width = np.ptp(local[:, 0]), np.ptp(local[:, 1])
    assert (length, width) == pytest.approx(TALOS.sole_size, abs=5e-4)
    # centred on the foot frame, and its underside on the floor plane of the frame
    assert 0.5 * (local[:, 0].max() + local[:, 0].min()) == pytest.approx(0.0, abs=5e-4)
    assert local[:, 2].min() == pytest.approx(0.0, abs=1e-3)


def test_talos_height_and_floor_box_match_its_meshes(talos):
    model, geom = talos
    data, gdata = model.createData(), geom.createData()
    q = _half_sitting(model, TALOS)
    pin.framesForwardKinematics(model, data, q)
    q[2] -= data.oMf[model.getFrameId("left_foot")].translation[2]
    pin.framesForwardKinematics(model, data, q)
    pin.updateGeometryPlacements(model, data, geom, gdata, q)
    pts = np.vstack([(m.rotation @ np.asarray(g.geometry.vertices()).T).T + m.translation
                     for g, m in zip(geom.geometryObjects, gdata.oMg, strict=True)
                     if hasattr(g.geometry, "vertices")])
    mid = 0.5 * (data.oMf[model.getFrameId("left_foot")].translation
                 + data.oMf[model.getFrameId("right_foot")].translation)
    depth, width = TALOS.footprint
    assert -0.5 * depth <= pts[:, 0].min() - mid[0] and pts[:, 0].max() - mid[0] <= 0.5 * depth
    assert np.abs(pts[:, 1] - mid[1]).max() <= 0.5 * width + 0.15  # arms: the envelope's
    q0 = pin.neutral(model)
    pin.framesForwardKinematics(model, data, q0)
    pin.updateGeometryPlacements(model, data, geom, gdata, q0)
    top = max(float(((m.rotation @ np.asarray(g.geometry.vertices()).T).T
                     + m.translation)[:, 2].max())
              for g, m in zip(geom.geometryObjects, gdata.oMg, strict=True)
              if hasattr(g.geometry, "vertices"))
    assert top - data.oMf[model.getFrameId("left_foot")].translation[2] == pytest.approx(
        TALOS.height, abs=5e-3)


def test_a_missing_package_is_a_clear_input_error(monkeypatch):
    def missing(name):
        raise metadata.PackageNotFoundError(name)

    monkeypatch.setattr(talos_data.metadata, "distribution", missing)
    with pytest.raises(InputError) as e:
        talos_data.talos_dir()
    assert e.value.field == "robot.model" and 'pivot-ompl[talos]' in e.value.reason


def test_a_scene_chooses_the_robot_and_its_defaults():
    s = scene_from_dict({**SCENE, "robot": {"model": "talos"}})
    assert s.robot_model == "talos" and s.model.robot_model == "talos"
    assert s.model.robot_footprint == TALOS.footprint and s.model.robot_height == TALOS.height
    assert s.walk.step_forward == TALOS.step_forward
    assert s.model.walking_extent()[2] == pytest.approx(TALOS.walk_envelope[2])
    default = scene_from_dict(SCENE)
    assert default.robot_model == "hrp2" and default.model.robot_footprint == HRP2.footprint
    with pytest.raises(SceneError) as e:
        scene_from_dict({**SCENE, "robot": {"model": "asimo"}})
    assert e.value.field == "robot.model"


def test_a_scene_footprint_is_only_ever_more_cautious():
    small = scene_from_dict({**SCENE, "robot": {"model": "talos", "footprint": [0.3, 1.0]}})
    assert small.model.robot_footprint == (TALOS.footprint[0], 1.0)
    big = scene_from_dict({**SCENE, "robot": {"model": "hrp2", "footprint": [0.45, 0.85]}})
    assert big.model.robot_footprint == (0.45, 0.85)


def test_the_held_body_follows_the_profile():
    a = BoxGraspModel((0.8, 0.6, 1.3), robot_model="hrp2")
    b = BoxGraspModel((0.8, 0.6, 1.3), robot_model="talos")
    assert a.held_polygons(0) != b.held_polygons(0)
    with pytest.raises(InputError):
        BoxGraspModel((0.8, 0.6, 1.3), robot_model="asimo")


def test_plans_record_the_model_compatibly(tmp_path):
    plan = Plan("t", "exact", (0.8, 0.6, 1.3), (0.5, 0.8), 0.25, 0.39, (0.0, 0.0, 0.0),
                robot_model="talos")
    doc = plan.to_dict()
    assert doc["robot_model"] == "talos"
    assert load_plan(plan.to_json(tmp_path / "p.json")).robot_model == "talos"
    hrp2 = dataclasses.replace(plan, robot_model="hrp2")
    assert "robot_model" not in hrp2.to_dict()  # HRP-2's plans are unchanged
    assert plan_from_dict(json.loads(hrp2.to_text())).robot_model == "hrp2"
    with pytest.raises(PlanFileError) as e:
        plan_from_dict({**doc, "robot_model": "asimo"})
    assert e.value.field == "robot_model"


def test_a_motions_urdf_name_resolves_through_its_profile():
    assert urdf_file(TALOS.urdf_name) == TALOS.urdf_path()
    assert urdf_file(HRP2.urdf_name).is_file()
    with pytest.raises(InputError):
        urdf_file("elsewhere/robot.urdf")


def test_the_robots_verb_lists_every_profile(capsys):
    from pivot_ompl.cli import main

    assert main(["robots", "--json"]) == 0
    rows = json.loads(capsys.readouterr().out)
    assert [r["model"] for r in rows] == list(PROFILES)
    talos = next(r for r in rows if r["model"] == "talos")
    assert talos["installed"] == "yes" and talos["footprint_m"] == list(TALOS.footprint)
    assert main(["robots"]) == 0
    assert "talos" in capsys.readouterr().out


def test_scene_digests_of_the_default_model_are_unchanged_and_name_another():
    from pivot_ompl.scene import load_scene, scene_digest

    # the digest main recorded for the shipped slot scene before profiles existed
    assert scene_digest(load_scene("slot")) == (
        "40a3ce1b7fee06ba2b4ff9462aa5afcc91cad9e8e35bb6449751d90477bf5e51")
    a = scene_from_dict({**SCENE, "robot": {"model": "talos", "footprint": [0.5, 0.8]}})
    b = scene_from_dict({**SCENE, "robot": {"model": "hrp2", "footprint": [0.5, 0.8]}})
    assert a.model.robot_footprint == b.model.robot_footprint
    assert scene_digest(a) != scene_digest(b)
