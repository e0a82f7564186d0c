"""The bundled vehicle controllers compiled: one data type, one update kernel (issue 14).

A :class:`ControllerData` holds everything one controller needs between updates -- its parameters per axis,
its own model (:class:`uvms.dynamics.plant.ModelData`), its memory (captured set point, PID integrators, the
IMU's delay line and pre-drawn noise, the update counter) and its scratch -- and :func:`controller_update`
runs one update on the simulation's state vector ``x`` (layout of :mod:`uvms.state`:
``[p(3) | quat(4) | nu(6) | q(n) | qd(n) | actuator states]``). The numba type of a ``ControllerData`` is the
same for every kind (unused fields hold small dummy arrays), so a compiled loop calling it compiles once.
Every function here is a kernel (:mod:`uvms.jit`: no reference counting, no allocation; the two
matrix inverses are in-place Cholesky solves into the named scratch ``L`` and ``column``), so an update costs
about its own arithmetic (1.8 us for ``smc-ab`` on the paper model, of which 1.3 us are its ABA).

Controller kinds (``NONE``, ``SLIDING``, ``PID``) and, for the sliding-mode law, its model of the vehicle's
acceleration (``predictor``: ``AB``, ``VEHICLE``, ``NE``) are numbered in :mod:`uvms.control.kinds`.

The equations (errors, surfaces, Slotine's law, the PID's anti-windup, the IMU) are derived in
:mod:`uvms.control.smc`, :mod:`uvms.control.sliding_kernels`, :mod:`uvms.control.pid`, :mod:`uvms.control.smc_ne`
and :mod:`uvms.sensors.body_acceleration`; the controllers' Python classes build the data (``compiled(n_updates)``) and
their ``update(measurement)`` calls :func:`controller_update`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from uvms.control import sliding_kernels as sk
from uvms.sensors.body_acceleration import ImuData, ImuParameters, imu_data, imu_measure
from uvms.control.kinds import AB, NE, NONE, SLIDING
from uvms.dynamics.blocks import cholesky_factor, cholesky_solve
from uvms.dynamics.plant import ModelData, empty_model_data, fluid_table, forward_into, inverse_into, mass_matrix_into
from uvms.hydro.flow import FlowData
from uvms.jit import block, kernel
from uvms.kinematics import normalised_rotation
from uvms.rotations import euler_zyx
from uvms.state import JOINTS, NU, POSITION, QUATERNION

# columns of ControllerData.gains (one row per axis slot, uvms.control.sliding_kernels.SURGE ... YAW)
BANDWIDTH, ETA, PHI, UNCERTAINTY, B_HAT, BETA, B_MODEL, KP, KI, KD, LIMIT = range(11)
N_GAINS = 11

# ControllerData.memory (int64)
COUNT, N_MEMORY = 0, 1


class ControllerData(NamedTuple):
    """One compiled controller: parameters, own model, memory and scratch (numba type shared by every kind).

    Axis slots (rows of ``gains``, columns of ``kin``): surge, sway, heave, roll, pitch, yaw
    (:mod:`uvms.control.sliding_kernels`); ``axes`` lists the controlled ones in logging order.
    """

    kind: int                   # NONE, SLIDING, PID (uvms.control.kinds)
    predictor: int              # AB, VEHICLE, NE (sliding mode; uvms.control.kinds)
    needs_acceleration: bool    # True only for NE with the IMU in "acceleration" mode
    n_joints: int
    period: float               # [s]
    body_velocity: bool         # surface s = vel + lambda e with vel the body velocity (else the error rates)
    b_from_model: bool          # b_hat from the controller model's inertia (else gains[:, B_HAT])
    beta_model: float           # beta with b_from_model
    log_b_hat: bool             # the signals include b_hat per axis
    axes: np.ndarray            # (k,) int64 axis slots, in logging order
    gains: np.ndarray           # (6, N_GAINS) per axis slot: lambda, eta, Phi, F, b_hat, beta, b from the model
                                #   (1.0) or b_hat/beta (0.0), kp, ki, kd, limit
    targets: np.ndarray         # (K, 7) waypoints [t_from, x, y, z, roll, pitch, yaw]; NaN: taken at the first update
    captured: np.ndarray        # (6,) pose at the first update (x, y, z, roll, pitch, yaw)
    desired: np.ndarray         # (6,) the set point of the last update
    memory: np.ndarray          # (N_MEMORY,) int64: update counter
    integral: np.ndarray        # (6,) PID integrators per axis slot
    system: ModelData           # controller model of the whole system (AB, NE); a dummy otherwise
    vehicle: ModelData          # controller model of the vehicle alone (VEHICLE, NE); a dummy otherwise
    flow: FlowData              # the controller model's water: a uniform current (``current``,
                                #   ``fluid_acceleration`` options of controller_data), or the run's own water
                                #   (``flow`` option: smc-ab's wave feed-forward), read at the update's time
    imu: ImuData                # the simulated IMU (NE; a noise-free placeholder otherwise)
    R: np.ndarray               # (3, 3) scratch: body-to-world rotation
    kin: np.ndarray             # (N_KIN_ROWS, 6) scratch: axis kinematics
    nu_dot: np.ndarray          # (6,) scratch: predicted nu_dot
    f_hat: np.ndarray           # (6,) scratch
    b_hat: np.ndarray           # (6,) scratch
    beta: np.ndarray            # (6,) scratch
    qdd: np.ndarray             # (n,) scratch
    tau_scratch: np.ndarray     # (n,) scratch
    M: np.ndarray               # (6 + n, 6 + n) scratch (NE)
    L: np.ndarray               # (6 + n, 6 + n) scratch: Cholesky factors (b from the model, NE)
    column: np.ndarray          # (6 + n,) scratch: right-hand sides and solutions
    inverse_diagonal: np.ndarray  # (6,) scratch: the diagonal of the controller model's inverse inertia
    f_system: np.ndarray        # (6,) scratch (NE)
    f_vehicle: np.ndarray       # (6,) scratch (NE)
    zero6: np.ndarray           # (6,) zeros
    empty: np.ndarray           # (0,)
    signals: np.ndarray         # (S,) the last update's logged values (names: the class's signal_names)


# ------------------------------------------------------------------------------------------- building


def _state_scratch(n: int) -> dict:
    return dict(R=np.zeros((3, 3)), kin=np.zeros((sk.N_KIN_ROWS, 6)), nu_dot=np.zeros(6), f_hat=np.zeros(6),
                b_hat=np.zeros(6), beta=np.zeros(6), qdd=np.zeros(n), tau_scratch=np.zeros(n),
                M=np.zeros((6 + n, 6 + n)), L=np.zeros((6 + n, 6 + n)), column=np.zeros(6 + n),
                inverse_diagonal=np.zeros(6), f_system=np.zeros(6), f_vehicle=np.zeros(6), zero6=np.zeros(6),
                empty=np.zeros(0))


def targets_table(desired_position, desired_attitude, waypoints=None) -> np.ndarray:
    """The (K, 7) waypoint table ``[t_from, x, y, z, roll, pitch, yaw]``: row 0 from ``desired_position``
    (3 or ``None``) and ``desired_attitude`` (3 values or ``None`` each; ``None``: the value at the first
    update), then ``waypoints`` rows (already checked)."""
    row = np.full(7, np.nan)
    row[0] = 0.0
    if desired_position is not None:
        row[1:4] = desired_position
    for j, value in enumerate(desired_attitude):
        if value is not None:
            row[4 + j] = value
    rows = [row] + [np.asarray(w, dtype=float) for w in (waypoints or ())]
    return np.array(rows, dtype=float).reshape(len(rows), 7)


def controller_data(*, kind: int, n_joints: int, period: float, axes, gains: np.ndarray, targets: np.ndarray,
                    n_signals: int, **options) -> ControllerData:
    """A fresh :class:`ControllerData` (memory reset). ``options`` set any other field (models, IMU, flags);
    the rest take neutral defaults."""
    n = int(n_joints)
    data = dict(kind=int(kind), predictor=AB, needs_acceleration=False, n_joints=n, period=float(period),
                body_velocity=True, b_from_model=False, beta_model=1.0, log_b_hat=False,
                axes=np.array(axes, dtype=np.int64), gains=np.array(gains, dtype=float).reshape(6, N_GAINS),
                targets=np.array(targets, dtype=float).reshape(-1, 7), captured=np.zeros(6), desired=np.zeros(6),
                memory=np.zeros(N_MEMORY, dtype=np.int64), integral=np.zeros(6), system=None, vehicle=None,
                imu=imu_data(ImuParameters(), float(period), 0), signals=np.zeros(n_signals), **_state_scratch(n))
    current = options.pop("current", np.zeros(3))
    fluid_acceleration = options.pop("fluid_acceleration", np.zeros(3))
    flow = options.pop("flow", None)          # a FlowData: the water itself (then current, fluid_acceleration unused)
    for key, value in options.items():
        if key not in data:
            raise TypeError(f"unknown ControllerData field {key!r}")
        data[key] = value
    for key in ("system", "vehicle"):
        if data[key] is None:
            data[key] = empty_model_data()
    data["flow"] = flow if flow is not None else fluid_table([0.0], [current], [fluid_acceleration])
    return ControllerData(**data)


def no_controller() -> ControllerData:
    """The placeholder of a run without a compiled controller (kind ``NONE``; never updated)."""
    return controller_data(kind=NONE, n_joints=0, period=1.0, axes=np.zeros(0, dtype=np.int64),
                           gains=np.zeros((6, N_GAINS)), targets=np.zeros((1, 7)), n_signals=0)


# ------------------------------------------------------------------------------------------ the kernels


@block
def _set_point(ctrl, t, x):
    """The first update captures the pose; the set point is the last waypoint whose time has come, its NaN
    entries replaced by the captured pose."""
    count = ctrl.memory[COUNT]
    if count == 0:
        for j in range(3):
            ctrl.captured[j] = x[POSITION + j]
        normalised_rotation(x[QUATERNION:NU], ctrl.R)       # the arithmetic of State.euler
        phi, theta, psi = euler_zyx(ctrl.R)
        ctrl.captured[3] = phi
        ctrl.captured[4] = theta
        ctrl.captured[5] = psi
    row = 0
    for k in range(1, ctrl.targets.shape[0]):
        if ctrl.targets[k, 0] <= t:
            row = k
    for j in range(6):
        value = ctrl.targets[row, 1 + j]
        ctrl.desired[j] = ctrl.captured[j] if math.isnan(value) else value


@block
def arm_reaction(ctrl, x, tau, a0, out):
    """The wrench (6,) the arm exerts on the vehicle moving with ``nu`` and ``a0`` (:mod:`uvms.control.smc_ne`)::

        qdd = M_qq^-1 (tau - RNEA_q(a0, 0));   out = RNEA_0(vehicle; a0) - RNEA_0(system; a0, qdd)
    """
    n = ctrl.n_joints
    nu = x[NU:JOINTS]
    q = x[JOINTS:JOINTS + n]
    qd = x[JOINTS + n:JOINTS + 2 * n]
    p = x[POSITION:QUATERNION]
    flow, zero6 = ctrl.flow, ctrl.zero6
    for i in range(n):
        ctrl.qdd[i] = 0.0
    inverse_into(ctrl.system, ctrl.R, p, nu, q, qd, a0, ctrl.qdd, zero6, flow, 0.0, ctrl.f_system, ctrl.tau_scratch)
    if n > 0:
        mass_matrix_into(ctrl.system, q, ctrl.M)
        for i in range(n):
            ctrl.qdd[i] = tau[i] - ctrl.tau_scratch[i]
        L = ctrl.L[:n, :n]
        cholesky_factor(ctrl.M[6:, 6:], L)
        cholesky_solve(L, ctrl.qdd, ctrl.qdd)
    inverse_into(ctrl.system, ctrl.R, p, nu, q, qd, a0, ctrl.qdd, zero6, flow, 0.0, ctrl.f_system, ctrl.tau_scratch)
    inverse_into(ctrl.vehicle, ctrl.R, p, nu, ctrl.empty, ctrl.empty, a0, ctrl.empty, zero6, flow, 0.0,
                 ctrl.f_vehicle, ctrl.empty)
    for j in range(6):
        out[j] = ctrl.f_vehicle[j] - ctrl.f_system[j]


@block
def _predict(ctrl, t, x, tau, nu_dot_true):
    """The controller model's ``nu_dot`` at ``f_0 = 0`` into ``ctrl.nu_dot``; returns the 6x6 inertia mapping
    a body wrench to ``nu_dot`` in that model (for ``b_source = "model"``). ``AB`` reads its water at the
    update's time ``t`` (a one-row table, the default, is the same at every time)."""
    n = ctrl.n_joints
    nu = x[NU:JOINTS]
    if ctrl.predictor == AB:
        forward_into(ctrl.system, ctrl.R, x[POSITION:QUATERNION], nu, x[JOINTS:JOINTS + n],
                     x[JOINTS + n:JOINTS + 2 * n], tau, ctrl.zero6, ctrl.zero6, ctrl.flow, t, False, ctrl.nu_dot,
                     ctrl.qdd)
        return ctrl.system.work.IA[0]
    wrench = ctrl.zero6
    if ctrl.predictor == NE:
        imu_measure(ctrl.imu, nu, nu_dot_true)
        wrench = ctrl.f_hat                       # scratch for the arm's reaction (f_hat is written later)
        arm_reaction(ctrl, x, tau, ctrl.imu.out, wrench)
    forward_into(ctrl.vehicle, ctrl.R, x[POSITION:QUATERNION], nu, ctrl.empty, ctrl.empty, ctrl.empty, wrench,
                 ctrl.zero6, ctrl.flow, 0.0, False, ctrl.nu_dot, ctrl.empty)
    return ctrl.vehicle.body.inertia_h[0]


@block
def _inverse_diagonal(A, L, column, out):
    """``out[j] = (A^-1)_jj`` for a symmetric positive-definite 6x6 ``A`` (``L``, ``column``: scratch):
    ``A^-1 e_j`` by Cholesky, one column at a time."""
    cholesky_factor(A, L)
    for j in range(6):
        for i in range(6):
            column[i] = 1.0 if i == j else 0.0
        cholesky_solve(L, column, column)
        out[j] = column[j]


@block
def _sliding_mode(ctrl, t, x, tau, nu_dot_true, wrench):
    inertia = _predict(ctrl, t, x, tau, nu_dot_true)
    need_model = ctrl.b_from_model
    for a in ctrl.axes:
        if ctrl.gains[a, B_MODEL] > 0.0:
            need_model = True
    if need_model:
        _inverse_diagonal(inertia, ctrl.L[:6, :6], ctrl.column[:6], ctrl.inverse_diagonal)
    for a in range(6):
        if ctrl.b_from_model or ctrl.gains[a, B_MODEL] > 0.0:
            ctrl.b_hat[a] = 1.0 / ctrl.inverse_diagonal[sk.WRENCH_INDEX[a]]       # 1 / (I^-1)_jj
            ctrl.beta[a] = ctrl.beta_model
        else:
            ctrl.b_hat[a] = ctrl.gains[a, B_HAT]
            ctrl.beta[a] = ctrl.gains[a, BETA]
    sk.surface_accelerations(ctrl.kin, ctrl.nu_dot, ctrl.body_velocity, ctrl.f_hat)
    signals = ctrl.signals
    i = 0
    for a in ctrl.axes:
        g = ctrl.gains[a]
        rate = ctrl.kin[sk.VELOCITY, a] if ctrl.body_velocity else ctrl.kin[sk.ERROR_RATE, a]
        s, k, _, command = sk.slotine(ctrl.kin[sk.ERROR, a], rate, ctrl.f_hat[a], g[BANDWIDTH], g[ETA], g[PHI],
                                      g[UNCERTAINTY], ctrl.b_hat[a], ctrl.beta[a], 0.0, 0.0,
                                      ctrl.kin[sk.ERROR_RATE, a])
        force = command / sk.surface_input_gain(ctrl.kin, ctrl.body_velocity, a)
        wrench[sk.WRENCH_INDEX[a]] = force
        signals[i] = s
        signals[i + 1] = k
        signals[i + 2] = ctrl.f_hat[a]
        signals[i + 3] = force
        signals[i + 4] = ctrl.kin[sk.ERROR, a]
        i += 5
        if ctrl.log_b_hat:
            signals[i] = ctrl.b_hat[a]
            i += 1
    signals[i] = ctrl.gains[ctrl.axes[0], PHI] if ctrl.axes.size else 0.0
    i += 1
    if ctrl.predictor == NE:
        for a in ctrl.axes:
            signals[i] = ctrl.imu.out[sk.WRENCH_INDEX[a]]
            i += 1


@kernel
def _sign(value):
    return 1.0 if value > 0.0 else (-1.0 if value < 0.0 else 0.0)


@block
def _pid(ctrl, wrench):
    """``f = -(kp e + ki z + kd e_dot)`` clipped to the limit, clamping anti-windup (:mod:`uvms.control.pid`)."""
    i = 0
    for a in ctrl.axes:
        g = ctrl.gains[a]
        kp, ki, kd, limit = g[KP], g[KI], g[KD], g[LIMIT]
        e = ctrl.kin[sk.ERROR, a]
        e_dot = ctrl.kin[sk.ERROR_RATE, a]
        z = ctrl.integral[a]
        unclamped = -(kp * e + ki * z + kd * e_dot)
        saturated = abs(unclamped) >= limit
        pushing = _sign(unclamped) == -_sign(e)          # integrating e moves the output that way
        if not (saturated and pushing):
            z = z + e * ctrl.period
        cap = limit / ki if ki > 0 else np.inf
        z = min(max(z, -cap), cap)
        ctrl.integral[a] = z
        force = min(max(-(kp * e + ki * z + kd * e_dot), -limit), limit)
        wrench[sk.WRENCH_INDEX[a]] = force
        ctrl.signals[i] = e
        ctrl.signals[i + 1] = z
        ctrl.signals[i + 2] = force
        i += 3


@kernel
def controller_update(ctrl, t, x, tau, nu_dot_true, wrench):
    """One update at time ``t`` [s] for the state vector ``x`` and the joint torques ``tau`` (n,) about to be
    applied (``nu_dot_true`` (6,), the true body acceleration, is read only if ``ctrl.needs_acceleration``):
    writes the body wrench ``wrench`` (6,) ``[K M N X Y Z]`` and ``ctrl.signals``, advances the memory."""
    for j in range(6):
        wrench[j] = 0.0
    if ctrl.kind == NONE:
        return
    _set_point(ctrl, t, x)
    sk.pose_kinematics_into(x[QUATERNION:NU], x[POSITION:QUATERNION], x[NU:JOINTS], ctrl.desired, ctrl.R, ctrl.kin)
    if ctrl.kind == SLIDING:
        _sliding_mode(ctrl, t, x, tau, nu_dot_true, wrench)
    else:
        _pid(ctrl, wrench)
    ctrl.memory[COUNT] += 1
