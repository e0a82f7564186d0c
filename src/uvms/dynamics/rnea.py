"""Inverse dynamics: the recursive Newton-Euler algorithm with hydrodynamics (Featherstone 2008, Table 5.1).

Given ``nu_dot`` and ``qdd``, the vehicle wrench ``f_0`` and joint torques ``tau`` that produce them::

    outward:  a_i = Xup_i a_p + S_i qdd_i + c_i      f_i = I^H_i a_i + p_i
    inward:   tau_i = S_i^T f_i - tau_p,i            f_p += Xup_i^T f_i

``tau_p`` is the joint's damping and friction (:func:`uvms.dynamics.passes.passive_joint_force`, left in
``u`` by the outward pass): the actuator's torque overcomes it.

``p_i`` is the same bias force (rigid velocity product and every hydrodynamic effect) as in the ABA, and
``I^H = I + I_A``. The vehicle's net ``f_0`` is the body wrench the thrusters must apply.
"""

from __future__ import annotations

from uvms.dynamics.blocks import mat6_vec, transform_force_add, transform_motion
from uvms.dynamics.kernel_model import Z_AXIS
from uvms.dynamics.passes import apply_external, outward_pass
from uvms.jit import kernel
from uvms.kinematics import JOINT_Z


@kernel
def rnea(km, ws, R0, p0, nu, q, qd, nu_dot, qdd, f_ee, flow, t, f_body_out, tau_out):
    """Write the body wrench ``f_body_out`` (6) and joint torques ``tau_out`` (n); ``f_ee``, the pose ``R0``,
    ``p0`` and the water ``flow`` at ``t`` as in the ABA."""
    nb = km.parent.shape[0]
    outward_pass(km, ws, R0, p0, nu, q, qd, flow, t)
    for k in range(6):
        ws.no_wrench[k] = 0.0
    apply_external(km, ws, ws.no_wrench, f_ee)
    h = ws.h

    # -- outward: accelerations and body forces f_i = I^H a_i + p_i
    for k in range(6):
        ws.a[0, k] = nu_dot[k]
    for i in range(nb):
        ai = ws.a[i]
        if i > 0:
            transform_motion(ws.E[i], ws.r[i], ws.a[km.parent[i]], ai)
            for k in range(6):
                ai[k] += ws.c[i, k]
            if km.joint_kind[i] == JOINT_Z:     # S = e_z (modified DH)
                ai[Z_AXIS] += qdd[i - 1]
            else:
                for k in range(6):
                    ai[k] += km.S[i, k] * qdd[i - 1]
        mat6_vec(km.inertia_h[i], ai, h)
        for k in range(6):
            ws.pA[i, k] += h[k]

    # -- inward: joint torques, forces handed to the parent
    for i in range(nb - 1, 0, -1):
        if km.joint_kind[i] == JOINT_Z:
            s = ws.pA[i, Z_AXIS]
        else:
            s = 0.0
            for k in range(6):
                s += km.S[i, k] * ws.pA[i, k]
        tau_out[i - 1] = s - ws.u[i]             # the outward pass left the joint's passive torque in u
        transform_force_add(ws.E[i], ws.r[i], ws.pA[i], ws.pA[km.parent[i]])
    for k in range(6):
        f_body_out[k] = ws.pA[0, k]
