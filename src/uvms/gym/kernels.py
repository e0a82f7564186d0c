"""Compiled helpers of the Gymnasium environments."""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.kinematics import quaternion_to_rotation
from uvms.state import JOINTS, NU, POSITION, QUATERNION
from uvms.thrusters.command import HEALEY, TABLE
from uvms.thrusters.healey import healey_voltage_for_thrust
from uvms.thrusters.table import table_command


@njit(cache=True, nogil=True)
def thrust_commands(kind, params, coefficients, thrusts, out):
    """``out[k, h]``: the command of thruster ``h`` for the steady thrust ``thrusts[k, h]`` [N] (Healey's
    steady-state voltage, a table thruster's inverse table, or the thrust itself), as the last stage of
    :func:`uvms.thrusters.command.allocate_command` (``kind``, ``params``, ``coefficients``: the fields of its
    :class:`~uvms.thrusters.command.ThrustCommand`)."""
    for k in range(thrusts.shape[0]):
        for h in range(thrusts.shape[1]):
            T = thrusts[k, h]
            if kind[h] == HEALEY:
                out[k, h] = healey_voltage_for_thrust(params[h], coefficients[h], T)
            elif kind[h] == TABLE:
                out[k, h] = table_command(params[h], T)
            else:
                out[k, h] = T


@njit(cache=True, nogil=True)
def attitude_error(t, q, out):
    """``out`` (3,): the rotation vector [rad] of ``R_t^T R`` for unit quaternions ``t`` (target) and ``q``
    ``[w x y z]`` (Hamilton, body to world): ``e = conj(t) q`` taken with ``e_w >= 0``, then
    ``2 atan2(|e_v|, e_w) e_v / |e_v|`` (``2 e_v / e_w`` as ``|e_v| -> 0``)."""
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


@njit(cache=True, nogil=True)
def observe_rows(x, target_position, target_quaternion, n_joints, n_thrusts, limit, R, quaternion, out):
    """``out[k]``: the observation of state vector ``x[k]`` (:mod:`uvms.gym.task`'s table): position error in
    world and body axes, attitude error (:func:`attitude_error`), ``nu``, ``q``, ``qd`` and ``n_thrusts``
    actuator states; non-finite entries read as 0 and every entry is clipped to ``+-limit``. ``R`` (3, 3) and
    ``quaternion`` (4,) are scratch."""
    for k in range(x.shape[0]):
        row = x[k]
        o = out[k]
        norm = np.sqrt(row[QUATERNION] ** 2 + row[QUATERNION + 1] ** 2 + row[QUATERNION + 2] ** 2
                       + row[QUATERNION + 3] ** 2)
        for j in range(4):
            quaternion[j] = row[QUATERNION + j] / norm
        quaternion_to_rotation(quaternion[0], quaternion[1], quaternion[2], quaternion[3], R)
        for i in range(3):
            o[i] = row[POSITION + i] - target_position[i]
        for i in range(3):
            o[3 + i] = R[0, i] * o[0] + R[1, i] * o[1] + R[2, i] * o[2]
        attitude_error(target_quaternion, quaternion, o[6:9])
        m = 6 + 2 * n_joints
        for j in range(m):
            o[9 + j] = row[NU + j]
        for j in range(n_thrusts):
            o[9 + m + j] = row[JOINTS + 2 * n_joints + j]
        for j in range(o.shape[0]):
            v = o[j]
            if not np.isfinite(v):
                o[j] = 0.0
            elif v > limit:
                o[j] = limit
            elif v < -limit:
                o[j] = -limit
