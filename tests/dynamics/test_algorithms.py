"""ABA against CRBA + RNEA, RNEA(ABA(tau)) == tau, on random chains and states (issue 2 and 3 acceptance)."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from tests.conftest import random_model
from uvms.dynamics.plant import kernel_model
from uvms.state import State


def random_state(rng, model, speed=1.0):
    n = model.n_joints
    return State.from_euler(model, position=rng.normal(size=3), euler=rng.uniform(-np.pi, np.pi, 3) * [1, 0.5, 1],
                            nu=rng.normal(scale=speed, size=6), q=rng.uniform(-np.pi, np.pi, n),
                            qd=rng.normal(scale=speed, size=n))


def rel_err(a, b):
    return np.linalg.norm(a - b) / max(np.linalg.norm(b), 1.0)


@pytest.mark.parametrize("hydro", [False, True], ids=["rigid", "hydrodynamic"])
def test_aba_matches_crba_rnea_on_random_chains(rng, hydro):
    """``M qdd_aba == [f0; tau] - h`` with M from CRBA (added mass included) and h from RNEA, 1..20 links."""
    worst = 0.0
    for trial in range(200):
        n = int(rng.integers(1, 21))
        model = random_model(rng, n, hydro=hydro)
        state = random_state(rng, model)
        tau = rng.normal(scale=3.0, size=n)
        f0 = rng.normal(scale=20.0, size=6)
        current = rng.normal(scale=0.5, size=3) if hydro else None
        fluid_acc = rng.normal(scale=0.2, size=3) if hydro else None
        acc = uvms.forward_dynamics(model, state, joint_torques=tau, body_wrench=f0, current=current,
                                    fluid_acceleration=fluid_acc)
        M = uvms.mass_matrix(model, state)
        h = uvms.bias_forces(model, state, current=current, fluid_acceleration=fluid_acc)
        rhs = np.concatenate([f0, tau]) - h
        worst = max(worst, rel_err(M @ acc.generalized, rhs))
    assert worst < 1e-9


@pytest.mark.parametrize("hydro", [False, True], ids=["rigid", "hydrodynamic"])
def test_rnea_inverts_aba(rng, hydro):
    """RNEA(ABA(tau)) == tau and the same vehicle wrench, with an end-effector force too."""
    for trial in range(200):
        n = int(rng.integers(1, 21))
        model = random_model(rng, n, hydro=hydro)
        state = random_state(rng, model)
        tau = rng.normal(scale=3.0, size=n)
        f0 = rng.normal(scale=20.0, size=6)
        f_ee = rng.normal(scale=5.0, size=6)
        current = rng.normal(scale=0.5, size=3) if hydro else None
        acc = uvms.forward_dynamics(model, state, joint_torques=tau, body_wrench=f0, ee_wrench=f_ee, current=current)
        f0_back, tau_back = uvms.inverse_dynamics(model, state, nu_dot=acc.nu_dot, qdd=acc.qdd, ee_wrench=f_ee,
                                                  current=current)
        assert rel_err(f0_back, f0) < 1e-9
        assert rel_err(tau_back, tau) < 1e-9


def test_mass_matrix_is_symmetric_positive_definite(rng):
    for trial in range(50):
        model = random_model(rng, int(rng.integers(1, 15)))
        M = uvms.mass_matrix(model, random_state(rng, model))
        np.testing.assert_allclose(M, M.T, atol=1e-12)
        assert np.linalg.eigvalsh(M).min() > 0


def test_fixed_base_matches_joint_block(rng):
    """Clamped vehicle: qdd solves the joint block of M with the joint rows of h; nu_dot is zero."""
    for trial in range(50):
        n = int(rng.integers(1, 12))
        model = random_model(rng, n)
        state = random_state(rng, model).replace(nu=np.zeros(6))
        tau = rng.normal(size=n)
        acc = uvms.forward_dynamics(model, state, joint_torques=tau, fixed_base=True)
        M = uvms.mass_matrix(model, state)
        h = uvms.bias_forces(model, state)
        qdd = np.linalg.solve(M[6:, 6:], tau - h[6:])
        assert np.all(acc.nu_dot == 0.0)
        assert rel_err(acc.qdd, qdd) < 1e-9


def test_fixed_base_refuses_a_moving_vehicle(rng):
    model = random_model(rng, 2)
    state = random_state(rng, model)
    with pytest.raises(ValueError, match="fixed_base"):
        uvms.forward_dynamics(model, state, fixed_base=True)


def test_every_model_gives_the_kernels_one_argument_type(rng):
    """``uvms.forward_dynamics`` and friends resolve each kernel's compiled specialisation once
    (``dynamics/api.py``): that is only right if every model's kernel arrays have the same numba type."""
    from numba import typeof

    paper = uvms.load_model("paper")
    models = [paper, paper.vehicle_only(), paper.with_hydrodynamics_scaled(added_mass=0.4, drag=0.4),
              random_model(rng, 7, hydro=True), random_model(rng, 2, hydro=False)]
    assert len({typeof(kernel_model(m)) for m in models}) == 1
    # interleaved calls on models of different sizes keep their own workspaces and results
    states = [random_state(rng, m) for m in models]
    first = [uvms.forward_dynamics(m, s).generalized for m, s in zip(models, states)]
    again = [uvms.forward_dynamics(m, s).generalized for m, s in zip(models[::-1], states[::-1])][::-1]
    for a, b in zip(first, again):
        np.testing.assert_array_equal(a, b)
