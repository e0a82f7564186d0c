"""SDF files with gz-sim's systems (``uvms.model.sdf``, issue 26).

gz-sim's Hydrodynamics force is written out here from its definition (``Hydrodynamics.cc``, ``PreUpdate``: the
applied wrench is ``Ma nu_dot + Cmat nu - Dmat nu`` with ``Ma`` the ``xDotU`` ... derivatives; ``Cmat`` from
``HydrodynamicsUtils.hh``'s ``buildCoriolisMatrix``, entry by entry; ``Dmat(i, j) = -lin - sum_k (quadAbs |nu_k| +
quad nu_k)``), with the Buoyancy system's ``rho V g`` up at the collisions' volume centre and Newton-Euler for
the rigid body, and solved for the acceleration: none of uvms's spatial algebra is used.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

import uvms
from tests.model import gazebo_fixtures as fx
from uvms.errors import UvmsInputError

G = 9.81


def S(v) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def gz_coriolis(Ma, s) -> np.ndarray:
    """gz-sim's ``buildCoriolisMatrix`` (the diagonal of ``Ma`` only), entry by entry."""
    C = np.zeros((6, 6))
    C[0, 4], C[0, 5] = -Ma[2, 2] * s[2], Ma[1, 1] * s[1]
    C[1, 3], C[1, 5] = Ma[2, 2] * s[2], -Ma[0, 0] * s[0]
    C[2, 3], C[2, 4] = -Ma[1, 1] * s[1], Ma[0, 0] * s[0]
    C[3, 1], C[3, 2], C[3, 4], C[3, 5] = -Ma[2, 2] * s[2], Ma[1, 1] * s[1], -Ma[5, 5] * s[5], Ma[4, 4] * s[4]
    C[4, 0], C[4, 2], C[4, 3], C[4, 5] = Ma[2, 2] * s[2], -Ma[0, 0] * s[0], Ma[5, 5] * s[5], -Ma[3, 3] * s[3]
    C[5, 0], C[5, 1], C[5, 3], C[5, 4] = -Ma[1, 1] * s[1], Ma[0, 0] * s[0], -Ma[4, 4] * s[4], Ma[3, 3] * s[3]
    return C


def fossen_coriolis(M_A, s) -> np.ndarray:
    """Fossen (2011) Eq. 6.43: ``C_A(nu) = [[0, -S(A11 v + A12 w)], [-S(A11 v + A12 w), -S(A21 v + A22 w)]]``
    (``M_A`` the positive added mass, linear-first); the fluid's force is ``-C_A(nu) nu``."""
    a = M_A @ s
    return np.block([[np.zeros((3, 3)), -S(a[:3])], [-S(a[:3]), -S(a[3:])]])


def gz_damping(lin, quad_abs, quad, s) -> np.ndarray:
    D = np.zeros((6, 6))
    for i in range(6):
        for j in range(6):
            D[i, j] = -lin[i, j] - sum(quad_abs[i, j, k] * abs(s[k]) + quad[i, j, k] * s[k] for k in range(6))
    return D


def _vehicle_sdf(p) -> str:
    m, v = "xyzkmn", "UVWPQR"
    tags = "".join(f"<{m[i]}Dot{v[i]}>{float(p['Ma'][i, i])!r}</{m[i]}Dot{v[i]}>" for i in range(6))
    for i in range(6):
        for j in range(6):
            tags += f"<{m[i]}{v[j]}>{float(p['lin'][i, j])!r}</{m[i]}{v[j]}>"
            for k in range(6):
                if p["quad_abs"][i, j, k]:
                    tags += f"<{m[i]}{v[j]}abs{v[k]}>{float(p['quad_abs'][i, j, k])!r}</{m[i]}{v[j]}abs{v[k]}>"
                if p["quad"][i, j, k]:
                    tags += f"<{m[i]}{v[j]}{v[k]}>{float(p['quad'][i, j, k])!r}</{m[i]}{v[j]}{v[k]}>"
    c, b, I = p["com"], p["box_centre"], p["I"]
    return (f'<?xml version="1.0"?><sdf version="1.9"><world name="w"><gravity>0 0 {-G!r}</gravity>'
            f'<plugin filename="gz-sim-buoyancy-system" name="gz::sim::systems::Buoyancy">'
            f'<uniform_fluid_density>{p["rho"]!r}</uniform_fluid_density></plugin><model name="auv">'
            f'<link name="base_link"><inertial><pose>{c[0]!r} {c[1]!r} {c[2]!r} 0 0 0</pose>'
            f'<mass>{p["mass"]!r}</mass><inertia><ixx>{I[0]!r}</ixx><iyy>{I[1]!r}</iyy><izz>{I[2]!r}</izz></inertia>'
            f'</inertial><collision name="c"><pose>{b[0]!r} {b[1]!r} {b[2]!r} 0 0 0</pose><geometry><box>'
            f'<size>{" ".join(repr(x) for x in p["box"])}</size></box></geometry></collision></link>'
            f'<plugin filename="gz-sim-hydrodynamics-system" name="gz::sim::systems::Hydrodynamics">'
            f'<link_name>base_link</link_name>{tags}</plugin></model></world></sdf>')


def _random_vehicle(rng) -> dict:
    quad_abs = -rng.uniform(0.0, 40.0, (6, 6, 6)) * (rng.uniform(size=(6, 6, 6)) < 0.3)
    for j in range(6):
        quad_abs[j, j, j] = -rng.uniform(50.0, 200.0)
    quad = -rng.uniform(0.0, 5.0, (6, 6, 6)) * (rng.uniform(size=(6, 6, 6)) < 0.1)
    Y = rng.normal(size=(6, 6))
    return dict(Ma=-np.diag(rng.uniform(5.0, 120.0, 6)), lin=-(Y @ Y.T * 4.0 + 10.0 * np.eye(6)),
                quad_abs=quad_abs, quad=quad, mass=150.0, com=[0.01, 0.0, -0.03], I=[3.0, 42.0, 41.0],
                rho=1025.0, box=[2.3, 0.3, 0.21], box_centre=[0.0, 0.0, 0.02])


def _gz_acceleration(p, R, nu_flu) -> np.ndarray:
    """gz-sim's equations (link axes, linear-first) solved for ``[v_dot; w_dot]``."""
    v, w = nu_flu[3:], nu_flu[:3]
    s = np.concatenate([v, w])
    Ma = p["Ma"]
    applied_rest = -fossen_coriolis(-Ma, s) @ s - gz_damping(p["lin"], p["quad_abs"], p["quad"], s) @ s
    m, rg = p["mass"], np.array(p["com"])
    weight = R.T @ np.array([0.0, 0.0, -m * G])
    buoy = R.T @ np.array([0.0, 0.0, p["rho"] * float(np.prod(p["box"])) * G])
    rb = np.array(p["box_centre"])
    tau = applied_rest + np.concatenate([weight + buoy, np.cross(rg, weight) + np.cross(rb, buoy)])
    I_o = np.diag(p["I"]) + m * (rg @ rg * np.eye(3) - np.outer(rg, rg))
    M_RB = np.block([[m * np.eye(3), -m * S(rg)], [m * S(rg), I_o]])
    bias = np.concatenate([m * (np.cross(w, v) + np.cross(w, np.cross(w, rg))),
                           np.cross(w, I_o @ w) + m * np.cross(rg, np.cross(w, v))])
    return np.linalg.solve(M_RB - Ma, tau - bias)        # the applied Ma nu_dot moved to the left


def test_gz_coriolis_matrix_is_fossens_with_the_opposite_sign_applied(rng):
    """gz-sim's ``buildCoriolisMatrix(Ma, s)`` (diagonal ``Ma`` of SNAME derivatives) equals Fossen's
    ``C_A(s)`` for ``M_A = -Ma``, and ``PreUpdate`` applies ``+Cmat s`` (``kTotalWrench -= Cmat s``, applied
    ``-kTotalWrench``): the opposite of Fossen's ``-C_A(nu) nu`` (and of Kirchhoff's ``-omega x (M_A v)``).
    uvms applies Fossen's (the physical) sign, so the comparison below takes gz-sim's added-mass and damping
    terms as written and the Coriolis term with Fossen's sign (docs/models.md says so)."""
    Ma = -np.diag(rng.uniform(1.0, 100.0, 6))
    s = rng.normal(size=6)
    np.testing.assert_allclose(gz_coriolis(Ma, s), fossen_coriolis(-Ma, s), rtol=1e-15, atol=1e-13)
    M_A = -Ma
    kirchhoff_force = -np.cross(s[3:], M_A[:3, :3] @ s[:3])
    np.testing.assert_allclose((-fossen_coriolis(M_A, s) @ s)[:3], kirchhoff_force, rtol=1e-13)


def test_gz_hydrodynamics_against_gz_equations(tmp_path, rng):
    p = _random_vehicle(rng)
    path = tmp_path / "auv.sdf"
    path.write_text(_vehicle_sdf(p))
    model = uvms.load_model(path)
    assert model.convention == "enu" and np.any(model.damping_cross[0])
    np.testing.assert_array_equal(model.gravity, [0.0, 0.0, -G])
    for _ in range(20):
        state = uvms.State.from_euler(model, position=rng.normal(size=3), euler=rng.uniform(-1.0, 1.0, 3),
                                      nu=rng.normal(size=6) * np.array([0.5, 0.5, 0.5, 1.5, 0.5, 0.5]))
        nu_dot = uvms.forward_dynamics(model, state).nu_dot
        ours = np.concatenate([nu_dot[3:], nu_dot[:3]])
        ref = _gz_acceleration(p, state.rotation, state.nu)
        np.testing.assert_allclose(ours, ref, rtol=0, atol=1e-10 * np.abs(ref).max())


def _bluerov2_heavy_sdf() -> str:
    """A BlueROV2 Heavy in SDF, our own file in the format of clydemcqueen/bluerov2_ignition, from published
    numbers: mass 13.5 kg (Blue Robotics' BlueROV2 Heavy), inertia diag(0.26, 0.23, 0.37) kg m^2 and added
    mass X_udot 6.36, Y_vdot 7.12, Z_wdot 18.68, K_pdot 0.189, M_qdot 0.135, N_rdot 0.222 (von Benzon et al.
    2022), surge drag xUabsU = -58.42 (bluerov2_ignition) and von Benzon's other quadratic terms; no linear term.
    Neutrally buoyant and level: the collision box (0.36 x 0.25 x 0.15 m) displaces 13.5 L, exactly m / rho in
    floating point, centred on the centre of mass."""
    rho, mass = 1000.0, 13.5
    hydro = {"xDotU": -6.36, "yDotV": -7.12, "zDotW": -18.68, "kDotP": -0.189, "mDotQ": -0.135, "nDotR": -0.222,
             "xUabsU": -58.42, "yVabsV": -217.0, "zWabsW": -190.0, "kPabsP": -1.19, "mQabsQ": -0.47,
             "nRabsR": -1.5}
    tags = "".join(f"<{k}>{v!r}</{k}>" for k, v in hydro.items())
    return (f'<?xml version="1.0"?><sdf version="1.6"><world name="w">'
            f'<plugin filename="gz-sim-buoyancy-system" name="gz::sim::systems::Buoyancy">'
            f'<uniform_fluid_density>{rho!r}</uniform_fluid_density></plugin><model name="bluerov2_heavy">'
            f'<link name="base_link"><inertial><mass>{mass!r}</mass><inertia><ixx>0.26</ixx><iyy>0.23</iyy>'
            f'<izz>0.37</izz></inertia></inertial><collision name="hull"><geometry><box>'
            f'<size>0.36 0.25 0.15</size></box></geometry></collision></link>'
            f'<plugin filename="gz-sim-hydrodynamics-system" name="gz::sim::systems::Hydrodynamics">'
            f'<link_name>base_link</link_name>{tags}</plugin></model></world></sdf>')


def test_bluerov2_heavy_reaches_its_steady_surge_speed(tmp_path):
    """Straight surge is an equilibrium of this level, neutral vehicle; it is not a stable one in Fossen's
    model (the added-mass Munk moment ``(Z_wdot - X_udot) u w`` beats the zero righting arm), so the vehicle is
    exactly neutral and symmetric: heave, sway and rotation stay exactly zero and ``u`` reaches
    ``sqrt(X / X_u|u|)``."""
    path = tmp_path / "bluerov2_heavy.sdf"
    path.write_text(_bluerov2_heavy_sdf())
    model = uvms.load_model(path)
    assert model.buoyancy_mass[0] == model.mass[0] == 13.5 and not np.any(model.cob[0] - model.com[0])
    result = uvms.simulate(model, duration=30.0, step=1e-3, body_wrench=np.array([0.0, 0.0, 0.0, 40.0, 0.0, 0.0]),
                           record_period=0.1)
    assert result.complete
    u = result.states[-1, 10]
    assert u == pytest.approx(math.sqrt(40.0 / 58.42), rel=1e-6)
    assert math.sqrt(40.0 / 58.42) == pytest.approx(0.8275, abs=5e-5)
    np.testing.assert_array_equal(result.states[:, [1, 2, 11, 12]], 0.0)    # no sway, no heave
    np.testing.assert_array_equal(result.states[:, 7:10], 0.0)              # no rotation


def _three_ways(tmp_path):
    (tmp_path / "rov.sdf").write_text(fx.sdf())
    (tmp_path / "rov.urdf").write_text(fx.uuv_urdf())
    (tmp_path / "plain.urdf").write_text(fx.plain_urdf())
    (tmp_path / "rov.yaml").write_text(fx.model_yaml("plain.urdf"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return [uvms.load_model(tmp_path / name) for name in ("rov.sdf", "rov.urdf", "rov.yaml")]


@pytest.mark.filterwarnings("ignore:.*crossed its position limit")   # limits are not enforced; all three alike
def test_the_same_robot_as_sdf_urdf_with_uuv_tags_and_yaml_moves_the_same(tmp_path):
    models = _three_ways(tmp_path)
    runs = []
    for model in models:
        state = uvms.State.from_euler(model, position=[1.0, -2.0, -5.0], euler=[0.1, -0.2, 0.3],
                                      nu=[0.1, -0.2, 0.05, 0.4, -0.1, 0.2], q=[0.3], qd=[-0.5])
        runs.append(uvms.simulate(model, state, duration=3.0, step=1e-3, joint_torques=np.array([0.3]),
                                  body_wrench=np.array([1.0, -2.0, 3.0, 30.0, 10.0, -20.0]), record_period=0.01))
    for other in runs[1:]:
        assert other.complete
        np.testing.assert_allclose(other.states, runs[0].states, rtol=0, atol=1e-12)
    assert np.ptp(runs[0].states[:, 0]) > 0.1 and np.ptp(runs[0].states[:, 13]) > 0.1   # it does move
    lay = [[(t.position, t.direction, t.max_thrust) for t in m.thrusters] for m in models]
    for other in lay[1:]:
        np.testing.assert_allclose(np.array([p + d for p, d, _ in other]), np.array([p + d for p, d, _ in lay[0]]),
                                   rtol=0, atol=1e-15)


def test_model_file_and_pose_relative_to(tmp_path):
    """A model file (no world) reads the same robot; ``relative_to`` poses and ``expressed_in`` axes resolve."""
    (tmp_path / "m.sdf").write_text(fx.sdf(world=False).replace(
        '<pose>0.6 0.0 -0.2 0 0 0</pose><inertial>', '<pose relative_to="camera">0.1 0.0 -0.3 0 0 0</pose><inertial>')
        .replace("<xyz>0 0 1</xyz><limit><lower>-2", '<xyz expressed_in="__model__">0 0 1</xyz><limit><lower>-2'))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        model = uvms.load_model(tmp_path / "m.sdf")
    np.testing.assert_allclose(model.joint_position[0], fx.SHOULDER, rtol=0, atol=1e-15)
    assert model.buoyancy_mass[0] == 0.0            # no Buoyancy system: gz-sim applies none


@pytest.mark.parametrize("text, message", [
    ('<sdf version="1.9"><world name="w"><include><uri>model://x</uri></include></world></sdf>', "<include>"),
    ('<sdf version="1.9"><world name="w"></world></sdf>', r"expected one \(non-static\) <model>, found 0"),
    ('<robot name="r"/>', "expected an <sdf> element"),
    ('<sdf version="1.9"><model name="m"><link name="a"><pose>1 2</pose></link></model></sdf>',
     "link 'a'.pose: expected 6 numbers, found 2"),
    ('<sdf version="1.9"><model name="m"><link name="a"/><link name="b"/><joint name="j" type="ball"><parent>a'
     '</parent><child>b</child></joint></model></sdf>', "unsupported joint type 'ball'"),
    ('<sdf version="1.9"><model name="m"><link name="a"><pose relative_to="nowhere">0 0 0 0 0 0</pose></link>'
     '</model></sdf>', "relative to 'nowhere'"),
])
def test_bad_sdf_one_line(tmp_path, text, message):
    (tmp_path / "bad.sdf").write_text(text)
    with pytest.raises(UvmsInputError, match=message) as info:
        uvms.load_model(tmp_path / "bad.sdf")
    assert "\n" not in str(info.value)


def test_validate_says_which_tag_each_hydrodynamic_number_came_from(tmp_path, capsys):
    from uvms.cli import main

    (tmp_path / "rov.sdf").write_text(fx.sdf())
    (tmp_path / "rov.urdf").write_text(fx.uuv_urdf())
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["validate", str(tmp_path / "rov.sdf")]) == 0
        sdf_out = capsys.readouterr().out
        assert main(["validate", str(tmp_path / "rov.urdf")]) == 0
        urdf_out = capsys.readouterr().out
    assert "hydrodynamics read from the file's tags:" in sdf_out
    assert "base_link: added mass: Hydrodynamics xDotU ... nDotR" in sdf_out
    assert "base_link: buoyancy: Buoyancy system: collision volumes" in sdf_out
    assert "base_link: added mass: hydrodynamic_model/added_mass" in urdf_out
    assert "base_link: buoyancy: volume" in urdf_out and "base_link: centre of buoyancy: center_of_buoyancy" in urdf_out


def _tethys_sdf(added_scale: float = 1.0) -> str:
    """A Tethys-like LRAUV: the Hydrodynamics numbers of gz-sim's ``examples/worlds/auv_controls.sdf``
    (Apache-2.0; ``yDotV = zDotW = -126.3`` kg against a rigid mass of 147.8 kg), on our own hull: a solid
    cylinder 2.3 m long, 0.3 m across (its inertia). World gravity zero: weight and buoyancy (equal in the
    example) are left out so that only the hydrodynamics act. ``added_scale`` multiplies the sway and heave
    added mass (1.2 x 147.8 / 126.3 makes it 1.2 times the rigid mass)."""
    m, L, r = 147.8, 2.3, 0.15
    Ixx, Iyy = m * r * r / 2.0, m * (3.0 * r * r + L * L) / 12.0
    hydro = {"xDotU": -4.876161, "yDotV": -126.324739 * added_scale, "zDotW": -126.324739 * added_scale,
             "kDotP": 0.0, "mDotQ": -33.46, "nDotR": -33.46, "xUabsU": -6.2282, "yVabsV": -601.27,
             "zWabsW": -601.27, "kPabsP": -0.1916, "mQabsQ": -632.698957, "nRabsR": -632.698957}
    tags = "".join(f"<{k}>{v!r}</{k}>" for k, v in hydro.items())
    return (f'<?xml version="1.0"?><sdf version="1.6"><world name="w"><gravity>0 0 0</gravity>'
            f'<model name="tethys"><link name="base_link"><inertial><mass>{m!r}</mass><inertia><ixx>{Ixx!r}</ixx>'
            f'<iyy>{Iyy!r}</iyy><izz>{Iyy!r}</izz></inertia></inertial></link>'
            f'<plugin filename="gz-sim-hydrodynamics-system" name="gz::sim::systems::Hydrodynamics">'
            f'<link_name>base_link</link_name>{tags}</plugin></model></world></sdf>')


def _lagged_added_mass_heave(m: float, M_A: float, c: float, w0: float, h: float, steps: int) -> np.ndarray:
    """gz-sim's explicit scheme on the heave axis alone, written out: the plugin applies ``-M_A (w_k -
    w_{k-1}) / h`` from the previous step's velocities and the physics integrates the rigid mass ``m``
    (semi-implicit Euler), with quadratic damping ``-c w |w|``."""
    w = np.zeros(steps + 1)
    w[0] = w_prev = w0
    with np.errstate(all="ignore"):           # the diverging case overflows
        for k in range(steps):
            force = -M_A * (w[k] - w_prev) / h - c * w[k] * abs(w[k])
            w_prev = w[k]
            w[k + 1] = w[k] + h * force / m
    return w


@pytest.mark.parametrize("added_scale", [1.0, 1.2 * 147.8 / 126.324739])
def test_tethys_added_mass_close_to_rigid_mass_runs_stably(tmp_path, added_scale):
    """With added mass at 0.85 and 1.2 times the rigid mass, uvms's run is stable: the kinetic energy
    ``nu^T M nu / 2`` (M with the added mass) never grows (damping only; the Coriolis terms do no work), down
    to 1e-9 relative per record. The explicit scheme gz-sim uses multiplies a velocity disturbance by
    ``-M_A / m`` each step: at 1.2 times the rigid mass its heave velocity grows without bound."""
    path = tmp_path / "tethys.sdf"
    path.write_text(_tethys_sdf(added_scale))
    model = uvms.load_model(path)
    state = uvms.State.from_euler(model, nu=[0.05, 0.1, -0.2, 2.0, 0.3, -0.4])
    result = uvms.simulate(model, state, duration=60.0, step=1e-3, record_period=0.05)
    assert result.complete and np.all(np.isfinite(result.states))
    energy = []
    for x in result.states[::10]:
        s = uvms.State.from_euler(model, nu=x[7:13])
        M = uvms.mass_matrix(model, s)
        energy.append(0.5 * x[7:13] @ M @ x[7:13])
    energy = np.array(energy)
    assert np.all(np.diff(energy) <= 1e-9 * energy[:-1]) and energy[-1] < 0.05 * energy[0]
    m, M_A = 147.8, 126.324739 * added_scale
    lagged = _lagged_added_mass_heave(m, M_A, 601.27, 0.2, 1e-3, 2000)
    if M_A > m:
        assert not np.all(np.isfinite(lagged)) or np.abs(lagged).max() > 1e6
    else:
        assert np.abs(lagged[-1]) < 0.2


def test_fluid_added_mass_about_the_inertial_frame(tmp_path, rng):
    """``<fluid_added_mass>`` (SDF 1.11) about an offset, turned inertial frame: its kinetic energy
    ``v_c^T M v_c / 2`` with ``v_c`` the inertial frame's velocity in its own axes equals uvms's
    ``nu^T I_A nu / 2`` about the link origin."""
    X = rng.normal(size=(6, 6))
    M = X @ X.T + np.eye(6)                         # linear-first, inertial frame
    names = "xyzpqr"
    tags = "".join(f"<{names[a]}{names[b]}>{float(M[a, b])!r}</{names[a]}{names[b]}>"
                   for a in range(6) for b in range(a, 6))
    c, rpy = np.array([0.2, -0.1, 0.05]), np.array([0.3, -0.2, 0.5])
    pose = " ".join(repr(float(x)) for x in (*c, *rpy))
    text = (f'<sdf version="1.11"><model name="m"><link name="base"><inertial><pose>{pose}</pose><mass>10</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz>'
            f'</inertia><fluid_added_mass>{tags}</fluid_added_mass></inertial></link></model></sdf>')
    (tmp_path / "f.sdf").write_text(text)
    model = uvms.load_model(tmp_path / "f.sdf")
    from uvms.rotations import rotation_from_euler

    R = rotation_from_euler(rpy)                     # inertial frame in the link frame
    for _ in range(5):
        w, v = rng.normal(size=3), rng.normal(size=3)
        s = np.concatenate([R.T @ (v + np.cross(w, c)), R.T @ w])
        nu = np.concatenate([w, v])
        assert nu @ model.added_mass[0] @ nu == pytest.approx(s @ M @ s, rel=1e-12)


def test_mixed_damping_follows_the_half_turn(tmp_path, rng):
    """``Model.in_frame`` maps the mixed quadratic damping too: the enu model and its ned image give the same
    motion mapped by the half turn (``docs/conventions.md``, "Frames")."""
    p = _random_vehicle(rng)
    (tmp_path / "auv.sdf").write_text(_vehicle_sdf(p))
    enu = uvms.load_model(tmp_path / "auv.sdf")
    ned = enu.in_frame("ned")
    h6 = np.array([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
    for _ in range(5):
        euler, nu = rng.uniform(-1.0, 1.0, 3), rng.normal(size=6)
        a = uvms.forward_dynamics(enu, uvms.State.from_euler(enu, euler=euler, nu=nu)).nu_dot
        b = uvms.forward_dynamics(ned, uvms.State.from_euler(ned, euler=euler * [1, -1, -1], nu=h6 * nu)).nu_dot
        np.testing.assert_allclose(h6 * b, a, rtol=0, atol=1e-12 * np.abs(a).max())


def test_sdf_collisions_as_shapes_through_a_model_yaml(tmp_path):
    """A model YAML over an SDF takes the collision primitives as shapes (``{type: from_collision}``) as it
    does over a URDF: the same box and cylinder give the same added mass, buoyancy and drag table."""
    inertial = '<inertial><mass>20</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz></inertia></inertial>'
    (tmp_path / "s.sdf").write_text(
        f'<sdf version="1.9"><model name="m"><link name="base">{inertial}'
        '<collision name="a"><pose>0.1 0 0.05 0 0 0.3</pose><geometry><box><size>0.6 0.3 0.2</size></box>'
        '</geometry></collision><collision name="b"><pose>-0.2 0.1 0 0 1.5707963267948966 0</pose><geometry>'
        '<cylinder><radius>0.05</radius><length>0.4</length></cylinder></geometry></collision></link></model></sdf>')
    (tmp_path / "u.urdf").write_text(
        '<robot name="m"><link name="base"><inertial><mass value="20"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" '
        'iyz="0" izz="1"/></inertial><collision><origin xyz="0.1 0 0.05" rpy="0 0 0.3"/><geometry><box '
        'size="0.6 0.3 0.2"/></geometry></collision><collision><origin xyz="-0.2 0.1 0" '
        'rpy="0 1.5707963267948966 0"/><geometry><cylinder radius="0.05" length="0.4"/></geometry></collision>'
        '</link></robot>')
    extra = "frame: enu\nvehicle:\n  shapes: [{type: from_collision, drag_coefficient: 1.1}]\n"
    (tmp_path / "s.yaml").write_text("urdf: s.sdf\n" + extra)
    (tmp_path / "u.yaml").write_text("urdf: u.urdf\n" + extra)
    a, b = uvms.load_model(tmp_path / "s.yaml"), uvms.load_model(tmp_path / "u.yaml")
    assert a.shape_count[0] == 2
    for field in ("added_mass", "buoyancy_mass", "cob", "shape_drag"):
        np.testing.assert_allclose(getattr(a, field), getattr(b, field), rtol=0, atol=1e-15)


def test_a_joint_pose_off_its_child_link_frame(tmp_path):
    """A joint whose ``<pose>`` (in its child link's frame) is not the identity: the axis passes through the
    joint frame, and the child's inertia is re-expressed there. The URDF written out by hand for the same arm
    (joint frame at the link pose times the joint pose; the inertial moved into it) moves the same."""
    c, s = math.cos, math.sin
    inertial = '<inertial><mass>{m}</mass><pose>{pose}</pose><inertia><ixx>0.02</ixx><iyy>0.1</iyy><izz>0.1</izz>' \
               '</inertia></inertial>'
    (tmp_path / "a.sdf").write_text(
        '<sdf version="1.9"><model name="m"><link name="base">'
        + inertial.format(m=50, pose="0 0 0 0 0 0").replace("0.02", "2").replace("0.1", "3")
        + '</link><link name="arm"><pose>0.6 0 -0.2 0 0 0.5</pose>' + inertial.format(m=5, pose="0.25 0 0 0 0 0")
        + '</link><joint name="j" type="revolute"><pose>0.1 0 0 0 0 0.2</pose><parent>base</parent><child>arm'
        '</child><axis><xyz>0 0 1</xyz></axis></joint></model></sdf>')
    x, y = 0.6 + 0.1 * c(0.5), 0.1 * s(0.5)
    (tmp_path / "a.urdf").write_text(
        '<robot name="m"><link name="base"><inertial><mass value="50"/><inertia ixx="2" ixy="0" ixz="0" iyy="3" '
        'iyz="0" izz="3"/></inertial></link><joint name="j" type="revolute">'
        f'<origin xyz="{x!r} {y!r} -0.2" rpy="0 0 0.7"/><parent link="base"/><child link="arm"/>'
        '<axis xyz="0 0 1"/></joint><link name="arm"><inertial>'
        f'<origin xyz="{0.15 * c(0.2)!r} {-0.15 * s(0.2)!r} 0" rpy="0 0 -0.2"/><mass value="5"/>'
        '<inertia ixx="0.02" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link></robot>')
    a, b = uvms.load_model(tmp_path / "a.sdf"), uvms.load_model(tmp_path / "a.urdf", frame="enu")
    state = uvms.State.from_euler(a, euler=[0.1, 0.2, 0.3], nu=[0.1, -0.2, 0.3, 0.4, 0.1, -0.1], q=[0.4], qd=[1.0])
    ga = uvms.forward_dynamics(a, state, joint_torques=[0.5]).generalized
    gb = uvms.forward_dynamics(b, state, joint_torques=[0.5]).generalized
    np.testing.assert_allclose(ga, gb, rtol=0, atol=1e-12 * np.abs(gb).max())


def test_a_thruster_commanded_by_angular_velocity_is_noted(tmp_path):
    """gz-sim's Thruster with ``use_angvel_cmd`` true takes the propeller's angular velocity as its command;
    uvms's ideal thruster takes the thrust: the warning says so (and names the joints), the thrusters stay."""
    text = fx.sdf().replace("<joint_name>thruster_1_joint</joint_name>",
                            "<joint_name>thruster_1_joint</joint_name><use_angvel_cmd>true</use_angvel_cmd>")
    (tmp_path / "rov.sdf").write_text(text)
    with pytest.warns(UserWarning, match=r"thruster thruster_1_joint: use_angvel_cmd: gz-sim commands it by the "
                                         r"propeller's angular velocity") as caught:
        model = uvms.load_model(tmp_path / "rov.sdf")
    assert len(model.thrusters) == 4
    assert not any("thruster_0_joint: use_angvel_cmd" in str(w.message) for w in caught)
    (tmp_path / "plain.sdf").write_text(fx.sdf().replace(
        "<joint_name>thruster_1_joint</joint_name>",
        "<joint_name>thruster_1_joint</joint_name><use_angvel_cmd>false</use_angvel_cmd>"))
    with warnings.catch_warnings(record=True) as plain:
        warnings.simplefilter("always")
        uvms.load_model(tmp_path / "plain.sdf")
    assert not any("use_angvel_cmd" in str(w.message) for w in plain)


_FEATURES_SDF = """<?xml version="1.0"?>
<sdf version="1.9"><model name="m">
  <frame name="mount" attached_to="base"><pose>0.3 0 -0.1 0 0 0</pose></frame>
  <link name="base"><inertial><mass>50</mass><inertia><ixx>2</ixx><iyy>3</iyy><izz>4</izz></inertia></inertial>
  </link>
  <link name="payload"><pose relative_to="base" degrees="true">0.1 0.2 0 0 0 90</pose>
    <inertial><pose>0.05 0 0 0 0 0</pose><mass>3</mass><inertia><ixx>0.1</ixx><iyy>0.2</iyy><izz>0.3</izz>
    </inertia></inertial></link>
  <joint name="fix" type="fixed"><parent>base</parent><child>payload</child></joint>
  <link name="slider"><pose relative_to="mount" rotation_format="quat_xyzw">0 0 0 0 0 0.7071067811865476
    0.7071067811865476</pose><inertial><mass>2</mass><inertia><ixx>0.01</ixx><iyy>0.02</iyy><izz>0.03</izz>
    </inertia></inertial></link>
  <joint name="slide" type="prismatic"><parent>base</parent><child>slider</child>
    <axis><xyz>1 0 0</xyz><limit><lower>-0.5</lower><upper>0.5</upper></limit></axis></joint>
  <plugin filename="gz-sim-hydrodynamics-system" name="gz::sim::systems::Hydrodynamics">
    <link_name>base</link_name><water_density>1025</water_density><default_current>0.2 -0.1 0.05</default_current>
    <xU>-5</xU><xDotU>-7</xDotU><disable_added_mass>true</disable_added_mass></plugin>
</model></sdf>
"""

_FEATURES_URDF = """<?xml version="1.0"?>
<robot name="m">
  <link name="base"><inertial><mass value="50"/><inertia ixx="2" ixy="0" ixz="0" iyy="3" iyz="0" izz="4"/></inertial>
  </link>
  <link name="payload"><inertial><origin xyz="0.05 0 0"/><mass value="3"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.2" iyz="0" izz="0.3"/></inertial></link>
  <joint name="fix" type="fixed"><parent link="base"/><child link="payload"/>
    <origin xyz="0.1 0.2 0" rpy="0 0 1.5707963267948966"/></joint>
  <link name="slider"><inertial><mass value="2"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.03"/>
    </inertial></link>
  <joint name="slide" type="prismatic"><parent link="base"/><child link="slider"/>
    <origin xyz="0.3 0 -0.1" rpy="0 0 1.5707963267948966"/><axis xyz="1 0 0"/>
    <limit lower="-0.5" upper="0.5" effort="0" velocity="0"/></joint>
</robot>
"""


def test_sdf_fixed_and_prismatic_joints_frames_degrees_and_quaternion_poses(tmp_path):
    """A fixed link posed in degrees, a prismatic link posed by a quaternion relative to a ``<frame>``: the same
    tree as the URDF written out by hand (fixed link merged, joint origin, axis, limits); the Hydrodynamics
    system's ``water_density``, ``default_current`` and linear term are read, and ``disable_added_mass`` leaves
    its added mass out with a note."""
    (tmp_path / "m.sdf").write_text(_FEATURES_SDF)
    (tmp_path / "m.urdf").write_text(_FEATURES_URDF)
    with pytest.warns(UserWarning, match="disable_added_mass: the plugin's added mass is left out"):
        sdf = uvms.load_model(tmp_path / "m.sdf")
    urdf = uvms.load_model(tmp_path / "m.urdf", frame="enu")
    assert sdf.joint_names == urdf.joint_names == ("slide",) and sdf.joint_type == urdf.joint_type
    for field in ("mass", "com", "inertia_com", "joint_position", "joint_rotation", "joint_axis", "joint_limits"):
        np.testing.assert_allclose(np.asarray(getattr(sdf, field), dtype=float),
                                   np.asarray(getattr(urdf, field), dtype=float), rtol=0, atol=1e-15, err_msg=field)
    assert sdf.mass[0] == 53.0
    assert sdf.density == 1025.0 and sdf.buoyancy_mass[0] == 0.0          # no Buoyancy system: none, as gz-sim
    np.testing.assert_array_equal(sdf.current, [0.2, -0.1, 0.05])
    assert sdf.damping_linear[0][3, 3] == 5.0 and not np.any(sdf.added_mass)


def test_a_world_files_gravity_is_read_in_either_frame(tmp_path):
    """The world's ``<gravity>`` (z up in SDF) becomes the model's, turned by the half turn when the file is read
    in the ``ned`` convention (``frame=``)."""
    (tmp_path / "w.sdf").write_text(fx.sdf().replace("<gravity>0 0 -9.81</gravity>", "<gravity>0.1 0.2 -9.7</gravity>"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        enu, ned = uvms.load_model(tmp_path / "w.sdf"), uvms.load_model(tmp_path / "w.sdf", frame="ned")
    np.testing.assert_array_equal(enu.gravity, [0.1, 0.2, -9.7])
    np.testing.assert_array_equal(ned.gravity, [0.1, -0.2, 9.7])


def test_buoyancy_of_sphere_cylinder_and_ellipsoid_collisions(tmp_path):
    """gz-sim's Buoyancy system (``uniform_fluid_density``): rho times each collision's volume, written out here
    (sphere 4/3 pi r^3, cylinder pi r^2 L, ellipsoid 4/3 pi a b c), at the volumes' centre; a mesh collision is
    not mapped (named in the warning)."""
    rho = 1020.0
    shapes = [("sphere", "<radius>0.2</radius>", (0.3, 0.0, 0.1), 4.0 / 3.0 * math.pi * 0.2 ** 3),
              ("cylinder", "<radius>0.1</radius><length>0.8</length>", (-0.2, 0.1, 0.0), math.pi * 0.1 ** 2 * 0.8),
              ("ellipsoid", "<radii>0.3 0.2 0.1</radii>", (0.0, -0.1, -0.05), 4.0 / 3.0 * math.pi * 0.3 * 0.2 * 0.1)]
    collisions = "".join(f'<collision name="{k}"><pose>{x} {y} {z} 0 0.3 0</pose><geometry><{k}>{size}</{k}>'
                         f'</geometry></collision>' for k, size, (x, y, z), _ in shapes)
    collisions += '<collision name="m"><geometry><mesh><uri>hull.dae</uri></mesh></geometry></collision>'
    (tmp_path / "b.sdf").write_text(
        f'<sdf version="1.9"><world name="w"><plugin filename="gz-sim-buoyancy-system" '
        f'name="gz::sim::systems::Buoyancy"><uniform_fluid_density>{rho!r}</uniform_fluid_density></plugin>'
        f'<model name="b"><link name="base"><inertial><mass>40</mass><inertia><ixx>1</ixx><iyy>1</iyy><izz>1</izz>'
        f'</inertia></inertial>{collisions}</link></model></world></sdf>')
    with pytest.warns(UserWarning, match="mesh"):
        model = uvms.load_model(tmp_path / "b.sdf")
    volumes = np.array([v for *_, v in shapes])
    centres = np.array([c for _, _, c, _ in shapes])
    assert model.buoyancy_mass[0] == pytest.approx(rho * volumes.sum(), rel=1e-12)
    np.testing.assert_allclose(model.cob[0], volumes @ centres / volumes.sum(), rtol=0, atol=1e-12)


def test_disable_coriolis_is_reported_not_applied(tmp_path):
    """``disable_coriolis`` cannot be honoured (uvms's added mass brings its Coriolis force with it): the added
    mass is kept and the warning says so."""
    (tmp_path / "m.sdf").write_text(_FEATURES_SDF.replace("<disable_added_mass>true</disable_added_mass>",
                                                          "<disable_coriolis>true</disable_coriolis>"))
    with pytest.warns(UserWarning, match="disable_coriolis not mapped"):
        model = uvms.load_model(tmp_path / "m.sdf")
    assert model.added_mass[0][3, 3] == 7.0
