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
def joint_transform(km, i, q_i, E_out, X_out):
    """``E_i = Rz(q_i + theta_offset_i)^T E_T`` and ``Xup_i = plucker(E_i, r_T)`` for joint ``i`` (modified DH)."""
    th = q_i + km.theta_offset[i]
    c = np.cos(th)
    s = np.sin(th)
    ET = km.tree_E[i]
    for j in range(3):
        E_out[0, j] = c * ET[0, j] + s * ET[1, j]
        E_out[1, j] = -s * ET[0, j] + c * ET[1, j]
        E_out[2, j] = ET[2, j]
    plucker(E_out, km.tree_r[i], X_out)


@njit(cache=True)
def body_hydro_forces(km, i, v, vc, af, g, f_added, f_drag, f_buoy, f_grav, scratch):
    """The four named forces on body ``i`` at velocity ``v`` (body axes): added-mass velocity and
    fluid-acceleration terms (Eq. 2), drag (Eqs. 3-6), buoyancy and fluid acceleration (Eqs. 7-8), gravity."""
    nu_r = scratch[0]
    a_fl = scratch[1]
    relative_velocity(v, vc, nu_r)
    fluid_acceleration_in_body(v, vc, af, a_fl)
    added_mass_force(km.added_mass[i], nu_r, a_fl, f_added)
    if i == 0:
        vehicle_drag_force(km.vehicle_drag_linear, km.vehicle_drag_angular, nu_r, f_drag)
    else:
        link_drag_force(km.link_drag[i], km.link_length[i], nu_r, f_drag)
    buoyancy_force(km.fluid_mass[i], km.cob[i], g, af, f_buoy)
    gravity_force(km.mass[i], km.com[i], g, f_grav)


@njit(cache=True)
def body_bias(km, ws, i):
    """``pA_i = v_i x* I_i v_i - f_i^hydro`` and ``IA_i = I^H_i`` (the start of the inward pass)."""
    v = ws.v[i]
    p = ws.pA[i]
    h = ws.w6[0]
    mat6_vec(km.inertia[i], v, h)
    for k in range(6):
        p[k] = 0.0
    crf_mul_add(v, h, 1.0, p)
    f = ws.f4
    body_hydro_forces(km, i, v, ws.vc[i], ws.af[i], ws.g[i], f[0], f[1], f[2], f[3], ws.w6[1:3])
    for k in range(6):
        p[k] -= f[0, k] + f[1, k] + f[2, k] + f[3, k]
    IA = ws.IA[i]
    IH = km.inertia_h[i]
    for r in range(6):
        for k in range(6):
            IA[r, k] = IH[r, k]


@njit(cache=True)
def outward_pass(km, ws, R0, nu, q, qd, v_current, a_fluid):
    """Pass 1, base to tip: transforms, velocities, velocity products and bias forces of every body.

    ``R0`` is the vehicle's body-to-world rotation, ``nu`` its body velocity ``[omega; v]``,
    ``v_current``/``a_fluid`` the world-frame current velocity and fluid acceleration.
    """
    nb = km.parent.shape[0]
    for k in range(3):                       # world vectors in vehicle axes: R^T a_g, R^T v_c, R^T a_f
        ws.g[0, k] = R0[0, k] * km.gravity[0] + R0[1, k] * km.gravity[1] + R0[2, k] * km.gravity[2]
        ws.vc[0, k] = R0[0, k] * v_current[0] + R0[1, k] * v_current[1] + R0[2, k] * v_current[2]
        ws.af[0, k] = R0[0, k] * a_fluid[0] + R0[1, k] * a_fluid[1] + R0[2, k] * a_fluid[2]
    for k in range(6):
        ws.v[0, k] = nu[k]
        ws.c[0, k] = 0.0
    body_bias(km, ws, 0)
    for i in range(1, nb):
        p = km.parent[i]
        joint_transform(km, i, q[i - 1], ws.E[i], ws.Xup[i])
        mat6_vec(ws.Xup[i], ws.v[p], ws.v[i])
        ws.v[i, 2] += qd[i - 1]
        vi = ws.v[i]
        w = qd[i - 1]                        # c_i = v_i x S qd_i, S = e_z (angular)
        ws.c[i, 0] = vi[1] * w
        ws.c[i, 1] = -vi[0] * w
        ws.c[i, 2] = 0.0
        ws.c[i, 3] = vi[4] * w
        ws.c[i, 4] = -vi[3] * w
        ws.c[i, 5] = 0.0
        mat3_vec(ws.E[i], ws.g[p], ws.g[i])
        mat3_vec(ws.E[i], ws.vc[p], ws.vc[i])
        mat3_vec(ws.E[i], ws.af[p], ws.af[i])
        body_bias(km, ws, i)


@njit(cache=True)
def apply_external(km, ws, f_body, f_ee):
    """External wrenches into the bias forces: ``f_body`` on the vehicle (thrusters, Eq. 11) and ``f_ee``
    (spatial force in end-effector axes) on the last link, ``beta_n -= eeX_n^T f_ee`` (Eq. 14)."""
    nb = km.parent.shape[0]
    for k in range(6):
        ws.pA[0, k] -= f_body[k]
    Xee = ws.m6[0]
    plucker(km.ee_E, km.ee_r, Xee)
    last = nb - 1
    for j in range(6):
        s = 0.0
        for k in range(6):
            s += Xee[k, j] * f_ee[k]
        ws.pA[last, j] -= s
