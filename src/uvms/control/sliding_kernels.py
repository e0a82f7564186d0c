"""Compiled pieces of the station keepers' update (paper Eqs. 24-30): the per-axis errors and rates, their
accelerations, and Slotine's per-axis law. The equations are derived in :mod:`uvms.control.smc` and
``docs/conventions.md`` ("Six-axis station keeping"); the compiled update :func:`uvms.control.kernels.controller_update`
calls these kernels, and the Python functions :func:`~uvms.control.smc.axis_kinematics` and
:func:`~uvms.control.smc.slotine_law` wrap them.

The pose kinematics (:func:`pose_kinematics_into`) are a (N_KIN_ROWS, 6) array whose columns are the axis slots
surge, sway, heave, roll, pitch, yaw. The paper's three axes (:func:`axis_kinematics_into`) are a (7, 3)
array, rows::

    ERROR       e_x, e_y [m], e_psi [rad]         (e = R^T (p - p_d), e_psi wrapped to (-pi, pi])
    ERROR_RATE  e_dot_x, e_dot_y [m/s], psi_dot [rad/s]
    VELOCITY    u, v [m/s], r [rad/s]
    ERROR3      e (3,) [m]                         RATE3   e_dot (3,) [m/s]
    OMEGA       p, q, r [rad/s]                    EULER   phi, theta, psi [rad]

Surfaces: ``body_velocity = True`` uses ``vel = VELOCITY`` in ``s = vel + lambda e``; ``False`` uses
``vel = ERROR_RATE`` (the ``"error_rate"`` surface).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from uvms.jit import block, kernel
from uvms.kinematics import normalised_rotation
from uvms.rotations import euler_zyx

ERROR, ERROR_RATE, VELOCITY, ERROR3, RATE3, OMEGA, EULER = range(7)
N_KINEMATICS_ROWS = 7



@block
def wrap(angle):
    """``angle`` wrapped to (-pi, pi] [rad]."""
    return -((-angle + math.pi) % (2.0 * math.pi) - math.pi)


SURGE, SWAY, HEAVE, ROLL, PITCH, YAW = range(6)
"""Axis slots: columns of the pose kinematics, rows of a controller's per-axis gains."""
AXIS_NAMES = ("surge", "sway", "heave", "roll", "pitch", "yaw")
WRENCH_INDEX = (3, 4, 5, 0, 1, 2)
"""Where each axis slot sits in ``nu``, ``nu_dot`` and the wrench ``[K, M, N, X, Y, Z]``."""

N_KIN_ROWS = 5
"""Rows of the pose kinematics (N_KIN_ROWS, 6), by axis slot: ERROR, ERROR_RATE, VELOCITY, then ``POSITION``
``(e (3), e_dot (3))`` and ``ANGULAR`` ``(p, q, r, phi, theta, psi)``."""
POSITION, ANGULAR = 3, 4


@kernel
def pose_kinematics_into(quaternion, position, nu, desired, R, kin):
    """Body-to-world ``R`` (3x3) of ``quaternion`` (normalised: :func:`uvms.kinematics.normalised_rotation`) and
    the pose kinematics ``kin`` (N_KIN_ROWS, 6) of a pose and body velocity ``nu = [omega; v]`` for the world
    set point ``desired`` = ``(x, y, z, roll, pitch, yaw)``; columns are the axis slots surge, sway, heave, roll,
    pitch, yaw::

        ERROR       e = R^T (p - p_d) (3),  wrap(phi - phi_d), theta - theta_d, wrap(psi - psi_d)
        ERROR_RATE  e_dot = v - omega x e (from R_dot = R [omega x]),  phi_dot, theta_dot, psi_dot (Eq. 1's T2)
        VELOCITY    u, v, w, p, q, r

    ``phi_dot = p + sin(theta) psi_dot``, ``theta_dot = cos(phi) q - sin(phi) r``,
    ``psi_dot = (sin(phi) q + cos(phi) r) / cos(theta)``."""
    normalised_rotation(quaternion, R)
    d0 = position[0] - desired[0]
    d1 = position[1] - desired[1]
    d2 = position[2] - desired[2]
    w0, w1, w2, u, v, w = nu[0], nu[1], nu[2], nu[3], nu[4], nu[5]
    e0 = R[0, 0] * d0 + R[1, 0] * d1 + R[2, 0] * d2          # e = R^T (p - p_d)
    e1 = R[0, 1] * d0 + R[1, 1] * d1 + R[2, 1] * d2
    e2 = R[0, 2] * d0 + R[1, 2] * d1 + R[2, 2] * d2
    ed0 = u - (w1 * e2 - w2 * e1)                             # e_dot = v - omega x e
    ed1 = v - (w2 * e0 - w0 * e2)
    ed2 = w - (w0 * e1 - w1 * e0)
    phi, theta, psi = euler_zyx(R)                            # ZYX Euler angles of R (roll 0 at gimbal lock)
    sp, cp = math.sin(phi), math.cos(phi)
    psi_dot = (sp * w1 + cp * w2) / math.cos(theta)
    theta_dot = cp * w1 - sp * w2
    phi_dot = w0 + psi_dot * math.sin(theta)
    rows = ((e0, e1, e2, wrap(phi - desired[3]), theta - desired[4], wrap(psi - desired[5])),
            (ed0, ed1, ed2, phi_dot, theta_dot, psi_dot), (u, v, w, w0, w1, w2), (e0, e1, e2, ed0, ed1, ed2),
            (w0, w1, w2, phi, theta, psi))
    for r in range(N_KIN_ROWS):
        row = rows[r]
        for j in range(6):
            kin[r, j] = row[j]


@kernel
def surface_accelerations(kin, nu_dot, body_velocity, out):
    """Time derivatives (6,) by axis slot of the surface's ``vel`` for a body acceleration
    ``nu_dot = [omega_dot; v_dot]``: the body accelerations ``(u_dot, v_dot, w_dot, p_dot, q_dot, r_dot)``, or for
    the error-rate surface ``e_ddot = v_dot - omega_dot x e - omega x e_dot`` and the derivatives of the Euler
    rates (:func:`pose_kinematics_into`)::

        psi_ddot   = (sin(phi) q_dot + cos(phi) r_dot) / cos(theta) + phi_dot theta_dot / cos(theta)
                     + theta_dot tan(theta) psi_dot
        theta_ddot = cos(phi) q_dot - sin(phi) r_dot - (sin(phi) q + cos(phi) r) phi_dot
        phi_ddot   = p_dot + cos(theta) theta_dot psi_dot + sin(theta) psi_ddot
    """
    if body_velocity:
        for a in range(6):
            out[a] = nu_dot[WRENCH_INDEX[a]]
        return
    a0, a1, a2 = nu_dot[0], nu_dot[1], nu_dot[2]
    e0, e1, e2 = kin[POSITION, 0], kin[POSITION, 1], kin[POSITION, 2]
    d0, d1, d2 = kin[POSITION, 3], kin[POSITION, 4], kin[POSITION, 5]
    p, q, r = kin[ANGULAR, 0], kin[ANGULAR, 1], kin[ANGULAR, 2]
    out[0] = nu_dot[3] - (a1 * e2 - a2 * e1) - (q * d2 - r * d1)
    out[1] = nu_dot[4] - (a2 * e0 - a0 * e2) - (r * d0 - p * d2)
    out[2] = nu_dot[5] - (a0 * e1 - a1 * e0) - (p * d1 - q * d0)
    phi, theta = kin[ANGULAR, 3], kin[ANGULAR, 4]
    sp, cp, ct, tt = math.sin(phi), math.cos(phi), math.cos(theta), math.tan(theta)
    psi_dot = kin[ERROR_RATE, YAW]
    theta_dot = cp * q - sp * r
    phi_dot = p + psi_dot * math.sin(theta)
    psi_ddot = (sp * a1 + cp * a2) / ct + phi_dot * theta_dot / ct + theta_dot * tt * psi_dot
    out[3] = a0 + ct * theta_dot * psi_dot + math.sin(theta) * psi_ddot
    out[4] = cp * a1 - sp * a2 - (sp * q + cp * r) * phi_dot
    out[5] = psi_ddot


@kernel
def surface_input_gain(kin, body_velocity, axis):
    """How an axis slot's surface acceleration responds per unit of ``command / b``: 1, except on the
    error-rate surface ``cos(phi) / cos(theta)`` for yaw (``psi_ddot``) and ``cos(phi)`` for pitch."""
    if body_velocity or axis <= ROLL:
        return 1.0
    if axis == PITCH:
        return math.cos(kin[ANGULAR, 3])
    return math.cos(kin[ANGULAR, 3]) / math.cos(kin[ANGULAR, 4])


_PAPER_SLOTS = (SURGE, SWAY, YAW)


@njit(cache=True)
def axis_kinematics_into(quaternion, position, nu, position_desired, yaw_desired, R, kin):
    """The surge, sway and yaw columns of :func:`pose_kinematics_into` in the (7, 3) layout of the module
    docstring (roll and pitch set points 0; they do not enter these columns)."""
    desired = np.zeros(6)
    desired[0] = position_desired[0]
    desired[1] = position_desired[1]
    desired[2] = position_desired[2]
    desired[5] = yaw_desired
    full = np.empty((N_KIN_ROWS, 6))
    pose_kinematics_into(quaternion, position, nu, desired, R, full)
    for c in range(3):
        a = _PAPER_SLOTS[c]
        kin[ERROR, c] = full[ERROR, a]
        kin[ERROR_RATE, c] = full[ERROR_RATE, a]
        kin[VELOCITY, c] = full[VELOCITY, a]
        kin[ERROR3, c] = full[POSITION, c]
        kin[RATE3, c] = full[POSITION, 3 + c]
        kin[OMEGA, c] = full[ANGULAR, c]
        kin[EULER, c] = full[ANGULAR, 3 + c]


@njit(cache=True)
def axis_accelerations(kin, nu_dot, body_velocity, out):
    """Time derivatives (3,) of the surface's ``vel`` of the surge, sway and yaw axes for a body acceleration
    ``nu_dot`` (:func:`surface_accelerations` on the (7, 3) table of :func:`axis_kinematics_into`)."""
    full = np.zeros((N_KIN_ROWS, 6))
    for c in range(3):
        full[POSITION, c] = kin[ERROR3, c]
        full[POSITION, 3 + c] = kin[RATE3, c]
        full[ANGULAR, c] = kin[OMEGA, c]
        full[ANGULAR, 3 + c] = kin[EULER, c]
    full[ERROR_RATE, YAW] = kin[ERROR_RATE, 2]
    acc = np.empty(6)
    surface_accelerations(full, nu_dot, body_velocity, acc)
    for c in range(3):
        out[c] = acc[_PAPER_SLOTS[c]]


@kernel
def slotine(error, rate, f_hat, bandwidth, eta, boundary_layer, uncertainty, b_hat, beta, rate_desired,
            acc_desired, error_rate):
    """One axis of Slotine's law (Eqs. 26-29 as corrected in the conventions): ``(s, k, u_hat, command)``.

    ``s = (rate - rate_desired) + lambda e``; ``u_hat = -f_hat + acc_desired - lambda e_dot``;
    ``k = beta (F + eta) + (beta - 1) |u_hat|``; ``command = b_hat (u_hat - k sat(s / Phi))``."""
    s = rate - rate_desired + bandwidth * error
    u_hat = -f_hat + acc_desired - bandwidth * error_rate
    k = beta * (uncertainty + eta) + (beta - 1.0) * abs(u_hat)
    saturated = min(1.0, max(-1.0, s / boundary_layer))
    return s, k, u_hat, b_hat * (u_hat - k * saturated)


def kinematics_buffers() -> tuple[np.ndarray, np.ndarray]:
    """Fresh ``(R, kin)`` arrays for :func:`axis_kinematics_into`."""
    return np.zeros((3, 3)), np.zeros((N_KINEMATICS_ROWS, 3))
