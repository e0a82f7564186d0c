"""``uvms.linearize``: against the test's own plain central differences of ``forward_dynamics`` in the same chart
(step-size study), against the mass matrix (CRBA), against Fossen's closed form ``-M^-1 D`` and the restoring
matrix of a vehicle at rest, against an explicit integral of the zero-order hold, and against a nonlinear
simulation of a small perturbation. Bad input: one line naming the argument."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad_vec
from scipy.linalg import expm
from scipy.spatial.transform import Rotation

import uvms
from uvms.errors import UvmsInputError
from tests.conftest import random_model

G = 9.81


def skew(v):
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def inverse_right_jacobian(phi):
    """Closed form of SO(3)'s inverse right Jacobian (Chirikjian, Stochastic Models, Information Theory and Lie
    Groups, vol. 2, Sec. 10.6): ``I + 1/2 [phi] + (1/a^2 - (1 + cos a) / (2 a sin a)) [phi]^2``, ``a = |phi|``."""
    a = np.linalg.norm(phi)
    S = skew(phi)
    if a < 1e-6:
        return np.eye(3) + 0.5 * S + S @ S / 12.0
    return np.eye(3) + 0.5 * S + (1.0 / a**2 - (1.0 + np.cos(a)) / (2.0 * a * np.sin(a))) * S @ S


def chart_field(model, state, dx, u, current=None):
    """The full nonlinear vector field in the chart ``R = R0 Exp(dtheta)`` (scipy's rotation-vector map), written
    independently of the module: [R v, J_r^-1 omega, forward_dynamics, qd, qdd]."""
    n = model.n_joints
    R = state.rotation @ Rotation.from_rotvec(dx[3:6]).as_matrix()
    x, y, z, w = Rotation.from_matrix(R).as_quat()
    nu = state.nu + dx[6:12]
    s = uvms.State(position=state.position + dx[:3], quaternion=[w, x, y, z], nu=nu, q=state.q + dx[12:12 + n],
                   qd=state.qd + dx[12 + n:])
    acc = uvms.forward_dynamics(model, s, body_wrench=u[:6], joint_torques=u[6:], current=current)
    return np.concatenate([R @ nu[3:], inverse_right_jacobian(dx[3:6]) @ nu[:3], acc.nu_dot, s.qd, acc.qdd])


def central_jacobian(model, state, u0, h, current=None):
    """Plain central differences, one absolute step ``h`` for every column."""
    N = 12 + 2 * model.n_joints
    columns = []
    for j in range(N + u0.size):
        e = np.zeros(N + u0.size)
        e[j] = h
        plus = chart_field(model, state, e[:N], u0 + e[N:], current)
        minus = chart_field(model, state, -e[:N], u0 - e[N:], current)
        columns.append((plus - minus) / (2 * h))
    return np.array(columns).T


def row_relative_error(J, reference):
    scale = np.max(np.abs(reference), axis=1)
    return float(np.max(np.max(np.abs(J - reference), axis=1) / scale))


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def moving_state(model, rng):
    n = model.n_joints
    return uvms.State.from_euler(model, position=[1.0, -2.0, 3.0], euler=[0.3, -0.4, 2.0],
                                 nu=rng.normal(scale=0.3, size=6), q=rng.uniform(-1, 1, n), qd=rng.normal(size=n))


@pytest.mark.parametrize("case", ["paper at rest", "paper moving in a current", "random arm moving"])
def test_agrees_with_central_differences_at_the_best_step(paper, case):
    """Step-size study: plain central differences of the chart field at steps 1e-2 ... 1e-8; at the best step
    every row agrees with the linearisation to 1e-6 of that row's largest entry, and the error curve has the
    expected shape (truncation error at large steps)."""
    rng = np.random.default_rng(16)
    current = None
    if case == "paper at rest":
        model, state = paper, uvms.State.zero(paper)
    elif case == "paper moving in a current":
        model, state, current = paper, moving_state(paper, rng), np.array([0.2, -0.1, 0.05])
    else:
        model = random_model(rng, 3, current=[0.1, 0.3, -0.2])
        state = moving_state(model, rng)
    u0 = np.concatenate([rng.normal(scale=5.0, size=6), rng.normal(scale=0.5, size=model.n_joints)])
    lin = uvms.linearize(model, state, body_wrench=u0[:6], joint_torques=u0[6:], current=current)
    reference = np.hstack([lin.A, lin.B])
    errors = {h: row_relative_error(central_jacobian(model, state, u0, h, current), reference)
              for h in 10.0 ** -np.arange(2, 9)}
    best = min(errors.values())
    assert best < 1e-6, errors
    if case != "paper at rest":
        assert errors[1e-2] > 100 * best        # a smooth field: O(h^2) truncation visible at large steps
    # the drift is the field itself at the operating point
    np.testing.assert_allclose(lin.drift, chart_field(model, state, np.zeros(lin.A.shape[0]), u0, current),
                               rtol=1e-12, atol=1e-12)


def test_input_matrix_is_the_inverse_mass_matrix(paper):
    """``M [nu_dot; qdd] + h = [f_0; tau]``: the acceleration rows of ``B`` are ``M^-1`` (CRBA), at any state."""
    rng = np.random.default_rng(7)
    for model in (paper, random_model(rng, 4)):
        state = moving_state(model, rng)
        lin = uvms.linearize(model, state)
        n = model.n_joints
        rows = list(range(6, 12)) + list(range(12 + n, 12 + 2 * n))
        Minv = np.linalg.inv(uvms.mass_matrix(model, state))
        np.testing.assert_allclose(lin.B[rows], Minv, rtol=0, atol=1e-8 * np.abs(Minv).max())
        others = np.delete(lin.B, rows, axis=0)
        assert np.all(others == 0.0)


def test_vehicle_at_rest_is_fossens_linear_form(paper):
    """Vehicle only, quadratic drag off, a full (symmetric positive definite) linear damping ``D``: at rest the
    velocity block is ``-M^-1 D`` with ``M = M_RB + M_A`` written out from the model's numbers; the attitude block
    is ``-M^-1 G`` with the restoring matrix of a neutral vehicle whose centre of buoyancy is ``h`` above its
    centre of mass at the origin: ``G = m_f g h diag(1, 1, 0)`` on the moments, no force."""
    rng = np.random.default_rng(3)
    X = rng.normal(size=(6, 6))
    D = X @ X.T + np.diag([2.0, 3.0, 4.0, 20.0, 30.0, 40.0])
    vehicle = paper.vehicle_only().with_effects(drag=False).replace(damping_linear=D[None], thrusters=())
    m, Ic, MA = float(vehicle.mass[0]), vehicle.inertia_com[0], vehicle.added_mass[0]
    assert np.all(vehicle.com[0] == 0.0)                 # CoM at the origin: M_RB = diag(I_c, m 1)
    M = np.zeros((6, 6))
    M[:3, :3], M[3:, 3:] = Ic, m * np.eye(3)
    M += MA
    lin = uvms.linearize(vehicle, uvms.State.zero(vehicle), step=0.05)
    np.testing.assert_allclose(lin.A[6:12, 6:12], -np.linalg.solve(M, D), rtol=1e-7, atol=1e-9)
    mf, h = float(vehicle.buoyancy_mass[0]), -float(vehicle.cob[0, 2])
    assert np.allclose(vehicle.cob[0, :2], 0.0) and mf == m and h > 0
    Gm = np.zeros((6, 3))
    Gm[:3] = mf * G * h * np.diag([1.0, 1.0, 0.0])
    np.testing.assert_allclose(lin.A[6:12, 3:6], -np.linalg.solve(M, Gm), rtol=1e-7, atol=1e-9)
    np.testing.assert_allclose(lin.A[6:12, 0:3], 0.0, atol=1e-12)     # a uniform fluid: position does not matter
    # kinematic rows at rest, level: p_dot = v, theta_dot = omega
    np.testing.assert_array_equal(lin.A[0:3, 9:12], np.eye(3))
    np.testing.assert_array_equal(lin.A[3:6, 6:9], np.eye(3))
    np.testing.assert_allclose(lin.drift, 0.0, atol=1e-12)
    # zero-order hold against the explicit integral Bd = int_0^T expm(A s) ds B
    integral, _ = quad_vec(lambda s: expm(lin.A * s), 0.0, 0.05, epsabs=1e-13)
    np.testing.assert_allclose(lin.Ad, expm(lin.A * 0.05), rtol=1e-12, atol=1e-14)
    np.testing.assert_allclose(lin.Bd, integral @ lin.B, rtol=1e-9, atol=1e-12)


def test_bundled_vehicle_at_rest_is_fossens_linear_form():
    """The BlueROV2 Heavy alone, its own numbers: Fossen's linear damping ``D_l`` (diagonal, about the origin),
    quadratic damping and shape drag (no first-order term at rest), CoM offset ``c`` from the origin, full
    added-mass matrix. At rest the velocity block is ``-M^-1 D_l`` with Featherstone's rigid-body inertia about the
    origin ``[[I_c + m [c x][c x]^T, m [c x]], [m [c x]^T, m 1]]`` plus the added mass; it rises (not neutral),
    which does not change that block."""
    vehicle = uvms.load_model("bluerov2_heavy_alpha5").vehicle_only().replace(thrusters=())
    m, c, Ic = float(vehicle.mass[0]), vehicle.com[0], vehicle.inertia_com[0]
    assert np.linalg.norm(c) > 1e-3 and np.all(vehicle.damping_point[0] == 0.0)
    S = skew(c)
    M = np.block([[Ic + m * S @ S.T, m * S], [m * S.T, m * np.eye(3)]]) + vehicle.added_mass[0]
    lin = uvms.linearize(vehicle, uvms.State.zero(vehicle))
    expected = -np.linalg.solve(M, vehicle.damping_linear[0])
    np.testing.assert_allclose(lin.A[6:12, 6:12], expected, rtol=0, atol=1e-8 * np.abs(expected).max())
    assert lin.drift[11] < 0                     # positively buoyant: accelerates up (world z down)


def test_kinematic_rows_of_a_moving_tilted_vehicle(paper):
    """``p_dot = R v`` and ``dtheta_dot = J_r^-1 omega`` differentiated by hand: ``-R0 [v0 x]``, ``R0``,
    ``-1/2 [omega0 x]``, ``I``."""
    state = moving_state(paper, np.random.default_rng(5))
    lin = uvms.linearize(paper, state)
    R0, omega, v = state.rotation, state.nu[:3], state.nu[3:]
    np.testing.assert_allclose(lin.A[0:3, 3:6], -R0 @ skew(v), atol=1e-15)
    np.testing.assert_allclose(lin.A[0:3, 9:12], R0, atol=1e-15)
    np.testing.assert_allclose(lin.A[3:6, 3:6], -0.5 * skew(omega), atol=1e-15)
    assert lin.state_names[:12] == ("x", "y", "z", "rx", "ry", "rz", "p", "q", "r", "u", "v", "w")
    assert lin.state_names[12] == "q_joint1" and lin.state_names[-1] == "qd_joint3"
    assert lin.input_names == ("K", "M", "N", "X", "Y", "Z", "tau_joint1", "tau_joint2", "tau_joint3")


def test_small_perturbation_follows_the_linear_model(paper):
    """A nonlinear simulation of the paper model released from a small perturbation of rest (tilt, velocity and
    arm motion) stays within O(|dx|^2) of ``expm(A t) dx0`` read in the same chart."""
    model = paper.replace(thrusters=())
    rest = uvms.State.zero(model)
    lin = uvms.linearize(model, rest)
    N = lin.A.shape[0]
    rng = np.random.default_rng(11)
    for eps in (1e-3, 2e-3):
        dx0 = eps * rng.normal(size=N)
        R = Rotation.from_rotvec(dx0[3:6])
        x, y, z, w = R.as_quat()
        start = uvms.State(position=dx0[:3], quaternion=[w, x, y, z], nu=dx0[6:12], q=dx0[12:15], qd=dx0[15:])
        result = uvms.simulate(model, start, duration=0.5, step=1e-3)
        final = result.state(-1)
        w, x, y, z = final.quaternion
        dx = np.concatenate([final.position, Rotation.from_quat([x, y, z, w]).as_rotvec(), final.nu, final.q,
                             final.qd])
        predicted = expm(lin.A * 0.5) @ dx0
        error = np.max(np.abs(dx - predicted)) / np.max(np.abs(predicted))
        assert error < 10 * eps, (eps, error)            # measured 6.5 eps and 3.9 eps
        assert np.max(np.abs(dx - dx0)) / np.max(np.abs(predicted)) > 0.3     # while the state did move


def test_bad_input_is_one_line_naming_the_argument(paper):
    rest = uvms.State.zero(paper)
    nan_state = uvms.State.trusted(np.zeros(3), np.array([1.0, 0, 0, 0]), np.array([0, 0, np.nan, 0, 0, 0]),
                                   np.zeros(3), np.zeros(3), np.zeros(0))
    cases = [
        (dict(state=nan_state), "state.nu", "expected finite values, got nan at index 2"),
        (dict(joint_torques=[1.0, 2.0]), "joint_torques", "expected 3 finite values"),
        (dict(body_wrench=np.zeros(5)), "body_wrench", "expected 6 finite values"),
        (dict(ee_wrench=[0, 0, 0, 0, 0, np.inf]), "ee_wrench", "expected 6 finite values"),
        (dict(current=[0.1, 0.2]), "current", "expected 3 finite values"),
        (dict(step=-0.01), "step", "expected a positive, finite number"),
        (dict(state=uvms.State.zero(paper.vehicle_only())), "state", "expected a state of the model's 3 joints"),
        (dict(model="paper"), "model", "expected a uvms Model"),
    ]
    for override, path, message in cases:
        args = dict(model=paper, state=rest)
        args.update(override)
        model, state = args.pop("model"), args.pop("state")
        with pytest.raises(UvmsInputError) as info:
            uvms.linearize(model, state, **args)
        assert info.value.path == path and message in str(info.value), (path, str(info.value))
        assert "\n" not in str(info.value)
    lin = uvms.linearize(paper, rest)
    with pytest.raises(UvmsInputError, match="unknown name 'x_dot'"):
        lin.select(["x", "x_dot"])
    with pytest.raises(UvmsInputError, match="given twice"):
        lin.select(inputs=["X", "X"])


def test_select_keeps_the_named_rows_and_columns(paper):
    lin = uvms.linearize(paper, uvms.State.zero(paper), step=0.02)
    sub = lin.select(["u", "x", "rz"], ["N", "X"])
    rows, cols = [9, 0, 5], [2, 3]
    np.testing.assert_array_equal(sub.A, lin.A[np.ix_(rows, rows)])
    np.testing.assert_array_equal(sub.B, lin.B[np.ix_(rows, cols)])
    assert sub.state_names == ("u", "x", "rz") and sub.input_names == ("N", "X")
    np.testing.assert_allclose(sub.Ad, expm(sub.A * 0.02), rtol=1e-12, atol=1e-15)
