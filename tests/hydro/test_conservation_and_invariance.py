"""Conservation laws, work of the velocity terms, drag dissipation, Galilean invariance, buoyancy, and the
vehicle against Fossen's equations written out by hand (issue 2 and 3 acceptance)."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from tests.conftest import random_model
from uvms.dynamics.energy import kinetic_energy, potential_energy, spatial_momentum
from uvms.rotations import rotation_from_quaternion
from uvms.sim.run import simulate
from uvms.spatial import skew


def paper_state(model, rng):
    return uvms.State.from_euler(model, euler=rng.uniform(-0.5, 0.5, 3), nu=rng.normal(scale=0.3, size=6),
                                 q=rng.uniform(-2, 2, 3), qd=rng.normal(scale=1.0, size=3))


@pytest.mark.parametrize("added_mass", [False, True], ids=["rigid", "added-mass"])
def test_free_floating_energy_and_momentum_conserved_over_10s(rng, added_mass):
    """No gravity, drag, buoyancy, current or inputs: T and world momentum constant to 1e-8 over 10 s (RK4, 1 ms)."""
    model = uvms.load_model("paper").with_effects(added_mass=added_mass, drag=False, buoyancy=False, gravity=False,
                                                  current=False)
    s0 = paper_state(model, rng)
    result = simulate(model, s0, duration=10.0, step=1e-3, record_period=1.0)
    T = [kinetic_energy(model, uvms.sim.integrate.unpack(x, 3)) for x in result.states]
    h = np.array([spatial_momentum(model, uvms.sim.integrate.unpack(x, 3), include_added_mass=added_mass)
                  for x in result.states])
    assert result.time[-1] == pytest.approx(10.0)
    assert np.max(np.abs(np.array(T) - T[0])) / T[0] < 1e-8
    assert np.max(np.linalg.norm(h - h[0], axis=1)) / np.linalg.norm(h[0]) < 1e-8


def test_added_mass_velocity_terms_do_no_work(rng):
    """zeta . h(zeta) == 0.5 zeta . M_dot zeta with h the RNEA bias (added mass, no drag/gravity/current)."""
    for trial in range(50):
        n = int(rng.integers(1, 8))
        model = random_model(rng, n, gravity=False).with_effects(drag=False, buoyancy=False, current=False)
        s = uvms.State.from_euler(model, euler=rng.uniform(-1, 1, 3), nu=rng.normal(size=6),
                                  q=rng.uniform(-3, 3, n), qd=rng.normal(size=n))
        z = s.generalized_velocity
        h = uvms.bias_forces(model, s)
        eps = 1e-3          # five-point central difference of M(q + t qd) at t = 0 (M depends on q only)
        M = [uvms.mass_matrix(model, s.replace(q=s.q + k * eps * s.qd)) for k in (-2, -1, 1, 2)]
        Mdot = (M[0] - 8 * M[1] + 8 * M[2] - M[3]) / (12 * eps)
        assert z @ h == pytest.approx(0.5 * z @ Mdot @ z, rel=1e-8, abs=1e-10)


def test_drag_power_is_never_positive(rng):
    """Each body's drag wrench does non-positive work on its fluid-relative velocity (random states, currents)."""
    for trial in range(300):
        n = int(rng.integers(1, 8))
        model = random_model(rng, n)
        s = uvms.State.from_euler(model, euler=rng.uniform(-1, 1, 3), nu=rng.normal(size=6),
                                  q=rng.uniform(-3, 3, n), qd=rng.normal(scale=2, size=n))
        w = uvms.hydrodynamic_wrenches(model, s, current=rng.normal(scale=0.5, size=3))
        power = np.einsum("ij,ij->i", w.wrenches["drag"], w.relative_velocity)
        assert np.all(power <= 1e-12)


def test_total_energy_never_increases_with_drag(rng):
    """Drag, gravity, buoyancy and added mass on, no inputs, still water: T + V non-increasing along a run."""
    model = uvms.load_model("paper")
    s0 = uvms.State.from_euler(model, euler=[0.3, -0.2, 0.5], nu=[0.5, -0.3, 0.4, 0.6, -0.4, 0.2],
                               q=[0.5, -1.0, 0.8], qd=[3.0, -2.0, 4.0])
    result = simulate(model, s0, duration=5.0, step=1e-3, record_period=0.01)
    E = np.array([kinetic_energy(model, s) + potential_energy(model, s)
                  for s in (uvms.sim.integrate.unpack(x, 3) for x in result.states)])
    assert E[-1] < E[0] - 1.0                                  # drag has dissipated energy [J]
    assert np.all(np.diff(E) <= 1e-9 * abs(E[0]))


def test_uniform_current_is_galilean(rng):
    """A constant current: the motion relative to the fluid equals the still-water motion, p = p_still + v_c t."""
    model = uvms.load_model("paper")
    vc = np.array([0.4, -0.3, 0.1])
    s_still = uvms.State.from_euler(model, euler=[0.2, -0.1, 0.7], nu=[0.2, -0.1, 0.3, 0.3, 0.1, -0.2],
                                    q=[0.3, -0.5, 0.9], qd=[1.0, -0.5, 0.7])
    R = s_still.rotation
    s_cur = s_still.replace(nu=s_still.nu + np.concatenate([np.zeros(3), R.T @ vc]))
    torques = uvms.TorqueSchedule(times=np.array([0.0, 1.0]), torques=np.array([[2.5, 0.3, -0.2], [0.01, 0.0, 0.0]]))
    a = simulate(model, s_still, duration=3.0, step=1e-3, joint_torques=torques, current=np.zeros(3),
                 record_period=0.1)
    b = simulate(model, s_cur, duration=3.0, step=1e-3, joint_torques=torques, current=vc, record_period=0.1)
    np.testing.assert_allclose(b.position, a.position + np.outer(a.time, vc), atol=1e-9)
    np.testing.assert_allclose(b.quaternion, a.quaternion, atol=1e-9)
    np.testing.assert_allclose(b.q, a.q, atol=1e-9)
    rel = np.array([x[7:13] - np.concatenate([np.zeros(3), rotation_from_quaternion(x[3:7]).T @ vc])
                    for x in b.states])
    np.testing.assert_allclose(rel, a.nu, atol=1e-9)


def test_tilted_paper_vehicle_rights_itself():
    """10 deg of roll: the righting moment of b0 = [0, 0, -0.0254] brings it back; oscillation decays."""
    model = uvms.load_model("paper")
    s0 = uvms.State.from_euler(model, euler=[np.radians(10), 0.0, 0.0])
    acc = uvms.forward_dynamics(model, s0)
    assert acc.nu_dot[0] < 0                                   # the first acceleration rolls it back
    result = simulate(model, s0, duration=40.0, step=2e-3, record_period=0.02)
    roll = result.euler[:, 0]
    assert roll.min() < 0                                      # it swings through upright...
    first, last = np.abs(roll[result.time < 5]).max(), np.abs(roll[result.time > 35]).max()
    assert last < 0.5 * first                                  # ...and the swing dies out


def test_neutrally_buoyant_body_at_rest_stays_at_rest(rng):
    for trial in range(20):
        n = int(rng.integers(1, 6))
        m = random_model(rng, n)
        model = m.replace(buoyancy_mass=m.mass, cob=m.com)
        s = uvms.State.from_euler(model, position=rng.normal(size=3), euler=rng.uniform(-1, 1, 3),
                                  q=rng.uniform(-3, 3, n))
        acc = uvms.forward_dynamics(model, s)
        assert np.abs(acc.generalized).max() < 1e-12


def fossen_nu_dot(model, state, f0):
    """The vehicle alone by Fossen (2011), written out in his linear-first form, converted at the end.

    M_RB nu_dot + C_RB(nu) nu + M_A nu_r_dot + C_A(nu_r) nu_r + D(nu_r) nu_r + g(eta) = tau  (CoM at origin).
    """
    m = model.mass[0]
    Ig = model.inertia_com[0]
    MA_ang_first = model.added_mass[0]
    MA = np.block([[MA_ang_first[3:, 3:], MA_ang_first[3:, :3]], [MA_ang_first[:3, 3:], MA_ang_first[:3, :3]]])
    M = np.block([[m * np.eye(3), np.zeros((3, 3))], [np.zeros((3, 3)), Ig]]) + MA
    v, w = state.nu[3:], state.nu[:3]
    C_RB_nu = np.concatenate([m * np.cross(w, v), np.cross(w, Ig @ w)])          # Fossen Eq. 3.56 form
    A11, A12, A21, A22 = MA[:3, :3], MA[:3, 3:], MA[3:, :3], MA[3:, 3:]
    a1 = A11 @ v + A12 @ w
    a2 = A21 @ v + A22 @ w
    C_A = np.block([[np.zeros((3, 3)), -skew(a1)], [-skew(a1), -skew(a2)]])       # Fossen Eq. 6.43
    C_A_nu = C_A @ np.concatenate([v, w])
    kl = 0.5 * model.density * model.vehicle_drag_area * model.vehicle_drag_coefficient
    kr = model.density * model.vehicle_rotational_drag_coefficient * model.vehicle_rotational_drag_side**5 / 32
    D_nu = np.concatenate([kl * np.abs(v) * v, kr * np.abs(w) * w])
    R = state.rotation
    W = m * model.gravity[2]
    B = model.buoyancy_mass[0] * model.gravity[2]
    f_g = R.T @ np.array([0, 0, W])
    f_b = -R.T @ np.array([0, 0, B])
    g_eta = -np.concatenate([f_g + f_b, np.cross(model.com[0], f_g) + np.cross(model.cob[0], f_b)])  # Fossen Eq. 4.6
    tau = np.concatenate([f0[3:], f0[:3]])
    nu_dot_lin_first = np.linalg.solve(M, tau - C_RB_nu - C_A_nu - D_nu - g_eta)
    return np.concatenate([nu_dot_lin_first[3:], nu_dot_lin_first[:3]])


def test_vehicle_alone_matches_fossen(rng):
    """The paper vehicle without the arm: ABA nu_dot == Fossen's M nu_dot + C nu + D nu + g = f0 (still water)."""
    model = uvms.load_model("paper").vehicle_only()
    for trial in range(100):
        s = uvms.State.from_euler(model, euler=rng.uniform(-1.2, 1.2, 3), nu=rng.normal(scale=0.5, size=6))
        f0 = rng.normal(scale=10, size=6)
        acc = uvms.forward_dynamics(model, s, body_wrench=f0)
        np.testing.assert_allclose(acc.nu_dot, fossen_nu_dot(model, s, f0), rtol=1e-10, atol=1e-10)


def test_arm_locked_at_zero_matches_a_composite_vehicle(rng):
    """Arm held at q = 0 (joint torques from RNEA keep qdd = 0): the vehicle moves as one rigid body whose
    inertia is the CRBA composite; check nu_dot against M_00^-1 (f0 - h_0) at rest (no velocity terms)."""
    model = uvms.load_model("paper")
    s = uvms.State.from_euler(model, euler=[0.1, -0.2, 0.3])
    f0 = rng.normal(scale=10, size=6)
    M = uvms.mass_matrix(model, s)
    h = uvms.bias_forces(model, s)
    nu_dot = np.linalg.solve(M[:6, :6], f0 - h[:6])
    _, tau = uvms.inverse_dynamics(model, s, nu_dot=nu_dot, qdd=np.zeros(3))
    acc = uvms.forward_dynamics(model, s, body_wrench=f0, joint_torques=tau)
    np.testing.assert_allclose(acc.qdd, 0.0, atol=1e-10)
    np.testing.assert_allclose(acc.nu_dot, nu_dot, atol=1e-10)
