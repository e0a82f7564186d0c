"""The outward pass shared by the articulated-body and Newton-Euler algorithms (Featherstone ch. 5, 7;
paper Section 4, "forward kinematics").

For each body ``i`` (vehicle 0, links 1..n), parent ``p = lambda(i)``, motion subspace ``S_i`` (a unit 6-vector:
``[axis; 0]`` for a revolute joint, ``[0; axis]`` for a prismatic one; ``[0 0 1 0 0 0]`` for a DH joint)::

    Xup_i = XJ(q_i) XT_i            v_i = Xup_i v_p + S_i qd_i       c_i = v_i x S_i qd_i
    p_i   = v_i x* I_i v_i - f_i^hydro - f_i^ext                      (the body's bias force)

with the hydrodynamic force of every effect evaluated at the current state (paper Eqs. 2-8)::

    f^hydro = [I_A a_fluid - (nu_r x*) I_A nu_r]  +  f^D(nu_r)  +  f^TB  +  f^gravity

The added mass's ``-I_A a`` is not a force here: it is in the articulated inertia ``I^H = I + I_A``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.dynamics.blocks import crf_mul_add, crm_mul, mat3_vec, mat6_vec, plucker
from uvms.hydro.added_mass import added_mass_force
from uvms.hydro.buoyancy import buoyancy_force, gravity_force
from uvms.hydro.current import fluid_acceleration_in_body, relative_velocity
from uvms.hydro.drag import link_drag_force, vehicle_drag_force
from uvms.hydro.fossen import fossen_damping_force
from uvms.hydro.shapes import shapes_drag_force


@njit(cache=True, inline="always")
def joint_transform(tree_E, tree_r, kind, S, q, E_out, r_out, X_out):
    """Joint ``i``'s transform from its parent (Featherstone Table 4.1, ``Xup_i = XJ(q) XT_i``) at joint
    coordinate ``q`` (offset included): ``E_out`` the parent-to-body coordinate rotation, ``r_out`` the body
    origin in parent coordinates and ``X_out = plucker(E_out, r_out)``.

    ``kind`` (:mod:`uvms.dynamics.kernel_model`): ``JOINT_Z`` revolute about z (modified DH),
    ``E = Rz(q)^T E_T``; ``JOINT_REVOLUTE`` about the unit axis ``S[0:3]`` (joint-frame coordinates),
    ``E = Rot(axis, q)^T E_T`` by Rodrigues' formula; ``JOINT_PRISMATIC`` along ``S[3:6]``, ``E = E_T``,
    ``r = r_T + E_T^T axis q``. Revolute joints keep ``r = r_T``.
    """
    if kind == 2:
        for a in range(3):
            for j in range(3):
                E_out[a, j] = tree_E[a, j]
            r_out[a] = tree_r[a] + (tree_E[0, a] * S[3] + tree_E[1, a] * S[4] + tree_E[2, a] * S[5]) * q
    elif kind == 0:
        c = np.cos(q)
        s = np.sin(q)
        for j in range(3):
            E_out[0, j] = c * tree_E[0, j] + s * tree_E[1, j]
            E_out[1, j] = -s * tree_E[0, j] + c * tree_E[1, j]
            E_out[2, j] = tree_E[2, j]
        for a in range(3):
            r_out[a] = tree_r[a]
    else:
        c = np.cos(q)
        s = np.sin(q)
        t = 1.0 - c
        x, y, z = S[0], S[1], S[2]
        # R = Rot(axis, q) (joint frame to body); E = R^T tree_E, so E[a, j] = sum_b R[b, a] tree_E[b, j]
        r00 = x * x * t + c
        r11 = y * y * t + c
        r22 = z * z * t + c
        r01 = t * x * y - s * z
        r10 = t * x * y + s * z
        r02 = t * x * z + s * y
        r20 = t * x * z - s * y
        r12 = t * y * z - s * x
        r21 = t * y * z + s * x
        for j in range(3):
            e0, e1, e2 = tree_E[0, j], tree_E[1, j], tree_E[2, j]
            E_out[0, j] = r00 * e0 + r10 * e1 + r20 * e2
            E_out[1, j] = r01 * e0 + r11 * e1 + r21 * e2
            E_out[2, j] = r02 * e0 + r12 * e1 + r22 * e2
        for a in range(3):
            r_out[a] = tree_r[a]
    plucker(E_out, r_out, X_out)


@njit(cache=True, inline="always")
def passive_joint_force(damping, friction, inv_speed, qd):
    """Joint damping and regularised Coulomb friction on a joint moving at ``qd`` (``docs/models.md``)::

        tau_p = -b qd - F_c clip(qd / v_s, -1, 1)       (``inv_speed = 1 / v_s``)
    """
    x = min(max(qd * inv_speed, -1.0), 1.0)
    return -damping * qd - friction * x


@njit(cache=True, inline="always")
def body_hydro_forces(I_A, drag_linear, drag_angular, cylinder, fossen, shapes, is_vehicle, mass, com, fluid_mass,
                      cob, v, vc, af, g, f, scratch):
    """The four named forces on one body at velocity ``v`` (body axes), into the rows of ``f``:
    ``f[0]`` added-mass velocity and fluid-acceleration terms (Eq. 2), ``f[1]`` drag (Eqs. 3-6), ``f[2]``
    buoyancy and fluid acceleration (Eqs. 7-8), ``f[3]`` gravity. ``scratch[0]`` returns ``nu_r``;
    ``cylinder`` is the link's row of :attr:`~uvms.dynamics.kernel_model.KernelModel.cylinder`; for a
    cylinder not along the body x axis from the origin, Eq. 6 is evaluated in the cylinder's frame (in
    ``scratch[2]``, ``scratch[3]``) and moved back to the body origin. ``fossen`` is the body's row of
    :attr:`~uvms.dynamics.kernel_model.KernelModel.fossen`: a body with Fossen damping adds
    :func:`~uvms.hydro.fossen.fossen_damping_force` to its drag (bodies without skip it, so the paper model's
    arithmetic is unchanged). ``shapes`` is the body's shape drag table (:func:`uvms.hydro.shapes.drag_table`,
    ``fossen[12, 4]`` real rows): a body with shapes adds :func:`~uvms.hydro.shapes.shapes_drag_force`, with
    ``scratch[4:6]`` as its work array.

    Takes the body's own arrays (not the whole model) so the call stays cheap inside the compiled loop.
    """
    nu_r = scratch[0]
    a_fl = scratch[1]
    relative_velocity(v, vc, nu_r)
    fluid_acceleration_in_body(v, vc, af, a_fl)
    added_mass_force(I_A, nu_r, a_fl, f[0])
    if is_vehicle:
        vehicle_drag_force(drag_linear, drag_angular, nu_r, f[1])
    elif cylinder[4, 2] == 0.0:
        link_drag_force(cylinder[4, 0], cylinder[4, 1], nu_r, f[1])
    else:
        cyl_E = cylinder[0:3]
        cyl_o = cylinder[3]
        nu_c = scratch[2]
        f_c = scratch[3]
        vo0 = nu_r[3] + (nu_r[1] * cyl_o[2] - nu_r[2] * cyl_o[1])
        vo1 = nu_r[4] + (nu_r[2] * cyl_o[0] - nu_r[0] * cyl_o[2])
        vo2 = nu_r[5] + (nu_r[0] * cyl_o[1] - nu_r[1] * cyl_o[0])
        for a in range(3):      # nu_c = [E w; E (v + w x o)], the relative velocity at the cylinder origin
            nu_c[a] = cyl_E[a, 0] * nu_r[0] + cyl_E[a, 1] * nu_r[1] + cyl_E[a, 2] * nu_r[2]
            nu_c[3 + a] = cyl_E[a, 0] * vo0 + cyl_E[a, 1] * vo1 + cyl_E[a, 2] * vo2
        link_drag_force(cylinder[4, 0], cylinder[4, 1], nu_c, f_c)
        fl = f[1]
        for a in range(3):      # back to body axes: F = E^T F_c, M = E^T M_c + o x F
            fl[a] = cyl_E[0, a] * f_c[0] + cyl_E[1, a] * f_c[1] + cyl_E[2, a] * f_c[2]
            fl[3 + a] = cyl_E[0, a] * f_c[3] + cyl_E[1, a] * f_c[4] + cyl_E[2, a] * f_c[5]
        fl[0] += cyl_o[1] * fl[5] - cyl_o[2] * fl[4]
        fl[1] += cyl_o[2] * fl[3] - cyl_o[0] * fl[5]
        fl[2] += cyl_o[0] * fl[4] - cyl_o[1] * fl[3]
    if fossen[12, 3] != 0.0:
        f_d = scratch[2]
        fossen_damping_force(fossen[0:6], fossen[6:12], fossen[12], nu_r, f_d)
        fd = f[1]
        for k in range(6):
            fd[k] += f_d[k]
    n_shapes = int(fossen[12, 4])
    if n_shapes > 0:
        f_s = scratch[2]
        shapes_drag_force(shapes[0:n_shapes], nu_r, f_s, scratch[4:6].reshape(12))
        fd = f[1]
        for k in range(6):
            fd[k] += f_s[k]
    buoyancy_force(fluid_mass, cob, g, af, f[2])
    gravity_force(mass, com, g, f[3])


@njit(cache=True, inline="always")
def outward_pass(km, ws, R0, nu, q, qd, v_current, a_fluid):
    """Pass 1, base to tip: transforms, velocities, velocity products and bias forces of every body, and each
    joint's passive torque (damping and friction, :func:`passive_joint_force`) into ``ws.u``.

    ``R0`` is the vehicle's body-to-world rotation, ``nu`` its body velocity ``[omega; v]``,
    ``v_current``/``a_fluid`` the world-frame current velocity and fluid acceleration.
    """
    nb = km.parent.shape[0]
    h = ws.w6[0]
    f = ws.f4
    scratch = ws.w6[1:7]
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
            kind = km.joint_kind[i]
            joint_transform(km.tree_E[i], km.tree_r[i], kind, km.S[i], q[i - 1] + km.joint[i, 0], ws.E[i], ws.r[i],
                            ws.Xup[i])
            mat6_vec(ws.Xup[i], ws.v[p], vi)
            w = qd[i - 1]
            if kind == 0:                        # S = e_z: the DH fast path
                vi[2] += w
                ws.c[i, 0] = vi[1] * w
                ws.c[i, 1] = -vi[0] * w
                ws.c[i, 2] = 0.0
                ws.c[i, 3] = vi[4] * w
                ws.c[i, 4] = -vi[3] * w
                ws.c[i, 5] = 0.0
            else:
                Sw = scratch[2]
                for k in range(6):
                    Sw[k] = km.S[i, k] * w
                    vi[k] += Sw[k]
                crm_mul(vi, Sw, ws.c[i])
            mat3_vec(ws.E[i], ws.g[p], ws.g[i])
            mat3_vec(ws.E[i], ws.vc[p], ws.vc[i])
            mat3_vec(ws.E[i], ws.af[p], ws.af[i])
        # bias force p_i = v_i x* I_i v_i - f_i^hydro and articulated inertia IA_i = I^H_i
        pA = ws.pA[i]
        mat6_vec(km.inertia[i], vi, h)
        for k in range(6):
            pA[k] = 0.0
        crf_mul_add(vi, h, 1.0, pA)
        body_hydro_forces(km.added_mass[i], km.vehicle_drag_linear, km.vehicle_drag_angular, km.cylinder[i],
                          km.fossen[i], km.shapes[i], i == 0, km.mass[i], km.com[i], km.fluid_mass[i], km.cob[i],
                          vi, ws.vc[i], ws.af[i], ws.g[i], f, scratch)
        for k in range(6):
            pA[k] -= f[0, k] + f[1, k] + f[2, k] + f[3, k]
        IA = ws.IA[i]
        IH = km.inertia_h[i]
        for r in range(6):
            for k in range(6):
                IA[r, k] = IH[r, k]
    for i in range(1, nb):                       # (a loop of its own: measurably faster than inside the one above)
        ws.u[i] = passive_joint_force(km.joint[i, 1], km.joint[i, 2], km.joint[i, 3], qd[i - 1])


@njit(cache=True)
def apply_external(ee_body, ee_E, ee_r, pA, f_body, f_ee, Xee):
    """External wrenches into the bias forces ``pA``: ``f_body`` on the vehicle (thrusters, Eq. 11) and
    ``f_ee`` (spatial force in end-effector axes) on the end effector's body ``b = ee_body``,
    ``beta_b -= eeX_b^T f_ee`` (Eq. 14). ``Xee`` is a 6x6 scratch matrix."""
    last = ee_body
    for k in range(6):
        pA[0, k] -= f_body[k]
    plucker(ee_E, ee_r, Xee)
    for j in range(6):
        s = 0.0
        for k in range(6):
            s += Xee[k, j] * f_ee[k]
        pA[last, j] -= s
