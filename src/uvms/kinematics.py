"""Forward kinematics: every body frame, every named frame and the end effector in the world.

``R_i = R_p E_i^T`` and ``p_i = p_p + R_p r_i`` down the tree, with ``E_i, r_i`` the joint transforms of
:func:`joint_transform` (the one kinematic primitive the dynamics passes share); the end effector is fixed in body ``ee_body`` (the last link by
default), and a named frame (:class:`uvms.model.model.Frame`) is fixed in its body.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.jit import block, kernel
from uvms.state import JOINTS, POSITION, QUATERNION

JOINT_Z = 0
"""Joint kind: revolute about the joint frame's z axis (every modified-DH joint); the kernels' fast path."""
JOINT_REVOLUTE = 1
"""Joint kind: revolute (or continuous) about any unit axis."""
JOINT_PRISMATIC = 2
"""Joint kind: prismatic along any unit axis."""
JOINT_OFFSET = 0
"""Column of a joint's row of parameters (:attr:`uvms.dynamics.kernel_model.KernelModel.joint`) holding its
offset (the modified-DH theta offset, rad, or a prismatic joint's, m), added to ``q`` before
:func:`joint_transform`."""


@block
def joint_transform(tree_E, tree_r, kind, S, q, E_out, r_out):
    """Joint ``i``'s transform from its parent (Featherstone Table 4.1, ``Xup_i = XJ(q) XT_i``) at joint
    coordinate ``q`` (offset included): ``E_out`` the parent-to-body coordinate rotation and ``r_out`` the body
    origin in parent coordinates, so that ``Xup_i = plucker(E_out, r_out)`` (applied by its structure,
    :func:`~uvms.dynamics.blocks.transform_motion`, never formed).

    ``kind`` (this module's joint kinds): ``JOINT_Z`` revolute about z (modified DH),
    ``E = Rz(q)^T E_T``; ``JOINT_REVOLUTE`` about the unit axis ``S[0:3]`` (joint-frame coordinates),
    ``E = Rot(axis, q)^T E_T`` by Rodrigues' formula; ``JOINT_PRISMATIC`` along ``S[3:6]``, ``E = E_T``,
    ``r = r_T + E_T^T axis q``. Revolute joints keep ``r = r_T``.
    """
    if kind == JOINT_PRISMATIC:
        for a in range(3):
            for j in range(3):
                E_out[a, j] = tree_E[a, j]
            r_out[a] = tree_r[a] + (tree_E[0, a] * S[3] + tree_E[1, a] * S[4] + tree_E[2, a] * S[5]) * q
    elif kind == JOINT_Z:
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


@kernel
def quaternion_to_rotation(qw, qx, qy, qz, R):
    """Body-to-world rotation of a unit quaternion ``[w, x, y, z]`` (into ``R``)."""
    R[0, 0] = 1 - 2 * (qy * qy + qz * qz)
    R[0, 1] = 2 * (qx * qy - qw * qz)
    R[0, 2] = 2 * (qx * qz + qw * qy)
    R[1, 0] = 2 * (qx * qy + qw * qz)
    R[1, 1] = 1 - 2 * (qx * qx + qz * qz)
    R[1, 2] = 2 * (qy * qz - qw * qx)
    R[2, 0] = 2 * (qx * qz - qw * qy)
    R[2, 1] = 2 * (qy * qz + qw * qx)
    R[2, 2] = 1 - 2 * (qx * qx + qy * qy)


@kernel
def normalised_rotation(quaternion, R):
    """Body-to-world ``R`` of a quaternion ``[w, x, y, z]`` normalised by ``s = 1 / |q|`` (the arithmetic of
    :meth:`uvms.state.State.rotation`): the one compiled copy for the plant, the controllers and the arm."""
    qw, qx, qy, qz = quaternion[0], quaternion[1], quaternion[2], quaternion[3]
    s = 1.0 / np.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    quaternion_to_rotation(qw * s, qx * s, qy * s, qz * s, R)


@kernel
def link_poses(km, R0, p0, q, R_out, p_out, E, r):
    """World pose of every body (``R_out[i]`` body-to-world, ``p_out[i]`` origin) and, at index ``nb``,
    of the end effector. ``R_out``/``p_out`` have ``nb + 1`` rows; ``E`` (3x3) and ``r`` (3) are scratch."""
    nb = km.parent.shape[0]
    for a in range(3):
        p_out[0, a] = p0[a]
        for k in range(3):
            R_out[0, a, k] = R0[a, k]
    for i in range(1, nb + 1):
        if i < nb:
            p = km.parent[i]
            joint_transform(km.tree_E[i], km.tree_r[i], km.joint_kind[i], km.S[i], q[i - 1] + km.joint[i, JOINT_OFFSET],
                            E, r)
        else:
            p = km.ee_body
            for a in range(3):
                r[a] = km.ee_r[a]
                for b in range(3):
                    E[a, b] = km.ee_E[a, b]
        for a in range(3):
            s = p_out[p, a]
            for k in range(3):
                s += R_out[p, a, k] * r[k]
            p_out[i, a] = s
            for b in range(3):
                s = 0.0
                for k in range(3):
                    s += R_out[p, a, k] * E[b, k]       # R_p E^T
                R_out[i, a, b] = s


@njit(cache=True)
def end_effector_path(km, states, out):
    """World end-effector position (``out[k]``, (K, 3)) of every recorded state vector ``states[k]``
    (:mod:`uvms.state` layout), in one compiled loop."""
    nb = km.parent.shape[0]
    n = nb - 1
    R = np.empty((nb + 1, 3, 3))
    p = np.empty((nb + 1, 3))
    E = np.empty((3, 3))
    r = np.empty(3)
    R0 = np.empty((3, 3))
    for k in range(states.shape[0]):
        x = states[k]
        quaternion_to_rotation(x[QUATERNION], x[QUATERNION + 1], x[QUATERNION + 2], x[QUATERNION + 3], R0)
        link_poses(km, R0, x[POSITION:QUATERNION], x[JOINTS:JOINTS + n], R, p, E, r)
        for a in range(3):
            out[k, a] = p[nb, a]
