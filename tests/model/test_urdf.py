"""Robot descriptions (URDF, xacro) and their YAML additions: tree order, frames, merged fixed links, the
paper's URDF against its DH file, joint damping and friction against closed forms, and every kind of bad input
(one line naming the file and the link or joint, exit code 2, nothing written)."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pytest

import uvms
from uvms.cli import main
from uvms.dynamics.plant import kernel_model
from uvms.errors import UvmsInputError
from uvms.model.model import END_EFFECTOR
from uvms.spatial import rotx, rotz

INERTIAL = ('<inertial><origin xyz="{c}" rpy="0 0 0"/><mass value="{m}"/>'
            '<inertia ixx="{i}" ixy="0" ixz="0" iyy="{i}" iyz="0" izz="{i}"/></inertial>')


def link(name: str, m: float = 1.0, c: str = "0 0 0", i: float = 0.01, inertial: bool = True) -> str:
    body = INERTIAL.format(m=m, c=c, i=i) if inertial else ""
    return f'<link name="{name}">{body}</link>'


def joint(name: str, kind: str, parent: str, child: str, xyz: str = "0 0 0", rpy: str = "0 0 0",
          axis: str | None = "0 0 1", extra: str = "") -> str:
    ax = f'<axis xyz="{axis}"/>' if axis is not None else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/>{ax}{extra}</joint>')


def robot(*parts: str, name: str = "rov") -> str:
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n' + "\n".join(parts) + "\n</robot>\n"


# A vehicle with two arms and a camera boom: arm A (revolute about z, then prismatic along x), arm B
# (continuous about y), a camera on a fixed joint, a gripper jaw fixed to arm A's last link.
TREE = robot(
    link("base", m=20.0, c="0 0 0.05", i=0.5),
    joint("a1", "revolute", "base", "a_link1", xyz="0.3 0.1 0", axis="0 0 1",
          extra='<limit lower="-1.0" upper="1.5" effort="20" velocity="2"/><dynamics damping="0.5" friction="0.2"/>'),
    link("a_link1", m=2.0, c="0.1 0 0", i=0.02),
    joint("a2", "prismatic", "a_link1", "a_link2", xyz="0.2 0 0", axis="1 0 0",
          extra='<limit lower="0" upper="0.1" effort="50" velocity="0.5"/>'),
    link("a_link2", m=1.0, c="0.05 0 0", i=0.01),
    joint("a_jaw_joint", "fixed", "a_link2", "a_jaw", xyz="0.1 0 0", rpy="0 0 1.5707963267948966"),
    link("a_jaw", m=0.2, c="0.02 0 0", i=0.001),
    joint("camera_joint", "fixed", "base", "camera", xyz="0.4 0 -0.1", rpy="0 0.3 0"),
    link("camera", m=0.5, c="0 0 0", i=0.002),
    joint("b1", "continuous", "base", "b_link1", xyz="0.3 -0.1 0", rpy="1.5707963267948966 0 0", axis="0 1 0"),
    link("b_link1", m=1.5, c="0 0 0.1", i=0.015),
)


@pytest.fixture
def tree(tmp_path):
    path = tmp_path / "tree.urdf"
    path.write_text(TREE)
    return uvms.load_model(path)


def test_tree_order_frames_and_merging(tree):
    # depth first from the root, children in file order; fixed joints are frames, not joints
    assert tree.joint_names == ("a1", "a2", "b1")
    assert tree.body_names == ("base", "a_link1", "a_link2", "b_link1")
    assert list(tree.joint_parent) == [0, 1, 0]
    assert tree.joint_type == ("revolute", "prismatic", "continuous")
    assert tree.frame_names == ("base", "a_link1", "a_link2", "a_jaw", "camera", "b_link1", END_EFFECTOR)
    # the camera (0.5 kg at (0.4, 0, -0.1)) is merged into the vehicle: mass and centre of mass add up
    assert tree.mass[0] == pytest.approx(20.5, abs=1e-15)
    np.testing.assert_allclose(tree.com[0], (20.0 * np.array([0, 0, 0.05]) + 0.5 * np.array([0.4, 0, -0.1])) / 20.5,
                               atol=1e-15)
    # the jaw is merged into a_link2, its CoM at (0.1, 0.02, 0) after the 90 deg yaw
    np.testing.assert_allclose(tree.com[2], (1.0 * np.array([0.05, 0, 0]) + 0.2 * np.array([0.1, 0.02, 0])) / 1.2,
                               atol=1e-15)
    # limits and dynamics kept; continuous joints have no position limits
    np.testing.assert_array_equal(tree.joint_limits[0], [-1.0, 1.5, 20.0, 2.0])
    np.testing.assert_array_equal(tree.joint_limits[2, :2], [-np.inf, np.inf])
    assert tree.joint_damping[0] == 0.5 and tree.joint_friction[0] == 0.2
    # the end effector defaults to the deepest link
    assert tree.frame(END_EFFECTOR).body == 2
    np.testing.assert_allclose(tree.frame(END_EFFECTOR).position, [0.1, 0, 0])


def test_frame_pose_by_hand(tree):
    """World poses of merged and moving frames, composed by hand from the URDF origins."""
    q = {"a1": 0.7, "a2": 0.05, "b1": -0.4}
    state = uvms.State.from_euler(tree, position=[1.0, 2.0, 3.0], euler=[0.1, -0.2, 0.3], q=q)
    R0, p0 = state.rotation, state.position
    # arm A: a1 rotates about z at (0.3, 0.1, 0); a2 slides along the rotated x; the jaw is 0.1 further, yawed
    R1 = R0 @ rotz(0.7)
    p1 = p0 + R0 @ np.array([0.3, 0.1, 0.0])
    p2 = p1 + R1 @ np.array([0.2 + 0.05, 0.0, 0.0])
    jaw = uvms.frame_pose(tree, state, "a_jaw")
    np.testing.assert_allclose(jaw.position, p2 + R1 @ np.array([0.1, 0, 0]), atol=1e-14)
    np.testing.assert_allclose(jaw.rotation, R1 @ rotz(np.pi / 2), atol=1e-14)
    # arm B: frame rolled by 90 deg, then rotation about its own y
    Rb = R0 @ rotx(np.pi / 2) @ np.array([[np.cos(-0.4), 0, np.sin(-0.4)], [0, 1, 0], [-np.sin(-0.4), 0, np.cos(-0.4)]])
    np.testing.assert_allclose(uvms.frame_pose(tree, state, "b_link1").rotation, Rb, atol=1e-14)
    # the camera does not move with any joint
    cam = uvms.frame_pose(tree, state, "camera")
    np.testing.assert_allclose(cam.position, p0 + R0 @ np.array([0.4, 0, -0.1]), atol=1e-14)
    # the end effector is the jaw (deepest link); the vehicle frame is the root link's frame
    np.testing.assert_allclose(uvms.end_effector_position(tree, state), jaw.position, atol=1e-14)
    np.testing.assert_allclose(uvms.frame_pose(tree, state, "base").position, p0, atol=0)
    with pytest.raises(UvmsInputError, match="no frame 'nope'.*frames: base, a_link1"):
        uvms.frame_pose(tree, state, "nope")


def test_state_from_joint_mapping(tree):
    by_name = uvms.State.from_euler(tree, q={"b1": 0.3, "a1": -0.2}, qd={"a2": 0.1})
    np.testing.assert_array_equal(by_name.q, [-0.2, 0.0, 0.3])
    np.testing.assert_array_equal(by_name.qd, [0.0, 0.1, 0.0])
    np.testing.assert_array_equal(uvms.State.from_euler(tree, q=[1, 2, 3]).q, [1, 2, 3])
    with pytest.raises(UvmsInputError, match="no joint 'c1'; joints: a1, a2, b1"):
        uvms.State.from_euler(tree, q={"c1": 1.0})


def test_any_frame_as_end_effector(tree, tmp_path):
    cam = tree.with_end_effector("camera")
    state = uvms.State.from_euler(cam, q=[0.3, 0.02, 0.1], euler=[0.2, 0.1, -0.3])
    np.testing.assert_allclose(uvms.end_effector_position(cam, state),
                               uvms.frame_pose(tree, state, "camera").position, atol=1e-15)
    # an end-effector wrench on the camera is a wrench on the vehicle: the same as that body wrench
    f_ee = np.array([0.1, -0.2, 0.3, 1.0, 2.0, -1.0])
    R = cam.frame("camera").rotation
    p = cam.frame("camera").position
    body = np.concatenate([R @ f_ee[:3] + np.cross(p, R @ f_ee[3:]), R @ f_ee[3:]])
    a = uvms.forward_dynamics(cam, state, ee_wrench=f_ee)
    b = uvms.forward_dynamics(cam, state, body_wrench=body)
    np.testing.assert_allclose(a.generalized, b.generalized, rtol=0, atol=1e-12)
    # and through the YAML additions
    (tmp_path / "tree.urdf").write_text(TREE)
    (tmp_path / "tree.yaml").write_text("urdf: tree.urdf\nend_effector: camera\n")
    via_yaml = uvms.load_model(tmp_path / "tree.yaml")
    assert via_yaml.frame(END_EFFECTOR).body == 0


def test_xacro_expands_to_the_same_model(tmp_path, tree):
    xacro = TREE.replace('<robot name="rov">', '<robot name="rov" xmlns:xacro="http://www.ros.org/wiki/xacro">'
                         '<xacro:property name="base_mass" value="20.0"/>')
    xacro = xacro.replace('<mass value="20.0"/>', '<mass value="${base_mass}"/>')
    (tmp_path / "tree.urdf.xacro").write_text(xacro)
    model = uvms.load_model(tmp_path / "tree.urdf.xacro")
    assert model.joint_names == tree.joint_names
    np.testing.assert_array_equal(kernel_model(model).inertia, kernel_model(tree).inertia)


def test_missing_mesh_is_a_warning(tmp_path):
    text = robot('<link name="base">' + INERTIAL.format(m=1.0, c="0 0 0", i=0.1)
                 + '<visual><geometry><mesh filename="meshes/hull.stl"/></geometry></visual></link>')
    (tmp_path / "m.urdf").write_text(text)
    with pytest.warns(UserWarning, match="mesh file.*not found.*meshes/hull.stl"):
        model = uvms.load_model(tmp_path / "m.urdf")
    assert model.n_joints == 0 and model.mass[0] == 1.0


def test_hydrodynamic_additions_by_link_name(tmp_path):
    """A link's buoyancy, added mass and cylinder in its own frame end up on its body, moved to the body
    frame; a fixed child's buoyancy is merged with the parent's."""
    (tmp_path / "tree.urdf").write_text(TREE)
    (tmp_path / "tree.yaml").write_text("""
urdf: tree.urdf
environment: {density: 1025.0}
vehicle:
  buoyancy: {volume: 0.02, center: [0.0, 0.0, -0.02]}
  added_mass: {diagonal: [1, 1, 1, 10, 10, 10], about: origin}
  drag: {area: [0.1, 0.1, 0.1], coefficient: [1.0, 1.0, 1.0], rotational: {side: 0.4, coefficient: 1.0}}
links:
  camera: {buoyancy: {mass: 0.5, center: [0.0, 0.0, 0.0]}}
  a_link2: {buoyancy: {mass: 1.0, center: [0.05, 0.0, 0.0]}}
  a_jaw: {buoyancy: {mass: 0.2, center: [0.02, 0.0, 0.0]}}
  b_link1:
    cylinder: {radius: 0.02, length: 0.2, drag_coefficient: 1.2, axis: [0, 0, 1]}
    added_mass: from_geometry
joints:
  a1: {damping: 1.5, friction_speed: 0.05}
""")
    model = uvms.load_model(tmp_path / "tree.yaml")
    assert model.buoyancy_mass[0] == pytest.approx(1025.0 * 0.02 + 0.5, rel=1e-15)
    np.testing.assert_allclose(model.cob[0], (20.5 * np.array([0, 0, -0.02]) + 0.5 * np.array([0.4, 0, -0.1])) / 21.0,
                               atol=1e-15)
    np.testing.assert_allclose(model.cob[2], (np.array([0.05, 0, 0]) + 0.2 * np.array([0.1, 0.02, 0])) / 1.2,
                               atol=1e-15)
    np.testing.assert_allclose(model.link_cylinder_rotation[2][:, 0], [0, 0, 1], atol=1e-15)
    # from_geometry: strip theory along the cylinder (link z): m_a' L for sway/surge, none along the axis
    ma = 1025.0 * np.pi * 0.02**2
    np.testing.assert_allclose(np.diag(model.added_mass[3])[3:], [ma * 0.2, ma * 0.2, 0.0], atol=1e-15)
    assert model.joint_damping[0] == 1.5 and model.joint_friction[0] == 0.2
    assert model.joint_friction_speed[0] == 0.05
    # a drag moment from the cylinder about link z: a link spinning about y (b1's axis) in still water
    state = uvms.State.from_euler(model, qd={"b1": 2.0})
    _, tau = uvms.inverse_dynamics(model.with_effects(added_mass=False, gravity=False, buoyancy=False,
                                                      joint_friction=False), state, nu_dot=np.zeros(6),
                                   qdd=np.zeros(3))
    k = 0.5 * 1025.0 * 1.2 * 2 * 0.02
    assert tau[2] == pytest.approx(k * 2.0 * 2.0 * 0.2**4 / 4, rel=1e-12)


def test_paper_urdf_matches_paper_yaml_over_case_2():
    """The shipped paper.urdf + paper_urdf.yaml and paper.yaml give the same case-2 trajectory to 1e-12."""
    from uvms.sim.scenario import load_scenario, run_scenario

    dh = uvms.load_model("paper")
    urdf = uvms.load_model("paper_urdf")
    assert urdf.joint_names == dh.joint_names and urdf.body_names == dh.body_names
    scenario = load_scenario("paper_case2_released")
    a = run_scenario(scenario)
    b = run_scenario(dataclasses.replace(scenario, model=urdf))
    assert a.states.shape == b.states.shape
    assert np.abs(a.states - b.states).max() <= 1e-12
    assert np.abs(a.end_effector - b.end_effector).max() <= 1e-12
    assert np.abs(a.states[-1, 13:16]).max() > 0.1          # the arm did move


# --- joint damping and friction -----------------------------------------------------------------------------

def one_joint(tmp_path, damping: float, friction: float, speed: float | None = None) -> uvms.Model:
    """A heavy vehicle with one link spinning about z through its CoM: rotational inertia J = 0.05 kg m^2."""
    text = robot(link("base", m=50.0, i=2.0), joint("j", "continuous", "base", "l", axis="0 0 1",
                 extra=f'<dynamics damping="{damping}" friction="{friction}"/>'), link("l", m=1.0, i=0.05))
    (tmp_path / "p.urdf").write_text(text)
    extra = f"joints: {{j: {{friction_speed: {speed}}}}}\n" if speed is not None else ""
    (tmp_path / "p.yaml").write_text("urdf: p.urdf\nenvironment: {gravity: [0.0, 0.0, 0.0]}\n" + extra)
    return uvms.load_model(tmp_path / "p.yaml")


def test_damped_joint_decays_exponentially(tmp_path):
    """Clamped vehicle, no gravity: J qdd = -b qd, so qd(t) = qd0 exp(-b t / J), q(t) = qd0 J / b (1 - exp(..))."""
    b, J, w0 = 0.1, 0.05, 3.0
    model = one_joint(tmp_path, damping=b, friction=0.0)
    result = uvms.simulate(model, uvms.State.from_euler(model, qd=[w0]), duration=1.0, step=1e-3, fixed_base=True)
    t = result.time
    np.testing.assert_allclose(result.states[:, 14], w0 * np.exp(-b * t / J), rtol=0, atol=1e-9)
    np.testing.assert_allclose(result.states[:, 13], w0 * J / b * (1 - np.exp(-b * t / J)), rtol=0, atol=1e-9)


def test_friction_holds_below_the_friction_torque_and_slides_above(tmp_path):
    """Regularised Coulomb friction tau_f = -F_c clip(qd / v_s, -1, 1) (docs/models.md): under a constant
    torque tau < F_c the joint creeps at qd = tau v_s / F_c, reached as 1 - exp(-t F_c / (J v_s)); above F_c it
    slides with J qdd = tau - F_c."""
    F, vs, J = 0.5, 0.01, 0.05
    model = one_joint(tmp_path, damping=0.0, friction=F, speed=vs)
    tau = 0.3
    held = uvms.simulate(model, duration=0.2, step=2e-5, fixed_base=True, joint_torques=np.array([tau]))
    creep = tau * vs / F
    np.testing.assert_allclose(held.states[:, 14], creep * (1 - np.exp(-held.time * F / (J * vs))), rtol=0,
                               atol=1e-9)
    assert 0.0 < held.states[-1, 13] < 0.0013    # held: 6 mrad/s creep for 0.2 s
    tau = 0.8
    slide = uvms.simulate(model, uvms.State.from_euler(model, qd=[1.0]), duration=0.5, step=1e-3, fixed_base=True,
                          joint_torques=np.array([tau]))
    np.testing.assert_allclose(slide.states[:, 14], 1.0 + (tau - F) / J * slide.time, rtol=0, atol=1e-9)
    # the inverse dynamics charges the friction to the actuator
    _, tau_id = uvms.inverse_dynamics(model, uvms.State.from_euler(model, qd=[1.0]), nu_dot=np.zeros(6),
                                      qdd=np.array([6.0]))
    assert tau_id[0] == pytest.approx(J * 6.0 + F, rel=1e-12)


# --- bad input ----------------------------------------------------------------------------------------------

GOOD = [link("base", m=10.0, i=0.5), joint("j1", "revolute", "base", "l1"), link("l1")]
BAD = {
    "broken_xml": ('<robot name="x"><link name="base">', "invalid XML"),
    "missing_parent": (robot(*GOOD, joint("j2", "revolute", "ghost", "l2"), link("l2")),
                       "joint 'j2': its parent link 'ghost' is not defined"),
    "missing_child": (robot(*GOOD, joint("j2", "revolute", "l1", "ghost")),
                      "joint 'j2': its child link 'ghost' is not defined"),
    "loop": (robot(*GOOD, link("l2"), joint("j2", "revolute", "l1", "l2"), joint("j3", "revolute", "l2", "l1")),
             "joint 'j3': link 'l1' is already the child of joint 'j1'"),
    "two_roots": (robot(*GOOD, link("other")), "expected one root link, found 2: 'base', 'other'"),
    "unknown_joint_type": (robot(link("base"), joint("j1", "ball", "base", "l1"), link("l1")),
                           "joint 'j1': unknown joint type 'ball'"),
    "floating_joint": (robot(link("base"), joint("j1", "floating", "base", "l1"), link("l1")),
                       "joint 'j1': unsupported joint type 'floating'"),
    "mimic": (robot(*GOOD, joint("j2", "revolute", "l1", "l2", extra='<mimic joint="j1"/>'), link("l2")),
              "joint 'j2': mimic joints are not supported"),
    # a joint moving no mass is frozen with a note since issue 26 (tests/model/test_uuv.py)
    "negative_mass": (robot(link("base"), joint("j1", "revolute", "base", "l1"), link("l1", m=-1.0)),
                      "link 'l1': expected a mass >= 0, found -1"),
    "inertia_not_psd": (robot(link("base"), joint("j1", "revolute", "base", "l1"), link("l1", i=-0.01)),
                        "link 'l1': expected a positive semi-definite inertia"),
    "inertia_triangle": (robot(link("base"), joint("j1", "revolute", "base", "l1"),
                               '<link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" '
                               'iyy="0.01" iyz="0" izz="0.03"/></inertial></link>'),
                         "link 'l1': expected principal moments with I1 + I2 >= I3"),
    "zero_axis": (robot(*GOOD[:1], joint("j1", "revolute", "base", "l1", axis="0 0 0"), GOOD[2]),
                  "joint 'j1': expected a non-zero joint axis"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_urdf_one_line_exit_2(tmp_path, capsys, case):
    text, expected = BAD[case]
    path = tmp_path / f"{case}.urdf"
    path.write_text(text)
    before = sorted(p.name for p in tmp_path.iterdir())
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    assert str(info.value).startswith(f"{path}: ") and expected in str(info.value)
    assert main(["validate", str(path)]) == 2
    out, err = capsys.readouterr()
    assert out == "" and len(err.splitlines()) == 1 and "Traceback" not in err and expected in err
    assert sorted(p.name for p in tmp_path.iterdir()) == before


BAD_ADDITIONS = {
    "unknown_link": ("links: {ghost: {buoyancy: {mass: 1.0}}}\n", "links.ghost: names link 'ghost', which the URDF"),
    "unknown_joint": ("joints: {ghost: {damping: 1.0}}\n", "joints.ghost: names joint 'ghost'"),
    "unknown_end_effector": ("end_effector: ghost\n", "end_effector: names link 'ghost'"),
    "unknown_fixed_joint": ("fixed_joints: [ghost]\n", "fixed_joints[0]: names joint 'ghost'"),
    "cylinder_on_vehicle": ("links: {base: {cylinder: {radius: 0.1, length: 1.0, drag_coefficient: 1.0}}}\n",
                            "links.base.cylinder: link 'base' is part of the vehicle"),
    "missing_urdf": None,
}


@pytest.mark.parametrize("case", sorted(BAD_ADDITIONS))
def test_bad_additions_one_line(tmp_path, capsys, case):
    (tmp_path / "r.urdf").write_text(robot(*GOOD))
    path = tmp_path / "r.yaml"
    if case == "missing_urdf":
        path.write_text("urdf: nowhere.urdf\n")
        expected = "urdf: no such file"
    else:
        addition, expected = BAD_ADDITIONS[case]
        path.write_text("urdf: r.urdf\n" + addition)
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    assert str(info.value).startswith(f"{path}: ") and expected in str(info.value)
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and expected in err


def test_validate_summarises_a_urdf(tmp_path, capsys):
    (tmp_path / "tree.urdf").write_text(TREE)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert main(["validate", str(tmp_path / "tree.urdf")]) == 0
    out = capsys.readouterr().out
    assert "rov: valid" in out and "joints:               3" in out


def test_joint_limits_reported_when_a_run_crosses_them(tree):
    """a1 has limits [-1, 1.5] rad, 2 rad/s, 20 N m: a 30 N m torque crosses the effort limit at once and the
    position and velocity limits later; nothing stops the joint (limits are reported, not enforced)."""
    with pytest.warns(UserWarning, match="joint 'a1' crossed its position limit"):
        result = uvms.simulate(tree, duration=1.0, step=1e-3, fixed_base=True, joint_torques=np.array([30.0, 0, 0]))
    lines = result.metadata["joint_limit_crossings"]
    assert any(line.startswith("joint 'a1' crossed its effort limit +/-20 at t = 0 s") for line in lines)
    assert any("joint 'a1' crossed its velocity limit +/-2" in line for line in lines)
    assert not any("'b1'" in line for line in lines)      # (a2 slides out past 0.1 m: centrifugal force)
    assert result.states[-1, 13] > 1.5
    quiet = uvms.simulate(tree, duration=0.1, step=1e-3, fixed_base=True, joint_torques=np.array([1.0, 0, 0]))
    assert "joint_limit_crossings" not in quiet.metadata
