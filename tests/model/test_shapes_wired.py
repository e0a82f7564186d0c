"""Hydrodynamic shapes in model files: buoyancy and added mass at build time, drag in the compiled dynamics,
``from_collision`` reading a URDF's primitives; bad shapes are one line naming the file and the field."""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

import uvms
from uvms.cli import main
from uvms.dynamics.plant import kernel_model
from uvms.errors import UvmsInputError
from uvms.state import State
from tests.helpers import assert_model_file_refused

RHO = 1025.0
URDF = """<?xml version="1.0"?>
<robot name="probe">
  <link name="hull">
    <inertial><origin xyz="0 0 0"/><mass value="{mass}"/>
      <inertia ixx="{i}" iyy="{i}" izz="{i}" ixy="0" ixz="0" iyz="0"/></inertial>
    {collision}
  </link>
</robot>
"""


def write(tmp_path, *, vehicle, collision="", mass=10.0, inertia=0.5, gravity=(0.0, 0.0, 9.81)):
    (tmp_path / "probe.urdf").write_text(URDF.format(mass=mass, i=inertia, collision=collision), encoding="utf-8")
    path = tmp_path / "probe.yaml"
    path.write_text(yaml.safe_dump({"urdf": "probe.urdf", "environment": {"density": RHO, "gravity": list(gravity)},
                                    "vehicle": vehicle}), encoding="utf-8")
    return path


def test_sphere_gives_half_displaced_mass_and_buoyancy_at_its_centre(tmp_path):
    a, c = 0.2, [0.05, -0.02, 0.03]
    model = uvms.load_model(write(tmp_path, vehicle={"shapes": [{"type": "sphere", "radius": a, "position": c}]}))
    V = 4.0 / 3.0 * math.pi * a**3
    # Lamb (1932): a sphere's added mass is half the displaced fluid mass, no rotational added mass; at the centre
    A_c = np.diag([0, 0, 0, RHO * V / 2, RHO * V / 2, RHO * V / 2])
    # moved to the body origin: the same congruence as a point mass m at c (Featherstone 2008, Eq. 2.63)
    m, S = RHO * V / 2, np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
    expected = A_c.copy()
    expected[:3, :3] = -m * S @ S
    expected[:3, 3:] = m * S
    expected[3:, :3] = -m * S
    np.testing.assert_allclose(model.added_mass[0], expected, rtol=1e-12, atol=1e-12)
    assert model.buoyancy_mass[0] == pytest.approx(RHO * V, rel=1e-14)
    np.testing.assert_allclose(model.cob[0], c, rtol=0, atol=1e-15)


def test_explicit_added_mass_and_buoyancy_override_shapes(tmp_path):
    model = uvms.load_model(write(tmp_path, vehicle={
        "shapes": [{"type": "sphere", "radius": 0.2}],
        "added_mass": {"diagonal": [1, 1, 1, 2, 2, 2], "about": "origin"},
        "buoyancy": {"mass": 3.0, "center": [0, 0, 0]}}))
    np.testing.assert_array_equal(model.added_mass[0], np.diag([1.0, 1, 1, 2, 2, 2]))
    assert model.buoyancy_mass[0] == 3.0


def test_cube_rotational_drag_through_the_dynamics_is_eq4(tmp_path):
    """A cube of side a with Cd on every face, spinning at omega about z (no gravity, no added mass): the
    dynamics gives I nu_dot = -rho Cd a^5 / 32 omega |omega| (paper Eq. 4, the strip integral)."""
    a, cd, inertia, w = 0.4, 1.1, 0.5, 2.3
    model = uvms.load_model(write(tmp_path, gravity=(0.0, 0.0, 0.0), inertia=inertia, vehicle={
        "shapes": [{"type": "box", "size": [a, a, a], "drag_coefficients": [cd, cd, cd]}],
        "added_mass": {"diagonal": [0, 0, 0, 0, 0, 0], "about": "origin"},
        "buoyancy": {"mass": 0.0, "center": [0, 0, 0]}}))
    state = State.from_euler(model, nu=[0, 0, w, 0, 0, 0])
    nu_dot = uvms.forward_dynamics(model, state).nu_dot
    expected = -RHO * cd * a**5 / 32.0 * w * abs(w) / inertia
    assert nu_dot[2] == pytest.approx(expected, rel=1e-12)
    np.testing.assert_allclose(nu_dot[[0, 1, 3, 4, 5]], 0.0, atol=1e-12)
    # switching drag off removes it (the shape drag is drag)
    off = uvms.forward_dynamics(model.with_effects(drag=False), state).nu_dot
    assert off[2] == 0.0
    # drag uses the model's density directly (a scenario's density override)
    dense = uvms.forward_dynamics(model.replace(density=2 * RHO), state).nu_dot
    assert dense[2] == pytest.approx(2 * expected, rel=1e-12)


def test_from_collision_reads_the_urdf_primitives(tmp_path):
    collision = """<collision><origin xyz="0.1 0 0"/><geometry><box size="0.2 0.3 0.4"/></geometry></collision>
    <collision><origin xyz="0 0 0.2"/><geometry><cylinder radius="0.05" length="0.5"/></geometry></collision>
    <collision><origin xyz="0 -0.2 0"/><geometry><sphere radius="0.1"/></geometry></collision>"""
    model = uvms.load_model(write(tmp_path, collision=collision, vehicle={
        "shapes": [{"type": "from_collision", "drag_coefficient": 1.0}]}))
    volumes = np.array([0.2 * 0.3 * 0.4, math.pi * 0.05**2 * 0.5, 4.0 / 3.0 * math.pi * 0.1**3])
    centres = np.array([[0.1, 0, 0], [0, 0, 0.2], [0, -0.2, 0]])
    assert model.buoyancy_mass[0] == pytest.approx(RHO * volumes.sum(), rel=1e-14)
    np.testing.assert_allclose(model.cob[0], volumes @ centres / volumes.sum(), atol=1e-15)
    assert model.shape_count[0] == 3
    # the URDF cylinder runs along z: its shape frame's x axis is the body z axis
    from uvms.hydro.shapes import COL_ROTATION
    R = model.shape_drag[0, 1, COL_ROTATION:COL_ROTATION + 9].reshape(3, 3)
    np.testing.assert_allclose(R[:, 0], [0, 0, 1], atol=1e-15)


def test_paper_model_has_no_shapes():
    model = uvms.load_model("paper")
    assert not model.shape_count.any() and not kernel_model(model).fossen[:, 12, 4].any()


@pytest.mark.parametrize("shape,field", [
    ({"type": "sphere", "radius": 0.0}, "vehicle.shapes[0].radius"),
    ({"type": "box", "size": [0.1, -0.2, 0.3]}, "vehicle.shapes[0].size"),
    ({"type": "cylinder", "radius": 0.1, "length": 0.0}, "vehicle.shapes[0].length"),
    ({"type": "cone", "radius": 0.1}, "vehicle.shapes[0]"),
])
def test_bad_shape_is_one_line(tmp_path, shape, field):
    path = write(tmp_path, vehicle={"shapes": [shape]})
    assert_model_file_refused(path, field)


def test_bad_added_mass_is_one_line(tmp_path):
    path = write(tmp_path, vehicle={"added_mass": {"matrix": [[1 if i == j else (0.5 if (i, j) == (0, 1) else 0)
                                                               for j in range(6)] for i in range(6)],
                                                   "about": "origin"}})
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    assert "symmetric" in str(info.value) and "vehicle.added_mass" in str(info.value)
    assert main(["validate", str(path)]) == 2


FIXED_CHILD = """<collision><origin xyz="0 0 0"/><geometry><sphere radius="0.01"/></geometry></collision>
  </link>
  <joint name="fix" type="fixed"><parent link="hull"/><child link="pod"/>
    <origin xyz="0.1 0.2 0.3" rpy="0 0 1.5707963267948966"/></joint>
  <link name="pod">"""


def test_damping_of_a_fixed_link_is_rotated_into_its_body(tmp_path):
    """A link fixed to the vehicle with a 90 deg yaw: its linear damping is B D_l B^T in vehicle axes
    (B = diag(R, R)) about the link's point moved into the vehicle frame; quadratic damping is refused there."""
    path = write(tmp_path, collision=FIXED_CHILD, vehicle={})
    data = yaml.safe_load(path.read_text())
    data["links"] = {"pod": {"damping": {"convention": "magnitude", "about": [0.05, 0.0, 0.0],
                                         "coefficients": {"X_u": 3.0, "Y_v": 5.0, "N_r": 0.2}}}}
    path.write_text(yaml.safe_dump(data))
    model = uvms.load_model(path)
    # link x -> vehicle y, link y -> vehicle -x: surge damping of the link is sway damping of the vehicle
    np.testing.assert_allclose(np.diag(model.damping_linear[0]), [0, 0, 0.2, 5.0, 3.0, 0], atol=1e-12)
    np.testing.assert_allclose(model.damping_point[0], [0.1, 0.25, 0.3], atol=1e-12)
    data["links"]["pod"]["damping"]["coefficients"]["X_u|u|"] = 10.0
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(UvmsInputError, match="links.pod.damping"):
        uvms.load_model(path)


def test_a_dh_model_takes_buoyancy_and_added_mass_from_its_shapes(tmp_path):
    """DH route: a body without ``buoyancy``/``added_mass`` gets them from its shapes (a sphere: rho V at its
    centre, rho V / 2 in every translation, moved to the body origin by the point-mass parallel-axis terms)."""
    import copy
    from importlib.resources import files

    import yaml

    data = yaml.safe_load((files("uvms.model") / "models" / "paper.yaml").read_text())
    r, c = 0.2, np.array([0.05, 0.0, -0.01])
    data = copy.deepcopy(data)
    for key in ("buoyancy", "added_mass"):
        del data["vehicle"][key]
    data["vehicle"]["shapes"] = [{"type": "sphere", "radius": r, "drag_coefficient": 0.5, "position": c.tolist()}]
    link = data["arm"]["links"][0]
    del link["buoyancy"]
    link["shapes"] = [{"type": "sphere", "radius": 0.02, "drag_coefficient": 0.5, "position": [0.1, 0.0, 0.0]}]
    path = tmp_path / "shapes.yaml"
    path.write_text(yaml.safe_dump(data))
    model = uvms.load_model(path)
    rho = model.density
    V = 4.0 / 3.0 * np.pi * r**3
    assert model.buoyancy_mass[0] == pytest.approx(rho * V, rel=1e-14)
    np.testing.assert_allclose(model.cob[0], c, atol=1e-15)
    m_a = rho * V / 2.0
    cx = np.array([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])
    expected = np.zeros((6, 6))                        # a point added mass m_a at c, about the origin
    expected[3:, 3:] = m_a * np.eye(3)
    expected[:3, 3:] = m_a * cx
    expected[3:, :3] = -m_a * cx
    expected[:3, :3] = -m_a * cx @ cx
    np.testing.assert_allclose(model.added_mass[0], expected, atol=1e-12)
    assert model.buoyancy_mass[1] == pytest.approx(rho * 4.0 / 3.0 * np.pi * 0.02**3, rel=1e-14)
    np.testing.assert_allclose(model.cob[1], [0.1, 0.0, 0.0], atol=1e-15)

    del data["vehicle"]["shapes"]
    path.write_text(yaml.safe_dump(data))
    with pytest.raises(UvmsInputError, match=r"vehicle\.buoyancy: expected a value \(required field, unless"):
        uvms.load_model(path)
