"""Orientation: ZYX Euler angles, rotation matrices and unit quaternions.

Conventions (``docs/conventions.md``, "Frames"): the world and body axes are the model's convention
(``Model.convention``: ``"ned"``, world x north, y east, z down, body forward-right-down, the default; or ``"enu"``,
world z up, body forward-left-up, :mod:`uvms.frames`); the formulas here hold in either. ``R`` is the rotation
from body to world, ``R = Rz(psi) Ry(theta) Rx(phi)`` (the paper's Eq. 1 ``T1``). Quaternions are ``[w, x, y, z]``
(scalar first), unit norm, with ``R(q)`` the same body-to-world rotation. The orientation is integrated as a
quaternion: Eq. 1's Euler-rate map ``T2`` is singular at ``theta = +/-90 deg``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from uvms.spatial import rotx, roty, rotz


def rotation_from_euler(euler: np.ndarray) -> np.ndarray:
    """``R = Rz(psi) Ry(theta) Rx(phi)`` from ``euler = (phi, theta, psi)`` [rad] (paper Eq. 1, ``T1``)."""
    phi, theta, psi = euler
    return rotz(psi) @ roty(theta) @ rotx(phi)


GIMBAL_LOCK_COS = 1e-13
"""At ``cos(theta) = hypot(R[2, 1], R[2, 2])`` below this (pitch within ~1e-13 rad of +/-90 deg) roll and yaw
are not separable (only ``psi -/+ phi`` is defined) and the two entries are round-off: roll is set to 0 and the
whole rotation about z goes into yaw (``docs/conventions.md``, "Euler angles at +/-90 deg of pitch"). Small
enough that ``R(euler(R)) == R`` to 1e-13 on either side of it."""


@njit(cache=True)
def euler_zyx(R):
    """ZYX Euler angles ``(phi, theta, psi)`` of a 3x3 rotation ``R`` as a tuple: the one implementation, compiled
    so that kernels call it too (:func:`euler_from_rotation` and :func:`euler_from_rotations` wrap it).

    Roll first, from ``R[2, 1:] = cos(theta) (sin(phi), cos(phi))``; then pitch and yaw from
    ``R Rx(phi)^T = Rz(psi) Ry(theta)`` (whose column 1 is ``(-sin(psi), cos(psi), 0)`` and row 2
    ``(-sin(theta), 0, cos(theta))``), so the three angles rebuild ``R`` to round-off even near +/-90 deg of
    pitch, where roll alone is ill-conditioned. At gimbal lock (:data:`GIMBAL_LOCK_COS`) roll is 0 and yaw holds
    the whole rotation about z. ``theta`` in [-pi/2, pi/2], the others in [-pi, pi].
    """
    c_theta = math.hypot(R[2, 1], R[2, 2])
    phi = math.atan2(R[2, 1], R[2, 2]) if c_theta >= GIMBAL_LOCK_COS else 0.0
    s = math.sin(phi)
    c = math.cos(phi)
    theta = math.atan2(-R[2, 0], c_theta)
    psi = math.atan2(R[0, 2] * s - R[0, 1] * c, R[1, 1] * c - R[1, 2] * s)
    return phi, theta, psi


def euler_from_rotation(R: np.ndarray) -> np.ndarray:
    """ZYX Euler angles ``(phi, theta, psi)`` of ``R`` [rad] (:func:`euler_zyx`; roll 0 at gimbal lock)."""
    return np.array(euler_zyx(np.ascontiguousarray(R, dtype=np.float64)))


def quaternion_from_rotation(R: np.ndarray) -> np.ndarray:
    """Unit quaternion ``[w, x, y, z]`` with ``w >= 0`` of a rotation matrix (Shepperd's method)."""
    t = np.trace(R)
    if t > max(R[0, 0], R[1, 1], R[2, 2]):
        w = 0.5 * np.sqrt(1.0 + t)
        q = np.array([w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)])
    else:
        i = int(np.argmax([R[0, 0], R[1, 1], R[2, 2]]))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = np.sqrt(max(1.0 + R[i, i] - R[j, j] - R[k, k], 0.0))
        v = np.zeros(3)
        v[i] = 0.5 * s
        v[j] = (R[j, i] + R[i, j]) / (2 * s)
        v[k] = (R[k, i] + R[i, k]) / (2 * s)
        q = np.array([(R[k, j] - R[j, k]) / (2 * s), *v])
    q = q / np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def rotation_from_quaternion(q: np.ndarray) -> np.ndarray:
    """Body-to-world rotation matrix of a quaternion ``[w, x, y, z]`` (normalised first)."""
    w, x, y, z = np.asarray(q, dtype=float).tolist()
    s = 1.0 / math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w * s, x * s, y * s, z * s
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def rotations_from_quaternions(q: np.ndarray) -> np.ndarray:
    """(K, 3, 3) body-to-world rotations of (K, 4) quaternions ``[w, x, y, z]`` (normalised first): the
    vectorised :func:`rotation_from_quaternion`, for whole recorded runs."""
    q = np.asarray(q, dtype=float).reshape(-1, 4)
    w, x, y, z = (q / np.linalg.norm(q, axis=1, keepdims=True)).T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], axis=-1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], axis=-1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], axis=-1),
    ], axis=1)


@njit(cache=True)
def _euler_rows(R, out):
    for k in range(R.shape[0]):
        out[k, 0], out[k, 1], out[k, 2] = euler_zyx(R[k])


def euler_from_rotations(R: np.ndarray) -> np.ndarray:
    """(K, 3) ZYX Euler angles ``(phi, theta, psi)`` of (K, 3, 3) rotations (:func:`euler_zyx` on each), for
    whole recorded runs."""
    R = np.ascontiguousarray(np.asarray(R, dtype=np.float64).reshape(-1, 3, 3))
    out = np.empty((R.shape[0], 3))
    _euler_rows(R, out)
    return out


def quaternion_from_euler(euler: np.ndarray) -> np.ndarray:
    """Unit quaternion of ZYX Euler angles ``(phi, theta, psi)``."""
    return quaternion_from_rotation(rotation_from_euler(euler))


def euler_from_quaternion(q: np.ndarray) -> np.ndarray:
    """ZYX Euler angles ``(phi, theta, psi)`` of a quaternion."""
    return euler_from_rotation(rotation_from_quaternion(q))


@njit(cache=True, nogil=True)
def attitude_error(t, q, out):
    """``out`` (3,): the rotation vector [rad] of ``R_t^T R`` (the attitude error in body axes) for unit
    quaternions ``t`` (target) and ``q`` ``[w x y z]`` (Hamilton, body to world), compiled so that kernels call
    it: ``e = conj(t) q`` taken with ``e_w >= 0``, then ``2 atan2(|e_v|, e_w) e_v / |e_v|`` (``2 e_v / e_w`` as
    ``|e_v| -> 0``)."""
    tw, tx, ty, tz = t[0], -t[1], -t[2], -t[3]
    qw, qx, qy, qz = q[0], q[1], q[2], q[3]
    ew = tw * qw - tx * qx - ty * qy - tz * qz
    ex = tw * qx + qw * tx + ty * qz - tz * qy
    ey = tw * qy + qw * ty + tz * qx - tx * qz
    ez = tw * qz + qw * tz + tx * qy - ty * qx
    if ew < 0.0:
        ew, ex, ey, ez = -ew, -ex, -ey, -ez
    s = np.sqrt(ex * ex + ey * ey + ez * ez)
    scale = 2.0 * np.arctan2(s, ew) / s if s > 1e-12 else 2.0 / ew
    out[0] = ex * scale
    out[1] = ey * scale
    out[2] = ez * scale


def quaternion_rate(q: np.ndarray, omega: np.ndarray) -> np.ndarray:
    """``q_dot = 0.5 q (x) [0, omega]`` for body-frame angular velocity ``omega`` (replaces Eq. 1's ``T2``)."""
    w, x, y, z = q
    p, qq, r = omega
    return 0.5 * np.array([
        -x * p - y * qq - z * r,
        w * p + y * r - z * qq,
        w * qq + z * p - x * r,
        w * r + x * qq - y * p,
    ])


def euler_rate_matrix(euler: np.ndarray) -> np.ndarray:
    """The paper's ``T2`` (Eq. 1): ``euler_dot = T2 omega``; singular at ``theta = +/-pi/2``."""
    phi, theta, _ = euler
    sp, cp, ct, tt = np.sin(phi), np.cos(phi), np.cos(theta), np.tan(theta)
    return np.array([[1.0, sp * tt, cp * tt], [0.0, cp, -sp], [0.0, sp / ct, cp / ct]])

