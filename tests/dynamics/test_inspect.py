"""Each body's named forces, read out of one evaluation of the articulated-body algorithm
(:mod:`uvms.dynamics.inspect`), against world-frame formulas written out here (paper Eqs. 2, 7-8)."""

from __future__ import annotations

import numpy as np

import uvms
from tests.conftest import random_model
from uvms.dynamics.plant import kernel_model


def _about_origin(point, force):
    return np.concatenate([np.cross(point, force), force])


def test_gravity_buoyancy_and_fluid_acceleration_are_the_world_formulas(rng):
    for n in (1, 3, 5):
        model = random_model(rng, n)
        s = uvms.State.from_euler(model, euler=rng.uniform(-1, 1, 3), nu=rng.normal(size=6),
                                  q=rng.uniform(-3, 3, n), qd=rng.normal(size=n))
        a_f, v_c = rng.normal(size=3), rng.normal(scale=0.5, size=3)
        w = uvms.hydrodynamic_wrenches(model, s, current=v_c, fluid_acceleration=a_f,
                                       joint_torques=rng.normal(size=n))
        poses = uvms.forward_kinematics(model, s)
        for i in range(model.n_bodies):
            Rt = poses.rotation[i].T                       # world to body axes
            g, af = Rt @ model.gravity, Rt @ a_f
            np.testing.assert_allclose(w.wrenches["gravity"][i], _about_origin(model.com[i], model.mass[i] * g),
                                       atol=1e-10)
            np.testing.assert_allclose(w.wrenches["buoyancy"][i],
                                       _about_origin(model.cob[i], -model.buoyancy_mass[i] * g), atol=1e-10)
            expected = model.added_mass[i][:, 3:] @ af + _about_origin(model.cob[i], model.buoyancy_mass[i] * af)
            np.testing.assert_allclose(w.wrenches["fluid_acceleration"][i], expected, atol=1e-10)


def test_added_mass_terms_match_eq_2_with_the_abas_accelerations(rng):
    """``added_mass_inertial = -I_A a_i`` with ``a_i`` the body accelerations of the same inputs' forward
    dynamics (propagated here with numpy's dense Plucker transforms), and the velocity term
    ``-(nu_r x*) I_A nu_r - I_A [0; omega x R^T v_c]`` (Eq. 2 with a uniform current)."""
    from uvms import spatial
    from uvms.dynamics.kernel_model import make_workspace
    from uvms.dynamics.passes import outward_pass
    from uvms.dynamics.plant import fluid_table

    model = random_model(rng, 3)
    s = uvms.State.from_euler(model, euler=rng.uniform(-1, 1, 3), nu=rng.normal(size=6), q=rng.uniform(-3, 3, 3),
                              qd=rng.normal(size=3))
    v_c, tau, f0 = rng.normal(scale=0.5, size=3), rng.normal(size=3), rng.normal(size=6)
    w = uvms.hydrodynamic_wrenches(model, s, current=v_c, joint_torques=tau, body_wrench=f0)
    acc = uvms.forward_dynamics(model, s, current=v_c, joint_torques=tau, body_wrench=f0)
    km = kernel_model(model)
    ws = make_workspace(model.n_bodies)
    outward_pass(km, ws, s.rotation, np.array(s.position), np.array(s.nu), np.array(s.q), np.array(s.qd),
                 fluid_table([0.0], [v_c], [np.zeros(3)]), 0.0)
    a = np.zeros((model.n_bodies, 6))
    a[0] = acc.nu_dot
    for i in range(1, model.n_bodies):
        X = spatial.plucker(ws.E[i], ws.r[i])
        a[i] = X @ a[km.parent[i]] + ws.c[i] + km.S[i] * acc.qdd[i - 1]
        I_A = model.added_mass[i]
        np.testing.assert_allclose(w.wrenches["added_mass_inertial"][i], -I_A @ a[i], atol=1e-10)
        nu_r = ws.v[i] - np.concatenate([np.zeros(3), ws.vc[i]])
        np.testing.assert_allclose(w.relative_velocity[i], nu_r, atol=1e-12)
        expected = -spatial.crf(nu_r) @ I_A @ nu_r - I_A[:, 3:] @ np.cross(ws.v[i][:3], ws.vc[i])
        np.testing.assert_allclose(w.wrenches["added_mass_velocity"][i], expected, atol=1e-10)
