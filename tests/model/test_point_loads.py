"""Point loads (``point_loads:`` in a model file, :mod:`uvms.model.loads`): folded into each body's mass, centre
of mass, inertia, displaced fluid and centre of buoyancy, checked against totals computed here by hand (first
moments, the parallel-axis theorem written as ``m (|r|^2 1 - r r^T)``, rotations written out), and the kernel's
gravity force against ``weight x lever`` by hand."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

import uvms
from uvms.errors import UvmsInputError

MODELS = Path(uvms.__file__).parent / "model" / "models"


def parallel_axis(m: float, r) -> np.ndarray:
    """Inertia of a point mass ``m`` at offset ``r`` about the origin: ``m (|r|^2 1 - r r^T)``."""
    r = np.asarray(r, dtype=float)
    return m * (r @ r * np.eye(3) - np.outer(r, r))


def paper_with(tmp_path, **extra) -> uvms.Model:
    """The paper's DH model with extra top-level keys, written to ``tmp_path``."""
    data = yaml.safe_load((MODELS / "paper.yaml").read_text())
    data.update(extra)
    path = tmp_path / "model.yaml"
    path.write_text(yaml.safe_dump(data))
    return uvms.load_model(path)


def test_point_mass_and_foam_fold_into_the_vehicle(tmp_path):
    base = uvms.load_model("paper")
    loads = [{"name": "lead", "body": "vehicle", "position": [0.3, -0.1, 0.2], "mass": 2.0},
             {"name": "foam", "body": "vehicle", "position": [-0.1, 0.05, -0.25], "volume": 0.003}]
    model = paper_with(tmp_path, point_loads=loads)
    m0, c0, I0 = base.mass[0], base.com[0], base.inertia_com[0]
    r = np.array([0.3, -0.1, 0.2])
    m = m0 + 2.0
    c = (m0 * c0 + 2.0 * r) / m
    I = I0 + parallel_axis(m0, c0 - c) + parallel_axis(2.0, r - c)
    assert model.mass[0] == pytest.approx(m, rel=1e-15)
    np.testing.assert_allclose(model.com[0], c, rtol=0, atol=1e-15)
    np.testing.assert_allclose(model.inertia_com[0], I, rtol=1e-13, atol=1e-15)
    rho = base.density
    mf0, b0, rb = base.buoyancy_mass[0], base.cob[0], np.array([-0.1, 0.05, -0.25])
    mf = mf0 + rho * 0.003
    assert model.buoyancy_mass[0] == pytest.approx(mf, rel=1e-15)
    np.testing.assert_allclose(model.cob[0], (mf0 * b0 + rho * 0.003 * rb) / mf, rtol=0, atol=1e-15)
    # an inertial point mass weighs as it is: no separate weight, and the links are untouched
    assert model.dry_mass is None
    np.testing.assert_array_equal(model.weight_mass, model.mass)
    np.testing.assert_array_equal(model.mass[1:], base.mass[1:])
    np.testing.assert_array_equal(model.inertia_com[1:], base.inertia_com[1:])


def test_inertia_about_the_origin_is_the_sum_of_the_parts(tmp_path):
    """The same fold seen another way: about the body origin, inertias simply add (Steiner both ways)."""
    base = uvms.load_model("paper")
    model = paper_with(tmp_path, point_loads=[{"name": "p", "body": base.body_names[2], "position": [0.05, 0.02, -0.03],
                                              "mass": 0.4}])
    about_origin = lambda mdl: mdl.inertia_com[2] + parallel_axis(mdl.mass[2], mdl.com[2])
    np.testing.assert_allclose(about_origin(model), about_origin(base) + parallel_axis(0.4, [0.05, 0.02, -0.03]),
                               rtol=1e-13, atol=1e-16)


URDF = """<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial><origin xyz="0 0 0.01"/><mass value="10"/><inertia ixx="0.2" ixy="0" ixz="0" iyy="0.3" iyz="0" izz="0.4"/></inertial>
  </link>
  <joint name="mount" type="fixed">
    <parent link="base"/><child link="sensor"/><origin xyz="0.2 0.1 -0.05" rpy="0 0 1.5707963267948966"/>
  </joint>
  <link name="sensor"/>
  <joint name="j" type="revolute">
    <parent link="base"/><child link="arm"/><origin xyz="0.1 0 0.2"/><axis xyz="0 1 0"/>
  </joint>
  <link name="arm">
    <inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>
"""


def urdf_model(tmp_path, additions: dict) -> uvms.Model:
    (tmp_path / "r.urdf").write_text(URDF)
    path = tmp_path / "r.yaml"
    path.write_text(yaml.safe_dump({"urdf": "r.urdf", **additions}))
    return uvms.load_model(path)


def test_a_load_on_a_merged_link_is_placed_through_its_frame(tmp_path):
    """``sensor`` is fixed to ``base`` turned 90 deg about z: its x is the body's y."""
    model = urdf_model(tmp_path, {"point_loads": [
        {"name": "dvl", "body": "sensor", "position": [0.1, 0.0, 0.0], "mass": 1.0, "buoyancy": 0.5}]})
    r = np.array([0.2, 0.1, -0.05]) + np.array([0.0, 0.1, 0.0])      # Rz(90 deg) (0.1, 0, 0) = (0, 0.1, 0)
    c = (10.0 * np.array([0, 0, 0.01]) + 1.0 * r) / 11.0
    assert model.mass[0] == pytest.approx(11.0)
    np.testing.assert_allclose(model.com[0], c, atol=1e-15)
    np.testing.assert_allclose(model.inertia_com[0], np.diag([0.2, 0.3, 0.4]) + parallel_axis(10.0, [0, 0, 0.01] - c)
                               + parallel_axis(1.0, r - c), rtol=1e-13, atol=1e-15)
    assert model.buoyancy_mass[0] == pytest.approx(0.5)
    np.testing.assert_allclose(model.cob[0], r, atol=1e-15)          # the only displaced fluid of the body


def test_a_weight_only_load_weighs_without_inertia(tmp_path):
    plain = urdf_model(tmp_path, {})
    model = urdf_model(tmp_path, {"point_loads": [
        {"name": "w", "body": "arm", "position": [0.0, 0.0, 0.3], "mass": 0.5, "inertial": False}]})
    np.testing.assert_array_equal(model.mass, plain.mass)
    np.testing.assert_array_equal(model.inertia_com, plain.inertia_com)
    np.testing.assert_allclose(model.weight_mass, [10.0, 1.5])
    np.testing.assert_allclose(model.weight_center[1], (1.0 * np.array([0, 0, 0.1]) + 0.5 * np.array([0, 0, 0.3])) / 1.5)
    # the dynamics weighs it: gravity on the arm is 1.5 kg at (0, 0, 0.1667) (arm frame = world axes at rest)
    state = uvms.State.zero(model)
    gravity = uvms.hydrodynamic_wrenches(model, state).wrenches["gravity"][1]
    g = np.array([0.0, 0.0, 9.81])
    lever = np.array([0.0, 0.0, (0.1 + 0.15) / 1.5])
    np.testing.assert_allclose(gravity[3:], 1.5 * g, rtol=1e-14)
    np.testing.assert_allclose(gravity[:3], np.cross(lever, 1.5 * g), atol=1e-14)


@pytest.mark.parametrize("load, message", [
    ({"name": "a", "body": "nowhere", "position": [0, 0, 0], "mass": 1.0},
     "point_loads[0].body: names 'nowhere', which is not a body or link of the model (links: base, sensor, arm)"),
    ({"name": "a", "body": "base", "position": [0, 0, 0], "buoyancy": 1.0, "volume": 0.001},
     "point_loads[0]: expected at most one of 'buoyancy' (kg) or 'volume' (m^3), found both"),
    ({"name": "a", "body": "base", "position": [0, 0, 0]},
     "point_loads[0]: expected a 'mass', a 'buoyancy' or a 'volume', found none"),
    ({"name": "a", "body": "base", "position": [0, 0, 0], "volume": 0.001, "inertial": False},
     "point_loads[0].inertial: expected a 'mass' for inertial: false"),
    ({"name": "a", "body": "base", "position": [0, 0, 0], "mass": -1.0}, "point_loads[0].mass"),
])
def test_bad_point_loads_are_one_line(tmp_path, load, message):
    with pytest.raises(UvmsInputError) as info:
        urdf_model(tmp_path, {"point_loads": [load]})
    text = str(info.value)
    assert "\n" not in text and message in text and "r.yaml" in text


def test_point_load_names_are_unique(tmp_path):
    load = {"name": "a", "body": "base", "position": [0, 0, 0], "mass": 1.0}
    with pytest.raises(UvmsInputError, match="expected unique point load names, found 'a' twice"):
        urdf_model(tmp_path, {"point_loads": [load, load]})


def test_ballast_of_trim_is_the_same_fold():
    """``uvms trim``'s ballast goes through the one fold: a ballast point at r gives the hand-computed inertia."""
    from uvms.analysis.trim import Ballast, with_ballast

    base = uvms.load_model("paper")
    ballast = Ballast(kind="mass", amount=1.5, mass_kg=1.5, displaced_mass_kg=0.0, position_m=np.array([0.1, 0.2, -0.1]),
                      region_m=np.zeros((2, 3)), net_buoyancy_after_N=0.0, righting_arm_after_m=0.0)
    model = with_ballast(base, ballast)
    m0, c0 = base.mass[0], base.com[0]
    c = (m0 * c0 + 1.5 * ballast.position_m) / (m0 + 1.5)
    np.testing.assert_allclose(model.inertia_com[0], base.inertia_com[0] + parallel_axis(m0, c0 - c)
                               + parallel_axis(1.5, ballast.position_m - c), rtol=1e-13, atol=1e-15)
    assert math.isclose(model.mass[0], m0 + 1.5)
