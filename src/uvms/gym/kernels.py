"""Compiled helpers of the Gymnasium environments."""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.kinematics import quaternion_to_rotation
from uvms.rotations import attitude_error
from uvms.state import JOINTS, NU, POSITION, QUATERNION
from uvms.thrusters.kinds import command_for_thrust


@njit(cache=True, nogil=True)
def thrust_commands(kind, params, coefficients, thrusts, out):
    """``out[k, h]``: the command of thruster ``h`` for the steady thrust ``thrusts[k, h]`` [N]
    (:func:`uvms.thrusters.kinds.command_for_thrust`), as the last stage of
    :func:`uvms.thrusters.command.allocate_command` (``kind``, ``params``, ``coefficients``: the fields of its
    :class:`~uvms.thrusters.command.ThrustCommand`)."""
    for k in range(thrusts.shape[0]):
        for h in range(thrusts.shape[1]):
            out[k, h] = command_for_thrust(kind[h], params[h], coefficients[h], thrusts[k, h])


@njit(cache=True, nogil=True)
def observe_rows(x, target_position, target_quaternion, n_joints, n_thrusts, limit, R, quaternion, out):
    """``out[k]``: the observation of state vector ``x[k]`` (:mod:`uvms.gym.task`'s table): position error in
    world and body axes, attitude error (:func:`uvms.rotations.attitude_error`), ``nu``, ``q``, ``qd`` and
    ``n_thrusts`` actuator states; non-finite entries read as 0 and every entry is clipped to ``+-limit``. ``R``
    (3, 3) and ``quaternion`` (4,) are scratch."""
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
