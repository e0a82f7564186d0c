"""``lqr``: a linear-quadratic station keeper designed from :func:`uvms.linearize` about the hold state.

Design (at the first update, when the arm's pose and torques are known; :meth:`LqrController.design`):

1. Hold state: position ``p_d``, attitude ``R_d`` (ZYX Euler ``(roll_d, pitch_d, yaw_d)``), at rest, joints at
   the measured ``q`` with ``qd = 0``; the measured joint torques held.
2. ``linearize`` about it (the controller's model: the plant's, its current included), vehicle rows and columns
   only: the arm is free (the articulated inertia, as in ``uvms validate``'s effective inertia) and its joint
   coordinates' coupling is left out of the design. Position errors are taken in the hold attitude's axes,
   ``e_p = R_d^T (p - p_d)``, attitude errors as the rotation vector ``e_R = Log(R_d^T R)`` (body axes), so that
   the axes surge, sway, heave, roll, pitch, yaw are ``e = [e_p; e_R]`` and ``nu = [omega; v]`` component by
   component (``docs/conventions.md``, "Linearisation").
3. The chosen ``axes`` (default all six): states ``[e_axes; nu_axes]``, inputs the wrench components of those axes.
   Weights by Bryson's rule (1 / the square of the largest acceptable value), diagonal::

       Q = diag(q_pose[axes], q_velocity[axes])      R = diag(r_wrench[axes])

   defaults: 0.05 m and 0.05 rad of pose error (400), 0.2 m/s and 0.2 rad/s (25), 50 N and 10 N m of wrench
   (4e-4, 1e-2).
4. ``K`` from the discrete algebraic Riccati equation of the zero-order-hold model at the controller's period
   (``design = "discrete"``, default; ``K = (R + Bd^T P Bd)^-1 Bd^T P Ad``) or the continuous one
   (``"continuous"``: ``K = R^-1 B^T P``), :func:`scipy.linalg.solve_discrete_are` / ``solve_continuous_are``.
5. Feedforward (``feedforward = true``): the wrench ``u_ff = -B_v^-1 nu_dot_0`` that holds the design state
   (``nu_dot_0``: the vehicle's acceleration there without thrust: weight, buoyancy, the arm, the model's
   current; ``B_v``: the vehicle block of ``B``), on the controlled axes.

Update: ``wrench[axes] = clip(u_ff - K [e; nu; z], +/- limit)``, the other components zero. Without integrators
(``q_integral = 0``, default) a constant disturbance the model does not know (an unknown current) leaves the
steady offset ``(I - Ad + Bd K)^-1 Bd w`` of the linear model. With ``q_integral > 0`` on an axis, that axis'
pose error is integrated, ``z_{k+1} = z_k + T e_k`` (``T`` the period; not while that axis' command is clipped:
anti-windup by conditional integration), and ``z`` joins the design's states (``Ad`` augmented with the same
sum, ``A`` with ``z_dot = e``): the offset goes to zero. Logs ``e_<axis>``, ``command_<axis>`` (and
``integral_<axis>``) per controlled axis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from uvms.control.base import ControlOutput, Measurement
from uvms.control.registry import choice, non_negative, optional, parameter, positive, register, vector
from uvms.errors import UvmsInputError

AXES: tuple[str, ...] = ("surge", "sway", "heave", "roll", "pitch", "yaw")
"""Axes the controller can hold, in the order of every per-axis parameter."""
POSE_INDEX: tuple[int, ...] = (0, 1, 2, 3, 4, 5)
"""Index of each axis in the pose error ``[e_p; e_R]``."""
VELOCITY_INDEX: tuple[int, ...] = (3, 4, 5, 0, 1, 2)
"""Index of each axis in ``nu = [omega; v]`` (and of its wrench component in ``[K M N X Y Z]``)."""

DEFAULT_Q_POSE = (400.0,) * 6
"""Bryson's rule for 0.05 m and 0.05 rad of pose error: 1 / 0.05^2 [1/m^2, 1/rad^2]."""
DEFAULT_Q_VELOCITY = (25.0,) * 6
"""Bryson's rule for 0.2 m/s and 0.2 rad/s: 1 / 0.2^2 [s^2/m^2, s^2/rad^2]."""
DEFAULT_R_WRENCH = (4e-4, 4e-4, 4e-4, 1e-2, 1e-2, 1e-2)
"""Bryson's rule for 50 N of force and 10 N m of moment: 1 / 50^2 [1/N^2], 1 / 10^2 [1/(N m)^2]."""


def axes_list(value) -> tuple[str, ...]:
    """A non-empty list of distinct axis names of :data:`AXES` (``ValueError`` otherwise)."""
    if isinstance(value, str) or not isinstance(value, (list, tuple)) or not value:
        raise ValueError(f"expected a non-empty list of axes from {', '.join(AXES)}, found {value!r}")
    for name in value:
        if name not in AXES:
            raise ValueError(f"unknown axis {name!r}; expected names from {', '.join(AXES)}")
    if len(set(value)) != len(value):
        twice = next(a for a in value if list(value).count(a) > 1)
        raise ValueError(f"axis {twice!r} is named twice in {list(value)!r}")
    return tuple(str(a) for a in value)


@dataclass(frozen=True)
class LqrParameters:
    """Axes, weights and target of the LQR station keeper (per-axis entries in the order of :data:`AXES`)."""

    axes: tuple[str, ...] = parameter(AXES, axes_list, "axes held (surge, sway, heave, roll, pitch, yaw)")
    q_pose: tuple[float, ...] = parameter(DEFAULT_Q_POSE, vector(6, positive, scalar=True),
                                          "Q weights of the pose errors [1/m^2 x3, 1/rad^2 x3]")
    q_velocity: tuple[float, ...] = parameter(DEFAULT_Q_VELOCITY, vector(6, positive, scalar=True),
                                              "Q weights of the velocities [s^2/m^2 x3, s^2/rad^2 x3]")
    r_wrench: tuple[float, ...] = parameter(DEFAULT_R_WRENCH, vector(6, positive, scalar=True),
                                            "R weights of the wrench [1/N^2 x3, 1/(N m)^2 x3]")
    q_integral: tuple[float, ...] = parameter((0.0,) * 6, vector(6, non_negative, scalar=True),
                                              "Q weights of the pose errors' time integrals (0: no integrator) "
                                              "[1/(m^2 s^2) x3, 1/(rad^2 s^2) x3]")
    limit: tuple[float, ...] | None = parameter(None, optional(vector(6, positive, scalar=True)),
                                                "output limits per axis [N x3, N m x3] (default: none)")
    design: str = parameter("discrete", choice("discrete", "continuous"),
                            "Riccati equation: discrete (zero-order hold at the period) or continuous")
    feedforward: bool = parameter(True, lambda v: _boolean(v), "add the wrench that holds the design state")
    desired_position: tuple[float, float, float] | None = parameter(
        None, optional(vector(3)), "world position to hold [m] (default: the position at the first update)")
    desired_attitude: tuple[float, float, float] | None = parameter(
        None, optional(vector(3)), "ZYX Euler angles to hold [rad] (default: level, the yaw at the first update)")


def _boolean(value) -> bool:
    if not isinstance(value, bool):
        raise ValueError(f"expected true or false, found {value!r}")
    return value


@dataclass(frozen=True, eq=False)
class LqrDesign:
    """The design of :meth:`LqrController.design`: ``wrench[axes] = feedforward - gain @ [e; nu]`` (module doc).

    Attributes:
        axes: the controlled axes.
        state_names, input_names: names of the design's states (``e_<axis>``, ``nu_<axis>``, then
            ``integral_<axis>``) and inputs.
        A, B: continuous matrices of the design states and inputs; Ad, Bd: zero-order hold at ``period``.
        Q, R: the weights.
        gain: ``K`` (k, 2 k + k_i), ``k_i`` the number of integrators.
        feedforward: (k,) the held wrench on the controlled axes [N, N m].
        closed_loop: eigenvalues of ``A - B K`` (continuous design) or ``Ad - Bd K`` (discrete design).
        hold_state: the :class:`~uvms.state.State` designed about.
    """

    axes: tuple[str, ...]
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    A: np.ndarray
    B: np.ndarray
    Ad: np.ndarray
    Bd: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    gain: np.ndarray
    feedforward: np.ndarray
    closed_loop: np.ndarray
    hold_state: object


def pose_error(state, position_desired: np.ndarray, rotation_desired: np.ndarray) -> np.ndarray:
    """``[R_d^T (p - p_d); Log(R_d^T R)]`` (6,) [m, rad]: the pose error in the hold attitude's axes."""
    from scipy.spatial.transform import Rotation

    e_p = rotation_desired.T @ (np.asarray(state.position) - position_desired)
    e_R = Rotation.from_matrix(rotation_desired.T @ state.rotation).as_rotvec()
    return np.concatenate([e_p, e_R])


@register("lqr")
class LqrController:
    """LQR station keeping on any subset of the six axes, designed from :func:`uvms.linearize` (module doc)."""

    Parameters = LqrParameters

    def __init__(self, model=None, parameters: LqrParameters | None = None, *, period: float = 0.01) -> None:
        if not period > 0:
            raise UvmsInputError(f"expected a period > 0 [s], found {period!r}", path="controller.period")
        if model is None:
            raise UvmsInputError("the lqr controller needs the plant model to design from", path="controller")
        self.model = model
        self.parameters = parameters or LqrParameters()
        self.period = float(period)
        self._axes = [AXES.index(a) for a in self.parameters.axes]
        self._integrated = [j for j, i in enumerate(self._axes) if self.parameters.q_integral[i] > 0]
        """Positions in ``axes`` of the axes with an integrator."""
        self.reset()

    def reset(self) -> None:
        """Forget the design and the captured hold pose (the next update designs again)."""
        self.current_design: LqrDesign | None = None
        self._integral = np.zeros(len(self._integrated))
        self._position_desired: np.ndarray | None = None
        self._rotation_desired: np.ndarray | None = None

    def hold_state(self, state):
        """The :class:`~uvms.state.State` held: the desired pose (defaults from ``state``), at rest, the arm at
        ``state.q`` with ``qd = 0``."""
        from uvms.state import State

        par = self.parameters
        position = state.position if par.desired_position is None else par.desired_position
        euler = (0.0, 0.0, float(state.euler[2])) if par.desired_attitude is None else par.desired_attitude
        return State.from_euler(self.model, position=position, euler=euler, q=state.q)

    def design(self, state, joint_torques=None) -> LqrDesign:
        """The gain and feedforward about :meth:`hold_state` of ``state`` with ``joint_torques`` held (module doc).

        Raises:
            UvmsInputError: the chosen axes cannot be stabilised by the model's linearisation.
        """
        from scipy.linalg import solve_continuous_are, solve_discrete_are

        from uvms.dynamics.linearize import discretize, linearize

        par = self.parameters
        hold = self.hold_state(state)
        lin = linearize(self.model, hold, joint_torques=joint_torques)
        R_d = hold.rotation
        T = np.eye(12)
        T[:3, :3] = R_d.T                      # [e_p; e_R; nu] = T [dp; dtheta; dnu]
        A12 = T @ lin.A[:12, :12] @ T.T
        B12 = T @ lin.B[:12, :6]
        rows = [POSE_INDEX[i] for i in self._axes] + [6 + VELOCITY_INDEX[i] for i in self._axes]
        cols = [VELOCITY_INDEX[i] for i in self._axes]
        A, B = A12[np.ix_(rows, rows)], B12[np.ix_(rows, cols)]
        Q = np.diag([par.q_pose[i] for i in self._axes] + [par.q_velocity[i] for i in self._axes])
        Rw = np.diag([par.r_wrench[i] for i in self._axes])
        Ad, Bd = discretize(A, B, self.period)
        k, ki = len(cols), len(self._integrated)
        if ki:                                  # integrators of the pose errors: z_dot = e (z_{k+1} = z_k + T e_k)
            C = np.zeros((ki, 2 * k))
            C[np.arange(ki), self._integrated] = 1.0
            A = np.block([[A, np.zeros((2 * k, ki))], [C, np.zeros((ki, ki))]])
            Ad = np.block([[Ad, np.zeros((2 * k, ki))], [self.period * C, np.eye(ki)]])
            B, Bd = np.vstack([B, np.zeros((ki, k))]), np.vstack([Bd, np.zeros((ki, k))])
            Q = np.diag(np.concatenate([np.diag(Q), [par.q_integral[self._axes[j]] for j in self._integrated]]))
        try:
            if par.design == "discrete":
                P = solve_discrete_are(Ad, Bd, Q, Rw)
                K = np.linalg.solve(Rw + Bd.T @ P @ Bd, Bd.T @ P @ Ad)
                closed = np.linalg.eigvals(Ad - Bd @ K)
                stable = bool(np.all(np.abs(closed) < 1.0))
            else:
                P = solve_continuous_are(A, B, Q, Rw)
                K = np.linalg.solve(Rw, B.T @ P)
                closed = np.linalg.eigvals(A - B @ K)
                stable = bool(np.all(closed.real < 0.0))
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise UvmsInputError(f"no LQR design for axes {', '.join(par.axes)} about the hold state ({exc})",
                                 path="controller.parameters.axes") from None
        if not stable:
            raise UvmsInputError(f"the LQR design for axes {', '.join(par.axes)} is not stable about the hold state",
                                 path="controller.parameters.axes")
        feedforward = np.zeros(len(self._axes))
        if par.feedforward:
            u_ff = -np.linalg.solve(lin.B[6:12, :6], lin.drift[6:12])
            feedforward = u_ff[cols]
        for a in (A, B, Ad, Bd, Q, Rw, K, feedforward, closed):
            a.setflags(write=False)
        names = (tuple(f"e_{a}" for a in par.axes) + tuple(f"nu_{a}" for a in par.axes)
                 + tuple(f"integral_{par.axes[j]}" for j in self._integrated))
        return LqrDesign(axes=par.axes, state_names=names, input_names=tuple(lin.input_names[c] for c in cols), A=A,
                         B=B, Ad=Ad, Bd=Bd, Q=Q, R=Rw, gain=K, feedforward=feedforward, closed_loop=closed,
                         hold_state=hold)

    def update(self, measurement: Measurement) -> ControlOutput:
        state = measurement.state
        if self.current_design is None:
            self.current_design = self.design(state, measurement.joint_torques)
            hold = self.current_design.hold_state
            self._position_desired = np.array(hold.position)
            self._rotation_desired = hold.rotation
        d = self.current_design
        e = pose_error(state, self._position_desired, self._rotation_desired)
        nu = np.asarray(state.nu)
        e_axes = e[[POSE_INDEX[i] for i in self._axes]]
        x = np.concatenate([e_axes, nu[[VELOCITY_INDEX[i] for i in self._axes]], self._integral])
        unclipped = d.feedforward - d.gain @ x
        command = unclipped
        if self.parameters.limit is not None:
            limit = np.array([self.parameters.limit[i] for i in self._axes])
            command = np.clip(unclipped, -limit, limit)
        for n, j in enumerate(self._integrated):
            if command[j] == unclipped[j]:
                self._integral[n] += self.period * e_axes[j]
        wrench = np.zeros(6)
        signals: dict[str, float] = {}
        for j, i in enumerate(self._axes):
            wrench[VELOCITY_INDEX[i]] = command[j]
            signals[f"e_{AXES[i]}"] = float(e[POSE_INDEX[i]])
            signals[f"command_{AXES[i]}"] = float(command[j])
        for n, j in enumerate(self._integrated):
            signals[f"integral_{AXES[self._axes[j]]}"] = float(self._integral[n])
        return ControlOutput(wrench=wrench, signals=signals)

