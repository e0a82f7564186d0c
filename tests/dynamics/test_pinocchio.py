"""Rigid-body dynamics against Pinocchio: ABA, CRBA, RNEA and forward kinematics on the paper's arm and on
random chains, floating and fixed base, with and without gravity.

Pinocchio has no hydrodynamics, so every uvms model here is rigid (``with_effects(added_mass=False, ...)``,
or ``random_model(..., hydro=False)``). The conversions between the two libraries' conventions live in
:mod:`uvms.interop.pinocchio_model`.
"""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from tests.conftest import random_model
from uvms.interop.pinocchio_model import (
    END_EFFECTOR_FRAME,
    body_wrench_force,
    generalized_from_pinocchio,
    matrix_from_pinocchio,
    pinocchio_configuration,
    pinocchio_model_from,
    pinocchio_velocity,
)

pin = pytest.importorskip("pinocchio")

N_STATES = 50
TOLERANCE = 1e-9


def close(actual: np.ndarray, expected: np.ndarray, tol: float = TOLERANCE) -> bool:
    """Equal to ``tol`` relative to the norm of ``expected``, or absolutely where that norm is below 1."""
    return bool(np.linalg.norm(actual - expected) <= tol * max(1.0, np.linalg.norm(expected)))


def rigid_paper(gravity: bool) -> uvms.Model:
    return uvms.load_model("paper").with_effects(added_mass=False, drag=False, buoyancy=False, gravity=gravity)


def random_state(rng: np.random.Generator, model, *, fixed_base: bool = False) -> uvms.State:
    n = model.n_joints
    return uvms.State.from_euler(
        model,
        position=rng.normal(size=3),
        euler=rng.uniform([-np.pi, -np.pi / 2, -np.pi], [np.pi, np.pi / 2, np.pi]),
        nu=np.zeros(6) if fixed_base else rng.normal(size=6) * np.array([1, 1, 1, 0.5, 0.5, 0.5]),
        q=rng.uniform(-np.pi, np.pi, n),
        qd=rng.normal(scale=2.0, size=n),
    )


def external_forces(pin_model, body_wrench=None, ee_wrench=None, ee_frame=None):
    """Pinocchio's ``fext`` (one local-frame force per joint) for a vehicle wrench and an end-effector wrench."""
    fext = pin.StdVec_Force()
    for _ in range(pin_model.njoints):
        fext.append(pin.Force.Zero())
    if body_wrench is not None:
        fext[1] = body_wrench_force(body_wrench)
    if ee_wrench is not None:
        f = pin.Force(np.array(ee_wrench[3:6]), np.array(ee_wrench[0:3]))
        fext[ee_frame.parentJoint] = fext[ee_frame.parentJoint] + ee_frame.placement.act(f)
    return fext


def assert_aba_matches(model, rng, *, fixed_base: bool, n_states: int = N_STATES, ee_wrench: bool = False):
    """``uvms.forward_dynamics`` equals ``pinocchio.aba`` at ``n_states`` random states and inputs."""
    n = model.n_joints
    pm_free = None if fixed_base else pinocchio_model_from(model)
    for _ in range(n_states):
        state = random_state(rng, model, fixed_base=fixed_base)
        tau = rng.normal(scale=2.0, size=n)
        wrench = None if fixed_base else rng.normal(size=6) * np.array([5, 5, 5, 30, 30, 30])
        f_ee = rng.normal(size=6) * np.array([1, 1, 1, 10, 10, 10]) if ee_wrench else None
        acc = uvms.forward_dynamics(model, state, joint_torques=tau, body_wrench=wrench, ee_wrench=f_ee,
                                    fixed_base=fixed_base)
        if fixed_base:
            pm = pinocchio_model_from(model, fixed_base=True, base_rotation=state.rotation,
                                      base_position=state.position)
            tau_pin = tau
        else:
            pm = pm_free
            tau_pin = np.concatenate([np.zeros(6), tau])
        pd = pm.createData()
        fext = external_forces(pm, wrench, f_ee, pm.frames[pm.getFrameId(END_EFFECTOR_FRAME)])
        ddq = pin.aba(pm, pd, pinocchio_configuration(state, fixed_base=fixed_base),
                      pinocchio_velocity(state, fixed_base=fixed_base), tau_pin, fext)
        expected = generalized_from_pinocchio(ddq, fixed_base=fixed_base)
        actual = acc.qdd if fixed_base else acc.generalized
        assert close(actual, expected), f"uvms {actual}\npinocchio {expected}"
        if fixed_base:
            assert np.all(acc.nu_dot == 0.0)


@pytest.mark.parametrize("gravity", [True, False], ids=["gravity", "no-gravity"])
@pytest.mark.parametrize("fixed_base", [False, True], ids=["floating", "fixed"])
def test_paper_arm_forward_dynamics_matches_pinocchio(rng, gravity, fixed_base):
    assert_aba_matches(rigid_paper(gravity), rng, fixed_base=fixed_base)


def test_end_effector_wrench_matches_pinocchio(rng):
    assert_aba_matches(rigid_paper(True), rng, fixed_base=False, n_states=10, ee_wrench=True)


@pytest.mark.parametrize("n", [1, 5, 12])
@pytest.mark.parametrize("fixed_base", [False, True], ids=["floating", "fixed"])
def test_random_chain_forward_dynamics_matches_pinocchio(n, fixed_base):
    rng = np.random.default_rng(1000 + n)
    model = random_model(rng, n, hydro=False)
    assert_aba_matches(model, rng, fixed_base=fixed_base, n_states=10, ee_wrench=True)


@pytest.mark.parametrize("n", [None, 1, 5, 12], ids=["paper", "random1", "random5", "random12"])
def test_mass_matrix_matches_crba(rng, n):
    model = rigid_paper(True) if n is None else random_model(rng, n, hydro=False)
    pm = pinocchio_model_from(model)
    pd = pm.createData()
    for _ in range(10):
        state = random_state(rng, model)
        M = pin.crba(pm, pd, pinocchio_configuration(state))
        M = np.triu(M) + np.triu(M, 1).T      # Pinocchio only guarantees the upper triangle
        expected = matrix_from_pinocchio(M)
        actual = uvms.mass_matrix(model, state)
        assert np.linalg.norm(actual - expected) <= TOLERANCE * np.linalg.norm(expected)
        assert np.linalg.norm(actual - actual.T) <= 1e-14 * np.linalg.norm(actual)


@pytest.mark.parametrize("n", [None, 5], ids=["paper", "random5"])
def test_inverse_dynamics_matches_rnea(rng, n):
    model = rigid_paper(True) if n is None else random_model(rng, n, hydro=False)
    pm = pinocchio_model_from(model)
    pd = pm.createData()
    for _ in range(10):
        state = random_state(rng, model)
        nu_dot = rng.normal(size=6)
        qdd = rng.normal(size=model.n_joints)
        f0, tau = uvms.inverse_dynamics(model, state, nu_dot=nu_dot, qdd=qdd)
        a_pin = np.concatenate([nu_dot[3:6], nu_dot[0:3], qdd])
        expected = generalized_from_pinocchio(
            pin.rnea(pm, pd, pinocchio_configuration(state), pinocchio_velocity(state), a_pin))
        assert close(np.concatenate([f0, tau]), expected)


@pytest.mark.parametrize("n", [None, 1, 5, 12], ids=["paper", "random1", "random5", "random12"])
@pytest.mark.parametrize("fixed_base", [False, True], ids=["floating", "fixed"])
def test_end_effector_pose_matches_pinocchio_frame(rng, n, fixed_base):
    model = rigid_paper(True) if n is None else random_model(rng, n, hydro=False)
    for _ in range(10):
        state = random_state(rng, model, fixed_base=fixed_base)
        if fixed_base:
            pm = pinocchio_model_from(model, fixed_base=True, base_rotation=state.rotation,
                                      base_position=state.position)
        else:
            pm = pinocchio_model_from(model)
        pd = pm.createData()
        pin.framesForwardKinematics(pm, pd, pinocchio_configuration(state, fixed_base=fixed_base))
        oMf = pd.oMf[pm.getFrameId(END_EFFECTOR_FRAME)]
        np.testing.assert_allclose(uvms.end_effector_position(model, state), oMf.translation, rtol=0, atol=1e-12)
        np.testing.assert_allclose(uvms.forward_kinematics(model, state).end_effector_rotation, oMf.rotation,
                                   rtol=0, atol=1e-12)


def test_paper_end_effector_at_zero_configuration():
    """Anchor independent of both libraries: straight arm, level vehicle at the origin -> [0.66, 0, 0]."""
    model = rigid_paper(True)
    state = uvms.State.zero(model)
    pm = pinocchio_model_from(model)
    pd = pm.createData()
    pin.framesForwardKinematics(pm, pd, pinocchio_configuration(state))
    np.testing.assert_allclose(pd.oMf[pm.getFrameId(END_EFFECTOR_FRAME)].translation, [0.66, 0.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(uvms.end_effector_position(model, state), [0.66, 0.0, 0.0], atol=1e-15)


def test_builder_shapes_and_gravity():
    model = rigid_paper(True)
    free = pinocchio_model_from(model)
    fixed = pinocchio_model_from(model, fixed_base=True)
    assert (free.nq, free.nv) == (7 + 3, 6 + 3)
    assert (fixed.nq, fixed.nv) == (3, 3)
    np.testing.assert_array_equal(free.gravity.linear, [0.0, 0.0, 9.81])
    assert np.isclose(sum(inertia.mass for inertia in free.inertias), 35.0)


def random_tree(rng: np.random.Generator, n: int) -> uvms.Model:
    """A random chain made a random tree: random parents, unit axes in any direction, revolute, continuous and
    prismatic joints, the end effector on a random body (rigid: no hydrodynamics). Bodies stay in depth-first
    order (each parent is on the path from the root to the previous body), as Pinocchio's CRBA requires."""
    model = random_model(rng, n, hydro=False)
    parents = []
    path = [0]                                   # the root-to-previous-body path
    for i in range(1, n + 1):
        k = int(rng.integers(0, len(path)))
        parents.append(path[k])
        path = path[:k + 1] + [i]
    axes = rng.normal(size=(n, 3))
    axes[rng.random(n) < 0.3] = [0.0, 0.0, 1.0]
    axes /= np.linalg.norm(axes, axis=1, keepdims=True)
    ee_body = int(rng.integers(0, n + 1))
    return model.replace(joint_parent=np.array(parents),
                         joint_axis=axes, joint_type=tuple(rng.choice(["revolute", "continuous", "prismatic"], n)),
                         ee_body=ee_body, frames=None)


@pytest.mark.parametrize("n", [1, 4, 9])
@pytest.mark.parametrize("fixed_base", [False, True], ids=["floating", "fixed"])
def test_random_tree_forward_dynamics_matches_pinocchio(n, fixed_base):
    rng = np.random.default_rng(2000 + n)
    model = random_tree(rng, n)
    assert "prismatic" in model.joint_type or n == 1
    assert_aba_matches(model, rng, fixed_base=fixed_base, n_states=10, ee_wrench=True)


@pytest.mark.parametrize("n", [4, 9])
def test_random_tree_mass_matrix_inverse_dynamics_and_frames_match_pinocchio(n):
    rng = np.random.default_rng(3000 + n)
    model = random_tree(rng, n)
    assert len(set(model.joint_parent)) < n and "prismatic" in model.joint_type     # branches, slides
    pm = pinocchio_model_from(model)
    pd = pm.createData()
    for _ in range(10):
        state = random_state(rng, model)
        M = pin.crba(pm, pd, pinocchio_configuration(state))
        expected = matrix_from_pinocchio(np.triu(M) + np.triu(M, 1).T)
        assert np.linalg.norm(uvms.mass_matrix(model, state) - expected) <= TOLERANCE * np.linalg.norm(expected)
        nu_dot, qdd = rng.normal(size=6), rng.normal(size=n)
        f0, tau = uvms.inverse_dynamics(model, state, nu_dot=nu_dot, qdd=qdd)
        expected = generalized_from_pinocchio(pin.rnea(pm, pd, pinocchio_configuration(state),
                                                       pinocchio_velocity(state),
                                                       np.concatenate([nu_dot[3:6], nu_dot[0:3], qdd])))
        assert close(np.concatenate([f0, tau]), expected)
        pin.framesForwardKinematics(pm, pd, pinocchio_configuration(state))
        oMf = pd.oMf[pm.getFrameId(END_EFFECTOR_FRAME)]
        np.testing.assert_allclose(uvms.end_effector_position(model, state), oMf.translation, rtol=0, atol=1e-12)
        poses = uvms.forward_kinematics(model, state)
        for i in range(1, n + 1):
            oMi = pd.oMi[pm.getJointId(model.joint_names[i - 1])]
            np.testing.assert_allclose(poses.position[i], oMi.translation, rtol=0, atol=1e-12)
            np.testing.assert_allclose(poses.rotation[i], oMi.rotation, rtol=0, atol=1e-12)
