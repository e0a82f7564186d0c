"""The compiled loop of a run with a prescribed joint motion (``Inputs(joint_motion=...)``,
:class:`uvms.sim.joint_motion.JointMotion`): every joint follows ``q(t)``, the vehicle moves freely.

The joints are not integrated: they are known functions of time. At every RK4 stage time ``t_s`` the loop
evaluates the motion's pieces (:func:`motion_at`: ``q, qd, qdd`` at ``t_s``) and the hybrid dynamics
(:func:`uvms.dynamics.hybrid.aba_prescribed`) gives the vehicle's ``nu_dot`` for the stage's vehicle state;
RK4 integrates the vehicle (position, quaternion, ``nu``) and the actuator states. The state's ``q, qd`` after
every step are set to the motion's at the step's end, so every recorded ``q, qd`` *is* the interpolant's at
its row's time (the stage derivative ``q' = qd(t), qd' = qdd(t)`` is written too, for readers of ``xdot``).

A log's thruster commands (``Inputs(thruster_commands=...)``, :class:`uvms.sim.inputs.CommandSchedule`) ride
along as a piecewise-constant table (``Motion.command_times``, ``Motion.commands``): at every step's start the
row in force (the last at or before ``t``) is copied into the held commands, which the actuators see over the
whole step, as the ordinary loop holds a controller's commands (:func:`hold_commands`).

The torques the motion takes are those of each recorded row's time and state, not a held value: the first
stage of the step that starts at a row evaluates exactly that (kept in ``Motion.row_tau``), and the rows no
step starts from (the last; a diverged run's) are evaluated afterwards (:func:`motion_torques`).

The RK4 loop repeats :func:`uvms.sim.integrate.rk4_steps` with the prescribed stage derivative in place of
the ordinary one: the ordinary loop stays as it was (no branch per stage, no new arrays in its plant).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from uvms.dynamics.hybrid import aba_prescribed, aba_prescribed_inlined
from uvms.dynamics.plant import plant_data
from uvms.jit import block, kernel
from uvms.lookup import last_at_or_before
from uvms.sim.integrate import check_state, stage_inputs, vehicle_rates
from uvms.state import JOINTS, NU, POSITION, QUATERNION


class Motion(NamedTuple):
    """A joint motion's pieces in the model's joint order (:meth:`~uvms.sim.joint_motion.JointMotion.for_model`)
    and the scratch of its evaluation."""

    breaks: np.ndarray          # (m + 1,) [s]
    coefficients: np.ndarray    # (m, n, 4) power basis, lowest power first
    prescribed: np.ndarray      # (n,) bool: which joints follow the motion (all, in a run)
    q: np.ndarray               # (n,) q(t) [rad or m]
    qd: np.ndarray              # (n,) dq/dt
    qdd: np.ndarray             # (n,) d2q/dt2
    free_torques: np.ndarray    # (n,) torques of joints not prescribed (zeros in a run)
    qdd_out: np.ndarray         # (n,) the hybrid dynamics' joint accelerations (= qdd)
    tau: np.ndarray             # (n,) the torques the motion takes [N m or N]
    row_tau: np.ndarray         # (rows, n) the torques at each recorded row, from the next step's first stage
    filled: np.ndarray          # (1,) int64: rows 0 .. filled - 1 of row_tau are set
    command_times: np.ndarray   # (K,) [s] increasing from 0: when each row of ``commands`` takes over (K = 0: none)
    commands: np.ndarray        # (K, m) the thrusters' commands, in the actuation's order and units


def motion_data(breaks: np.ndarray, coefficients: np.ndarray, rows: int, table=None) -> Motion:
    """A :class:`Motion` of fresh C-ordered arrays (every joint prescribed) for a record of ``rows`` rows;
    ``table = (times, commands)`` the thrusters' command table (default: none)."""
    n = coefficients.shape[1]
    times, commands = (np.zeros(0), np.zeros((0, 0))) if table is None else table
    return Motion(np.ascontiguousarray(breaks, dtype=float), np.ascontiguousarray(coefficients, dtype=float),
                  np.ones(n, dtype=np.bool_), *(np.zeros(n) for _ in range(6)), np.zeros((rows, n)),
                  np.zeros(1, dtype=np.int64), np.ascontiguousarray(times, dtype=float),
                  np.ascontiguousarray(np.reshape(commands, (len(times), -1)) if len(times) else np.zeros((0, 0)),
                                       dtype=float))


@block
def motion_at(motion, t):
    """``motion.q, qd, qdd`` at ``t`` [s]: the piece ``k`` with ``breaks[k] <= t < breaks[k+1]`` (the first or
    the last beyond the ends) by bisection, each polynomial by Horner's rule."""
    b = motion.breaks
    lo = last_at_or_before(b, t, b.shape[0] - 1)
    s = t - b[lo]
    c = motion.coefficients[lo]
    for j in range(c.shape[0]):
        c0, c1, c2, c3 = c[j, 0], c[j, 1], c[j, 2], c[j, 3]
        motion.q[j] = c0 + s * (c1 + s * (c2 + s * c3))
        motion.qd[j] = c1 + s * (2.0 * c2 + 3.0 * s * c3)
        motion.qdd[j] = 2.0 * c2 + 6.0 * s * c3


@block
def hold_commands(motion, t, command):
    """``command[:m]`` = the command table's row in force at ``t`` [s] (the last with ``command_times[k] <= t``,
    bisection; 1e-12 s of slack so a row at exactly a step's time takes over at that step); nothing without
    a table."""
    times = motion.command_times
    K = times.shape[0]
    if K == 0:
        return
    row = motion.commands[last_at_or_before(times, t + 1e-12, K)]
    for j in range(row.shape[0]):
        command[j] = row[j]


@block
def prescribed_derivative(plant, held, motion, t, x, xdot):
    """``xdot = f(t, x)`` with the joints on the motion at ``t`` (module docstring); the torques it takes in
    ``motion.tau``."""
    n = plant.body.parent.shape[0] - 1
    qw, qx, qy, qz = stage_inputs(plant, held, t, x, xdot)
    motion_at(motion, t)
    R = plant.scratch.R
    vecs = plant.scratch.vecs
    nu = vecs[3]
    aba_prescribed_inlined(plant.body, plant.work, R, x[POSITION:QUATERNION], nu, motion.q, motion.qd, motion.qdd,
                           motion.free_torques, motion.prescribed, vecs[0], held.ee_wrench, plant.fluid, t,
                           plant.fixed_base, xdot[NU:JOINTS], motion.qdd_out, motion.tau)
    vehicle_rates(R, nu, qw, qx, qy, qz, xdot)
    for j in range(n):
        xdot[JOINTS + j] = motion.qd[j]
        xdot[JOINTS + n + j] = motion.qdd[j]


@block
def set_joints(motion, t, x):
    """The state's ``q, qd`` set to the motion's at ``t``."""
    motion_at(motion, t)
    n = motion.q.shape[0]
    for j in range(n):
        x[JOINTS + j] = motion.q[j]
        x[JOINTS + n + j] = motion.qd[j]


@kernel
def rk4_prescribed_steps(plant, held, motion, x, h, n_steps, step0, record):
    """:func:`uvms.sim.integrate.rk4_steps` (same grid ``t = k h``, recording and divergence check) with the
    stage derivative :func:`prescribed_derivative`, and the joints set to the motion after every step."""
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
        t = (step0 + step) * h
        hold_commands(motion, t, held.command)
        for stage in range(4):              # one call site, so the derivative (and its hybrid ABA) is inlined once
            if stage == 0:
                ts, xs = t, x
            elif stage == 3:
                ts, xs = t + h, xt
            else:
                ts, xs = t + 0.5 * h, xt
            ks = stages[stage]
            prescribed_derivative(plant, held, motion, ts, xs, ks)
            if stage == 0 and (step0 + step) % every == 0:   # the recorded row at t: keep its torques
                row = record.count[0] - 1
                if row >= 0 and out_t[row] == t:
                    for j in range(n):
                        motion.row_tau[row, j] = motion.tau[j]
                    motion.filled[0] = row + 1
            if stage < 3:
                c = h if stage == 2 else 0.5 * h
                for k in range(N):
                    xt[k] = x[k] + c * ks[k]
        for k in range(N):
            x[k] += h / 6.0 * (k1[k] + 2.0 * k2[k] + 2.0 * k3[k] + k4[k])
        norm = np.sqrt(x[QUATERNION] ** 2 + x[QUATERNION + 1] ** 2 + x[QUATERNION + 2] ** 2 + x[QUATERNION + 3] ** 2)
        for k in range(QUATERNION, NU):
            x[k] /= norm
        t_end = (step0 + step + 1) * h
        set_joints(motion, t_end, x)
        code = check_state(x, n, bounds)
        if code != 0:
            return step + 1, code
        n_out = record.count[0]
        if (step0 + step + 1) % every == 0 and n_out < out_t.shape[0]:
            out_t[n_out] = t_end
            for k in range(N):
                out_x[n_out, k] = x[k]
            record.count[0] = n_out + 1
    return n_steps, 0


@njit(cache=True, nogil=True)
def advance_prescribed(plant, held, motion, record, x, h, start, stop):
    """:func:`rk4_prescribed_steps` from global step ``start`` to ``stop`` (steps of ``h`` seconds) on a
    :class:`~uvms.dynamics.plant.Plant`; returns ``(done, code)`` as :func:`uvms.sim.compiled_loop.advance`."""
    k, code = rk4_prescribed_steps(plant_data(plant), held, motion, x, h, stop - start, start, record)
    return start + k, code


@njit(cache=True, nogil=True)
def motion_torques(plant, held, motion, times, states, tau):
    """``tau[r]`` (n) the torques the motion takes at ``times[r]`` in ``states[r]`` (the hybrid dynamics, with
    ``nu`` zero for a clamped vehicle); the actuators' wrench as the stage derivative sees it."""
    p = plant_data(plant)
    xdot = p.scratch.stages[5]
    n = tau.shape[1]
    for r in range(times.shape[0]):
        x = states[r]
        hold_commands(motion, times[r], held.command)
        stage_inputs(p, held, times[r], x, xdot)
        motion_at(motion, times[r])
        vecs = p.scratch.vecs
        aba_prescribed(p.body, p.work, p.scratch.R, x[POSITION:QUATERNION], vecs[3], motion.q, motion.qd, motion.qdd,
                       motion.free_torques, motion.prescribed, vecs[0], held.ee_wrench, p.fluid, times[r], p.fixed_base,
                       xdot[NU:JOINTS], motion.qdd_out, motion.tau)
        for j in range(n):
            tau[r, j] = motion.tau[j]


# ----------------------------------------------------------------------------------------- the Python side


class MotionLog:
    """What :func:`uvms.sim.record.result_of` reads of a run's updates: one update at step 0 and no signals (a
    prescribed run has no controller; its torques are computed per row, :func:`motion_torques`)."""

    def __init__(self, n: int) -> None:
        self.steps, self.torques = np.zeros(1, dtype=np.int64), np.zeros((1, n))

    def held(self, which: np.ndarray) -> dict[str, np.ndarray]:
        return {}


def command_signals(plan, times: np.ndarray) -> dict[str, np.ndarray]:
    """``{"thruster_command_<thruster>": (K,)}``: the held thruster commands at each recorded row (those in force
    over the step that starts there; the last row's, the last held), none without a command table."""
    motion = plan.motion
    if motion.command_times.shape[0] == 0:
        return {}
    h = plan.timing.h
    steps = np.floor(np.asarray(times, dtype=float) / h + 0.5) * h         # rows lie on the step grid
    k = np.clip(np.searchsorted(motion.command_times, steps + 1e-12, side="right") - 1, 0, None)
    return {f"thruster_command_{th.name}": motion.commands[k, j].copy() for j, th in enumerate(plan.thrusters)}


def row_torques(plan, times: np.ndarray, states: np.ndarray) -> np.ndarray:
    """(K, n) the torques ``plan``'s joint motion takes at each recorded row: those the loop kept
    (``Motion.row_tau``), the others by :func:`motion_torques`."""
    motion = plan.motion
    filled = min(int(motion.filled[0]), times.shape[0])
    tau = np.zeros((times.shape[0], plan.layout.n_joints))
    tau[:filled] = motion.row_tau[:filled]
    rest = tau[filled:]
    motion_torques(plan.plant, plan.held, motion, np.ascontiguousarray(times[filled:], dtype=float),
                   np.ascontiguousarray(states[filled:], dtype=float), rest)
    tau[filled:] = rest
    return tau


def prescribed_advance(plan):
    """``advance(start, stop) -> (done, code)`` of ``plan``'s compiled prescribed loop (for
    :func:`uvms.sim.chunks.run_in_chunks` and :func:`uvms.sim.batch.run_plans`)."""
    h = plan.timing.h

    def advance(start: int, stop: int):
        return advance_prescribed(plan.plant, plan.held, plan.motion, plan.samples, plan.x, h, start, stop)

    return advance


def run_prescribed(plan, chunking):
    """Advance ``plan`` (with a joint motion) to its end or divergence in calls cut by
    :func:`uvms.sim.chunks.run_in_chunks`; returns ``(outcome, log)`` as :func:`uvms.sim.compiled_loop.run_compiled`."""
    from uvms.sim.chunks import run_in_chunks

    return run_in_chunks(plan, chunking, prescribed_advance(plan)), MotionLog(plan.layout.n_joints)
