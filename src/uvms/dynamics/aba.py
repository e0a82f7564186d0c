"""Forward dynamics: the articulated-body algorithm with hydrodynamics (Featherstone 2008, Table 7.1;
McMillan, Orin & McGhee 1995; paper Sections 3-4, Eqs. 13-23).

Three passes, in the book's symbols (``S_i`` the joint's unit motion subspace; ``e_z`` for a DH joint):

1. outward (:func:`uvms.dynamics.passes.outward_pass`): ``Xup, v, c`` and ``IA_i = I^H_i``, ``pA_i = beta^H``
2. inward, tip to base (Eqs. 13-14), ``tau_p`` the joint's damping and friction
   (:func:`uvms.dynamics.passes.passive_joint_force`, left in ``u`` by the outward pass)::

       U_i = IA_i S     d_i = S^T U_i     u_i = tau_i + tau_p,i - S^T pA_i
       Ia = IA_i - U_i U_i^T / d_i        pa = pA_i + Ia c_i + U_i u_i / d_i
       IA_p += Xup_i^T Ia Xup_i           pA_p += Xup_i^T pa

3. outward, accelerations (Eqs. 16, 20, 22)::

       a_0 = -IA_0^-1 pA_0   (floating base; a_0 = 0 when the vehicle is clamped)
       a'  = Xup_i a_p + c_i    qdd_i = (u_i - U_i^T a') / d_i    a_i = a' + S qdd_i

``a_0`` is the vehicle's spatial acceleration in body axes, which is exactly ``nu_dot``.
"""

from __future__ import annotations

from numba import njit

from uvms.dynamics.blocks import cholesky_solve6, congruence_add_plucker, mat6_vec, mat6T_vec_add
from uvms.dynamics.passes import apply_external, outward_pass


@njit(cache=True)
def aba(km, ws, R0, nu, q, qd, tau, f_body, f_ee, v_current, a_fluid, fixed_base, nu_dot, qdd):
    """Write ``nu_dot`` (6) and ``qdd`` (n) for the state and inputs; see the module docstring."""
    nb = km.parent.shape[0]
    outward_pass(km, ws, R0, nu, q, qd, v_current, a_fluid)
    apply_external(km.ee_body, km.ee_E, km.ee_r, ws.pA, f_body, f_ee, ws.m6[0])

    # -- pass 2: articulated inertias and bias forces, tip to base (Eqs. 13-14)
    Ia = ws.m6[1]
    tmp = ws.m6[2]
    pa = ws.w6[0]
    for i in range(nb - 1, 0, -1):
        p = km.parent[i]
        IA = ws.IA[i]
        U = ws.U[i]
        if km.joint_kind[i] == 0:               # S = e_z (modified DH): S^T x = x[2], IA S = IA[:, 2]
            for k in range(6):
                U[k] = IA[k, 2]
            d = U[2]
            sp = ws.pA[i, 2]
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
                sp += S[k] * ws.pA[i, k]
        ws.d[i] = d
        ws.u[i] = (tau[i - 1] + ws.u[i]) - sp
        inv_d = 1.0 / ws.d[i]
        for r in range(6):
            Ur = U[r] * inv_d
            for k in range(6):
                Ia[r, k] = IA[r, k] - Ur * U[k]
        mat6_vec(Ia, ws.c[i], pa)
        for k in range(6):
            pa[k] += ws.pA[i, k] + U[k] * ws.u[i] * inv_d
        congruence_add_plucker(ws.E[i], ws.r[i], Ia, ws.IA[p], tmp)
        mat6T_vec_add(ws.Xup[i], pa, ws.pA[p])

    # -- pass 3: accelerations, base to tip (Eqs. 16, 20, 22)
    if fixed_base:
        for k in range(6):
            ws.a[0, k] = 0.0
    else:
        rhs = ws.w6[1]
        for k in range(6):
            rhs[k] = -ws.pA[0, k]
        cholesky_solve6(ws.IA[0], rhs, tmp, ws.a[0])
    for k in range(6):
        nu_dot[k] = ws.a[0, k]
    for i in range(1, nb):
        p = km.parent[i]
        ai = ws.a[i]
        mat6_vec(ws.Xup[i], ws.a[p], ai)
        s = 0.0
        for k in range(6):
            ai[k] += ws.c[i, k]
            s += ws.U[i, k] * ai[k]
        qdd[i - 1] = (ws.u[i] - s) / ws.d[i]
        if km.joint_kind[i] == 0:
            ai[2] += qdd[i - 1]
        else:
            for k in range(6):
                ai[k] += km.S[i, k] * qdd[i - 1]
