"""One robot written three ways, for the importer tests: an SDF (gz-sim systems), a URDF with UUV Simulator's
plugin tags, and a uvms model YAML over a plain URDF.

The robot is our own test vehicle (no published model's file is copied): a 120 kg box-shaped vehicle, z up
(x forward, y left), a one-link arm on a revolute shoulder, a camera on a pinned revolute mount (lower = upper =
0, no mass), four thrusters on continuous spin joints (0.001 kg, no inertia: UUV Simulator's thruster links).
Its hydrodynamics are given once here, in uvms's own terms (link axes, ``[angular; linear]``, matrix entries),
and each writer puts them in its format's own conventions, written out here from the formats' definitions:

* UUV Simulator (``HydrodynamicModel.cc``): linear-first ``[u v w p q r]`` in the link's axes turned to z down
  (y and z negated), damping as derivatives (negative), added mass as the positive matrix;
* gz-sim's Hydrodynamics (``Hydrodynamics.cc``): linear-first in the link's own axes, every value a SNAME
  derivative (``xDotU = -M_A[0, 0]``, ``xU = -D_l[u, u]``, ``xUabsU = -D_q[u, u]``).
"""

from __future__ import annotations

import numpy as np

RHO = 1028.0
MASS = 120.0
COM = (0.02, -0.01, 0.05)
INERTIA = ((8.0, 0.3, 0.0), (0.3, 12.0, -0.2), (0.0, -0.2, 14.0))
BOX = (1.0, 0.5, 0.25)                  # buoyancy box (m), centred at CENTRE
CENTRE = (0.0, 0.0, 0.1)
SHOULDER = (0.6, 0.0, -0.2)
ARM = {"mass": 5.0, "com": (0.25, 0.0, 0.0), "inertia": (0.02, 0.1, 0.1)}
THRUSTERS = (((-0.5, 0.3, 0.0), (0.0, 0.0, 0.0)), ((-0.5, -0.3, 0.0), (0.0, 0.0, 0.0)),
             ((0.0, 0.3, 0.1), (0.0, -np.pi / 2, 0.0)), ((0.0, -0.3, 0.1), (0.0, -np.pi / 2, 0.0)))
"""Thruster joint origins ``(xyz, rpy)`` on the base; each pushes along its joint's x axis."""
MAX_THRUST = 80.0
TO_LINEAR_FIRST = [3, 4, 5, 0, 1, 2]     # linear-first index -> uvms index
H6 = np.array([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])


def hydrodynamics(seed: int = 7) -> dict:
    """Added mass ``A`` (symmetric positive definite), linear damping ``D_l`` (symmetric positive definite) and
    quadratic ``D_q`` (positive diagonal), uvms order and link axes (z up)."""
    rng = np.random.default_rng(seed)
    X = rng.normal(size=(6, 6))
    A = X @ X.T * 6.0 + np.diag([30.0, 60.0, 40.0, 90.0, 150.0, 200.0])
    Y = rng.normal(size=(6, 6))
    D_l = Y @ Y.T * 3.0 + np.diag([10.0, 12.0, 8.0, 60.0, 80.0, 120.0])
    D_q = np.diag(rng.uniform(5.0, 300.0, 6))
    return {"A": 0.5 * (A + A.T), "D_l": 0.5 * (D_l + D_l.T), "D_q": D_q}


def linear_first(M: np.ndarray) -> np.ndarray:
    """A uvms-order matrix in linear-first order."""
    return np.asarray(M)[np.ix_(TO_LINEAR_FIRST, TO_LINEAR_FIRST)]


def _f(x) -> str:
    return " ".join(repr(float(v)) for v in np.ravel(x))


def _inertia_xml(m, I) -> str:
    I = np.asarray(I, dtype=float)
    if I.ndim == 1:
        I = np.diag(I)
    I = I.tolist()
    return (f'<mass value="{m!r}"/><inertia ixx="{I[0][0]!r}" ixy="{I[0][1]!r}" ixz="{I[0][2]!r}" '
            f'iyy="{I[1][1]!r}" iyz="{I[1][2]!r}" izz="{I[2][2]!r}"/>')


def _urdf_body(tags: str = "") -> str:
    """The URDF links and joints (the same for the UUV file and the YAML's plain URDF)."""
    parts = [f'<link name="base_link"><inertial><origin xyz="{_f(COM)}" rpy="0 0 0"/>{_inertia_xml(MASS, INERTIA)}'
             '</inertial></link>',
             f'<joint name="shoulder" type="revolute"><origin xyz="{_f(SHOULDER)}" rpy="0 0 0"/>'
             '<parent link="base_link"/><child link="arm"/><axis xyz="0 0 1"/>'
             '<limit lower="-2" upper="2" effort="100" velocity="2"/></joint>',
             f'<link name="arm"><inertial><origin xyz="{_f(ARM["com"])}" rpy="0 0 0"/>'
             f'{_inertia_xml(ARM["mass"], ARM["inertia"])}</inertial></link>',
             '<joint name="camera_mount" type="revolute"><origin xyz="0.5 0 0.1" rpy="0 0 0"/>'
             '<parent link="base_link"/><child link="camera"/><axis xyz="0 1 0"/>'
             '<limit lower="0" upper="0" effort="0" velocity="0"/></joint><link name="camera"/>']
    for k, (xyz, rpy) in enumerate(THRUSTERS):
        parts.append(f'<joint name="thruster_{k}_joint" type="continuous"><origin xyz="{_f(xyz)}" rpy="{_f(rpy)}"/>'
                     f'<parent link="base_link"/><child link="thruster_{k}"/><axis xyz="1 0 0"/></joint>'
                     f'<link name="thruster_{k}"><inertial>{_inertia_xml(0.001, (0.0, 0.0, 0.0))}</inertial></link>')
    return f'<?xml version="1.0"?>\n<robot name="testrov">{"".join(parts)}{tags}</robot>\n'


def uuv_urdf(h: dict | None = None) -> str:
    """The URDF with UUV Simulator's plugin blocks (the thrusters ZeroOrder, Basic conversion)."""
    h = h or hydrodynamics()
    turn = H6[:, None] * h["A"] * H6[None, :]                   # to the link's z-down axes
    added = linear_first(turn)
    lin = -linear_first(H6[:, None] * h["D_l"] * H6[None, :])
    quad = -np.diag(linear_first(h["D_q"]))
    volume = float(np.prod(BOX))
    cob = CENTRE
    block = (f'<gazebo><plugin name="uuv_plugin" filename="libuuv_underwater_object_ros_plugin.so">'
             f'<fluid_density>{RHO!r}</fluid_density><flow_velocity_topic>current</flow_velocity_topic>'
             f'<link name="base_link"><neutrally_buoyant>0</neutrally_buoyant><volume>{volume!r}</volume>'
             f'<box><width>0.5</width><length>1.0</length><height>0.25</height></box>'
             f'<center_of_buoyancy>{_f(cob)}</center_of_buoyancy><hydrodynamic_model><type>fossen</type>'
             f'<added_mass>{_f(added)}</added_mass><linear_damping>{_f(lin)}</linear_damping>'
             f'<quadratic_damping>{_f(quad)}</quadratic_damping></hydrodynamic_model></link></plugin></gazebo>')
    for k in range(len(THRUSTERS)):
        block += (f'<gazebo><plugin name="t{k}" filename="libuuv_thruster_ros_plugin.so">'
                  f'<linkName>thruster_{k}</linkName><jointName>thruster_{k}_joint</jointName>'
                  f'<thrusterID>{k}</thrusterID><thrustMin>{-MAX_THRUST!r}</thrustMin>'
                  f'<thrustMax>{MAX_THRUST!r}</thrustMax><dynamics><type>ZeroOrder</type></dynamics>'
                  f'<conversion><type>Basic</type><rotorConstant>0.0004</rotorConstant></conversion></plugin></gazebo>')
    block += '<gazebo reference="camera"><sensor name="cam" type="camera"/></gazebo>'
    return _urdf_body(block)


def plain_urdf() -> str:
    return _urdf_body()


def model_yaml(urdf_name: str, h: dict | None = None) -> str:
    """A uvms model YAML over the plain URDF, in uvms's own terms (``frame: enu``)."""
    h = h or hydrodynamics()

    def rows(M):
        return "[" + ", ".join("[" + ", ".join(repr(float(x)) for x in r) + "]" for r in np.asarray(M)) + "]"

    thrusters = []
    for k, (xyz, rpy) in enumerate(THRUSTERS):
        from uvms.rotations import rotation_from_euler

        direction = rotation_from_euler(np.array(rpy)) @ np.array([1.0, 0.0, 0.0])
        thrusters.append(f"  - {{name: thruster_{k}, position: [{_f(xyz).replace(' ', ', ')}], "
                         f"direction: [{_f(direction).replace(' ', ', ')}], model: ideal, "
                         f"max_thrust: {MAX_THRUST!r}}}")
    return "\n".join([
        f"urdf: {urdf_name}", "name: testrov", "frame: enu",
        f"environment: {{density: {RHO!r}}}",
        "fixed_joints: [camera_mount, thruster_0_joint, thruster_1_joint, thruster_2_joint, thruster_3_joint]",
        "vehicle:",
        f"  added_mass: {{matrix: {rows(h['A'])}, about: origin}}",
        f"  buoyancy: {{volume: {float(np.prod(BOX))!r}, center: [{_f(CENTRE).replace(' ', ', ')}]}}",
        f"  damping: {{linear: {rows(h['D_l'])}, quadratic: {rows(h['D_q'])}}}",
        "thrusters:", *thrusters, ""])


def sdf(h: dict | None = None, *, world: bool = True) -> str:
    """The SDF (a world holding the model, with the Buoyancy system), gz-sim's conventions."""
    h = h or hydrodynamics()
    Ma, lin, quad = -linear_first(h["A"]), -linear_first(h["D_l"]), -np.diag(linear_first(h["D_q"]))
    m, v = "xyzkmn", "UVWPQR"
    hydro = "".join(f"<{m[i]}Dot{v[j]}>{float(Ma[i, j])!r}</{m[i]}Dot{v[j]}>" for i in range(6) for j in range(6))
    hydro += "".join(f"<{m[i]}{v[j]}>{float(lin[i, j])!r}</{m[i]}{v[j]}>" for i in range(6) for j in range(6))
    hydro += "".join(f"<{m[i]}{v[i]}abs{v[i]}>{float(quad[i])!r}</{m[i]}{v[i]}abs{v[i]}>" for i in range(6))
    I = np.array(INERTIA).tolist()
    inertia = (f"<inertia><ixx>{I[0][0]!r}</ixx><ixy>{I[0][1]!r}</ixy><ixz>{I[0][2]!r}</ixz><iyy>{I[1][1]!r}</iyy>"
               f"<iyz>{I[1][2]!r}</iyz><izz>{I[2][2]!r}</izz></inertia>")
    parts = [f'<link name="base_link"><inertial><pose>{_f(COM)} 0 0 0</pose><mass>{MASS!r}</mass>{inertia}'
             f'</inertial><collision name="hull"><pose>{_f(CENTRE)} 0 0 0</pose><geometry><box><size>{_f(BOX)}'
             '</size></box></geometry></collision></link>',
             f'<link name="arm"><pose>{_f(SHOULDER)} 0 0 0</pose><inertial><pose>{_f(ARM["com"])} 0 0 0</pose>'
             f'<mass>{ARM["mass"]!r}</mass><inertia><ixx>0.02</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia>'
             '</inertial></link>',
             '<joint name="shoulder" type="revolute"><parent>base_link</parent><child>arm</child>'
             '<axis><xyz>0 0 1</xyz><limit><lower>-2</lower><upper>2</upper><effort>100</effort>'
             '<velocity>2</velocity></limit></axis></joint>',
             '<link name="camera"><pose relative_to="base_link">0.5 0 0.1 0 0 0</pose><inertial><mass>0</mass>'
             '<inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial></link>',
             '<joint name="camera_mount" type="revolute"><parent>base_link</parent><child>camera</child>'
             '<axis><xyz>0 1 0</xyz><limit><lower>0</lower><upper>0</upper></limit></axis></joint>']
    plugins = [f'<plugin filename="gz-sim-hydrodynamics-system" name="gz::sim::systems::Hydrodynamics">'
               f'<link_name>base_link</link_name>{hydro}</plugin>']
    for k, (xyz, rpy) in enumerate(THRUSTERS):
        parts.append(f'<link name="thruster_{k}"><pose>{_f(xyz)} {_f(rpy)}</pose><inertial><mass>0.001</mass>'
                     '<inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial></link>'
                     f'<joint name="thruster_{k}_joint" type="continuous"><parent>base_link</parent>'
                     f'<child>thruster_{k}</child><axis><xyz>1 0 0</xyz></axis></joint>')
        plugins.append(f'<plugin filename="gz-sim-thruster-system" name="gz::sim::systems::Thruster">'
                       f'<joint_name>thruster_{k}_joint</joint_name><thrust_coefficient>0.004</thrust_coefficient>'
                       f'<fluid_density>{RHO!r}</fluid_density><propeller_diameter>0.1</propeller_diameter>'
                       f'<max_thrust_cmd>{MAX_THRUST!r}</max_thrust_cmd><min_thrust_cmd>{-MAX_THRUST!r}'
                       '</min_thrust_cmd></plugin>')
    model = f'<model name="testrov">{"".join(parts)}{"".join(plugins)}</model>'
    buoyancy = (f'<plugin filename="gz-sim-buoyancy-system" name="gz::sim::systems::Buoyancy">'
                f'<uniform_fluid_density>{RHO!r}</uniform_fluid_density></plugin>')
    if not world:
        return f'<?xml version="1.0"?>\n<sdf version="1.9">{model}</sdf>\n'
    return (f'<?xml version="1.0"?>\n<sdf version="1.9"><world name="w"><gravity>0 0 -9.81</gravity>{buoyancy}'
            f'<model name="ground"><static>true</static><link name="g"/></model>{model}</world></sdf>\n')
