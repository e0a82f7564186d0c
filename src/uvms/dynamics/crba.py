"""Mass matrix: the composite-rigid-body algorithm (Featherstone 2008, Table 6.2), floating base.

Generalized velocity ``[nu; qd]`` (vehicle first). With ``I^H = I + I_A`` (added mass included)::

    IC_i = I^H_i;   tip to base: IC_p += Xup_i^T IC_i Xup_i
    H[0:6, 0:6] = IC_0;   F = IC_i S_i,  H[i, i] = S_i^T F,  then F = Xup_j^T F up the tree:
    H[i, j] = S_j^T F for each ancestor joint j,  H[0:6, i] = F at the vehicle.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.dynamics.blocks import congruence_add_plucker, transform_force_add
from uvms.dynamics.kernel_model import Z_AXIS
from uvms.dynamics.passes import joint_transform
from uvms.jit import block, kernel
from uvms.kinematics import JOINT_OFFSET, JOINT_Z


@block
def sdot(kind, S, x):
    """``S^T x`` for 6-vectors (``x[Z_AXIS]`` for a joint about z, ``kind == JOINT_Z``)."""
    if kind == JOINT_Z:
        return x[Z_AXIS]
    s = 0.0
    for k in range(6):
        s += S[k] * x[k]
    return s


@kernel
def crba(km, ws, q, M):
    """Write the ``(6+n) x (6+n)`` joint-space inertia matrix ``M`` (added mass included)."""
    nb = km.parent.shape[0]
    for i in range(nb):
        if i > 0:
            joint_transform(km.tree_E[i], km.tree_r[i], km.joint_kind[i], km.S[i], q[i - 1] + km.joint[i, JOINT_OFFSET],
                            ws.E[i], ws.r[i])
        for r in range(6):
            for k in range(6):
                ws.IA[i, r, k] = km.inertia_h[i, r, k]

    # -- composite inertias, tip to base
    for i in range(nb - 1, 0, -1):
        congruence_add_plucker(ws.E[i], ws.r[i], ws.IA[i], ws.IA[km.parent[i]], ws.rotated)

    # -- rows and columns of M
    for r in range(6):
        for k in range(6):
            M[r, k] = ws.IA[0, r, k]
    F = ws.column
    G = ws.column_up
    for i in range(1, nb):
        if km.joint_kind[i] == JOINT_Z:
            for k in range(6):
                F[k] = ws.IA[i, k, Z_AXIS]
        else:
            for k in range(6):
                s = 0.0
                for m in range(6):
                    s += ws.IA[i, k, m] * km.S[i, m]
                F[k] = s
        M[5 + i, 5 + i] = sdot(km.joint_kind[i], km.S[i], F)
        j = i
        while km.parent[j] > 0:
            for k in range(6):
                G[k] = 0.0
            transform_force_add(ws.E[j], ws.r[j], F, G)
            for k in range(6):
                F[k] = G[k]
            j = km.parent[j]
            h = sdot(km.joint_kind[j], km.S[j], F)
            M[5 + i, 5 + j] = h
            M[5 + j, 5 + i] = h
        for k in range(6):
            G[k] = 0.0
        transform_force_add(ws.E[j], ws.r[j], F, G)
        for k in range(6):
            M[k, 5 + i] = G[k]
            M[5 + i, k] = G[k]


@njit(cache=True)
def crba_alloc(km, ws, q):
    """:func:`crba` into a new array (for the Python API)."""
    nb = km.parent.shape[0]
    M = np.zeros((5 + nb, 5 + nb))
    crba(km, ws, q, M)
    return M
