"""The state vector, its time derivative, and the compiled fixed-step RK4 loop (paper Section 4).

State vector ``x`` (what is integrated; :class:`~uvms.state.State` is its labelled form)::

    x = [p (3, world, m) | quaternion (4, [w x y z], body to world) | nu (6, [omega; v], body axes)
         | q (n) | qd (n) | actuator states]

    p_dot = R v        quat_dot = 0.5 quat (x) [0, omega]        nu_dot, qdd = ABA(...)        q_dot = qd

The quaternion replaces Eq. 1's Euler-rate map ``T2`` (singular at pitch = +/-90 deg) and is renormalised
after every step. Inputs (joint torques, body wrench, end-effector wrench, actuator commands) are held
constant over a call (zero-order hold between controller updates); the current and fluid acceleration are
tables in time, interpolated linearly at every stage (a constant current is a one-row table).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from uvms.dynamics.aba import aba
from uvms.kinematics import quaternion_to_rotation
from uvms.sim.actuation import actuator_rates
from uvms.state import State

P, QUAT, NU, JOINTS = 0, 3, 7, 13

STATUS_OK, STATUS_NONFINITE, STATUS_BOUND = 0, 1, 2


def layout(n_joints: int, n_actuator: int) -> dict[str, slice]:
    """Slices of the state vector."""
    n = n_joints
    return {"position": slice(0, 3), "quaternion": slice(3, 7), "nu": slice(7, 13), "q": slice(13, 13 + n),
            "qd": slice(13 + n, 13 + 2 * n), "actuator": slice(13 + 2 * n, 13 + 2 * n + n_actuator)}


def pack(state) -> np.ndarray:
    """``x`` of a :class:`~uvms.state.State`."""
    if not isinstance(state, State):
        from uvms.checks import fail, show

        raise fail("state", f"expected a uvms State, got {show(state)}")
    return np.concatenate([state.position, state.quaternion, state.nu, state.q, state.qd, state.actuator])


def unpack(x: np.ndarray, n_joints: int):
    """The :class:`~uvms.state.State` of ``x`` (one copy of ``x``; the fields are read-only views of it)."""
    n = n_joints
    if type(n) is not int and not isinstance(n, np.integer) or n < 0 or not isinstance(x, np.ndarray) \
            or x.ndim != 1 or x.size < 13 + 2 * n or x.dtype.kind != "f":
        from uvms.checks import fail, show

        raise fail("x", f"expected a float state vector of at least 13 + 2 n values for n_joints = {n!r} "
                        f"(uvms.sim.integrate layout), got {show(x)}")
    c = x.copy()
    c.flags.writeable = False
    return State.trusted(c[0:3], c[3:7], c[7:13], c[13:13 + n], c[13 + n:13 + 2 * n], c[13 + 2 * n:])


@njit(cache=True)
def interpolate(table_t, table_v, t, out):
    """Linear interpolation of a (K, 3) table at ``t``, held constant outside its range."""
    K = table_t.shape[0]
    if K == 1 or t <= table_t[0]:
        for k in range(3):
            out[k] = table_v[0, k]
        return
    if t >= table_t[K - 1]:
        for k in range(3):
            out[k] = table_v[K - 1, k]
        return
    lo = 0
    hi = K - 1
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if table_t[mid] <= t:
            lo = mid
        else:
            hi = mid
    s = (t - table_t[lo]) / (table_t[hi] - table_t[lo])
    for k in range(3):
        out[k] = (1.0 - s) * table_v[lo, k] + s * table_v[hi, k]


@njit(cache=True, inline="always")
def state_derivative(km, ws, act, x, t, tau, f_ext, f_ee, command, env_t, env_vc, env_af, fixed_base, xdot,
                     R, vecs, thrust):
    """``xdot = f(t, x)`` for held inputs. ``R`` (3x3), ``vecs`` (5, 6) and ``thrust`` (m) are scratch."""
    nb = km.parent.shape[0]
    n = nb - 1
    qw, qx, qy, qz = x[3], x[4], x[5], x[6]
    norm = np.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    qw, qx, qy, qz = qw / norm, qx / norm, qy / norm, qz / norm
    quaternion_to_rotation(qw, qx, qy, qz, R)
    a0 = 13 + 2 * n
    f_body = vecs[0]
    actuator_rates(act, x[a0:], command, f_body, xdot[a0:], thrust)
    for k in range(6):
        f_body[k] += f_ext[k]
    vc = vecs[1]
    af = vecs[2]
    interpolate(env_t, env_vc, t, vc)
    interpolate(env_t, env_af, t, af)
    nu = vecs[3]
    for k in range(6):
        nu[k] = 0.0 if fixed_base else x[7 + k]
    aba(km, ws, R, nu, x[13:13 + n], x[13 + n:13 + 2 * n], tau, f_body, f_ee, vc, af, fixed_base, xdot[7:13],
        xdot[13 + n:13 + 2 * n])
    w0, w1, w2 = nu[0], nu[1], nu[2]
    for r in range(3):
        xdot[r] = R[r, 0] * nu[3] + R[r, 1] * nu[4] + R[r, 2] * nu[5]
    xdot[3] = 0.5 * (-qx * w0 - qy * w1 - qz * w2)
    xdot[4] = 0.5 * (qw * w0 + qy * w2 - qz * w1)
    xdot[5] = 0.5 * (qw * w1 + qz * w0 - qx * w2)
    xdot[6] = 0.5 * (qw * w2 + qx * w1 - qy * w0)
    for j in range(n):
        xdot[13 + j] = x[13 + n + j]


@njit(cache=True)
def check_state(x, n, bounds):
    """0 if ``x`` is finite and within ``bounds`` = (|p|, |nu|, |qd|, |actuator|) limits, else the index of
    the first offending entry + 1 (negative for a non-finite value)."""
    for k in range(x.shape[0]):
        if not np.isfinite(x[k]):
            return -(k + 1)
    for k in range(x.shape[0]):
        v = abs(x[k])
        if k < 3:
            lim = bounds[0]
        elif k < 7:
            continue
        elif k < 13:
            lim = bounds[1]
        elif k < 13 + n:
            continue
        elif k < 13 + 2 * n:
            lim = bounds[2]
        else:
            lim = bounds[3]
        if v > lim:
            return k + 1
    return 0


@njit(cache=True)
def rk4(km, ws, act, x, t0, h, n_steps, step0, record_every, tau, f_ext, f_ee, command, env_t, env_vc, env_af,
        fixed_base, bounds, out_t, out_x, n_out):
    """Advance ``x`` (in place) by ``n_steps`` classical RK4 steps of size ``h``, from global step ``step0``.

    ``t0`` is the time of global step 0: step ``k`` starts at ``t0 + k h``, the same floating-point value
    however a run is cut into calls (a long run is integrated in several calls, :data:`uvms.sim.run.CHUNK_SECONDS`).
    Whenever the global step count ``step0 + k`` is a multiple of ``record_every`` the time and state are
    written to ``out_t[n_out]``, ``out_x[n_out]``.
    Returns ``(steps_done, n_out, code)``: ``code`` is 0, or the :func:`check_state` code of the first bad step.
    """
    N = x.shape[0]
    n = km.parent.shape[0] - 1
    k1 = np.empty(N)
    k2 = np.empty(N)
    k3 = np.empty(N)
    k4 = np.empty(N)
    xt = np.empty(N)
    R = np.empty((3, 3))
    vecs = np.empty((5, 6))
    thrust = np.empty(max(act.kind.shape[0], 1))
    for k in range(N):
        k1[k] = k2[k] = k3[k] = k4[k] = 0.0
    for step in range(n_steps):
        t = t0 + (step0 + step) * h
        state_derivative(km, ws, act, x, t, tau, f_ext, f_ee, command, env_t, env_vc, env_af, fixed_base, k1,
                         R, vecs, thrust)
        for k in range(N):
            xt[k] = x[k] + 0.5 * h * k1[k]
        state_derivative(km, ws, act, xt, t + 0.5 * h, tau, f_ext, f_ee, command, env_t, env_vc, env_af,
                         fixed_base, k2, R, vecs, thrust)
        for k in range(N):
            xt[k] = x[k] + 0.5 * h * k2[k]
        state_derivative(km, ws, act, xt, t + 0.5 * h, tau, f_ext, f_ee, command, env_t, env_vc, env_af,
                         fixed_base, k3, R, vecs, thrust)
        for k in range(N):
            xt[k] = x[k] + h * k3[k]
        state_derivative(km, ws, act, xt, t + h, tau, f_ext, f_ee, command, env_t, env_vc, env_af, fixed_base,
                         k4, R, vecs, thrust)
        for k in range(N):
            x[k] += h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k])
        norm = np.sqrt(x[3] ** 2 + x[4] ** 2 + x[5] ** 2 + x[6] ** 2)
        for k in range(3, 7):
            x[k] /= norm
        code = check_state(x, n, bounds)
        if code != 0:
            return step + 1, n_out, code
        if (step0 + step + 1) % record_every == 0 and n_out < out_t.shape[0]:
            out_t[n_out] = t0 + (step0 + step + 1) * h
            for k in range(N):
                out_x[n_out, k] = x[k]
            n_out += 1
    return n_steps, n_out, 0
