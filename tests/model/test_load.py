"""Loading model files: bundled names and paths, values landing in the right Model fields, input errors."""

from __future__ import annotations

import copy
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
import yaml

from uvms.errors import UvmsInputError
from uvms.hydro.added_mass import cylinder_added_mass
from uvms.model import Model, build_model, bundled_models, load_model
from uvms.model.schema import ModelSpec
from uvms.spatial import rotx, rotz, shift_spatial_inertia

PAPER_PATH = Path(str(files("uvms.model") / "models" / "paper.yaml"))
PAPER = yaml.safe_load(PAPER_PATH.read_text())
LINK_ADDED_MASS = np.diag([0.0, 0.0017, 0.0017, 0.0, 0.1078, 0.1078])


def build(mutate=None) -> Model:
    """The paper model with its YAML data changed in place by ``mutate``."""
    data = copy.deepcopy(PAPER)
    if mutate is not None:
        mutate(data)
    return build_model(ModelSpec.model_validate(data), None)


@pytest.fixture(scope="module")
def model() -> Model:
    return load_model("paper")


def test_bundled_models_lists_paper():
    assert "paper" in bundled_models()


def test_by_name_and_by_path_agree(model, tmp_path):
    copy_path = tmp_path / "copy.yaml"
    copy_path.write_text(PAPER_PATH.read_text())
    for other in (load_model(PAPER_PATH), load_model(str(copy_path))):
        for field in ("mass", "inertia_com", "added_mass", "joint_rotation", "joint_position", "ee_position"):
            np.testing.assert_array_equal(getattr(other, field), getattr(model, field))
    assert model.source == str(PAPER_PATH) and load_model(copy_path).source == str(copy_path)


def test_numbers_without_a_dot_in_exponent_form_are_numbers(model, tmp_path):
    """``3.2e1`` is a float in YAML 1.1, ``32e0`` only in YAML 1.2: model files accept both."""
    text = PAPER_PATH.read_text()
    data = yaml.safe_load(text)
    assert data["vehicle"]["mass"] == 32.0
    path = tmp_path / "exp.yaml"
    path.write_text(text.replace("mass: 32.0", "mass: 32e0", 1))
    assert "mass: 32e0" in path.read_text()
    np.testing.assert_array_equal(load_model(path).mass, model.mass)


def test_paper_bodies(model):
    assert model.name == "paper" and model.n_joints == 3
    assert model.body_names == ("vehicle", "link1", "link2", "link3")
    np.testing.assert_array_equal(model.mass, [32.0, 1.0, 1.0, 1.0])
    np.testing.assert_array_equal(model.com, [[0, 0, 0], [0.11, 0, 0], [0.11, 0, 0], [0.11, 0, 0]])
    np.testing.assert_array_equal(model.inertia_com[0], np.diag([0.498, 0.878, 1.254]))
    for i in (1, 2, 3):  # appendix diag(0, 0.0137, 0.0137) about the joint, minus m * 0.11^2
        np.testing.assert_allclose(model.inertia_com[i], np.diag([0.0, 0.0016, 0.0016]), atol=1e-12, rtol=0)
        np.testing.assert_array_equal(model.added_mass[i], LINK_ADDED_MASS)
    np.testing.assert_array_equal(model.added_mass[0], np.diag([2.654, 3.438, 0.249, 14.9, 18.0, 115.8]))
    np.testing.assert_array_equal(model.buoyancy_mass, [32.0, 1.0, 1.0, 1.0])
    np.testing.assert_array_equal(model.cob, [[0, 0, -0.0254], [0.11, 0, 0], [0.11, 0, 0], [0.11, 0, 0]])


def test_paper_hydrodynamics_and_environment(model):
    np.testing.assert_array_equal(model.vehicle_drag_area, [0.061] * 3)
    np.testing.assert_array_equal(model.vehicle_drag_coefficient, [1.07] * 3)
    assert (model.vehicle_rotational_drag_side, model.vehicle_rotational_drag_coefficient) == (0.596, 1.07)
    np.testing.assert_array_equal(model.vehicle_box, [0.596] * 3)
    np.testing.assert_array_equal(model.link_radius, [0.0125] * 3)
    np.testing.assert_array_equal(model.link_length, [0.22] * 3)
    np.testing.assert_array_equal(model.link_drag_coefficient, [1.1] * 3)
    assert model.density == 1000.0
    # the paper's layout plus a sway thruster, all Healey, equal to the bundled "paper-sway" layout
    from uvms.thrusters.layouts import layout, layout_matrix

    assert [t.name for t in model.thrusters] == ["surge_port", "surge_starboard", "heave", "sway"]
    assert all(t.model == "healey" for t in model.thrusters)
    np.testing.assert_allclose(layout_matrix(model.thrusters), layout_matrix(layout("paper-sway")))
    np.testing.assert_array_equal(model.gravity, [0, 0, 9.81])
    np.testing.assert_array_equal(model.current, [0, 0, 0])
    np.testing.assert_array_equal(model.fluid_acceleration, [0, 0, 0])


def test_paper_kinematics_table_1(model):
    np.testing.assert_allclose(model.joint_rotation, [np.eye(3), rotx(-np.pi / 2), np.eye(3)], atol=1e-15)
    np.testing.assert_array_equal(model.joint_position, [[0, 0, 0], [0.22, 0, 0], [0.22, 0, 0]])
    np.testing.assert_array_equal(model.theta_offset, [0, 0, 0])
    np.testing.assert_array_equal(model.ee_rotation, np.eye(3))
    np.testing.assert_array_equal(model.ee_position, [0.22, 0, 0])


def test_mount_applies_to_joint_1_only():
    def mount(d):
        d["arm"]["mount"] = {"position": [0.1, 0.2, 0.3], "rotation_rpy": [0.0, 0.0, np.pi / 2]}
        d["arm"]["links"][0]["dh"].update(a_prev=0.05, theta_offset=0.3)

    model = build(mount)
    np.testing.assert_allclose(model.joint_rotation[0], rotz(np.pi / 2), atol=1e-15)
    np.testing.assert_allclose(model.joint_position[0], [0.1, 0.2 + 0.05, 0.3], atol=1e-15)
    np.testing.assert_allclose(model.joint_rotation[1], rotx(-np.pi / 2), atol=1e-15)
    np.testing.assert_array_equal(model.theta_offset, [0.3, 0, 0])


def test_about_com_and_from_geometry_added_mass():
    I_A = np.diag([2.654, 3.438, 0.249, 14.9, 18.0, 115.8])

    def change(d):
        d["vehicle"]["com"] = [0.01, 0.0, 0.02]
        d["arm"]["links"][0]["added_mass"] = {"diagonal": list(np.diag(LINK_ADDED_MASS)), "about": "com"}
        d["arm"]["links"][1]["added_mass"] = "from_geometry"
        d["arm"]["links"][2]["inertia"] = {"matrix": np.diag([0.0, 0.0016, 0.0016]).tolist(), "about": "com"}

    model = build(change)
    np.testing.assert_array_equal(model.added_mass[0], shift_spatial_inertia(I_A, np.array([0.01, 0.0, 0.02])))
    np.testing.assert_array_equal(model.added_mass[1], shift_spatial_inertia(LINK_ADDED_MASS, np.array([0.11, 0, 0])))
    assert model.added_mass[1][2, 4] == pytest.approx(0.1078 * 0.11)  # coupling from the shift
    np.testing.assert_array_equal(model.added_mass[2], cylinder_added_mass(1000.0, 0.0125, 0.22))
    np.testing.assert_array_equal(model.inertia_com[3], np.diag([0.0, 0.0016, 0.0016]))


def test_vehicle_without_arm_has_empty_joint_arrays():
    model = build(lambda d: d.pop("arm"))
    assert model.n_joints == 0 and model.n_dof == 6 and model.body_names == ("vehicle",)
    assert model.joint_rotation.shape == (0, 3, 3) and model.joint_position.shape == (0, 3)
    assert model.theta_offset.shape == model.link_radius.shape == model.link_drag_coefficient.shape == (0,)
    assert model.added_mass.shape == (1, 6, 6) and model.inertia_com.shape == (1, 3, 3)
    np.testing.assert_array_equal(model.ee_rotation, np.eye(3))


@pytest.mark.parametrize("content, where", [
    ("name: x\nvehicle: [1, 2\n  mass: 3\n", "line 3, column 7: invalid YAML"),
    ("name: x\nname: y\n", "line 2, column 1: invalid YAML: duplicate key 'name'"),
    ("", "expected a mapping of model fields at the top level, found an empty file"),
    ("- 1\n- 2\n", "found a list: is this a uvms file?"),      # the kind of value, never the content
    ("name: x\nvehicle: {mass: 0}\n", "vehicle.mass: expected a number > 0, found 0"),
])
def test_input_errors_are_one_line(tmp_path, content, where):
    path = tmp_path / "bad.yaml"
    path.write_text(content)
    with pytest.raises(UvmsInputError) as info:
        load_model(path)
    assert str(info.value).startswith(f"{path}: ") and where in str(info.value)
    assert "\n" not in str(info.value) and info.value.source == str(path)


def test_missing_file_or_name(tmp_path):
    with pytest.raises(UvmsInputError, match=r"no such file or bundled model \(bundled: .*paper"):
        load_model("no_such_model")
    with pytest.raises(UvmsInputError, match="no such file"):
        load_model(tmp_path / "missing.yaml")
    with pytest.raises(UvmsInputError, match="found a directory"):
        load_model(tmp_path)


@pytest.mark.parametrize("parameters, field", [
    ("{foo: 1}", "thrusters[0].parameters.foo: unknown healey parameter"),
    ("{time_constant: 0.1}", "thrusters[0].parameters.time_constant: unknown healey parameter"),
    ("{max_voltage: -24}", "thrusters[0].parameters"),
])
def test_thruster_parameter_errors_name_the_file(tmp_path, parameters, field):
    text = (files("uvms.model") / "models" / "paper.yaml").read_text()
    line = next(ln for ln in text.splitlines() if ln.strip().startswith("- {name: surge_port"))
    path = tmp_path / "thr.yaml"
    path.write_text(text.replace(line, line.replace("model: healey}", f"model: healey, parameters: {parameters}}}")))
    with pytest.raises(UvmsInputError) as info:
        load_model(path)
    assert str(info.value).startswith(f"{path}: {field}")


def test_a_model_file_is_built_once_until_it_changes(tmp_path):
    """A sweep loads one model file for every run: the built (immutable) model is reused until the file
    changes."""
    import os
    import shutil

    import uvms
    from uvms.model.load import resolve_model_path

    path = tmp_path / "paper.yaml"
    shutil.copy(resolve_model_path("paper"), path)
    first = uvms.load_model(path)
    assert uvms.load_model(str(path)) is first
    text = path.read_text().replace("mass: 32.0", "mass: 33.0", 1)
    assert text != path.read_text()
    path.write_text(text)
    os.utime(path, ns=(os.stat(path).st_atime_ns, os.stat(path).st_mtime_ns + 10**9))
    second = uvms.load_model(path)
    assert second is not first and second.mass[0] == 33.0
