"""The outward pass shared by the articulated-body and Newton-Euler algorithms (Featherstone ch. 5, 7;
paper Section 4, "forward kinematics").

For each body ``i`` (vehicle 0, links 1..n), parent ``p = lambda(i)``, joint axis ``S = [0 0 1 0 0 0]``::

    Xup_i = XJ(q_i) XT_i            v_i = Xup_i v_p + S qd_i         c_i = v_i x S qd_i
    p_i   = v_i x* I_i v_i - f_i^hydro - f_i^ext                      (the body's bias force)

with the hydrodynamic force of every effect evaluated at the current state (paper Eqs. 2-8)::

    f^hydro = [I_A a_fluid - (nu_r x*) I_A nu_r]  +  f^D(nu_r)  +  f^TB  +  f^gravity

The added mass's ``-I_A a`` is not a force here: it is in the articulated inertia ``I^H = I + I_A``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.dynamics.blocks import crf_mul_add, mat3_vec, mat6_vec, plucker
from uvms.hydro.added_mass import added_mass_force
from uvms.hydro.buoyancy import buoyancy_force, gravity_force
from uvms.hydro.current import fluid_acceleration_in_body, relative_velocity
from uvms.hydro.drag import link_drag_force, vehicle_drag_force


@njit(cache=True)
def joint_transform(tree_E, tree_r, theta, E_out, X_out):
    """``E_i = Rz(theta)^T E_T`` and ``Xup_i = plucker(E_i, r_T)`` for a revolute joint about z (modified DH),
    ``theta = q_i + theta_offset_i``."""
    c = np.cos(theta)
    s = np.sin(theta)
    for j in range(3):
        E_out[0, j] = c * tree_E[0, j] + s * tree_E[1, j]
        E_out[1, j] = -s * tree_E[0, j] + c * tree_E[1, j]
        E_out[2, j] = tree_E[2, j]
    plucker(E_out, tree_r, X_out)


@njit(cache=True)
def body_hydro_forces(I_A, drag_linear, drag_angular, link_drag, link_length, is_vehicle, mass, com, fluid_mass,
                      cob, v, vc, af, g, f, scratch):
    """The four named forces on one body at velocity ``v`` (body axes), into the rows of ``f``:
    ``f[0]`` added-mass velocity and fluid-acceleration terms (Eq. 2), ``f[1]`` drag (Eqs. 3-6), ``f[2]``
    buoyancy and fluid acceleration (Eqs. 7-8), ``f[3]`` gravity. ``scratch[0]`` returns ``nu_r``.

    Takes the body's own arrays (not the whole model) so the call stays cheap inside the compiled loop.
    """
    nu_r = scratch[0]
    a_fl = scratch[1]
    relative_velocity(v, vc, nu_r)
    fluid_acceleration_in_body(v, vc, af, a_fl)
    added_mass_force(I_A, nu_r, a_fl, f[0])
    if is_vehicle:
        vehicle_drag_force(drag_linear, drag_angular, nu_r, f[1])
    else:
        link_drag_force(link_drag, link_length, nu_r, f[1])
    buoyancy_force(fluid_mass, cob, g, af, f[2])
    gravity_force(mass, com, g, f[3])


@njit(cache=True, inline="always")
def outward_pass(km, ws, R0, nu, q, qd, v_current, a_fluid):
    """Pass 1, base to tip: transforms, velocities, velocity products and bias forces of every body.

    ``R0`` is the vehicle's body-to-world rotation, ``nu`` its body velocity ``[omega; v]``,
    ``v_current``/``a_fluid`` the world-frame current velocity and fluid acceleration.
    """
    nb = km.parent.shape[0]
    h = ws.w6[0]
    f = ws.f4
    scratch = ws.w6[1:3]
    for i in range(nb):
        vi = ws.v[i]
        if i == 0:                               # world vectors in vehicle axes: R^T a_g, R^T v_c, R^T a_f
            for k in range(3):
                ws.g[0, k] = R0[0, k] * km.gravity[0] + R0[1, k] * km.gravity[1] + R0[2, k] * km.gravity[2]
                ws.vc[0, k] = R0[0, k] * v_current[0] + R0[1, k] * v_current[1] + R0[2, k] * v_current[2]
                ws.af[0, k] = R0[0, k] * a_fluid[0] + R0[1, k] * a_fluid[1] + R0[2, k] * a_fluid[2]
            for k in range(6):
                vi[k] = nu[k]
                ws.c[0, k] = 0.0
        else:                                    # Xup_i, v_i = Xup_i v_p + S qd_i, c_i = v_i x S qd_i
            p = km.parent[i]
            joint_transform(km.tree_E[i], km.tree_r[i], q[i - 1] + km.theta_offset[i], ws.E[i], ws.Xup[i])
            mat6_vec(ws.Xup[i], ws.v[p], vi)
            w = qd[i - 1]
            vi[2] += w
            ws.c[i, 0] = vi[1] * w
            ws.c[i, 1] = -vi[0] * w
            ws.c[i, 2] = 0.0
            ws.c[i, 3] = vi[4] * w
            ws.c[i, 4] = -vi[3] * w
            ws.c[i, 5] = 0.0
            mat3_vec(ws.E[i], ws.g[p], ws.g[i])
            mat3_vec(ws.E[i], ws.vc[p], ws.vc[i])
            mat3_vec(ws.E[i], ws.af[p], ws.af[i])
        # bias force p_i = v_i x* I_i v_i - f_i^hydro and articulated inertia IA_i = I^H_i
        pA = ws.pA[i]
        mat6_vec(km.inertia[i], vi, h)
        for k in range(6):
            pA[k] = 0.0
        crf_mul_add(vi, h, 1.0, pA)
        body_hydro_forces(km.added_mass[i], km.vehicle_drag_linear, km.vehicle_drag_angular, km.link_drag[i],
                          km.link_length[i], i == 0, km.mass[i], km.com[i], km.fluid_mass[i], km.cob[i], vi,
                          ws.vc[i], ws.af[i], ws.g[i], f, scratch)
        for k in range(6):
            pA[k] -= f[0, k] + f[1, k] + f[2, k] + f[3, k]
        IA = ws.IA[i]
        IH = km.inertia_h[i]
        for r in range(6):
            for k in range(6):
                IA[r, k] = IH[r, k]


@njit(cache=True)
def apply_external(ee_E, ee_r, pA, f_body, f_ee, Xee):
    """External wrenches into the bias forces ``pA``: ``f_body`` on the vehicle (thrusters, Eq. 11) and
    ``f_ee`` (spatial force in end-effector axes) on the last link, ``beta_n -= eeX_n^T f_ee`` (Eq. 14).
    ``Xee`` is a 6x6 scratch matrix."""
    last = pA.shape[0] - 1
    for k in range(6):
        pA[0, k] -= f_body[k]
    plucker(ee_E, ee_r, Xee)
    for j in range(6):
        s = 0.0
        for k in range(6):
            s += Xee[k, j] * f_ee[k]
        pA[last, j] -= s
