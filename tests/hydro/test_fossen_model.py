"""Fossen's damping wired into model files and the compiled dynamics.

* the steady surge speed under a constant thrust is the positive root of ``X_u u + X_u|u| u^2 = X``;
* a vehicle-only model in Fossen's form agrees with an independent NumPy implementation of
  ``M nu_dot + C(nu) nu + D(nu) nu + g(eta) = tau`` written here from Fossen (2011), Eqs. 6.43/6.44 (the
  Sagatun-Fossen form of ``C_RB`` and ``C_A``), ``D = D_l + D_q |nu|`` and the restoring forces ``g(eta)``;
* with damping only, the kinetic energy decays monotonically;
* bad damping input is one line naming the file and the field.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

import uvms
from uvms.cli import main
from uvms.dynamics.energy import kinetic_energy
from uvms.dynamics.plant import kernel_model
from uvms.errors import UvmsInputError
from uvms.sim.run import simulate
from uvms.state import State

# BlueROV2 Heavy surge coefficients in SNAME derivative signs (docs/vehicle_sources.md)
X_U, X_UU = -4.03, -18.18


def vehicle_yaml(tmp_path, *, damping, mass=11.5, com=(0.0, 0.0, 0.0), inertia=(0.16, 0.16, 0.16),
                 added=(0.12, 0.12, 0.12, 5.5, 12.7, 14.57), buoyancy_mass=0.0, cob=(0.0, 0.0, 0.0),
                 gravity=(0.0, 0.0, 9.81), added_matrix=None, name="fossen.yaml"):
    added_mass = {"matrix": added_matrix, "about": "origin"} if added_matrix is not None else {
        "diagonal": list(added), "about": "origin"}
    data = {
        "name": "fossen-test",
        "environment": {"gravity": list(gravity)},
        "vehicle": {
            "mass": mass, "com": list(com),
            "inertia": {"diagonal": list(inertia), "about": "com"},
            "buoyancy": {"mass": buoyancy_mass, "center": list(cob)},
            "added_mass": added_mass,
            "drag": {"area": [0.0, 0.0, 0.0], "coefficient": [0.0, 0.0, 0.0],
                     "rotational": {"side": 0.0, "coefficient": 0.0}},
            "damping": damping,
            "box": [0.46, 0.58, 0.25],
        },
    }
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def test_steady_surge_speed_is_the_root_of_the_damping_balance(tmp_path):
    path = vehicle_yaml(tmp_path, damping={"coefficients": {"X_u": X_U, "X_u|u|": X_UU, "Y_v": -6.22,
                                                            "Z_w": -5.18, "N_r": -0.07, "N_r|r|": -1.55}},
                        gravity=(0.0, 0.0, 0.0))
    model = uvms.load_model(path)
    X = 20.0
    # X + X_u u + X_u|u| u|u| = 0 with u > 0:  (-X_UU) u^2 + (-X_U) u - X = 0
    a, b, c = -X_UU, -X_U, -X
    u_expected = (-b + math.sqrt(b * b - 4 * a * c)) / (2 * a)
    result = simulate(model, duration=20.0, step=1e-3, body_wrench=[0, 0, 0, X, 0, 0])
    nu = result.nu[-1]
    assert nu[3] == pytest.approx(u_expected, rel=1e-9)
    assert np.allclose(nu[[0, 1, 2, 4, 5]], 0.0, atol=1e-12)
    # not the root without the quadratic term: the test can fail
    assert abs(nu[3] - X / -X_U) > 1.0


# --- the independent NumPy implementation (Fossen's linear-first order [v; w]) ---------------------------------

def S(a):
    return np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])


def coriolis(M, nu):
    """Fossen (2011) Eqs. 6.43/6.44 (Sagatun and Fossen): C(nu) of a symmetric inertia M, order [v; w]."""
    v, w = nu[:3], nu[3:]
    a = M[:3, :3] @ v + M[:3, 3:] @ w
    b = M[3:, :3] @ v + M[3:, 3:] @ w
    return np.block([[np.zeros((3, 3)), -S(a)], [-S(a), -S(b)]])


def swap(A):
    """[angular; linear] <-> [linear; angular] for a 6x6 matrix."""
    P = np.block([[np.zeros((3, 3)), np.eye(3)], [np.eye(3), np.zeros((3, 3))]])
    return P @ A @ P.T


def fossen_acceleration(m, r_g, I_c, M_A_uvms, D_l_uvms, D_q_uvms, point, W, B, r_b, R, nu_uvms, tau_uvms):
    nu = np.concatenate([nu_uvms[3:], nu_uvms[:3]])
    tau = np.concatenate([tau_uvms[3:], tau_uvms[:3]])
    I_o = I_c - m * S(r_g) @ S(r_g)
    M_RB = np.block([[m * np.eye(3), -m * S(r_g)], [m * S(r_g), I_o]])          # Fossen Eq. 3.44
    M_A = swap(M_A_uvms)
    D_l, D_q = swap(D_l_uvms), swap(D_q_uvms)
    H = np.block([[np.eye(3), S(point).T], [np.zeros((3, 3)), np.eye(3)]])      # nu_p = H(r) nu
    nu_p = H @ nu
    d = H.T @ ((D_l + D_q @ np.diag(np.abs(nu_p))) @ nu_p)
    f_g = R.T @ np.array([0.0, 0.0, W])
    f_b = -R.T @ np.array([0.0, 0.0, B])
    g = -np.concatenate([f_g + f_b, np.cross(r_g, f_g) + np.cross(r_b, f_b)])
    rhs = tau - coriolis(M_RB, nu) @ nu - coriolis(M_A, nu) @ nu - d - g
    nu_dot = np.linalg.solve(M_RB + M_A, rhs)
    return np.concatenate([nu_dot[3:], nu_dot[:3]])


def random_spd(rng, n, scale):
    Q = rng.normal(size=(n, n))
    return scale * (Q @ Q.T / n + 0.1 * np.eye(n))


def test_vehicle_in_fossen_form_matches_numpy_reference(tmp_path):
    rng = np.random.default_rng(7)
    A = random_spd(rng, 6, 5.0)
    D_l = random_spd(rng, 6, 8.0)
    D_q = np.diag(rng.uniform(1.0, 30.0, 6))
    point = [0.05, -0.02, 0.08]
    m, r_g, r_b, m_f = 11.5, np.array([0.01, -0.02, 0.02]), np.array([0.0, 0.01, -0.01]), 11.7
    inertia = (0.21, 0.25, 0.3)
    path = vehicle_yaml(tmp_path, mass=m, com=r_g.tolist(), inertia=inertia, added_matrix=A.tolist(),
                        buoyancy_mass=m_f, cob=r_b.tolist(),
                        damping={"about": point, "linear": D_l.tolist(), "quadratic": np.diag(D_q).tolist()})
    model = uvms.load_model(path)
    g0 = 9.81
    for _ in range(20):
        euler = rng.uniform(-1.0, 1.0, 3)
        nu = rng.normal(size=6) * np.array([0.5, 0.5, 0.5, 1.0, 1.0, 1.0])
        tau = rng.normal(size=6) * 10.0
        state = State.from_euler(model, euler=euler, nu=nu)
        got = uvms.forward_dynamics(model, state, body_wrench=tau).nu_dot
        want = fossen_acceleration(m, r_g, np.diag(inertia), A, D_l, D_q, np.array(point), m * g0, m_f * g0, r_b,
                                   state.rotation, nu, tau)
        np.testing.assert_allclose(got, want, rtol=0, atol=1e-10)
    # the reference without D differs: the damping is really in the dynamics
    assert not np.allclose(got, fossen_acceleration(m, r_g, np.diag(inertia), A, 0 * D_l, 0 * D_q, np.array(point),
                                                    m * g0, m_f * g0, r_b, state.rotation, nu, tau), atol=1e-3)


def test_energy_decays_monotonically_with_damping_only(tmp_path):
    rng = np.random.default_rng(3)
    D_l = random_spd(rng, 6, 2.0)
    path = vehicle_yaml(tmp_path, gravity=(0.0, 0.0, 0.0), added_matrix=random_spd(rng, 6, 3.0).tolist(),
                        damping={"about": [0.1, 0.0, 0.05], "linear": D_l.tolist(),
                                 "quadratic": [1.5, 1.5, 1.5, 18.0, 21.0, 37.0]})
    model = uvms.load_model(path)
    start = State.from_euler(model, nu=[0.4, -0.3, 0.5, 1.0, -0.5, 0.3])
    result = simulate(model, start, duration=5.0, step=1e-3, record_period=0.01)
    E = np.array([kinetic_energy(model, result.state(k)) for k in range(len(result.time))])
    assert E[0] > 1.0 and E[-1] < 0.05 * E[0]
    assert np.all(np.diff(E) < 0.0)


def test_paper_model_has_no_fossen_damping():
    km = kernel_model(uvms.load_model("paper"))
    assert not km.fossen.any()


@pytest.mark.parametrize("damping,field", [
    ({"linear": [1, 1, 1, -4.0, 1, 1]}, "vehicle.damping.linear"),
    ({"coefficients": {"X_u": 4.03}}, "vehicle.damping.coefficients"),
    ({"coefficients": {"X_u": -4.0, "Q_z": 1.0}}, "vehicle.damping.coefficients.Q_z"),
    ({"linear": [1, 2, 3]}, "vehicle.damping.linear"),
    ({"coefficients": {"X_u": -1.0}, "linear": [1, 1, 1, 1, 1, 1]}, "vehicle.damping"),
])
def test_bad_damping_is_one_line_naming_file_and_field(tmp_path, capsys, damping, field):
    path = vehicle_yaml(tmp_path, damping=damping)
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    text = str(info.value)
    assert "\n" not in text and str(path) in text and field in text, text
    assert main(["validate", str(path)]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
