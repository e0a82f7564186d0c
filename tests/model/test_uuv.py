"""UUV Simulator's plugin tags read from a URDF (``uvms.model.uuv``, issue 26).

The accelerations uvms computes for a vehicle described only by UUV Simulator's tags are checked against UUV
Simulator's own Fossen model written out here from its definition (``HydrodynamicModel.cc``, ``HMFossen``:
damping ``-D(nu) nu``, added mass ``-M_A nu_dot``, Coriolis ``-C_A(nu) nu`` with ``C_A`` from ``M_A nu``; all in
the link's axes turned to z down, linear-first; ``BuoyantObject.cc``: ``rho V g`` up at the centre of buoyancy)
and Newton-Euler for the rigid body (Fossen 2011, Eq. 3.44 and the rigid-body bias), solved for the
acceleration: nothing of uvms's spatial algebra is used.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import uvms
from tests.model import gazebo_fixtures as fx
from uvms.errors import UvmsInputError

H = np.diag([1.0, -1.0, -1.0])
RHO, G = 1025.0, 9.81


def S(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _vehicle(rng):
    """UUV tags of a vehicle alone (no arm), with every Fossen tag of HMFossen used, non-trivially."""
    X = rng.normal(size=(6, 6))
    Ma = X @ X.T * 20.0 + np.diag([300.0, 500.0, 800.0, 100.0, 150.0, 120.0])
    Ma = 0.5 * (Ma + Ma.T)
    Y = rng.normal(size=(6, 6))
    DLin = -(Y @ Y.T * 10.0 + np.diag([70.0, 60.0, 700.0, 250.0, 300.0, 100.0]))
    DNonLin = -rng.uniform(100.0, 1500.0, 6)
    DFwd = -rng.uniform(1.0, 30.0, (6, 6))
    p = dict(Ma=Ma, DLin=DLin, DNonLin=DNonLin, DFwd=DFwd, scale_m=0.9, off_m=3.0, scale_d=1.2, off_l=-5.0,
             off_nl=-20.0, off_f=-2.0, volume=1.2, scale_v=1.05, off_v=0.01, cob=np.array([0.01, -0.02, 0.3]),
             mass=1200.0, com=np.array([0.05, 0.02, -0.04]),
             I=np.array([[500.0, 10.0, -5.0], [10.0, 900.0, 8.0], [-5.0, 8.0, 800.0]]))
    return p


def _f(x):
    return " ".join(repr(float(v)) for v in np.ravel(x))


def _urdf(p) -> str:
    I = np.asarray(p["I"]).tolist()
    fossen = (f"<type>fossen</type><added_mass>{_f(p['Ma'])}</added_mass>"
              f"<linear_damping>{_f(p['DLin'])}</linear_damping>"
              f"<quadratic_damping>{_f(p['DNonLin'])}</quadratic_damping>"
              f"<linear_damping_forward_speed>{_f(p['DFwd'])}</linear_damping_forward_speed>"
              f"<scaling_added_mass>{p['scale_m']!r}</scaling_added_mass><offset_added_mass>{p['off_m']!r}"
              f"</offset_added_mass><scaling_damping>{p['scale_d']!r}</scaling_damping>"
              f"<offset_linear_damping>{p['off_l']!r}</offset_linear_damping>"
              f"<offset_nonlin_damping>{p['off_nl']!r}</offset_nonlin_damping>"
              f"<offset_lin_forward_speed_damping>{p['off_f']!r}</offset_lin_forward_speed_damping>")
    return (f'<?xml version="1.0"?><robot name="uuvtest"><link name="base_link"><inertial>'
            f'<origin xyz="{_f(p["com"])}" rpy="0 0 0"/><mass value="{p["mass"]!r}"/>'
            f'<inertia ixx="{I[0][0]!r}" ixy="{I[0][1]!r}" ixz="{I[0][2]!r}" iyy="{I[1][1]!r}" iyz="{I[1][2]!r}" '
            f'izz="{I[2][2]!r}"/></inertial></link>'
            f'<gazebo><plugin name="uuv_plugin" filename="libuuv_underwater_object_ros_plugin.so">'
            f'<fluid_density>{RHO!r}</fluid_density><link name="base_link"><volume>{p["volume"]!r}</volume>'
            f'<scaling_volume>{p["scale_v"]!r}</scaling_volume><offset_volume>{p["off_v"]!r}</offset_volume>'
            f'<center_of_buoyancy>{_f(p["cob"])}</center_of_buoyancy><hydrodynamic_model>{fossen}'
            f'</hydrodynamic_model></link></plugin></gazebo></robot>')


def _uuv_acceleration(p, R_flu, nu_flu) -> np.ndarray:
    """UUV Simulator's equations of motion (FRD body axes, linear-first) solved for ``[v_dot; w_dot]``."""
    e = np.eye(6)
    v, w = H @ nu_flu[3:], H @ nu_flu[:3]                  # HydrodynamicModel::ToNED
    nu = np.concatenate([v, w])
    M_A = p["scale_m"] * (p["Ma"] + p["off_m"] * e)
    D = -(p["DLin"] + p["off_l"] * e) - nu[0] * (p["DFwd"] + p["off_f"] * e)
    for i in range(6):
        D[i, i] += -(p["DNonLin"][i] + p["off_nl"]) * abs(nu[i])
    D *= p["scale_d"]
    ab = M_A @ nu
    C_A = np.block([[np.zeros((3, 3)), -S(ab[:3])], [-S(ab[:3]), -S(ab[3:])]])
    tau = -D @ nu - C_A @ nu
    R = H @ R_flu @ H                                      # body FRD -> world NED
    m, rg = p["mass"], H @ p["com"]
    weight = R.T @ np.array([0.0, 0.0, m * G])
    volume = max(0.0, p["scale_v"] * (p["volume"] + p["off_v"]))
    buoy = R.T @ np.array([0.0, 0.0, -RHO * volume * G])
    rb = H @ p["cob"]
    tau += np.concatenate([weight + buoy, np.cross(rg, weight) + np.cross(rb, buoy)])
    I_c = H @ p["I"] @ H
    I_o = I_c + m * (rg @ rg * np.eye(3) - np.outer(rg, rg))
    M_RB = np.block([[m * np.eye(3), -m * S(rg)], [m * S(rg), I_o]])
    bias = np.concatenate([m * (np.cross(w, v) + np.cross(w, np.cross(w, rg))),
                           np.cross(w, I_o @ w) + m * np.cross(rg, np.cross(w, v))])
    return np.linalg.solve(M_RB + M_A, tau - bias)


def test_uuv_fossen_model_against_uuv_equations(tmp_path, rng):
    p = _vehicle(rng)
    path = tmp_path / "uuvtest.urdf"
    path.write_text(_urdf(p))
    model = uvms.load_model(path)
    assert model.convention == "enu" and model.n_joints == 0 and model.density == RHO
    for _ in range(20):
        state = uvms.State.from_euler(model, position=rng.normal(size=3), euler=rng.uniform(-1.0, 1.0, 3),
                                      nu=rng.normal(size=6) * np.array([0.5, 0.5, 0.5, 1.5, 1.0, 1.0]))
        nu_dot = uvms.forward_dynamics(model, state).nu_dot
        ours = np.concatenate([H @ nu_dot[3:], H @ nu_dot[:3]])
        ref = _uuv_acceleration(p, state.rotation, state.nu)
        np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-10 * np.abs(ref).max())


def test_uuv_tags_reordered_and_turned(tmp_path):
    """A published table lands where the conventions say: UUV's linear-first z-down ``X_u`` at uvms's (3, 3),
    sway/yaw coupling signs unchanged (both flip), surge/heave coupling negated."""
    p = _vehicle(np.random.default_rng(3))
    p.update(scale_m=1.0, off_m=0.0)
    path = tmp_path / "uuvtest.urdf"
    path.write_text(_urdf(p))
    A = uvms.load_model(path).added_mass[0]
    Ma = p["Ma"]
    assert A[3, 3] == Ma[0, 0] and A[0, 0] == Ma[3, 3] and A[2, 4] == Ma[5, 1] and A[3, 5] == -Ma[0, 2]


def test_asymmetric_added_mass_is_symmetrised_with_a_note(tmp_path):
    p = _vehicle(np.random.default_rng(5))
    p["Ma"] = p["Ma"].copy()
    p["Ma"][2, 5] += 0.001                       # RexROV2's published table has 10.774 / 10.775
    path = tmp_path / "uuvtest.urdf"
    path.write_text(_urdf(p))
    with pytest.warns(UserWarning, match="added_mass made symmetric"):
        model = uvms.load_model(path)
    np.testing.assert_array_equal(model.added_mass[0], model.added_mass[0].T)


def test_pinned_thruster_and_massless_joints_frozen_with_one_note(tmp_path):
    (tmp_path / "rov.urdf").write_text(fx.uuv_urdf())
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = uvms.load_model(tmp_path / "rov.urdf")
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1
    assert "pinned by its limits (lower = upper): camera_mount" in messages[0]
    assert "spin joint" not in messages[0]               # spin joints are frozen without a note
    assert "not mapped: base_link/box" in messages[0]
    assert model.joint_names == ("shoulder",)
    assert [t.name for t in model.thrusters] == [f"thruster_{k}" for k in range(4)]
    np.testing.assert_allclose(model.thrusters[2].direction, (0.0, 0.0, 1.0), atol=1e-15)   # pitched -90 deg: up


def test_massless_moving_link_is_frozen(tmp_path):
    text = ('<robot name="r"><link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" '
            'iyy="1" iyz="0" izz="1"/></inertial></link><joint name="j" type="revolute"><parent link="base"/>'
            '<child link="frame"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
            '<link name="frame"/></robot>')
    (tmp_path / "r.urdf").write_text(text)
    with pytest.warns(UserWarning, match="moves no mass or no inertia about its axis: j"):
        model = uvms.load_model(tmp_path / "r.urdf")
    assert model.n_joints == 0


def test_pinned_joint_frozen_at_its_value(tmp_path):
    text = ('<robot name="r"><link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" '
            'iyy="1" iyz="0" izz="1"/></inertial></link><joint name="tilt" type="revolute"><parent link="base"/>'
            '<child link="cam"/><origin xyz="1 0 0"/><axis xyz="0 0 1"/>'
            '<limit lower="0.5" upper="0.5" effort="1" velocity="1"/></joint><link name="cam"/></robot>')
    (tmp_path / "r.urdf").write_text(text)
    with pytest.warns(UserWarning, match="pinned"):
        model = uvms.load_model(tmp_path / "r.urdf")
    cam = model.frame("cam")
    np.testing.assert_allclose(cam.rotation[:2, 0], [np.cos(0.5), np.sin(0.5)], rtol=1e-15)


def test_thruster_limits_from_basic_conversion_and_clamps(tmp_path):
    text = fx.uuv_urdf().replace("<thrustMin>-80.0</thrustMin><thrustMax>80.0</thrustMax>",
                                 "<clampMin>-300</clampMin><clampMax>400</clampMax>", 1)
    (tmp_path / "rov.urdf").write_text(text)
    with pytest.warns(UserWarning, match="thruster 0: limits 64 N forward, 36 N reverse"):
        model = uvms.load_model(tmp_path / "rov.urdf")
    assert model.thrusters[0].max_thrust == pytest.approx(0.0004 * 300.0 ** 2, rel=1e-15)


@pytest.mark.parametrize("bad, message", [
    ("<type>fossen</type>", "hydrodynamic_model type fossen, sphere"),
    ("<added_mass>1 2 3</added_mass>", "expected 36 numbers, found 3"),
    ("<linear_damping>1 2 nan 4 5 6</linear_damping>", "finite numbers"),
])
def test_bad_uuv_tags_one_line(tmp_path, bad, message):
    p = _vehicle(np.random.default_rng(1))
    text = _urdf(p)
    if bad.startswith("<type>"):
        text = text.replace(bad, "<type>fancy</type>")
    else:
        tag = bad[1:bad.index(">")]
        start, end = text.index(f"<{tag}>"), text.index(f"</{tag}>") + len(tag) + 3
        text = text[:start] + bad + text[end:]
    (tmp_path / "u.urdf").write_text(text)
    with pytest.raises(UvmsInputError, match=message) as info:
        uvms.load_model(tmp_path / "u.urdf")
    assert "\n" not in str(info.value) and str(tmp_path / "u.urdf") in str(info.value)


def test_yaml_additions_take_precedence_over_the_tags(tmp_path):
    (tmp_path / "rov.urdf").write_text(fx.uuv_urdf())
    (tmp_path / "rov.yaml").write_text("urdf: rov.urdf\nframe: enu\nvehicle:\n"
                                       "  added_mass: {diagonal: [1, 1, 1, 2, 2, 2], about: origin}\n")
    with pytest.warns(UserWarning, match=r"base_link/\* \(described by"):
        model = uvms.load_model(tmp_path / "rov.yaml")
    np.testing.assert_array_equal(np.diag(model.added_mass[0]), [1, 1, 1, 2, 2, 2])


def test_uuv_sphere_model_is_a_uvms_sphere(tmp_path):
    """``hydrodynamic_model`` ``sphere``: the added mass of a sphere in potential flow, ``rho V / 2`` on each
    translation and none on rotation (Newman, Marine Hydrodynamics, 1977, Sec. 4.13), and its volume buoyancy."""
    r = 0.3
    text = ('<robot name="s"><link name="base"><inertial><mass value="100"/><inertia ixx="4" ixy="0" ixz="0" '
            'iyy="4" iyz="0" izz="4"/></inertial></link><gazebo><plugin name="u" '
            'filename="libuuv_underwater_object_ros_plugin.so"><fluid_density>1000</fluid_density>'
            f'<link name="base"><volume>{4 / 3 * np.pi * r ** 3!r}</volume><hydrodynamic_model><type>sphere</type>'
            f'<radius>{r!r}</radius></hydrodynamic_model></link></plugin></gazebo></robot>')
    (tmp_path / "s.urdf").write_text(text)
    with pytest.warns(UserWarning, match="sphere model's drag is not mapped"):
        model = uvms.load_model(tmp_path / "s.urdf")
    half = 0.5 * 1000.0 * 4.0 / 3.0 * np.pi * r ** 3
    np.testing.assert_allclose(model.added_mass[0], np.diag([0, 0, 0, half, half, half]), rtol=1e-12, atol=1e-9)
    assert model.buoyancy_mass[0] == pytest.approx(2.0 * half, rel=1e-15)


def test_uuv_cylinder_takes_its_size_from_the_link_box(tmp_path):
    """UUV Simulator's ``HMCylinder`` without ``radius``, ``length`` or ``axis`` takes the smallest extent of
    the link's ``<box>`` as radius and the largest as length and axis (Oberon 7's links are written so)."""
    def robot(model: str, box: str) -> str:
        return ('<robot name="c"><link name="base"><inertial><mass value="10"/><inertia ixx="1" ixy="0" ixz="0" '
                'iyy="1" iyz="0" izz="1"/></inertial></link><gazebo><plugin name="u" '
                'filename="libuuv_underwater_object_ros_plugin.so"><fluid_density>1000</fluid_density>'
                f'<link name="base"><volume>0.01</volume>{box}<hydrodynamic_model><type>cylinder</type>{model}'
                '</hydrodynamic_model></link></plugin></gazebo></robot>')
    box = "<box><width>0.1</width><length>0.6</length><height>0.2</height></box>"
    (tmp_path / "a.urdf").write_text(robot("", box))
    (tmp_path / "b.urdf").write_text(robot("<radius>0.1</radius><length>0.6</length><axis>j</axis>", ""))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a, b = uvms.load_model(tmp_path / "a.urdf"), uvms.load_model(tmp_path / "b.urdf")
    np.testing.assert_array_equal(a.added_mass, b.added_mass)
    assert a.added_mass[0][4, 4] < 0.1 * a.added_mass[0][3, 3]      # little along the axis (y), much across


def _plugin_robot(links: str, plugin: str, extra: str = "") -> str:
    return (f'<robot name="r">{links}<gazebo><plugin name="u" filename="libuuv_underwater_object_ros_plugin.so">'
            f'<fluid_density>1000</fluid_density>{plugin}</plugin></gazebo>{extra}</robot>')


_BASE = ('<link name="base"><inertial><mass value="100"/><inertia ixx="4" ixy="0" ixz="0" iyy="4" iyz="0" '
         'izz="4"/></inertial></link>')


def test_a_neutrally_buoyant_link_displaces_its_mass_with_the_links_fixed_to_it(tmp_path):
    """``neutrally_buoyant`` (``BuoyantObject``: volume = mass / rho): the vehicle's 100 kg and the 5 kg of a
    link fixed to it (Gazebo lumps fixed links into one), not the 1 g of a thruster on a spin joint; the
    ``volume`` tag beside it does not count, the centre of buoyancy is the tag's."""
    links = (_BASE + '<joint name="fix" type="fixed"><parent link="base"/><child link="ballast"/>'
             '<origin xyz="0 0 -0.2"/></joint><link name="ballast"><inertial><mass value="5"/><inertia ixx="0.01" '
             'ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'
             '<joint name="spin" type="continuous"><parent link="base"/><child link="prop"/><axis xyz="1 0 0"/>'
             '</joint><link name="prop"><inertial><mass value="0.001"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" '
             'iyz="0" izz="0"/></inertial></link>')
    plugin = ('<link name="base"><neutrally_buoyant>1</neutrally_buoyant><volume>0.5</volume>'
              '<center_of_buoyancy>0 0 0.05</center_of_buoyancy></link>')
    (tmp_path / "n.urdf").write_text(_plugin_robot(links, plugin))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = uvms.load_model(tmp_path / "n.urdf")
    assert model.buoyancy_mass[0] == pytest.approx(105.0, rel=1e-15)
    np.testing.assert_allclose(model.cob[0], [0.0, 0.0, 0.05], rtol=0, atol=1e-15)
    assert dict(model.hydro_sources)["base: buoyancy"] == "neutrally_buoyant"


def test_uuv_spheroid_model_has_lambs_added_mass(tmp_path):
    """``hydrodynamic_model`` ``spheroid`` (``radius`` b, ``length`` 2a along the link's x axis): the added mass
    of a prolate spheroid in potential flow written out here from Lamb's closed form (Lamb, Hydrodynamics,
    1932, sec. 373; Newman 1977, sec. 4.13): ``k1 = alpha0 / (2 - alpha0)``, ``k2 = beta0 / (2 - beta0)``,
    ``k' = e^4 (beta0 - alpha0) / ((2 - e^2) (2 e^2 - (2 - e^2)(beta0 - alpha0)))`` with the eccentricity e."""
    a, b, rho = 0.8, 0.2, 1000.0
    plugin = (f'<link name="base"><volume>0.1</volume><hydrodynamic_model><type>spheroid</type><radius>{b!r}</radius>'
              f'<length>{2 * a!r}</length><cd>0.5</cd></hydrodynamic_model></link>')
    (tmp_path / "s.urdf").write_text(_plugin_robot(_BASE, plugin))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = uvms.load_model(tmp_path / "s.urdf")
    e = np.sqrt(1.0 - (b / a) ** 2)
    L = np.log((1.0 + e) / (1.0 - e))
    alpha0 = 2.0 * (1.0 - e * e) / e ** 3 * (0.5 * L - e)
    beta0 = 1.0 / (e * e) - (1.0 - e * e) / (2.0 * e ** 3) * L
    k1, k2 = alpha0 / (2.0 - alpha0), beta0 / (2.0 - beta0)
    kp = e ** 4 * (beta0 - alpha0) / ((2.0 - e * e) * (2.0 * e * e - (2.0 - e * e) * (beta0 - alpha0)))
    m = rho * 4.0 / 3.0 * np.pi * a * b * b
    turn = kp * m * (a * a + b * b) / 5.0
    np.testing.assert_allclose(model.added_mass[0], np.diag([0.0, turn, turn, k1 * m, k2 * m, k2 * m]),
                               rtol=1e-9, atol=1e-9 * m)
    assert model.buoyancy_mass[0] == pytest.approx(100.0, rel=1e-15)     # the volume tag: 0.1 m^3
    assert dict(model.hydro_sources)["base: added mass"] == "hydrodynamic_model/type spheroid (uvms shape)"


def _thruster_robot(dynamics: str, conversion: str, limits: str = "") -> str:
    links = (_BASE + '<joint name="tj" type="continuous"><parent link="base"/><child link="t"/>'
             '<origin xyz="-0.4 0.1 0" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/></joint>'
             '<link name="t"><inertial><mass value="0.001"/><inertia ixx="0" ixy="0" ixz="0" iyy="0" iyz="0" '
             'izz="0"/></inertial></link>')
    thruster = ('<gazebo><plugin name="t0" filename="libuuv_thruster_ros_plugin.so"><linkName>t</linkName>'
                f'<jointName>tj</jointName><thrusterID>3</thrusterID>{limits}<dynamics>{dynamics}</dynamics>'
                f'<conversion>{conversion}</conversion></plugin></gazebo>')
    return _plugin_robot(links, '<link name="base"><volume>0.1</volume></link>', thruster)


def test_first_order_thruster_with_a_linear_interp_table(tmp_path):
    """``FirstOrder`` (``timeConstant``) with a ``LinearInterp`` table: a uvms ``first_order`` thruster with
    that time constant, along the spin joint's axis (turned 90 deg about z: +y) at its link's origin, limited
    by the table at the clamps (``clampMax`` 150 -> 30 N, ``clampMin`` -150 -> -20 N: the smaller, 20 N); the
    lag of a table is applied as UUV does, so only the asymmetric limits are noted."""
    table = ("<type>LinearInterp</type><inputValues>-200 -100 0 100 200</inputValues>"
             "<outputValues>-30 -10 0 20 40</outputValues>")
    text = _thruster_robot("<type>FirstOrder</type><timeConstant>0.25</timeConstant>", table,
                           "<clampMin>-150</clampMin><clampMax>150</clampMax>")
    (tmp_path / "t.urdf").write_text(text)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        model = uvms.load_model(tmp_path / "t.urdf")
    (t,) = model.thrusters
    assert t.name == "thruster_3" and t.model == "first_order"
    assert t.parameters.time_constant == 0.25 and t.parameters.max_thrust == pytest.approx(20.0, rel=1e-15)
    np.testing.assert_allclose(t.position, [-0.4, 0.1, 0.0], rtol=0, atol=1e-15)
    np.testing.assert_allclose(t.direction, [0.0, 1.0, 0.0], rtol=0, atol=1e-15)
    text = " ".join(str(w.message) for w in caught)
    assert "limits 30 N forward, 20 N reverse" in text and "FirstOrder lag applied to the thrust" not in text


def test_first_order_thruster_with_a_basic_conversion_is_noted(tmp_path):
    text = _thruster_robot("<type>FirstOrder</type><timeConstant>0.1</timeConstant>",
                           "<type>Basic</type><rotorConstant>0.001</rotorConstant>",
                           "<clampMin>-100</clampMin><clampMax>100</clampMax>")
    (tmp_path / "t.urdf").write_text(text)
    with pytest.warns(UserWarning, match="FirstOrder lag applied to the thrust"):
        model = uvms.load_model(tmp_path / "t.urdf")
    assert model.thrusters[0].parameters.max_thrust == pytest.approx(0.001 * 100.0 ** 2, rel=1e-15)


@pytest.mark.parametrize("dynamics, conversion, message", [
    ("<type>Yoerger</type>", "<type>Basic</type><rotorConstant>0.001</rotorConstant>",
     "dynamics type ZeroOrder or FirstOrder, found 'Yoerger' (not mapped)"),
    ("<type>ZeroOrder</type>", "<type>Bessa</type><rotorConstantL>0.001</rotorConstantL>",
     "conversion type Basic or LinearInterp, found 'Bessa' (not mapped)"),
    ("<type>FirstOrder</type>", "<type>Basic</type><rotorConstant>0.001</rotorConstant>", "<timeConstant> > 0"),
    ("<type>ZeroOrder</type>", "<type>LinearInterp</type><inputValues>0 1</inputValues><outputValues>0</outputValues>",
     "as many inputValues as outputValues"),
])
def test_thrusters_uvms_cannot_map_are_refused_in_one_line(tmp_path, capsys, dynamics, conversion, message):
    """A thruster whose dynamics or conversion uvms does not have is refused by the CLI (exit 2, one line naming
    the file and the plugin): a vehicle missing a thruster would fly differently without saying so."""
    from uvms.cli import main

    (tmp_path / "t.urdf").write_text(_thruster_robot(dynamics, conversion))
    assert main(["validate", str(tmp_path / "t.urdf")]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and message in err and "t.urdf" in err and "Traceback" not in err
