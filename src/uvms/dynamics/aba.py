"""Forward dynamics: the articulated-body algorithm with hydrodynamics (Featherstone 2008, Table 7.1;
McMillan, Orin & McGhee 1995; paper Sections 3-4, Eqs. 13-23).

Three passes, in the book's symbols (``S_i`` the joint's unit motion subspace; ``e_z`` for a DH joint):

1. outward (:func:`uvms.dynamics.passes.outward_pass`): ``Xup = plucker(E, r)`` (kept as ``E, r``), ``v, c``,
   each body's named forces and ``IA_i = I^H_i``, ``pA_i = beta^H``
2. inward, tip to base (Eqs. 13-14), ``tau_p`` the joint's damping and friction
   (:func:`uvms.dynamics.passes.passive_joint_force`, left in ``u`` by the outward pass)::

       U_i = IA_i S     d_i = S^T U_i     u_i = tau_i + tau_p,i - S^T pA_i
       Ia = IA_i - U_i U_i^T / d_i        pa = pA_i + Ia c_i + U_i u_i / d_i
       IA_p += Xup_i^T Ia Xup_i           pA_p += Xup_i^T pa

3. outward, accelerations (Eqs. 16, 20, 22)::

       a_0 = -IA_0^-1 pA_0   (floating base; a_0 = 0 when the vehicle is clamped)
       a'  = Xup_i a_p + c_i    qdd_i = (u_i - U_i^T a') / d_i    a_i = a' + S qdd_i

``a_0`` is the vehicle's spatial acceleration in body axes, which is exactly ``nu_dot``; every body's ``a_i`` is
left in ``ws.a`` (read by :mod:`uvms.dynamics.inspect`). Transforms are applied by their structure
(:func:`~uvms.dynamics.blocks.transform_motion`, :func:`~uvms.dynamics.blocks.transform_force_add`,
:func:`~uvms.dynamics.blocks.congruence_add_plucker`), never as dense 6x6 products.
"""

from __future__ import annotations

from numba import njit

from uvms.dynamics.blocks import cholesky_solve6, congruence_add_plucker, transform_force_add, transform_motion
from uvms.dynamics.kernel_model import Z_AXIS
from uvms.dynamics.passes import apply_external, outward_pass
from uvms.jit import OPTIONS, kernel
from uvms.kinematics import JOINT_Z


@kernel
def aba(km, ws, R0, p0, nu, q, qd, tau, f_body, f_ee, flow, t, fixed_base, nu_dot, qdd):
    """Write ``nu_dot`` (6) and ``qdd`` (n) for the state and inputs (the vehicle at ``R0``, ``p0``, in the water
    ``flow`` at time ``t``, :func:`~uvms.dynamics.passes.outward_pass`); see the module docstring."""
    nb = km.parent.shape[0]
    outward_pass(km, ws, R0, p0, nu, q, qd, flow, t)
    apply_external(km, ws, f_body, f_ee)

    # -- pass 2: articulated inertias and bias forces, tip to base (Eqs. 13-14)
    Ia = ws.Ia
    pa = ws.pa
    for i in range(nb - 1, 0, -1):
        p = km.parent[i]
        IA = ws.IA[i]
        U = ws.U[i]
        pA = ws.pA[i]
        c = ws.c[i]
        if km.joint_kind[i] == JOINT_Z:         # S = e_z (modified DH): S^T x = x[Z_AXIS], IA S = IA[:, Z_AXIS]
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
        ws.u[i] = u
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
        congruence_add_plucker(ws.E[i], ws.r[i], Ia, ws.IA[p], ws.rotated)
        transform_force_add(ws.E[i], ws.r[i], pa, ws.pA[p])

    # -- pass 3: accelerations, base to tip (Eqs. 16, 20, 22)
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
        U = ws.U[i]
        c = ws.c[i]
        s = 0.0
        for k in range(6):
            ai[k] += c[k]
            s += U[k] * ai[k]
        qddi = (ws.u[i] - s) / ws.d[i]
        qdd[i - 1] = qddi
        if km.joint_kind[i] == JOINT_Z:
            ai[Z_AXIS] += qddi
        else:
            for k in range(6):
                ai[k] += km.S[i, k] * qddi


aba_inlined = njit(forceinline=True, **{**OPTIONS, "cache": False})(aba.py_func)
"""The same :func:`aba`, inlined by LLVM into its caller (the RK4 stage,
:func:`uvms.sim.integrate.state_derivative`, and :func:`uvms.dynamics.plant.plant_forward`): a call passes the
model and workspace (~70 arrays) as arguments, which costs about 0.2 us of a 1.3 us evaluation (measured on the
paper model). Not cached on its own: LLVM inlines only a function whose IR it has, and numba keeps a cached
function as object code, so a caller compiled after loading it would call it instead. The callers are cached
(with the inlined copy); the price is about 20 s more in a process that compiles one of them. numba's
``inline="always"`` would inline at its own IR level and always, but compiles each copy four times slower."""
