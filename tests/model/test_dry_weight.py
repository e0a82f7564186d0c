"""Dry weight (``inertia_includes_added_mass: true`` with ``weight:`` per link, :func:`uvms.model.loads.with_dry_weight`).

A URDF whose inertial masses lump in added mass is weighed by its dry mass. Where lumping is exact (an added-mass
matrix that is itself a rigid-body spatial inertia), the lumped model with its dry weight must move exactly as the
split one (rigid body + added mass): the forward dynamics of the two agree. The statics (report, trim, potential
energy, the kernel's gravity) are checked against hand computations with the dry mass."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import uvms
from uvms.analysis.report import model_report
from uvms.analysis.trim import rest_attitude, statics
from uvms.dynamics.energy import potential_energy
from uvms.errors import UvmsInputError

G = 9.81
M_R, C_R, I_R = 10.0, np.array([0.01, 0.0, 0.02]), np.diag([0.2, 0.3, 0.4])        # dry vehicle
M_A, C_A, J_A = 6.0, np.array([0.0, 0.01, -0.01]), np.diag([0.05, 0.08, 0.06])     # its added mass, lumped
ARM = (1.0, np.array([0.0, 0.0, 0.1]))                                             # arm link: mass, CoM (link frame)
JOINT = np.array([0.1, 0.0, 0.2])                                                  # arm joint in the vehicle frame
FLUID, COB = 11.2, np.array([0.0, 0.0, -0.03])                                      # vehicle's displaced fluid [kg]


def skew(r):
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def point_inertia(m, r):
    r = np.asarray(r, dtype=float)
    return m * (r @ r * np.eye(3) - np.outer(r, r))


def urdf(mass, com, inertia) -> str:
    I = np.asarray(inertia, dtype=float).tolist()
    mass, com = float(mass), [float(x) for x in com]
    return f"""<?xml version="1.0"?>
<robot name="r">
  <link name="base">
    <inertial><origin xyz="{com[0]!r} {com[1]!r} {com[2]!r}"/><mass value="{mass!r}"/>
      <inertia ixx="{I[0][0]!r}" ixy="{I[0][1]!r}" ixz="{I[0][2]!r}" iyy="{I[1][1]!r}" iyz="{I[1][2]!r}" izz="{I[2][2]!r}"/>
    </inertial>
  </link>
  <joint name="j" type="revolute">
    <parent link="base"/><child link="arm"/><origin xyz="0.1 0 0.2"/><axis xyz="0 1 0"/>
  </joint>
  <link name="arm">
    <inertial><origin xyz="0 0 0.1"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
  </link>
</robot>
"""


def write(tmp_path, name, urdf_text, additions) -> uvms.Model:
    (tmp_path / f"{name}.urdf").write_text(urdf_text)
    path = tmp_path / f"{name}.yaml"
    path.write_text(yaml.safe_dump({"urdf": f"{name}.urdf", **additions}))
    return uvms.load_model(path)


def added_mass_about_origin():
    """The added mass as the spatial inertia of a body (M_A, C_A, J_A) about the origin, [angular; linear]."""
    S = skew(C_A)
    return np.block([[J_A + M_A * S @ S.T, M_A * S], [M_A * S.T, M_A * np.eye(3)]])


@pytest.fixture(scope="module")
def pair(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("dry")
    buoyancy = {"mass": FLUID, "center": COB.tolist()}
    split = write(tmp, "split", urdf(M_R, C_R, I_R), {
        "vehicle": {"buoyancy": buoyancy, "added_mass": {"matrix": added_mass_about_origin().tolist(), "about": "origin"}}})
    m = M_R + M_A
    c = (M_R * C_R + M_A * C_A) / m
    I = I_R + point_inertia(M_R, C_R - c) + J_A + point_inertia(M_A, C_A - c)
    lumped = write(tmp, "lumped", urdf(m, c, I), {
        "inertia_includes_added_mass": True,
        "vehicle": {"buoyancy": buoyancy, "weight": {"mass": M_R, "center": C_R.tolist()}},
        "links": {"arm": {"weight": {"mass": ARM[0], "center": ARM[1].tolist()}}}})
    return split, lumped


def test_lumped_with_dry_weight_moves_as_rigid_plus_added(pair):
    split, lumped = pair
    state = uvms.State.from_euler(split, euler=[0.3, -0.2, 0.5], nu=[0.1, -0.2, 0.15, 0.3, -0.1, 0.2], q=[0.4],
                                  qd=[-0.3])
    a = uvms.forward_dynamics(split, state, joint_torques=[0.2]).generalized
    b = uvms.forward_dynamics(lumped, state, joint_torques=[0.2]).generalized
    np.testing.assert_allclose(b, a, rtol=1e-10, atol=1e-12)


def test_weight_is_the_dry_mass_and_inertia_the_urdf(pair):
    split, lumped = pair
    np.testing.assert_allclose(lumped.weight_mass, [M_R, ARM[0]])
    np.testing.assert_allclose(lumped.weight_center[0], C_R, atol=1e-15)
    assert lumped.mass[0] == pytest.approx(M_R + M_A)                   # the URDF's inertial mass is kept
    assert not lumped.added_mass.any()                                   # it is in the inertia already


def test_report_and_trim_weigh_the_dry_mass(pair):
    split, lumped = pair
    m = M_R + ARM[0]
    r_G = (M_R * C_R + ARM[0] * (JOINT + ARM[1])) / m                    # arm at q = 0
    d = r_G - COB
    report = model_report(lumped, q=[0.0])
    assert report.mass_kg == pytest.approx(m, rel=1e-15)
    assert report.net_buoyancy_N == pytest.approx((FLUID - m) * G, rel=1e-12)
    np.testing.assert_allclose(report.center_of_mass_m, r_G, atol=1e-15)
    # the vehicle settles with r_B straight above r_G (z down): R^T e_z along d, roll and pitch from it
    roll, pitch, _ = rest_attitude(lumped, statics(lumped, np.zeros(1)))
    R = uvms.State.from_euler(lumped, euler=[roll, pitch, 0.0]).rotation
    np.testing.assert_allclose(R.T @ np.array([0.0, 0.0, 1.0]), d / np.linalg.norm(d), atol=1e-12)
    assert (report.trim_roll_rad, report.trim_pitch_rad) == pytest.approx((roll, pitch), abs=1e-15)
    # the split model (its URDF mass is the dry mass) rests at the same attitude
    assert rest_attitude(split, statics(split, np.zeros(1)))[:2] == pytest.approx((roll, pitch), abs=1e-14)


def test_restoring_moment_at_a_tilt_by_hand(pair):
    """Gravity on the dry masses and buoyancy, summed over the bodies about the vehicle origin, at roll 0.2 rad."""
    _, lumped = pair
    state = uvms.State.from_euler(lumped, euler=[0.2, 0.0, 0.0])
    w = uvms.hydrodynamic_wrenches(lumped, state).wrenches
    R = state.rotation
    g_body = R.T @ np.array([0.0, 0.0, G])
    moment = np.cross(C_R, M_R * g_body) + np.cross(JOINT + ARM[1], ARM[0] * g_body) + np.cross(COB, -FLUID * g_body)
    total = w["gravity"][0, :3] + w["buoyancy"][0, :3]
    arm = w["gravity"][1] + w["buoyancy"][1]                              # the arm's wrench, arm axes = body axes at q=0
    total = total + arm[:3] + np.cross(JOINT, arm[3:])
    np.testing.assert_allclose(total, moment, rtol=1e-12, atol=1e-14)


def test_potential_energy_weighs_the_dry_mass(pair):
    _, lumped = pair
    state = uvms.State.from_euler(lumped, position=[0.0, 0.0, 2.0], euler=[0.0, 0.1, 0.0])
    R, p, g = state.rotation, np.array([0.0, 0.0, 2.0]), np.array([0.0, 0.0, G])
    arm_point = p + R @ (JOINT + ARM[1])
    V = -M_R * g @ (p + R @ C_R) - ARM[0] * g @ arm_point + FLUID * g @ (p + R @ COB)
    assert potential_energy(lumped, state) == pytest.approx(V, rel=1e-12)


@pytest.mark.parametrize("additions, message", [
    ({"inertia_includes_added_mass": True, "vehicle": {"weight": {"mass": 1.0}}},
     "links.arm.weight: expected the dry weight of body 'arm'"),
    ({"inertia_includes_added_mass": True, "links": {"arm": {"weight": {"mass": 1.0}}}},
     "vehicle.weight: expected the dry weight of body 'base'"),
    ({"vehicle": {"weight": {"mass": 1.0}}}, "vehicle.weight: a dry weight is read only with inertia_includes_added_mass"),
    ({"inertia_includes_added_mass": True, "vehicle": {"weight": {"mass": 1.0},
                                                       "added_mass": {"diagonal": [1, 1, 1, 1, 1, 1], "about": "origin"}},
      "links": {"arm": {"weight": {"mass": 1.0}}}}, "vehicle.added_mass: expected no added_mass"),
    ({"inertia_includes_added_mass": "yes"}, "inertia_includes_added_mass"),
])
def test_bad_dry_weight_is_one_line(tmp_path, additions, message):
    with pytest.raises(UvmsInputError) as info:
        write(tmp_path, "bad", urdf(M_R, C_R, I_R), additions)
    text = str(info.value)
    assert "\n" not in text and message in text and "bad.yaml" in text
