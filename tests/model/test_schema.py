"""Model-file schema: shapes, signs and physical admissibility; one-line error messages."""

from __future__ import annotations

import copy
from importlib.resources import files

import numpy as np
import pytest
import yaml
from pydantic import ValidationError

from uvms.model.load import format_validation_error
from uvms.model.schema import (
    LinkInertiaSpec,
    ModelSpec,
    ThrusterSpec,
    VehicleInertiaSpec,
    check_rotational_inertia,
    inertia_com,
)

PAPER = yaml.safe_load((files("uvms.model") / "models" / "paper.yaml").read_text())


def paper() -> dict:
    """A fresh, mutable copy of the bundled paper model's YAML data."""
    return copy.deepcopy(PAPER)


def error_line(data: dict) -> str:
    with pytest.raises(ValidationError) as info:
        ModelSpec.model_validate(data)
    return format_validation_error(info.value, "bad.yaml", schema=ModelSpec)


def test_paper_validates_and_is_frozen():
    spec = ModelSpec.model_validate(paper())
    assert spec.name == "paper" and len(spec.arm.links) == 3
    assert spec.arm.links[1].dh.alpha_prev == pytest.approx(-np.pi / 2, abs=1e-16)
    assert spec.environment.density == 1000.0 and len(spec.thrusters) == 4
    with pytest.raises(ValidationError):
        spec.name = "other"


def test_defaults_for_optional_sections():
    data = paper()
    del data["environment"], data["arm"], data["thrusters"]
    spec = ModelSpec.model_validate(data)
    assert spec.arm is None and spec.thrusters == ()
    # gravity not given: 9.81 m/s^2 down in the file's frame, resolved when the model is built (ned: +z)
    assert spec.frame == "ned" and spec.environment.gravity is None and spec.environment.current == (0.0, 0.0, 0.0)
    from uvms.model.build import gravity_of

    assert np.array_equal(gravity_of(spec, None), [0.0, 0.0, 9.81])


def test_paper_link_inertia_about_com_is_on_the_triangle_boundary():
    """0.0137 - 1 kg * 0.11^2 = 0.0016 on y and z, 0 on x: I_y + I_x == I_z exactly, accepted."""
    inertia = LinkInertiaSpec(diagonal=(0.0, 0.0137, 0.0137), about="joint")
    I_com = inertia_com(1.0, (0.11, 0.0, 0.0), inertia)
    np.testing.assert_allclose(I_com, np.diag([0.0, 0.0016, 0.0016]), atol=1e-12, rtol=0)
    check_rotational_inertia(I_com)
    with pytest.raises(Exception, match="triangle"):
        check_rotational_inertia(np.diag([0.0, 0.0016, 0.0016 * (1 + 1e-6)]))


def test_inertia_is_checked_about_the_com_after_the_parallel_axis_shift():
    """diag(0, 0.0137, 0.0137) about the joint with the CoM at 0.2 m gives I_yy = 0.0137 - 0.04 < 0 about the CoM."""
    data = paper()
    data["arm"]["links"][0]["com"] = [0.2, 0.0, 0.0]
    line = error_line(data)
    assert "arm.links[0].inertia.diagonal" in line and "positive semi-definite" in line


@pytest.mark.parametrize("matrix, match", [
    ([[1.0, 0.1, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], "symmetric"),
    ([[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]], "positive semi-definite"),
    ([[0.1, 0.0, 0.0], [0.0, 0.1, 0.0], [0.0, 0.0, 0.3]], "triangle"),
])
def test_rotational_inertia_checks(matrix, match):
    check_rotational_inertia(np.eye(3))
    with pytest.raises(Exception, match=match):
        check_rotational_inertia(np.array(matrix))


def test_inertia_needs_exactly_one_form():
    with pytest.raises(ValidationError, match="exactly one of 'diagonal' or 'matrix', found both"):
        VehicleInertiaSpec(diagonal=(1.0, 1.0, 1.0), matrix=np.eye(3).tolist(), about="com")
    with pytest.raises(ValidationError, match="found neither"):
        VehicleInertiaSpec(about="com")


def test_added_mass_matrix_form_and_from_geometry_accepted():
    data = paper()
    data["vehicle"]["added_mass"] = {"matrix": np.diag([2.654, 3.438, 0.249, 14.9, 18.0, 115.8]).tolist(),
                                     "about": "origin"}
    data["arm"]["links"][2]["added_mass"] = "from_geometry"
    spec = ModelSpec.model_validate(data)
    assert spec.arm.links[2].added_mass == "from_geometry"


@pytest.mark.parametrize("mutate, path, words", [
    (lambda d: d["vehicle"].update(mas=1.0), "vehicle.mas", "unknown key; expected one of: added_mass, box"),
    (lambda d: d["arm"]["links"][1].pop("mass"), "arm.links[1].mass", "expected a value (required field), found none"),
    (lambda d: d["arm"]["links"][1].update(mass=-1.0), "arm.links[1].mass", "expected a number > 0, found -1.0"),
    (lambda d: d["arm"]["links"][1].update(mass=True), "arm.links[1].mass", "expected a number, found True"),
    (lambda d: d["vehicle"].update(com=[0, 0, 0, 0]), "vehicle.com", "expected a list of 3 finite numbers"),
    (lambda d: d["vehicle"]["drag"].update(area=[0.1, -0.1, 0.1]), "vehicle.drag.area", ">= 0"),
    (lambda d: d["environment"].update(density=float("nan")), "environment.density", "finite"),
    (lambda d: d["arm"]["links"][0]["added_mass"].update(diagonal=[0, 1, 1, 0, -1, 1]),
     "arm.links[0].added_mass.diagonal", "positive semi-definite added-mass matrix"),
    (lambda d: d["arm"]["links"][0].update(added_mass="strip_theory"), "arm.links[0].added_mass",
     "expected 'from_geometry' or a mapping"),
    (lambda d: d["arm"]["links"][0]["inertia"].update(about="origin"), "arm.links[0].inertia.about",
     "expected 'com' or 'joint', found 'origin'"),
    (lambda d: d["arm"]["links"][2].update(name="link1"), "arm.links", "unique link names"),
])
def test_one_line_errors_name_the_field(mutate, path, words):
    data = paper()
    mutate(data)
    line = error_line(data)
    assert line.startswith(f"bad.yaml: {path}: ") and words in line
    assert "\n" not in line


def test_several_errors_still_one_line():
    data = paper()
    del data["vehicle"]["mass"], data["vehicle"]["box"]
    line = error_line(data)
    assert "\n" not in line and line.endswith("(and 1 more error)")


def test_thruster_spec():
    t = ThrusterSpec(name="surge_left", position=(0.0, -0.15, 0.0), direction=(1.0, 0.0, 0.0), model="healey",
                     parameters={"R": 0.05}, max_thrust=50.0)
    assert t.direction == (1.0, 0.0, 0.0) and t.parameters == {"R": 0.05}
    with pytest.raises(ValidationError, match="non-zero direction"):
        ThrusterSpec(name="t", position=(0.0, 0.0, 0.0), direction=(0.0, 0.0, 0.0), model="ideal")
    with pytest.raises(ValidationError, match="unique thruster names"):
        ModelSpec.model_validate({**paper(), "thrusters": [t.model_dump(), t.model_dump()]})


def test_thruster_parameters_are_checked(tmp_path):
    """An unknown Healey parameter is one line naming thrusters[i].parameters.<key>."""
    import yaml

    from uvms.errors import UvmsInputError
    from uvms.model.load import load_model, resolve_model_path

    data = yaml.safe_load(resolve_model_path("paper").read_text())
    data["thrusters"][1]["parameters"] = {"pitchh": 0.4}
    path = tmp_path / "bad_thruster.yaml"
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(UvmsInputError) as info:
        load_model(path)
    assert "thrusters[1].parameters.pitchh" in str(info.value) and "\n" not in str(info.value)
    data["thrusters"][1]["parameters"] = {"pitch": 0.5}
    path.write_text(yaml.safe_dump(data))
    assert load_model(path).thrusters[1].parameters.pitch == 0.5
