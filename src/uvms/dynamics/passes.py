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

from uvms.dynamics.blocks import crf_mul_add, crm_mul, mat3_vec, mat6_vec, transform_force_add, transform_motion
from uvms.dynamics.kernel_model import ADDED_MASS, BUOYANCY, DAMPING, DRAG, FRICTION, GRAVITY, INV_SPEED, Z_AXIS
from uvms.hydro.added_mass import added_mass_force
from uvms.hydro.buoyancy import buoyancy_force, gravity_force
from uvms.hydro.current import fluid_acceleration_in_body, relative_velocity
from uvms.hydro.drag import link_drag_force, vehicle_drag_force
from uvms.hydro.flow import bodies_waves, local_parts_add, uniform_at
from uvms.hydro.fossen import CROSS_ABS_END, CROSS_END, CROSS_ROWS, fossen_cross_damping_force, fossen_damping_force
from uvms.hydro.shapes import shapes_drag_force
from uvms.jit import block
from uvms.kinematics import JOINT_OFFSET, JOINT_Z, joint_transform


@block
def passive_joint_force(damping, friction, inv_speed, qd):
    """Joint damping and regularised Coulomb friction on a joint moving at ``qd`` (``docs/models.md``)::

        tau_p = -b qd - F_c clip(qd / v_s, -1, 1)       (``inv_speed = 1 / v_s``)
    """
    x = min(max(qd * inv_speed, -1.0), 1.0)
    return -damping * qd - friction * x


@block
def cylinder_drag_force(cylinder, nu_r, out, nu_c, f_c):
    """Eq. 6's drag of a link's cylinder (``cylinder``: the link's row of
    :attr:`~uvms.dynamics.kernel_model.KernelModel.cylinder`) into ``out``, body axes about the body origin.

    A cylinder along the body x axis from the origin is evaluated directly; any other in its own frame (the
    relative velocity at its origin in ``nu_c``, its force in ``f_c``) and moved back to the body origin."""
    if cylinder[4, 2] == 0.0:
        link_drag_force(cylinder[4, 0], cylinder[4, 1], nu_r, out)
        return
    cyl_E = cylinder[0:3]
    cyl_o = cylinder[3]
    vo0 = nu_r[3] + (nu_r[1] * cyl_o[2] - nu_r[2] * cyl_o[1])
    vo1 = nu_r[4] + (nu_r[2] * cyl_o[0] - nu_r[0] * cyl_o[2])
    vo2 = nu_r[5] + (nu_r[0] * cyl_o[1] - nu_r[1] * cyl_o[0])
    for a in range(3):      # nu_c = [E w; E (v + w x o)], the relative velocity at the cylinder origin
        nu_c[a] = cyl_E[a, 0] * nu_r[0] + cyl_E[a, 1] * nu_r[1] + cyl_E[a, 2] * nu_r[2]
        nu_c[3 + a] = cyl_E[a, 0] * vo0 + cyl_E[a, 1] * vo1 + cyl_E[a, 2] * vo2
    link_drag_force(cylinder[4, 0], cylinder[4, 1], nu_c, f_c)
    for a in range(3):      # back to body axes: F = E^T F_c, M = E^T M_c + o x F
        out[a] = cyl_E[0, a] * f_c[0] + cyl_E[1, a] * f_c[1] + cyl_E[2, a] * f_c[2]
        out[3 + a] = cyl_E[0, a] * f_c[3] + cyl_E[1, a] * f_c[4] + cyl_E[2, a] * f_c[5]
    out[0] += cyl_o[1] * out[5] - cyl_o[2] * out[4]
    out[1] += cyl_o[2] * out[3] - cyl_o[0] * out[5]
    out[2] += cyl_o[0] * out[4] - cyl_o[1] * out[3]


@block
def body_hydro_forces(km, ws, i):
    """The named forces on body ``i`` at its velocity ``ws.v[i]`` into ``ws.forces[i]`` (slots of
    :mod:`uvms.dynamics.kernel_model`): ``ADDED_MASS`` (Eq. 2, velocity and fluid-acceleration terms),
    ``DRAG`` (Eqs. 3-6), ``BUOYANCY`` (buoyancy and fluid acceleration, Eqs. 7-8), ``GRAVITY``; the body's
    velocity relative to the fluid into ``ws.nu_r[i]``.

    The vehicle's drag is Eqs. 3-5, a link's its cylinder's (:func:`cylinder_drag_force`). A body with Fossen
    damping (``km.fossen[i, 12, 3] != 0``) adds :func:`~uvms.hydro.fossen.fossen_damping_force` to its drag,
    one with mixed quadratic terms (``km.fossen[i, 12, 5] != 0``)
    :func:`~uvms.hydro.fossen.fossen_cross_damping_force`,
    a body with shapes (``km.fossen[i, 12, 4]`` rows of ``km.shapes[i]``) adds
    :func:`~uvms.hydro.shapes.shapes_drag_force`; bodies without skip them (the paper model's arithmetic is
    unchanged).
    """
    v = ws.v[i]
    nu_r = ws.nu_r[i]
    f = ws.forces[i]
    relative_velocity(v, ws.vc[i], nu_r)
    fluid_acceleration_in_body(v, ws.vc[i], ws.af[i], ws.a_fluid)
    added_mass_force(km.added_mass[i], nu_r, ws.a_fluid, f[ADDED_MASS])
    if i == 0:
        vehicle_drag_force(km.vehicle_drag_linear, km.vehicle_drag_angular, nu_r, f[DRAG])
    else:
        cylinder_drag_force(km.cylinder[i], nu_r, f[DRAG], ws.nu_c, ws.f_c)
    fossen = km.fossen[i]
    if fossen[12, 3] != 0.0:
        fossen_damping_force(fossen[0:6], fossen[6:12], fossen[12], nu_r, ws.nu_c)
        for k in range(6):
            f[DRAG, k] += ws.nu_c[k]
    if fossen[12, 5] != 0.0:
        fossen_cross_damping_force(fossen[CROSS_ROWS:CROSS_ABS_END], fossen[CROSS_ABS_END:CROSS_END], fossen[12], nu_r,
                                   ws.nu_c)
        for k in range(6):
            f[DRAG, k] += ws.nu_c[k]
    n_shapes = int(fossen[12, 4])
    if n_shapes > 0:
        shapes_drag_force(km.shapes[i, 0:n_shapes], nu_r, ws.nu_c, ws.shape_work)
        for k in range(6):
            f[DRAG, k] += ws.nu_c[k]
    buoyancy_force(km.fluid_mass[i], km.cob[i], ws.g[i], ws.af[i], f[BUOYANCY])
    gravity_force(km.mass[i], km.com[i], ws.g[i], f[GRAVITY])


@block
def body_poses(km, ws, R0, p0, q):
    """Every body's joint transform (``ws.E[i]``, ``ws.r[i]``), world pose ``R_i = R_p E_i^T``, ``p_i = p_p +
    R_p r_i`` (``ws.R_world``, ``ws.p_world``; the vehicle's ``R0``, ``p0``) and centre of buoyancy in the world
    ``p_i + R_i b_i`` (``ws.points``), base to tip: where a flow that varies in space is evaluated."""
    for i in range(km.parent.shape[0]):
        R = ws.R_world[i]
        if i == 0:
            for r in range(3):
                ws.p_world[0, r] = p0[r]
                for k in range(3):
                    R[r, k] = R0[r, k]
        else:
            p = km.parent[i]
            E = ws.E[i]
            ri = ws.r[i]
            joint_transform(km.tree_E[i], km.tree_r[i], km.joint_kind[i], km.S[i], q[i - 1] + km.joint[i, JOINT_OFFSET],
                            E, ri)
            Rp = ws.R_world[p]
            for r in range(3):
                ws.p_world[i, r] = ws.p_world[p, r] + Rp[r, 0] * ri[0] + Rp[r, 1] * ri[1] + Rp[r, 2] * ri[2]
                for k in range(3):
                    R[r, k] = Rp[r, 0] * E[k, 0] + Rp[r, 1] * E[k, 1] + Rp[r, 2] * E[k, 2]
        b = km.cob[i]
        for r in range(3):
            ws.points[i, r] = ws.p_world[i, r] + R[r, 0] * b[0] + R[r, 1] * b[1] + R[r, 2] * b[2]


@block
def body_fluid(km, ws, flow, t, i):
    """The water at body ``i`` (:func:`uvms.hydro.flow.fluid_at` at its centre of buoyancy ``ws.points[i]``,
    world pose ``R_i = ws.R_world[i]``; :func:`body_poses`) in body axes: ``ws.vc[i] = R_i^T u_f``,
    ``ws.af[i] = R_i^T a_f``. The uniform part is the stage's (``ws.table_v``, ``ws.table_a``: evaluated once
    per pass), the waves' sums every body's at once before (:func:`uvms.hydro.flow.bodies_waves`), the other
    parts that vary in space are added at the point (:func:`uvms.hydro.flow.local_parts_add`)."""
    R = ws.R_world[i]
    u_f = ws.fluid_v
    a_f = ws.fluid_a
    for r in range(3):
        u_f[r] = ws.table_v[r]
        a_f[r] = ws.table_a[r]
    local_parts_add(flow, t, ws.points[i], i, u_f, a_f, ws.fluid_grad)
    for k in range(3):
        ws.vc[i, k] = R[0, k] * u_f[0] + R[1, k] * u_f[1] + R[2, k] * u_f[2]
        ws.af[i, k] = R[0, k] * a_f[0] + R[1, k] * a_f[1] + R[2, k] * a_f[2]


@block
def outward_pass(km, ws, R0, p0, nu, q, qd, flow, t):
    """Pass 1, base to tip: transforms, velocities, velocity products, named hydrodynamic forces
    (:func:`body_hydro_forces`) and bias forces of every body, and each joint's passive torque (damping and
    friction, :func:`passive_joint_force`) into ``ws.u``.

    ``R0`` is the vehicle's body-to-world rotation, ``p0`` its world position, ``nu`` its body velocity
    ``[omega; v]``, ``flow`` the water (:class:`uvms.hydro.flow.FlowData`) and ``t`` the time [s]. A uniform
    flow (``flow.uniform_only``) is evaluated once and its world vectors rotated down the tree like gravity;
    any other at every body's own centre of buoyancy (:func:`body_fluid`; its uniform table once per pass), the
    bodies' joint transforms and world poses first (:func:`body_poses`), then the waves of all of them in one
    call (:func:`uvms.hydro.flow.bodies_waves`).
    """
    nb = km.parent.shape[0]
    h = ws.h
    uniform = flow.uniform_only
    v_current = ws.fluid_v
    a_fluid = ws.fluid_a
    if uniform:
        uniform_at(flow, t, v_current, a_fluid)
    else:
        uniform_at(flow, t, ws.table_v, ws.table_a)
        body_poses(km, ws, R0, p0, q)
        bodies_waves(flow, ws.points, t, nb)
    for i in range(nb):
        vi = ws.v[i]
        ci = ws.c[i]
        if i == 0:                               # world vectors in vehicle axes: R^T a_g, R^T v_c, R^T a_f
            for k in range(3):
                ws.g[0, k] = R0[0, k] * km.gravity[0] + R0[1, k] * km.gravity[1] + R0[2, k] * km.gravity[2]
            if uniform:
                for k in range(3):
                    ws.vc[0, k] = R0[0, k] * v_current[0] + R0[1, k] * v_current[1] + R0[2, k] * v_current[2]
                    ws.af[0, k] = R0[0, k] * a_fluid[0] + R0[1, k] * a_fluid[1] + R0[2, k] * a_fluid[2]
            else:
                body_fluid(km, ws, flow, t, 0)
            for k in range(6):
                vi[k] = nu[k]
                ci[k] = 0.0
        else:                                    # Xup_i, v_i = Xup_i v_p + S qd_i, c_i = v_i x S qd_i
            p = km.parent[i]
            kind = km.joint_kind[i]
            E = ws.E[i]
            if uniform:                          # (else done by body_poses)
                joint_transform(km.tree_E[i], km.tree_r[i], kind, km.S[i], q[i - 1] + km.joint[i, JOINT_OFFSET], E,
                                ws.r[i])
            transform_motion(E, ws.r[i], ws.v[p], vi)
            w = qd[i - 1]
            if kind == JOINT_Z:                  # S = e_z: the DH fast path
                vi[Z_AXIS] += w
                ci[0] = vi[1] * w
                ci[1] = -vi[0] * w
                ci[2] = 0.0
                ci[3] = vi[4] * w
                ci[4] = -vi[3] * w
                ci[5] = 0.0
            else:
                Sw = ws.sw
                for k in range(6):
                    Sw[k] = km.S[i, k] * w
                    vi[k] += Sw[k]
                crm_mul(vi, Sw, ci)
            mat3_vec(E, ws.g[p], ws.g[i])
            if uniform:
                mat3_vec(E, ws.vc[p], ws.vc[i])
                mat3_vec(E, ws.af[p], ws.af[i])
            else:
                body_fluid(km, ws, flow, t, i)
        # bias force p_i = v_i x* I_i v_i - f_i^hydro and articulated inertia IA_i = I^H_i
        pA = ws.pA[i]
        mat6_vec(km.inertia[i], vi, h)
        for k in range(6):
            pA[k] = 0.0
        crf_mul_add(vi, h, 1.0, pA)
        body_hydro_forces(km, ws, i)
        f = ws.forces[i]
        for k in range(6):
            pA[k] -= f[ADDED_MASS, k] + f[DRAG, k] + f[BUOYANCY, k] + f[GRAVITY, k]
        IA = ws.IA[i]
        IH = km.inertia_h[i]
        for r in range(6):
            for k in range(6):
                IA[r, k] = IH[r, k]
    for i in range(1, nb):                       # (a loop of its own: measurably faster than inside the one above)
        ws.u[i] = passive_joint_force(km.joint[i, DAMPING], km.joint[i, FRICTION], km.joint[i, INV_SPEED], qd[i - 1])


@block
def apply_external(km, ws, f_body, f_ee):
    """External wrenches into the bias forces ``ws.pA``: ``f_body`` on the vehicle (thrusters, Eq. 11) and
    ``f_ee`` (spatial force in end-effector axes) on the end effector's body ``b = km.ee_body``,
    ``beta_b -= eeX_b^T f_ee`` (Eq. 14), ``eeX_b = plucker(km.ee_E, km.ee_r)``."""
    for k in range(6):
        ws.pA[0, k] -= f_body[k]
    f = ws.f_ee
    for k in range(6):
        f[k] = 0.0
    transform_force_add(km.ee_E, km.ee_r, f_ee, f)
    for k in range(6):
        ws.pA[km.ee_body, k] -= f[k]
