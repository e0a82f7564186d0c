"""Hybrid dynamics (Featherstone 2008, sec. 9.2; :mod:`uvms.dynamics.hybrid`) against independent algorithms:
the articulated-body algorithm driven by the torques it returns, the composite-rigid-body mass matrix with the
Newton-Euler bias (floating base), the Newton-Euler algorithm (clamped vehicle, hydrodynamics on) and
Pinocchio's RNEA (rigid, clamped)."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from tests.conftest import random_model
from uvms.dynamics.hybrid import aba_prescribed
from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.plant import fluid_table, kernel_model


def hybrid(model, state, qdd, *, tau=None, prescribed=None, fixed_base=False, body_wrench=None):
    """``(nu_dot, qdd, tau)`` of the hybrid kernel at ``state`` (the model's current)."""
    n = model.n_joints
    out = np.zeros(6), np.zeros(n), np.zeros(n)
    aba_prescribed(kernel_model(model), make_workspace(model.n_bodies), np.array(state.rotation, dtype=float),
                   np.array(state.position, dtype=float), np.array(state.nu, dtype=float), np.array(state.q, dtype=float), np.array(state.qd, dtype=float),
                   np.array(qdd, dtype=float), np.zeros(n) if tau is None else np.array(tau, dtype=float),
                   np.ones(n, dtype=np.bool_) if prescribed is None else np.array(prescribed, dtype=np.bool_),
                   np.zeros(6) if body_wrench is None else np.array(body_wrench, dtype=float), np.zeros(6),
                   fluid_table([0.0], [model.current], [model.fluid_acceleration]), 0.0, bool(fixed_base), *out)
    return out


def random_state(rng, model, *, fixed_base=False):
    n = model.n_joints
    return uvms.State.from_euler(model, position=rng.normal(size=3), euler=rng.uniform(-1.2, 1.2, 3),
                                 nu=np.zeros(6) if fixed_base else rng.normal(scale=0.4, size=6),
                                 q=rng.uniform(-np.pi, np.pi, n), qd=rng.normal(scale=1.5, size=n))


def close(actual, expected, tol):
    return bool(np.linalg.norm(np.subtract(actual, expected)) <= tol * max(1.0, np.linalg.norm(expected)))


@pytest.mark.parametrize("which", ["paper", "random"])
def test_the_aba_driven_by_the_hybrid_torques_gives_the_prescribed_accelerations(rng, which):
    """ABA(tau = hybrid's tau_out) returns the given qdd and the hybrid's nu_dot (hydrodynamics on)."""
    for _ in range(30):
        model = uvms.load_model("paper") if which == "paper" else random_model(rng, int(rng.integers(1, 7)))
        state = random_state(rng, model)
        qdd = rng.normal(scale=3.0, size=model.n_joints)
        wrench = rng.normal(size=6) * [2, 2, 2, 20, 20, 20]
        nu_dot, qdd_out, tau = hybrid(model, state, qdd, body_wrench=wrench)
        assert np.array_equal(qdd_out, qdd)
        acc = uvms.forward_dynamics(model, state, joint_torques=tau, body_wrench=wrench)
        assert close(acc.qdd, qdd, 1e-10), (acc.qdd, qdd)
        assert close(acc.nu_dot, nu_dot, 1e-10), (acc.nu_dot, nu_dot)


def test_a_mix_of_prescribed_and_free_joints_is_consistent_with_the_aba(rng):
    """Free joints take their torque, prescribed ones their acceleration: ABA(tau_out) reproduces both."""
    for _ in range(30):
        model = random_model(rng, int(rng.integers(2, 7)))
        n = model.n_joints
        state = random_state(rng, model)
        mask = rng.random(n) < 0.5
        qdd, tau = rng.normal(scale=3.0, size=n), rng.normal(scale=2.0, size=n)
        nu_dot, qdd_out, tau_out = hybrid(model, state, qdd, tau=tau, prescribed=mask)
        assert np.array_equal(qdd_out[mask], qdd[mask]) and np.array_equal(tau_out[~mask], tau[~mask])
        acc = uvms.forward_dynamics(model, state, joint_torques=tau_out)
        assert close(acc.qdd, qdd_out, 1e-10) and close(acc.nu_dot, nu_dot, 1e-10)
    model = random_model(rng, 4)                   # nothing prescribed: the ABA itself
    state = random_state(rng, model)
    tau = rng.normal(size=4)
    nu_dot, qdd_out, _ = hybrid(model, state, np.zeros(4), tau=tau, prescribed=np.zeros(4, dtype=bool))
    acc = uvms.forward_dynamics(model, state, joint_torques=tau)
    assert close(qdd_out, acc.qdd, 1e-12) and close(nu_dot, acc.nu_dot, 1e-12)


def test_floating_base_torques_equal_the_mass_matrix_solution(rng):
    """With f_0 the body wrench: ``M [nu_dot; qdd] + h = [f_0; tau]`` (CRBA and the Newton-Euler bias) solved for
    nu_dot and tau equals the hybrid's (hydrodynamics on)."""
    for _ in range(30):
        model = random_model(rng, int(rng.integers(1, 7)))
        state = random_state(rng, model)
        qdd = rng.normal(scale=3.0, size=model.n_joints)
        f0 = rng.normal(size=6)
        M, h = uvms.mass_matrix(model, state), uvms.bias_forces(model, state)
        nu_dot_expected = np.linalg.solve(M[:6, :6], f0 - h[:6] - M[:6, 6:] @ qdd)
        tau_expected = M[6:, :6] @ nu_dot_expected + M[6:, 6:] @ qdd + h[6:]
        nu_dot, _, tau = hybrid(model, state, qdd, body_wrench=f0)
        assert close(nu_dot, nu_dot_expected, 1e-9) and close(tau, tau_expected, 1e-9)


def test_clamped_vehicle_torques_equal_the_newton_euler_torques_in_fluid(rng):
    """Vehicle clamped, every joint prescribed: tau_out is the RNEA's (added mass, drag, buoyancy, gravity)."""
    for _ in range(30):
        model = random_model(rng, int(rng.integers(1, 7)))
        state = random_state(rng, model, fixed_base=True)
        qdd = rng.normal(scale=3.0, size=model.n_joints)
        nu_dot, _, tau = hybrid(model, state, qdd, fixed_base=True)
        _, tau_expected = uvms.inverse_dynamics(model, state, nu_dot=np.zeros(6), qdd=qdd)
        assert np.all(nu_dot == 0.0)
        assert close(tau, tau_expected, 1e-12)


def test_clamped_vehicle_torques_equal_pinocchio_rnea(rng):
    """Rigid paper arm (gravity on), vehicle clamped: tau_out is Pinocchio's RNEA."""
    pin = pytest.importorskip("pinocchio")
    from uvms.interop.pinocchio_model import pinocchio_configuration, pinocchio_model_from, pinocchio_velocity

    model = uvms.load_model("paper").with_effects(added_mass=False, drag=False, buoyancy=False, gravity=True)
    for _ in range(20):
        state = random_state(rng, model, fixed_base=True)
        qdd = rng.normal(scale=3.0, size=3)
        pm = pinocchio_model_from(model, fixed_base=True, base_rotation=state.rotation, base_position=state.position)
        expected = pin.rnea(pm, pm.createData(), pinocchio_configuration(state, fixed_base=True),
                            pinocchio_velocity(state, fixed_base=True), qdd)
        _, _, tau = hybrid(model, state, qdd, fixed_base=True)
        assert close(tau, expected, 1e-9), (tau, expected)
