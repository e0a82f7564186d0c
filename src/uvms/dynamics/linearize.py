"""Linear state-space model of the vehicle-manipulator system about any state: ``uvms.linearize``.

State perturbation (``12 + 2 n``), in this order (``docs/conventions.md``, "Linearisation")::

    dx = [dp (3, world, m) | dtheta (3, body axes, rad) | dnu (6, [omega; v]) | dq (n) | dqd (n)]

``dtheta`` is the rotation vector of the attitude perturbation in body axes about the operating attitude
``R0``: ``R = R0 Exp(dtheta)`` (a minimal, non-singular chart: ``dtheta = 0`` at the operating point whatever
``R0``). Inputs (``6 + n``): the body wrench ``[K M N X Y Z]`` (paper Eq. 11's ``f_0``) and the joint torques.
The model is ``dx_dot = drift + A dx + B du``; ``drift`` (the state derivative at the operating point) is zero
at an equilibrium.

Rows and how they are obtained:

- ``dp_dot = R v``: ``d/d dtheta = -R0 [v0 x]``, ``d/dv = R0`` (exact, written out).
- ``dtheta_dot = J_r(dtheta)^-1 omega`` (the right Jacobian of SO(3)) ``= omega - 1/2 omega x dtheta + ...``:
  ``d/d dtheta = -1/2 [omega0 x]``, ``d/d omega = I`` (exact).
- ``dq_dot = qd``: identity (exact).
- ``nu_dot``, ``qdd``: :func:`uvms.forward_dynamics` (the articulated-body algorithm, Eqs. 13-23) by central
  differences, one column at a time, with step ``h_j = H max(1, |x0_j|)``, ``H = eps^(1/3) = 6.1e-6`` (the
  optimum of a central difference of a smooth function of unit scale), combined as ``2 D(h/2) - D(h)``.
  Why that combination: quadratic drag ``-c v |v|`` (Eqs. 3-6, Fossen's ``D_q``) is continuously
  differentiable but not twice at zero relative velocity (a vehicle at rest in still water, the usual
  operating point); there a central difference is ``D(h) = -c h`` instead of the true ``0``. The combination
  removes that first-order error exactly and leaves the ``O(h^2)`` error of smooth terms (halved). Complex
  steps are not possible (the compiled kernels are real, and ``|v|`` is not analytic).

With ``step``, the zero-order-hold discretisation: ``[[Ad, Bd], [0, I]] = expm([[A, B], [0, 0]] step)``
(:func:`scipy.linalg.expm`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uvms import checks
from uvms.errors import UvmsInputError

STEP = float(np.finfo(float).eps) ** (1.0 / 3.0)
"""Relative finite-difference step ``H`` of the dynamics columns (module docstring)."""

VEHICLE_STATE_NAMES: tuple[str, ...] = ("x", "y", "z", "rx", "ry", "rz", "p", "q", "r", "u", "v", "w")
"""Names of the 12 vehicle entries of the state perturbation: world position, body rotation vector, ``nu``."""
WRENCH_NAMES: tuple[str, ...] = ("K", "M", "N", "X", "Y", "Z")
"""Names of the body-wrench inputs (``[moment; force]``, body axes)."""


@dataclass(frozen=True, eq=False)
class Linearization:
    """``dx_dot = drift + A dx + B du`` about ``state`` (module docstring for the coordinates).

    Attributes:
        A: (N, N) continuous state matrix, ``N = 12 + 2 n``.
        B: (N, 6 + n) continuous input matrix.
        drift: (N,) state derivative at the operating point (zero at an equilibrium).
        state_names: names of the rows of ``A`` (:data:`VEHICLE_STATE_NAMES`, then ``q_<joint>``, ``qd_<joint>``).
        input_names: names of the columns of ``B`` (:data:`WRENCH_NAMES`, then ``tau_<joint>``).
        state: the operating :class:`~uvms.state.State`.
        inputs: (6 + n,) operating inputs ``[body wrench; joint torques]``.
        step: discretisation step [s], or ``None``.
        Ad, Bd: zero-order-hold discrete matrices for ``step`` (``None`` without a step).
    """

    A: np.ndarray
    B: np.ndarray
    drift: np.ndarray
    state_names: tuple[str, ...]
    input_names: tuple[str, ...]
    state: object
    inputs: np.ndarray
    step: float | None = None
    Ad: np.ndarray | None = None
    Bd: np.ndarray | None = None

    def state_index(self, names) -> list[int]:
        """Row indices of the named states (``UvmsInputError`` for an unknown one)."""
        return _indices(names, self.state_names, "states")

    def input_index(self, names) -> list[int]:
        """Column indices of the named inputs (``UvmsInputError`` for an unknown one)."""
        return _indices(names, self.input_names, "inputs")

    def select(self, states=None, inputs=None) -> "Linearization":
        """The subsystem of the named states and inputs (default: all), coupling to the others dropped; the
        discrete matrices are recomputed for the subsystem when there is a step."""
        rows = self.state_index(self.state_names if states is None else states)
        cols = self.input_index(self.input_names if inputs is None else inputs)
        A, B = self.A[np.ix_(rows, rows)], self.B[np.ix_(rows, cols)]
        Ad, Bd = discretize(A, B, self.step) if self.step is not None else (None, None)
        return Linearization(A=A, B=B, drift=self.drift[rows], state_names=tuple(self.state_names[i] for i in rows),
                             input_names=tuple(self.input_names[i] for i in cols), state=self.state,
                             inputs=self.inputs[cols], step=self.step, Ad=Ad, Bd=Bd)


def _indices(names, known: tuple[str, ...], what: str) -> list[int]:
    if isinstance(names, str):
        names = [names]
    out = []
    for name in names:
        if name not in known:
            raise UvmsInputError(f"unknown name {name!r}; expected one of: {', '.join(known)}", path=what)
        out.append(known.index(name))
    if len(set(out)) != len(out):
        raise UvmsInputError(f"a name is given twice in {list(names)!r}", path=what)
    return out


def state_names(model) -> tuple[str, ...]:
    """Names of the state perturbation of ``model`` (:attr:`Linearization.state_names`)."""
    return (VEHICLE_STATE_NAMES + tuple(f"q_{j}" for j in model.joint_names)
            + tuple(f"qd_{j}" for j in model.joint_names))


def input_names(model) -> tuple[str, ...]:
    """Names of the inputs of ``model`` (:attr:`Linearization.input_names`)."""
    return WRENCH_NAMES + tuple(f"tau_{j}" for j in model.joint_names)


def skew(v) -> np.ndarray:
    """``[v x]``."""
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def quaternion_exp(phi: np.ndarray) -> np.ndarray:
    """Unit quaternion ``[w, x, y, z]`` of the rotation vector ``phi`` (``Exp(phi)``)."""
    angle = float(np.linalg.norm(phi))
    half = 0.5 * angle
    scale = math.sin(half) / angle if angle > 1e-8 else 0.5 - angle * angle / 48.0
    return np.array([math.cos(half), *(scale * phi)])


def quaternion_product(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Hamilton product ``a (x) b`` of ``[w, x, y, z]`` quaternions."""
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def perturbed_state(state, dx: np.ndarray, n: int):
    """The :class:`~uvms.state.State` at chart coordinates ``dx`` about ``state`` (``R = R0 Exp(dtheta)``)."""
    from uvms.state import State

    return State(position=state.position + dx[0:3],
                 quaternion=quaternion_product(state.quaternion, quaternion_exp(dx[3:6])),
                 nu=state.nu + dx[6:12], q=state.q + dx[12:12 + n], qd=state.qd + dx[12 + n:12 + 2 * n],
                 actuator=state.actuator)


def _checked_state(model, state):
    checks.state(model, state)
    for name in ("position", "quaternion", "nu", "q", "qd"):
        value = np.asarray(getattr(state, name), dtype=float)
        if not np.all(np.isfinite(value)):
            i = int(np.flatnonzero(~np.isfinite(value))[0])
            raise checks.fail(f"state.{name}", f"expected finite values, got {value[i]} at index {i}")
    return state


def linearize(model, state, *, joint_torques=None, body_wrench=None, ee_wrench=None, current=None,
              step=None) -> Linearization:
    """Continuous (and with ``step``, discrete) state-space matrices about ``state`` (module docstring).

    Args:
        model: a :class:`uvms.Model`.
        state: the operating :class:`uvms.State` (need not be an equilibrium: see ``drift``).
        joint_torques: (n,) operating joint torques [N m]; zero when omitted.
        body_wrench: (6,) operating body wrench ``[K M N X Y Z]`` [N m, N]; zero when omitted.
        ee_wrench: (6,) end-effector wrench held constant (end-effector axes), not an input column.
        current: (3,) world current [m/s] (default: the model's).
        step: discretisation step [s] for ``Ad``, ``Bd`` (zero-order hold).

    Raises:
        UvmsInputError: a wrong model or state, a non-finite state entry, inputs of the wrong size or not
            finite, a step that is not a positive number (one line naming the argument).
    """
    from uvms.dynamics.api import forward_dynamics

    checks.model(model)
    _checked_state(model, state)
    n = model.n_joints
    tau0 = checks.optional_vector(joint_torques, n, "joint_torques", " (one per joint)")
    f0 = checks.optional_vector(body_wrench, 6, "body_wrench", " [moment; force]")
    fee = checks.optional_vector(ee_wrench, 6, "ee_wrench", " [moment; force]")
    vc = checks.optional_vector(current, 3, "current", " (world frame, m/s)", model.current)
    step = None if step is None else checks.number(step, "step", positive=True, unit="s")
    u0 = np.concatenate([f0, tau0])

    def dynamics(dx: np.ndarray, u: np.ndarray) -> np.ndarray:
        acc = forward_dynamics(model, perturbed_state(state, dx, n), joint_torques=u[6:], body_wrench=u[:6],
                               ee_wrench=fee, current=vc)
        return acc.generalized

    N, m = 12 + 2 * n, 6 + n
    x0 = np.concatenate([state.position, np.zeros(3), state.nu, state.q, state.qd])
    zero = np.zeros(N)
    acc0 = dynamics(zero, u0)
    J_x = np.empty((6 + n, N))
    J_u = np.empty((6 + n, m))
    for j in range(N):
        J_x[:, j] = _derivative(lambda h: dynamics(_unit(N, j, h), u0), STEP * max(1.0, abs(x0[j])))
    for j in range(m):
        J_u[:, j] = _derivative(lambda h: dynamics(zero, u0 + _unit(m, j, h)), STEP * max(1.0, abs(u0[j])))

    R0 = state.rotation
    omega0, v0 = np.asarray(state.nu[:3]), np.asarray(state.nu[3:])
    A = np.zeros((N, N))
    A[0:3, 3:6] = -R0 @ skew(v0)
    A[0:3, 9:12] = R0
    A[3:6, 3:6] = -0.5 * skew(omega0)
    A[3:6, 6:9] = np.eye(3)
    A[12:12 + n, 12 + n:] = np.eye(n)
    A[6:12] = J_x[:6]
    A[12 + n:] = J_x[6:]
    B = np.zeros((N, m))
    B[6:12] = J_u[:6]
    B[12 + n:] = J_u[6:]
    drift = np.concatenate([R0 @ v0, omega0, acc0[:6], state.qd, acc0[6:]])
    Ad, Bd = discretize(A, B, step) if step is not None else (None, None)
    return Linearization(A=A, B=B, drift=drift, state_names=state_names(model), input_names=input_names(model),
                         state=state, inputs=u0, step=step, Ad=Ad, Bd=Bd)


def _unit(size: int, j: int, h: float) -> np.ndarray:
    e = np.zeros(size)
    e[j] = h
    return e


def _derivative(f, h: float) -> np.ndarray:
    """``2 D(h/2) - D(h)`` with ``D(h) = (f(h) - f(-h)) / 2h`` (module docstring)."""
    def central(s):
        return (f(s) - f(-s)) / (2.0 * s)

    return 2.0 * central(0.5 * h) - central(h)


def discretize(A: np.ndarray, B: np.ndarray, step: float) -> tuple[np.ndarray, np.ndarray]:
    """Zero-order-hold ``(Ad, Bd)``: ``[[Ad, Bd], [0, I]] = expm([[A, B], [0, 0]] step)``."""
    from scipy.linalg import expm

    N, m = B.shape
    block = np.zeros((N + m, N + m))
    block[:N, :N], block[:N, N:] = A, B
    E = expm(block * step)
    return E[:N, :N], E[:N, N:]
