"""The state vector, its time derivative, and the compiled fixed-step RK4 loop (paper Section 4).

State vector ``x`` (what is integrated; :class:`~uvms.state.State` is its labelled form, :mod:`uvms.state` the
owner of its layout)::

    x = [p (3, world, m) | quaternion (4, [w x y z], body to world) | nu (6, [omega; v], body axes)
         | q (n) | qd (n) | actuator states]

    p_dot = R v        quat_dot = 0.5 quat (x) [0, omega]        nu_dot, qdd = ABA(...)        q_dot = qd

The quaternion replaces Eq. 1's Euler-rate map ``T2`` (singular at pitch = +/-90 deg) and is renormalised
after every step. Inputs (joint torques, body wrench, end-effector wrench, actuator commands) are held
constant over a call (zero-order hold between controller updates); the water (:mod:`uvms.hydro.flow`: a
current table in time, depth profiles, gridded fields, waves) is evaluated at every stage at every body's own
position (:func:`uvms.dynamics.passes.outward_pass`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from uvms.dynamics.aba import aba_inlined
from uvms.dynamics.plant import plant_data
from uvms.hydro.flow import interpolate
from uvms.jit import block, kernel
from uvms.kinematics import quaternion_to_rotation
from uvms.state import JOINTS, NU, POSITION, QUATERNION, State
from uvms.thrusters.actuation import actuator_rates


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
            or x.ndim != 1 or x.size < JOINTS + 2 * n or x.dtype.kind != "f":
        from uvms.checks import fail, show

        raise fail("x", f"expected a float state vector of at least 13 + 2 n values for n_joints = {n!r} "
                        f"(uvms.state layout), got {show(x)}")
    c = x.copy()
    c.flags.writeable = False
    return State.trusted(c[POSITION:QUATERNION], c[QUATERNION:NU], c[NU:JOINTS], c[JOINTS:JOINTS + n],
                         c[JOINTS + n:JOINTS + 2 * n], c[JOINTS + 2 * n:], c)


class Samples(NamedTuple):
    """Where the compiled loop records the state: every ``every``-th global step, ``times[k]``, ``states[k]``;
    ``count[0]`` rows written so far."""

    every: int
    times: np.ndarray           # (K,) [s]
    states: np.ndarray          # (K, N)
    count: np.ndarray           # (1,) int64


def samples(n_rows: int, size: int, every: int) -> Samples:
    """Empty :class:`Samples` of ``n_rows`` rows of states of ``size``."""
    return Samples(int(every), np.zeros(n_rows), np.zeros((n_rows, size)), np.zeros(1, dtype=np.int64))


@block
def stage_inputs(plant, held, t, x, xdot):
    """The part of ``xdot = f(t, x)`` shared by every derivative (:func:`state_derivative`,
    :func:`uvms.sim.prescribed.prescribed_derivative`): the body-to-world rotation of the normalised quaternion
    into ``plant.scratch.R``, the actuators' state rates into ``xdot`` and their body wrench plus the held one
    plus the model's constant disturbance wrench (``Model.disturbance_wrench``) into ``vecs[0]``, and the
    vehicle's velocity ``nu`` (zero when clamped) into ``vecs[3]``. Returns the normalised quaternion. (The water
    is evaluated per body inside the ABA's outward pass.)

    This is the one place the disturbance enters: every simulation (``simulate``, ``rollout``, the
    ``Simulator``, the batch stepper, replays, the prescribed-joint loop and so ``identify``) takes its state
    derivative through here (``docs/conventions.md``, "Where a model's disturbance wrench enters")."""
    scratch = plant.scratch
    R = scratch.R
    vecs = scratch.vecs
    n = plant.body.parent.shape[0] - 1
    qw, qx, qy, qz = x[QUATERNION], x[QUATERNION + 1], x[QUATERNION + 2], x[QUATERNION + 3]
    norm = np.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    qw, qx, qy, qz = qw / norm, qx / norm, qy / norm, qz / norm
    quaternion_to_rotation(qw, qx, qy, qz, R)
    a0 = JOINTS + 2 * n
    f_body = vecs[0]
    actuator_rates(plant.actuators, x[a0:], held.command, f_body, xdot[a0:], scratch.thrust)
    disturbance = plant.body.disturbance
    for k in range(6):
        f_body[k] += held.body_wrench[k]
        f_body[k] += disturbance[k]
    nu = vecs[3]
    fixed_base = plant.fixed_base
    for k in range(6):
        nu[k] = 0.0 if fixed_base else x[NU + k]
    return qw, qx, qy, qz


@block
def vehicle_rates(R, nu, qw, qx, qy, qz, xdot):
    """``p_dot = R v`` and ``quat_dot = 0.5 quat (x) [0, omega]`` into ``xdot`` (module docstring)."""
    w0, w1, w2 = nu[0], nu[1], nu[2]
    for r in range(3):
        xdot[POSITION + r] = R[r, 0] * nu[3] + R[r, 1] * nu[4] + R[r, 2] * nu[5]
    xdot[QUATERNION] = 0.5 * (-qx * w0 - qy * w1 - qz * w2)
    xdot[QUATERNION + 1] = 0.5 * (qw * w0 + qy * w2 - qz * w1)
    xdot[QUATERNION + 2] = 0.5 * (qw * w1 + qz * w0 - qx * w2)
    xdot[QUATERNION + 3] = 0.5 * (qw * w2 + qx * w1 - qy * w0)


@block
def state_derivative(plant, held, t, x, xdot):
    """``xdot = f(t, x)`` for the held inputs (:class:`~uvms.dynamics.plant.Held`) on the plant
    (:class:`~uvms.dynamics.plant.Plant`; its scratch is used)."""
    n = plant.body.parent.shape[0] - 1
    qw, qx, qy, qz = stage_inputs(plant, held, t, x, xdot)
    R = plant.scratch.R
    vecs = plant.scratch.vecs
    nu = vecs[3]
    aba_inlined(plant.body, plant.work, R, x[POSITION:QUATERNION], nu, x[JOINTS:JOINTS + n],
                x[JOINTS + n:JOINTS + 2 * n], held.joint_torques, vecs[0], held.ee_wrench, plant.fluid, t,
                plant.fixed_base, xdot[NU:JOINTS], xdot[JOINTS + n:JOINTS + 2 * n])
    vehicle_rates(R, nu, qw, qx, qy, qz, xdot)
    for j in range(n):
        xdot[JOINTS + j] = x[JOINTS + n + j]


@kernel
def derivative_kernel(plant, held, t, x, xdot):
    """:func:`state_derivative` on a :class:`~uvms.dynamics.plant.PlantData` as a function of its own: the one
    compiled copy (with its inlined ABA) for every caller outside the RK4 loop."""
    state_derivative(plant, held, t, x, xdot)


@njit(cache=True)
def derivative(plant, held, t, x, xdot):
    """:func:`state_derivative` on a :class:`~uvms.dynamics.plant.Plant`, callable from Python (the adaptive
    integrators, sensor models)."""
    derivative_kernel(plant_data(plant), held, t, x, xdot)


@kernel
def check_state(x, n, bounds):
    """0 if ``x`` is finite and within ``bounds`` = (|p|, |nu|, |qd|, |actuator|) limits, else the index of
    the first offending entry + 1 (negative for a non-finite value)."""
    for k in range(x.shape[0]):
        if not np.isfinite(x[k]):
            return -(k + 1)
    for k in range(x.shape[0]):
        v = abs(x[k])
        if k < QUATERNION:
            lim = bounds[0]
        elif k < NU:
            continue
        elif k < JOINTS:
            lim = bounds[1]
        elif k < JOINTS + n:
            continue
        elif k < JOINTS + 2 * n:
            lim = bounds[2]
        else:
            lim = bounds[3]
        if v > lim:
            return k + 1
    return 0


@njit(cache=True, nogil=True)
def rk4(plant, held, x, t0, h, n_steps, step0, record):
    """:func:`rk4_steps` on a :class:`~uvms.dynamics.plant.Plant` (read once into its named tuple)."""
    return rk4_steps(plant_data(plant), held, x, t0, h, n_steps, step0, record)


@kernel
def rk4_steps(plant, held, x, t0, h, n_steps, step0, record):
    """Advance ``x`` (in place) by ``n_steps`` classical RK4 steps of size ``h``, from global step ``step0``.

    ``t0`` is the time of global step 0: step ``k`` starts at ``t0 + k h``, the same floating-point value
    however a run is cut into calls (a long run is integrated in several calls, :data:`uvms.sim.run.CHUNK_SECONDS`).
    Whenever the global step count ``step0 + k`` is a multiple of ``record.every`` the time and state are
    written to the next row of ``record`` (:class:`Samples`).
    Returns ``(steps_done, code)``: ``code`` is 0, or the :func:`check_state` code of the first bad step.
    """
    N = x.shape[0]
    n = plant.body.parent.shape[0] - 1
    stages = plant.scratch.stages
    k1 = stages[0]
    k2 = stages[1]
    k3 = stages[2]
    k4 = stages[3]
    xt = stages[4]
    bounds = plant.bounds
    every = record.every
    out_t = record.times
    out_x = record.states
    for step in range(n_steps):
        t = t0 + (step0 + step) * h
        for stage in range(4):              # one call site, so the derivative (and its ABA) is inlined once
            if stage == 0:
                ts, xs = t, x
            elif stage == 3:
                ts, xs = t + h, xt
            else:
                ts, xs = t + 0.5 * h, xt
            ks = stages[stage]
            state_derivative(plant, held, ts, xs, ks)
            if stage < 3:                   # the next stage's state: x + h/2 k1, x + h/2 k2, x + h k3
                c = h if stage == 2 else 0.5 * h
                for k in range(N):
                    xt[k] = x[k] + c * ks[k]
        for k in range(N):
            x[k] += h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k])
        norm = np.sqrt(x[QUATERNION] ** 2 + x[QUATERNION + 1] ** 2 + x[QUATERNION + 2] ** 2 + x[QUATERNION + 3] ** 2)
        for k in range(QUATERNION, NU):
            x[k] /= norm
        code = check_state(x, n, bounds)
        if code != 0:
            return step + 1, code
        n_out = record.count[0]
        if (step0 + step + 1) % every == 0 and n_out < out_t.shape[0]:
            out_t[n_out] = t0 + (step0 + step + 1) * h
            for k in range(N):
                out_x[n_out, k] = x[k]
            record.count[0] = n_out + 1
    return n_steps, 0
