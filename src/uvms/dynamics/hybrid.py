"""Hybrid dynamics: the articulated-body algorithm with some joint accelerations given (Featherstone, *Rigid
Body Dynamics Algorithms*, 2008, sec. 9.2), with the same hydrodynamics as :mod:`uvms.dynamics.aba`.

A joint whose acceleration ``qdd_i`` is *prescribed* (``prescribed[i - 1]`` true) transmits its body's whole
articulated inertia to the parent: the joint is, for the inward pass, rigid with a known extra acceleration
``S_i qdd_i``. A free joint is the ABA's. Pass 1 (:func:`uvms.dynamics.passes.outward_pass`) is shared; then::

    pass 2, tip to base (prescribed joint i)          (free joint i: as in uvms.dynamics.aba)
        Ia = IA_i                                      Ia = IA_i - U_i U_i^T / d_i
        pa = pA_i + IA_i (c_i + S_i qdd_i)             pa = pA_i + Ia c_i + U_i u_i / d_i
        IA_p += Xup_i^T Ia Xup_i        pA_p += Xup_i^T pa

    pass 3, base to tip
        a_0 = -IA_0^-1 pA_0   (a_0 = 0 when the vehicle is clamped)
        a_i = Xup_i a_p + c_i + S_i qdd_i              qdd_i = (u_i - U_i^T (Xup_i a_p + c_i)) / d_i
        tau_i = S_i^T (IA_i a_i + pA_i) - tau_p,i      (tau_i the input)

``tau_i`` is the torque (force, for a prismatic joint) the actuator applies to make the joint follow
``qdd_i``: the projection of the force ``IA_i a_i + pA_i`` that the articulated body ``i`` needs (Featherstone
eq. 7.32's joint equation ``S^T f = tau``), less the joint's own damping and friction ``tau_p`` (left in
``ws.u`` by the outward pass), as :mod:`uvms.dynamics.rnea` does. With every joint prescribed and the vehicle
clamped this is the recursive Newton-Euler algorithm; with none prescribed it is the ABA.
"""

from __future__ import annotations

from numba import njit

from uvms.dynamics.blocks import cholesky_solve6, congruence_add_plucker, transform_force_add, transform_motion
from uvms.dynamics.kernel_model import Z_AXIS
from uvms.dynamics.passes import apply_external, outward_pass
from uvms.jit import OPTIONS, kernel
from uvms.kinematics import JOINT_Z


@kernel
def aba_prescribed(km, ws, R0, p0, nu, q, qd, qdd_given, tau, prescribed, f_body, f_ee, flow, t, fixed_base,
                   nu_dot, qdd, tau_out):
    """Hybrid dynamics (module docstring): write ``nu_dot`` (6), ``qdd`` (n; the given value at a prescribed
    joint) and ``tau_out`` (n; the torque a prescribed joint takes, the input ``tau`` at a free one).

    Args (beside the ABA's, :func:`uvms.dynamics.aba.aba`): ``qdd_given`` (n) the prescribed accelerations (read
    at prescribed joints only), ``tau`` (n) the torques of the free joints (read at free joints only),
    ``prescribed`` (n) booleans: which joints follow ``qdd_given``.
    """
    nb = km.parent.shape[0]
    outward_pass(km, ws, R0, p0, nu, q, qd, flow, t)
    apply_external(km, ws, f_body, f_ee)

    # -- pass 2: articulated inertias and bias forces, tip to base
    Ia = ws.Ia
    pa = ws.pa
    for i in range(nb - 1, 0, -1):
        p = km.parent[i]
        IA = ws.IA[i]
        U = ws.U[i]
        pA = ws.pA[i]
        c = ws.c[i]
        z = km.joint_kind[i] == JOINT_Z         # S = e_z (modified DH): S^T x = x[Z_AXIS], IA S = IA[:, Z_AXIS]
        if prescribed[i - 1]:                   # rigid on its joint: Ia = IA_i, pa = pA_i + IA_i (c + S qdd)
            sa = ws.sw
            if z:
                for k in range(6):
                    sa[k] = c[k]
                sa[Z_AXIS] += qdd_given[i - 1]
            else:
                for k in range(6):
                    sa[k] = c[k] + km.S[i, k] * qdd_given[i - 1]
            for r in range(6):
                s = 0.0
                for k in range(6):
                    s += IA[r, k] * sa[k]
                pa[r] = pA[r] + s
            congruence_add_plucker(ws.E[i], ws.r[i], IA, ws.IA[p], ws.rotated)
            transform_force_add(ws.E[i], ws.r[i], pa, ws.pA[p])
            continue
        if z:
            for k in range(6):
                U[k] = IA[k, Z_AXIS]
            d = U[Z_AXIS]
            sp = pA[Z_AXIS]
        else:
            S = km.S[i]
            for k in range(6):
                s = 0.0
                for j in range(6):
                    s += IA[k, j] * S[j]
                U[k] = s
            d = 0.0
            sp = 0.0
            for k in range(6):
                d += S[k] * U[k]
                sp += S[k] * pA[k]
        ws.d[i] = d
        u = (tau[i - 1] + ws.u[i]) - sp
        inv_d = 1.0 / d
        for r in range(6):
            Ur = U[r] * inv_d
            for k in range(6):
                Ia[r, k] = IA[r, k] - Ur * U[k]
        for r in range(6):                      # pa = pA + Ia c + U u / d
            s = 0.0
            for k in range(6):
                s += Ia[r, k] * c[k]
            pa[r] = s + (pA[r] + U[r] * u * inv_d)
        ws.u[i] = u
        congruence_add_plucker(ws.E[i], ws.r[i], Ia, ws.IA[p], ws.rotated)
        transform_force_add(ws.E[i], ws.r[i], pa, ws.pA[p])

    # -- pass 3: accelerations (and the prescribed joints' torques), base to tip
    a0 = ws.a[0]
    if fixed_base:
        for k in range(6):
            a0[k] = 0.0
    else:
        rhs = ws.rhs
        for k in range(6):
            rhs[k] = -ws.pA[0, k]
        cholesky_solve6(ws.IA[0], rhs, ws.chol, a0)
    for k in range(6):
        nu_dot[k] = a0[k]
    for i in range(1, nb):
        ai = ws.a[i]
        transform_motion(ws.E[i], ws.r[i], ws.a[km.parent[i]], ai)
        c = ws.c[i]
        for k in range(6):
            ai[k] += c[k]
        z = km.joint_kind[i] == JOINT_Z
        if prescribed[i - 1]:
            qddi = qdd_given[i - 1]
            IA = ws.IA[i]
            pA = ws.pA[i]
            if z:                               # tau_i = S^T (IA_i a_i + pA_i) - tau_p,i: row Z_AXIS only
                ai[Z_AXIS] += qddi
                s = pA[Z_AXIS]
                for k in range(6):
                    s += IA[Z_AXIS, k] * ai[k]
            else:
                for k in range(6):
                    ai[k] += km.S[i, k] * qddi
                s = 0.0
                for r in range(6):
                    f = pA[r]
                    for k in range(6):
                        f += IA[r, k] * ai[k]
                    s += km.S[i, r] * f
            tau_out[i - 1] = s - ws.u[i]        # u still holds the passive torque of a prescribed joint
        else:
            U = ws.U[i]
            s = 0.0
            for k in range(6):
                s += U[k] * ai[k]
            qddi = (ws.u[i] - s) / ws.d[i]
            if z:
                ai[Z_AXIS] += qddi
            else:
                for k in range(6):
                    ai[k] += km.S[i, k] * qddi
            tau_out[i - 1] = tau[i - 1]
        qdd[i - 1] = qddi


aba_prescribed_inlined = njit(forceinline=True, **{**OPTIONS, "cache": False})(aba_prescribed.py_func)
"""The same :func:`aba_prescribed`, inlined by LLVM into the prescribed-motion RK4 stage
(:mod:`uvms.sim.prescribed`), as :data:`uvms.dynamics.aba.aba_inlined` is into the ordinary one (the reasons are
given there)."""
