"""Compiled pieces of the sliding-mode update (paper Eqs. 24-30): the axis errors and rates, their
accelerations, and Slotine's per-axis law. The equations are derived in :mod:`uvms.control.smc`, whose
Python functions (:func:`~uvms.control.smc.axis_kinematics`, :func:`~uvms.control.smc.slotine_law`) wrap these
kernels; a controller update calls them directly, so it costs a few microseconds, not tens.

The axis kinematics of a state are a (7, 3) array, rows::

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

from uvms.kinematics import quaternion_to_rotation
from uvms.rotations import euler_zyx

ERROR, ERROR_RATE, VELOCITY, ERROR3, RATE3, OMEGA, EULER = range(7)
N_KINEMATICS_ROWS = 7

S, K, F_HAT, COMMAND, E, B_HAT = range(6)
"""Columns of the per-axis signal array written by :func:`sliding_mode_wrench`."""
N_SIGNAL_COLUMNS = 6

_WRENCH_INDEX = (3, 4, 2)   # surge -> X, sway -> Y, yaw -> N in [K, M, N, X, Y, Z]


@njit(cache=True, inline="always")
def wrap(angle):
    """``angle`` wrapped to (-pi, pi] [rad]."""
    return -((-angle + math.pi) % (2.0 * math.pi) - math.pi)


@njit(cache=True)
def axis_kinematics_into(quaternion, position, nu, position_desired, yaw_desired, R, kin):
    """Body-to-world ``R`` (3x3) of ``quaternion`` (normalised here) and the (7, 3) axis kinematics ``kin``
    of a pose and body velocity ``nu = [omega; v]`` for the desired pose ``(position_desired, yaw_desired)``.

    ``e_dot = v - omega x e`` follows from ``R_dot = R [omega x]``; ``psi_dot`` is Eq. 1's ``T2`` row
    ``(sin(phi) q + cos(phi) r) / cos(theta)``."""
    qw, qx, qy, qz = quaternion[0], quaternion[1], quaternion[2], quaternion[3]
    norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    quaternion_to_rotation(qw / norm, qx / norm, qy / norm, qz / norm, R)
    d0 = position[0] - position_desired[0]
    d1 = position[1] - position_desired[1]
    d2 = position[2] - position_desired[2]
    w0, w1, w2, u, v, w = nu[0], nu[1], nu[2], nu[3], nu[4], nu[5]
    e0 = R[0, 0] * d0 + R[1, 0] * d1 + R[2, 0] * d2          # e = R^T (p - p_d)
    e1 = R[0, 1] * d0 + R[1, 1] * d1 + R[2, 1] * d2
    e2 = R[0, 2] * d0 + R[1, 2] * d1 + R[2, 2] * d2
    ed0 = u - (w1 * e2 - w2 * e1)                             # e_dot = v - omega x e
    ed1 = v - (w2 * e0 - w0 * e2)
    ed2 = w - (w0 * e1 - w1 * e0)
    phi, theta, psi = euler_zyx(R)                            # ZYX Euler angles of R (roll 0 at gimbal lock)
    psi_dot = (math.sin(phi) * w1 + math.cos(phi) * w2) / math.cos(theta)
    rows = ((e0, e1, wrap(psi - yaw_desired)), (ed0, ed1, psi_dot), (u, v, w2), (e0, e1, e2), (ed0, ed1, ed2),
            (w0, w1, w2), (phi, theta, psi))
    for r in range(N_KINEMATICS_ROWS):
        row = rows[r]
        kin[r, 0] = row[0]
        kin[r, 1] = row[1]
        kin[r, 2] = row[2]


@njit(cache=True)
def axis_accelerations(kin, nu_dot, body_velocity, out):
    """Time derivatives (3,) of the surface's ``vel`` for a body acceleration ``nu_dot = [omega_dot; v_dot]``:
    ``(u_dot, v_dot, r_dot)``, or for the error-rate surface ``(e_ddot_x, e_ddot_y, psi_ddot)`` with
    ``e_ddot = v_dot - omega_dot x e - omega x e_dot`` and ``psi_ddot`` the derivative of Eq. 1's ``T2`` row."""
    if body_velocity:
        out[0] = nu_dot[3]
        out[1] = nu_dot[4]
        out[2] = nu_dot[2]
        return
    a0, a1, a2 = nu_dot[0], nu_dot[1], nu_dot[2]
    e0, e1, e2 = kin[ERROR3, 0], kin[ERROR3, 1], kin[ERROR3, 2]
    d0, d1, d2 = kin[RATE3, 0], kin[RATE3, 1], kin[RATE3, 2]
    p, q, r = kin[OMEGA, 0], kin[OMEGA, 1], kin[OMEGA, 2]
    out[0] = nu_dot[3] - (a1 * e2 - a2 * e1) - (q * d2 - r * d1)
    out[1] = nu_dot[4] - (a2 * e0 - a0 * e2) - (r * d0 - p * d2)
    phi, theta = kin[EULER, 0], kin[EULER, 1]
    sp, cp, ct, tt = math.sin(phi), math.cos(phi), math.cos(theta), math.tan(theta)
    psi_dot = kin[ERROR_RATE, 2]
    theta_dot = cp * q - sp * r
    phi_dot = p + psi_dot * math.sin(theta)
    out[2] = (sp * a1 + cp * a2) / ct + phi_dot * theta_dot / ct + theta_dot * tt * psi_dot


@njit(cache=True, inline="always")
def input_gain(kin, body_velocity, axis):
    """How an axis' acceleration responds per unit of ``command / b``: 1, except ``cos(phi) / cos(theta)``
    for ``psi_ddot`` on the error-rate surface."""
    if body_velocity or axis < 2:
        return 1.0
    return math.cos(kin[EULER, 0]) / math.cos(kin[EULER, 1])


@njit(cache=True)
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


@njit(cache=True)
def sliding_mode_wrench(kin, nu_dot_hat, body_velocity, bandwidth, eta, boundary_layer, uncertainty, b_hat, beta,
                        f_hat, wrench, signals):
    """The station-keeping body wrench ``[K, M, N, X, Y, Z]`` (surge, sway and yaw set, the rest zero).

    ``nu_dot_hat`` is the controller model's ``nu_dot`` at ``f_0 = 0``; ``uncertainty``, ``b_hat``, ``beta``
    are per axis (3,). Writes ``f_hat`` (3,) scratch, ``wrench`` (6,), and ``signals`` (3, 6): per axis
    ``s, k, f_hat, command, e, b_hat`` (columns :data:`S` ... :data:`B_HAT`)."""
    axis_accelerations(kin, nu_dot_hat, body_velocity, f_hat)
    for k in range(6):
        wrench[k] = 0.0
    for j in range(3):
        rate = kin[VELOCITY, j] if body_velocity else kin[ERROR_RATE, j]
        s, k, _, command = slotine(kin[ERROR, j], rate, f_hat[j], bandwidth, eta, boundary_layer, uncertainty[j],
                                   b_hat[j], beta[j], 0.0, 0.0, kin[ERROR_RATE, j])
        force = command / input_gain(kin, body_velocity, j)
        wrench[_WRENCH_INDEX[j]] = force
        signals[j, S] = s
        signals[j, K] = k
        signals[j, F_HAT] = f_hat[j]
        signals[j, COMMAND] = force
        signals[j, E] = kin[ERROR, j]
        signals[j, B_HAT] = b_hat[j]


def kinematics_buffers() -> tuple[np.ndarray, np.ndarray]:
    """Fresh ``(R, kin)`` arrays for :func:`axis_kinematics_into`."""
    return np.zeros((3, 3)), np.zeros((N_KINEMATICS_ROWS, 3))
