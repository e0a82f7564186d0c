"""Labelled Python entry points to the compiled dynamics (checks at the boundary, Pinocchio-style).

``forward_dynamics`` (ABA), ``inverse_dynamics`` (RNEA) and ``mass_matrix`` (CRBA) take a frozen
:class:`~uvms.model.Model` and a :class:`~uvms.state.State`. Vectors are ``[angular; linear]``, body axes.
Current and fluid acceleration default to the model's environment and may be overridden per call
(world frame).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass

import numpy as np

from uvms import checks
from uvms.dynamics.aba import aba
from uvms.dynamics.crba import crba
from uvms.dynamics.fastcall import specialised
from uvms.dynamics.kernel_model import make_workspace
from uvms.dynamics.rnea import rnea

_local = threading.local()
"""Per-thread workspaces by number of bodies: a call reuses one instead of allocating ~16 arrays. (The kernels
hold the GIL today; one workspace per thread keeps this right if they ever release it.)"""
_entries: dict[tuple, tuple] = {}
"""Compiled entry point of a kernel for one model's kernel arrays: ``(kernel, id(arrays)) -> (arrays, entry)``
(the arrays are held so that their id is not reused). The other arguments are built here, always as fresh
C-ordered float64 arrays and a bool, so the types of a call are those of its first call."""
_MAX_ENTRIES = 64


def _workspace(n_bodies: int):
    cache = _local.__dict__.setdefault("workspaces", {})
    ws = cache.get(n_bodies)
    if ws is None:
        ws = cache[n_bodies] = make_workspace(n_bodies)
    return ws


def _call(kernel, km, *args) -> None:
    """``kernel(km, *args)`` through its resolved specialisation (:func:`~uvms.dynamics.fastcall.specialised`),
    skipping numba's per-call typing of the ~20 model and ~16 workspace arrays (5-10 us)."""
    key = (kernel, id(km))
    hit = _entries.get(key)
    if hit is None:
        if len(_entries) >= _MAX_ENTRIES:
            _entries.pop(next(iter(_entries)))
        hit = _entries[key] = (km, specialised(kernel, km, *args))
    hit[1](km, *args)


_vec = checks.optional_vector
"""``(value, size, name)``: a fresh float64 array of ``size`` finite values (zeros for ``None``), else a one-line
:class:`~uvms.errors.UvmsInputError` naming the argument."""
_PER_JOINT = " (one per joint)"
_WRENCH = " [moment; force]"


@dataclass(frozen=True)
class Accelerations:
    """Result of :func:`forward_dynamics`.

    ``nu_dot`` (6): time derivative of the body velocity ``nu = [omega; v]`` (the spatial acceleration in
    body axes) [rad/s^2, m/s^2]; ``qdd`` (n): joint accelerations [rad/s^2].
    """

    nu_dot: np.ndarray
    qdd: np.ndarray

    @property
    def generalized(self) -> np.ndarray:
        """``[nu_dot; qdd]`` (6 + n)."""
        return np.concatenate([self.nu_dot, self.qdd])


@dataclass(frozen=True)
class Environment:
    """World-frame current velocity [m/s] and fluid acceleration [m/s^2] for one evaluation."""

    current: np.ndarray
    fluid_acceleration: np.ndarray


def environment(model, current=None, fluid_acceleration=None) -> Environment:
    """The model's environment, with per-call overrides."""
    return _environment(checks.model(model), current, fluid_acceleration)


def _environment(model, current, fluid_acceleration) -> Environment:
    return Environment(_vec(current, 3, "current", " (world frame, m/s)", model.current),
                       _vec(fluid_acceleration, 3, "fluid_acceleration", " (world frame, m/s^2)",
                            model.fluid_acceleration))


def _state_arrays(model, state, fixed_base: bool):
    checks.state(model, state)
    nu = np.array(state.nu, dtype=float)
    if fixed_base is not False and checks.flag(fixed_base, "fixed_base") and np.any(nu != 0.0):
        raise checks.fail("fixed_base", "True needs a vehicle at rest (state.nu == 0): a clamped vehicle does not "
                                        "move")
    return (state.rotation, nu, np.array(state.q, dtype=float), np.array(state.qd, dtype=float))


def forward_dynamics(model, state, *, joint_torques=None, body_wrench=None, ee_wrench=None, fixed_base=False,
                     current=None, fluid_acceleration=None) -> Accelerations:
    """Accelerations of the vehicle and the arm by the hydrodynamic articulated-body algorithm (Eqs. 13-23).

    Args:
        joint_torques: (n,) [N m]; zero when omitted.
        body_wrench: (6,) wrench ``f_0 = [moment; force]`` on the vehicle, body axes (thrusters, Eq. 11).
        ee_wrench: (6,) spatial force on the end effector in end-effector axes (Eq. 14's ``f_ee``).
        fixed_base: clamp the vehicle (a land-based arm): ``nu_dot = 0``.
        current, fluid_acceleration: (3,) world-frame overrides of the model's environment.
    """
    R0, nu, q, qd = _state_arrays(model, state, fixed_base)
    n = model.n_joints
    env = _environment(model, current, fluid_acceleration)
    nu_dot = np.zeros(6)
    qdd = np.zeros(n)
    tau = _vec(joint_torques, n, "joint_torques", _PER_JOINT)
    f_body = _vec(body_wrench, 6, "body_wrench", _WRENCH)
    f_ee = _vec(ee_wrench, 6, "ee_wrench", _WRENCH)
    _call(aba, model.kernel, _workspace(model.n_bodies), R0, nu, q, qd, tau, f_body, f_ee, env.current,
          env.fluid_acceleration, bool(fixed_base), nu_dot, qdd)
    total = sum(nu_dot.tolist()) + sum(qdd.tolist())  # any NaN or inf makes the sum one: fast test
    if total - total != 0.0 and not checks.finite(nu_dot, qdd):
        raise checks.overflow("the accelerations", {
            "state.nu": nu, "state.qd": qd, "joint_torques": tau, "body_wrench": f_body, "ee_wrench": f_ee,
            "current": env.current, "fluid_acceleration": env.fluid_acceleration})
    return Accelerations(nu_dot=nu_dot, qdd=qdd)


def inverse_dynamics(model, state, *, nu_dot, qdd, ee_wrench=None, current=None,
                     fluid_acceleration=None) -> tuple[np.ndarray, np.ndarray]:
    """The vehicle wrench (6,) and joint torques (n,) that produce ``nu_dot`` and ``qdd`` (RNEA)."""
    R0, nu, q, qd = _state_arrays(model, state, False)
    n = model.n_joints
    env = _environment(model, current, fluid_acceleration)
    f0 = np.zeros(6)
    tau = np.zeros(n)
    a0, qdd, f_ee = (checks.vector(nu_dot, 6, "nu_dot"), checks.vector(qdd, n, "qdd", _PER_JOINT),
                     _vec(ee_wrench, 6, "ee_wrench", _WRENCH))
    _call(rnea, model.kernel, _workspace(model.n_bodies), R0, nu, q, qd, a0, qdd, f_ee, env.current,
          env.fluid_acceleration, f0, tau)
    total = sum(f0.tolist()) + sum(tau.tolist())  # any NaN or inf makes the sum one: fast test
    if total - total != 0.0 and not checks.finite(f0, tau):
        raise checks.overflow("the wrench and torques", {
            "state.nu": nu, "state.qd": qd, "nu_dot": a0, "qdd": qdd, "ee_wrench": f_ee, "current": env.current,
            "fluid_acceleration": env.fluid_acceleration})
    return f0, tau


def mass_matrix(model, state) -> np.ndarray:
    """Joint-space inertia matrix ``M`` (6+n, 6+n) of ``[nu; qd]``, added mass included (CRBA)."""
    checks.state(model, state)
    M = np.zeros((model.n_dof, model.n_dof))
    _call(crba, model.kernel, _workspace(model.n_bodies), np.array(state.q, dtype=float), M)
    return M


def bias_forces(model, state, *, current=None, fluid_acceleration=None) -> np.ndarray:
    """``h`` (6+n) with ``M [nu_dot; qdd] + h = [f_0; tau]``: RNEA at zero acceleration."""
    checks.state(model, state)
    f0, tau = inverse_dynamics(model, state, nu_dot=np.zeros(6), qdd=np.zeros(model.n_joints), current=current,
                               fluid_acceleration=fluid_acceleration)
    return np.concatenate([f0, tau])
