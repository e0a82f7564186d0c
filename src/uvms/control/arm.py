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
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.rnea import rnea
from uvms.errors import UvmsInputError


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
        """Desired ``(q_d, qd_d, qdd_d)`` at time ``t`` [rad, rad/s, rad/s^2]."""
        if self._spline is None or t <= self.times[0] or t >= self.times[-1]:
            q = self.angles[0] if self._spline is None or t <= self.times[0] else self.angles[-1]
            return q.copy(), np.zeros(self.n_joints), np.zeros(self.n_joints)
        return self._spline(t), self._spline(t, 1), self._spline(t, 2)


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
        self._ws = make_workspace(model.n_bodies)
        self._zero6 = np.zeros(6)
        self._f0 = np.zeros(6)
        self._tau = np.zeros(n)
        self._current = np.array(model.current, dtype=float)
        self._fluid_acceleration = np.array(model.fluid_acceleration, dtype=float)

    def torques(self, time: float, state) -> np.ndarray:
        """Joint torques (n,) [N m] at ``time`` for the measured ``state``."""
        q_d, qd_d, qdd_d = self.trajectory(time)
        q, qd = np.array(state.q, dtype=float), np.array(state.qd, dtype=float)
        qdd_ref = qdd_d + self.kd * (qd_d - qd) + self.kp * (q_d - q)
        nu = np.array(state.nu, dtype=float) if self.base == "moving" else self._zero6
        rnea(self.model.kernel, self._ws, state.rotation, nu, q, qd, self._zero6, qdd_ref, self._zero6,
             self._current, self._fluid_acceleration, self._f0, self._tau)
        return self._tau.copy()

    __call__ = torques


class PdArm:
    """Joint-space PD tracking of a :class:`JointTrajectory`: ``tau = kp (q_d - q) + kd (qd_d - qd)``.

    ``kp`` [N m/rad] and ``kd`` [N m s/rad], one value or one per joint (defaults 25 and 5).
    """

    def __init__(self, trajectory: JointTrajectory, *, kp=25.0, kd=5.0, period: float = 0.01) -> None:
        n = trajectory.n_joints
        self.trajectory, self.period = trajectory, float(period)
        self.kp, self.kd = _gains(kp, n, "arm.kp"), _gains(kd, n, "arm.kd")

    def torques(self, time: float, state) -> np.ndarray:
        """Joint torques (n,) [N m] at ``time`` for the measured ``state``."""
        q_d, qd_d, _ = self.trajectory(time)
        return self.kp * (q_d - np.asarray(state.q)) + self.kd * (qd_d - np.asarray(state.qd))

    __call__ = torques
