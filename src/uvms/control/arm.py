"""Arm commands: joint-space trajectories and the torques that track them.

A :class:`JointTrajectory` interpolates joint angles between knots with a cubic spline whose velocity is
zero at the first and last knot (``scipy.interpolate.CubicSpline``, ``bc_type="clamped"``); it holds the end
values outside its time range. Two trackers turn it into joint torques, each callable as
``(t, state) -> tau`` so that it plugs into ``simulate(joint_torques=...)`` (held over the control period):

- :class:`ComputedTorqueArm`: ``tau = RNEA_q(q, qd; qdd_ref)`` with
  ``qdd_ref = qdd_d + kd (qd_d - qd) + kp (q_d - q)`` and the model's recursive Newton-Euler algorithm
  (hydrodynamics included). ``base="fixed"`` computes it for a clamped vehicle (``nu = 0``, ``nu_dot = 0``),
  ``base="moving"`` with the vehicle's measured velocity ``nu`` (its acceleration is not measured: 0).
  With the plant's own model and a fixed base, the error obeys ``e_ddot + kd e_dot + kp e = 0``.
- :class:`PdArm`: ``tau = kp (q_d - q) + kd (qd_d - qd)``, no model.

Compiled side (issue 14): an :class:`ArmData` and :func:`arm_torques` give the joint torques inside a compiled
loop; kinds (:mod:`uvms.control.kinds`) ``CONSTANT`` (:func:`constant_arm`), ``SCHEDULE`` (piecewise constant,
:func:`schedule_arm`), ``COMPUTED_TORQUE`` (:meth:`ComputedTorqueArm.compiled`) and ``PD`` (:meth:`PdArm.compiled`). The
trackers' Python ``torques(time, state)`` call the same kernel. The spline is evaluated in compiled code from
scipy's own piecewise-polynomial coefficients (``CubicSpline.c``, ``.x``): on the interval
``x_i <= t < x_{i+1}`` (closed at the last knot), ``sum_k c[3-k, i] (t - x_i)^k`` and its derivatives, with the
powers accumulated as scipy accumulates them.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from uvms.control.kinds import COMPUTED_TORQUE, CONSTANT, PD, SCHEDULE
from uvms.dynamics.plant import ModelData, empty_model_data, fluid_table, inverse_into, model_data
from uvms.hydro.flow import FlowData
from uvms.errors import UvmsInputError
from uvms.jit import kernel
from uvms.kinematics import normalised_rotation
from uvms.state import JOINTS, NU, POSITION, QUATERNION

@dataclass(frozen=True, eq=False)
class JointTrajectory:
    """Joint angles ``angles[k]`` (n,) [rad] at ``times[k]`` [s], interpolated by a clamped cubic spline."""

    times: np.ndarray
    angles: np.ndarray
    _spline: Any = field(init=False, repr=False)

    def __post_init__(self) -> None:
        t = np.array(self.times, dtype=float).reshape(-1)
        q = np.array(self.angles, dtype=float)
        q = q.reshape(1, -1) if q.ndim == 1 and t.size == 1 else q
        if t.size == 0 or q.ndim != 2 or q.shape[0] != t.size:
            raise UvmsInputError(f"expected one row of joint angles per time, found {t.size} times and angles "
                                 f"of shape {np.shape(self.angles)}", path="arm.trajectory")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(q))) or np.any(np.diff(t) <= 0):
            raise UvmsInputError("expected finite angles at strictly increasing times", path="arm.trajectory")
        t.setflags(write=False)
        q.setflags(write=False)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "angles", q)
        spline = None
        if t.size > 1:
            from scipy.interpolate import CubicSpline

            spline = CubicSpline(t, q, axis=0, bc_type="clamped")
        object.__setattr__(self, "_spline", spline)

    @property
    def n_joints(self) -> int:
        return int(self.angles.shape[1])

    def __call__(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Desired ``(q_d, qd_d, qdd_d)`` at time ``t`` [rad, rad/s, rad/s^2] (the compiled
        :func:`desired_motion`)."""
        n = self.n_joints
        out = np.zeros((3, n))
        breaks, coefficients = self.pieces()
        desired_motion(self.times, self.angles, breaks, coefficients, float(t), out[0], out[1], out[2])
        return out[0], out[1], out[2]

    def pieces(self) -> tuple[np.ndarray, np.ndarray]:
        """scipy's piecewise-polynomial breakpoints (K,) and coefficients (4, K - 1, n) of the spline
        (one knot: empty)."""
        if self._spline is None:
            return np.zeros(0), np.zeros((4, 0, self.n_joints))
        return (np.ascontiguousarray(self._spline.x, dtype=float),
                np.ascontiguousarray(self._spline.c, dtype=float))


def _gains(value, n: int, name: str) -> np.ndarray:
    g = np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()
    if not np.all(np.isfinite(g)) or np.any(g < 0):
        raise UvmsInputError(f"expected non-negative gains (one, or one per joint), found {value!r}", path=name)
    return g


class ComputedTorqueArm:
    """Computed-torque tracking of a :class:`JointTrajectory` with the model's Newton-Euler equations.

    Args:
        model: the model whose RNEA is used (the plant's for perfect feedback linearization).
        trajectory: the desired joint motion.
        kp, kd: per-joint gains [1/s^2, 1/s] (default ``omega = 10`` rad/s, critically damped: 100, 20).
        base: ``"fixed"`` (vehicle assumed clamped) or ``"moving"`` (measured vehicle velocity included).
        period: update period [s] of the command when used with ``simulate``.
    """

    def __init__(self, model, trajectory: JointTrajectory, *, kp=100.0, kd=20.0, base: str = "fixed",
                 period: float = 0.01) -> None:
        n = model.n_joints
        if trajectory.n_joints != n:
            raise UvmsInputError(f"expected {n} joint angles per knot, found {trajectory.n_joints}",
                                 path="arm.trajectory")
        if base not in ("fixed", "moving"):
            raise UvmsInputError(f"expected fixed or moving, found {base!r}", path="arm.base")
        self.model, self.trajectory, self.base, self.period = model, trajectory, base, float(period)
        self.kp, self.kd = _gains(kp, n, "arm.kp"), _gains(kd, n, "arm.kd")
        self._data: ArmData | None = None

    def compiled(self) -> ArmData:
        """A fresh :class:`ArmData` (kind ``COMPUTED_TORQUE``) with its own model data."""
        return _tracker_data(COMPUTED_TORQUE, self.trajectory, self.kp, self.kd, model=self.model,
                             moving_base=self.base == "moving")

    def torques(self, time: float, state) -> np.ndarray:
        """Joint torques (n,) [N m] at ``time`` for the measured ``state`` (:func:`arm_torques`)."""
        if self._data is None:
            self._data = self.compiled()
        return _python_torques(self._data, time, state)

    __call__ = torques


class PdArm:
    """Joint-space PD tracking of a :class:`JointTrajectory`: ``tau = kp (q_d - q) + kd (qd_d - qd)``.

    ``kp`` [N m/rad] and ``kd`` [N m s/rad], one value or one per joint (defaults 25 and 5).
    """

    def __init__(self, trajectory: JointTrajectory, *, kp=25.0, kd=5.0, period: float = 0.01) -> None:
        n = trajectory.n_joints
        self.trajectory, self.period = trajectory, float(period)
        self.kp, self.kd = _gains(kp, n, "arm.kp"), _gains(kd, n, "arm.kd")
        self._data: ArmData | None = None

    def compiled(self) -> ArmData:
        """A fresh :class:`ArmData` (kind ``PD``)."""
        return _tracker_data(PD, self.trajectory, self.kp, self.kd)

    def torques(self, time: float, state) -> np.ndarray:
        """Joint torques (n,) [N m] at ``time`` for the measured ``state`` (:func:`arm_torques`)."""
        if self._data is None:
            self._data = self.compiled()
        return _python_torques(self._data, time, state)

    __call__ = torques


# ------------------------------------------------------------------------------------------ compiled


class ArmData(NamedTuple):
    """A compiled joint-torque source (numba type shared by every kind)."""

    kind: int                   # CONSTANT, SCHEDULE, COMPUTED_TORQUE, PD (uvms.control.kinds)
    n_joints: int
    constant: np.ndarray        # (n,) CONSTANT torques [N m]
    times: np.ndarray           # (K,) SCHEDULE: row k from times[k]; trackers: the knot times
    rows: np.ndarray            # (K, n) SCHEDULE: torques; trackers: the knot angles
    half_step: float            # SCHEDULE: evaluated at (t + half_step) + 1e-12 (breakpoints snap to the grid)
    breaks: np.ndarray          # (P + 1,) spline breakpoints (scipy's x)
    coefficients: np.ndarray    # (4, P, n) spline coefficients (scipy's c, highest power first)
    kp: np.ndarray              # (n,)
    kd: np.ndarray              # (n,)
    moving_base: bool           # COMPUTED_TORQUE: the measured nu enters the RNEA (else nu = 0)
    model: ModelData            # COMPUTED_TORQUE: the model of the RNEA; a dummy otherwise
    flow: FlowData              # that model's water: its uniform current and fluid acceleration
    desired: np.ndarray         # (3, n) scratch: q_d, qd_d, qdd_d
    qdd_ref: np.ndarray         # (n,) scratch
    R: np.ndarray               # (3, 3) scratch
    nu: np.ndarray              # (6,) scratch
    f0: np.ndarray              # (6,) scratch
    zero6: np.ndarray           # (6,)


def _arm_data(kind: int, n: int, **fields) -> ArmData:
    data = dict(kind=kind, n_joints=n, constant=np.zeros(n), times=np.zeros(1), rows=np.zeros((1, n)),
                half_step=0.0, breaks=np.zeros(0), coefficients=np.zeros((4, 0, n)), kp=np.zeros(n), kd=np.zeros(n),
                moving_base=False, model=None, flow=None,
                desired=np.zeros((3, n)), qdd_ref=np.zeros(n), R=np.zeros((3, 3)), nu=np.zeros(6), f0=np.zeros(6),
                zero6=np.zeros(6))
    data.update(fields)
    if data["model"] is None:
        data["model"] = empty_model_data()
    if data["flow"] is None:
        data["flow"] = fluid_table([0.0], [np.zeros(3)], [np.zeros(3)])
    return ArmData(**data)


def constant_arm(tau) -> ArmData:
    """Constant joint torques ``tau`` (n,) [N m] (kind ``CONSTANT``; zeros: no torques)."""
    tau = np.array(tau, dtype=float).reshape(-1)
    return _arm_data(CONSTANT, tau.size, constant=tau)


def schedule_arm(schedule, step: float) -> ArmData:
    """A :class:`~uvms.sim.inputs.TorqueSchedule` sampled as ``simulate`` samples it, ``schedule(t + 0.5 step)``
    (kind ``SCHEDULE``): row ``k`` in force from ``times[k] - 0.5 step - 1e-12`` on."""
    times = np.array(schedule.times, dtype=float)
    rows = np.array(schedule.torques, dtype=float).reshape(times.size, -1)
    return _arm_data(SCHEDULE, rows.shape[1], times=times, rows=rows, half_step=0.5 * float(step))


def _tracker_data(kind, trajectory: JointTrajectory, kp, kd, *, model=None, moving_base=False) -> ArmData:
    breaks, coefficients = trajectory.pieces()
    fields = dict(times=np.array(trajectory.times, dtype=float), rows=np.array(trajectory.angles, dtype=float),
                  breaks=breaks, coefficients=coefficients, kp=np.array(kp, dtype=float),
                  kd=np.array(kd, dtype=float), moving_base=bool(moving_base))
    if model is not None:
        fields.update(model=model_data(model), flow=fluid_table([0.0], [model.current], [model.fluid_acceleration]))
    return _arm_data(kind, trajectory.n_joints, **fields)


def _python_torques(data: ArmData, time: float, state) -> np.ndarray:
    x = np.concatenate([state.position, state.quaternion, state.nu, state.q, state.qd]).astype(float)
    tau = np.zeros(data.n_joints)
    arm_torques(data, float(time), x, tau)
    return tau


@kernel
def _interval(breaks, t):
    """``i`` with ``breaks[i] <= t < breaks[i + 1]``, the last interval closed on the right."""
    last = breaks.shape[0] - 2
    if t >= breaks[last + 1]:
        return last
    lo, hi = 0, last
    while lo < hi:
        mid = (lo + hi + 1) // 2
        if breaks[mid] <= t:
            lo = mid
        else:
            hi = mid - 1
    return lo


@kernel
def _piece(coefficients, i, j, s, order):
    """Derivative ``order`` (0, 1, 2) of ``sum_k c[K-1-k] s^k`` on piece ``i`` for joint ``j``, the power of
    ``s`` raised term by term (the arithmetic of scipy's piecewise-polynomial evaluation)."""
    K = coefficients.shape[0]
    value = 0.0
    power = 1.0
    for k in range(K):
        if k >= order:
            factor = 1.0
            for f in range(k, k - order, -1):
                factor *= f
            value = value + coefficients[K - 1 - k, i, j] * power * factor
            if k < K - 1:
                power *= s
    return value


@kernel
def desired_motion(times, angles, breaks, coefficients, t, q_d, qd_d, qdd_d):
    """The clamped cubic spline's ``(q_d, qd_d, qdd_d)`` at ``t``: the end angles at rest outside
    ``(times[0], times[-1])`` and for a single knot (:class:`JointTrajectory`)."""
    n = angles.shape[1]
    if breaks.shape[0] == 0 or t <= times[0] or t >= times[times.shape[0] - 1]:
        row = 0 if breaks.shape[0] == 0 or t <= times[0] else times.shape[0] - 1
        for j in range(n):
            q_d[j] = angles[row, j]
            qd_d[j] = 0.0
            qdd_d[j] = 0.0
        return
    i = _interval(breaks, t)
    s = t - breaks[i]
    for j in range(n):
        q_d[j] = _piece(coefficients, i, j, s, 0)
        qd_d[j] = _piece(coefficients, i, j, s, 1)
        qdd_d[j] = _piece(coefficients, i, j, s, 2)


@kernel
def arm_torques(arm, t, x, tau):
    """The joint torques ``tau`` (n,) [N m] at time ``t`` [s] for the state vector ``x``
    (:mod:`uvms.state` layout)::

        CONSTANT         tau = constant
        SCHEDULE         tau = rows[k], k the last row with times[k] <= (t + half_step) + 1e-12
        PD               tau = kp (q_d - q) + kd (qd_d - qd)
        COMPUTED_TORQUE  tau = RNEA_q(q, qd; qdd_d + kd (qd_d - qd) + kp (q_d - q)), nu = 0 unless moving_base
    """
    n = arm.n_joints
    if arm.kind == CONSTANT:
        for j in range(n):
            tau[j] = arm.constant[j]
        return
    if arm.kind == SCHEDULE:
        at = (t + arm.half_step) + 1e-12
        k = 0
        for r in range(1, arm.times.shape[0]):
            if arm.times[r] <= at:
                k = r
        for j in range(n):
            tau[j] = arm.rows[k, j]
        return
    q = x[JOINTS:JOINTS + n]
    qd = x[JOINTS + n:JOINTS + 2 * n]
    desired_motion(arm.times, arm.rows, arm.breaks, arm.coefficients, t, arm.desired[0], arm.desired[1],
                   arm.desired[2])
    q_d, qd_d, qdd_d = arm.desired[0], arm.desired[1], arm.desired[2]
    if arm.kind == PD:
        for j in range(n):
            tau[j] = arm.kp[j] * (q_d[j] - q[j]) + arm.kd[j] * (qd_d[j] - qd[j])
        return
    for j in range(n):
        arm.qdd_ref[j] = qdd_d[j] + arm.kd[j] * (qd_d[j] - qd[j]) + arm.kp[j] * (q_d[j] - q[j])
    for j in range(6):
        arm.nu[j] = x[NU + j] if arm.moving_base else 0.0
    normalised_rotation(x[QUATERNION:NU], arm.R)
    inverse_into(arm.model, arm.R, x[POSITION:QUATERNION], arm.nu, q, qd, arm.zero6, arm.qdd_ref, arm.zero6, arm.flow,
                 0.0, arm.f0, tau)
