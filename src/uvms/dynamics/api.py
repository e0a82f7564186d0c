"""Labelled Python entry points to the compiled dynamics (checks at the boundary, Pinocchio-style).

:class:`Dynamics` owns one compiled plant of a model (:class:`uvms.dynamics.plant.Plant`: kernel arrays,
workspace, scratch) and evaluates ``forward`` (ABA), ``inverse`` (RNEA) and ``mass_matrix`` (CRBA) on it,
checking every argument once at the boundary; package code that evaluates the dynamics from Python holds a
``Dynamics`` as Pinocchio code holds its ``data``. ``forward_dynamics``, ``inverse_dynamics`` and
``mass_matrix`` are the convenience entries: one line over a per-thread ``Dynamics`` of the model.

States are :class:`~uvms.state.State`; vectors are ``[angular; linear]``, body axes. Current and fluid
acceleration default to the model's environment and may be overridden per call (world frame).
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from uvms import checks
from uvms.dynamics.plant import build_plant, fluid_table, plant_forward, plant_inverse, plant_mass_matrix
from uvms.state import State

_SLOT = "_uvms_dynamics"
"""The model attribute holding a ``threading.local`` with each thread's :class:`Dynamics` of that model (used by
the convenience functions)."""


def dynamics_of(model) -> "Dynamics":
    """This thread's :class:`Dynamics` of ``model`` (built at the first call; kept in a thread-local slot of the
    model object, so it goes with the model)."""
    try:
        return model.__dict__[_SLOT].dynamics
    except (KeyError, AttributeError):
        pass
    checks.model(model)
    local = model.__dict__.setdefault(_SLOT, threading.local())     # atomic: one slot per model
    local.dynamics = Dynamics(model)
    return local.dynamics


_vec = checks.optional_vector
"""``(value, size, name)``: a fresh float64 array of ``size`` finite values (zeros for ``None``), else a one-line
:class:`~uvms.errors.UvmsInputError` naming the argument."""
_PER_JOINT = " (one per joint)"


def _read(value, size: int, name: str, what: str) -> np.ndarray:
    """An input the kernel only reads: a writeable C-ordered float64 array of the right shape is used as it is
    (no copy; its values are checked only if the result is not finite, :meth:`Dynamics.forward`), anything else
    (a read-only array included: numba compiles read-only arrays as another type) is converted and checked by
    :func:`uvms.checks.vector`."""
    if type(value) is np.ndarray and value.dtype == np.float64 and value.shape == (size,) \
            and value.flags.c_contiguous and value.flags.writeable:
        return value
    return checks.vector(value, size, name, what)     # a read-only array too: numba would compile it apart


_WRENCH = " [moment; force]"


class Accelerations(NamedTuple):
    """Result of :func:`forward_dynamics` (a named pair: ``nu_dot, qdd = forward_dynamics(...)`` also works).

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


class Dynamics:
    """The compiled dynamics of one model, with every argument checked (module docstring).

    Args:
        model: a :class:`~uvms.model.Model`.
        fixed_base: clamp the vehicle (a land-based arm): ``nu_dot = 0``, and states must have ``nu = 0``.
    """

    def __init__(self, model, *, fixed_base: bool = False) -> None:
        self.model = checks.model(model)
        self.fixed_base = checks.flag(fixed_base, "fixed_base")
        self._env = np.array([model.current, model.fluid_acceleration], dtype=float)
        self._flow = fluid_table([0.0], self._env[0:1], self._env[1:2])
        """The plant's water: the model's uniform environment, its one row overwritten for a call's overrides."""
        self.plant, self.data = build_plant(model, fixed_base=self.fixed_base, fluid=self._flow)
        n = self._n = model.n_joints
        self._zero6 = np.zeros(6)
        self._zero_n = np.zeros(n)
        self._no_wrenches = np.zeros(12)
        """``[body wrench | ee wrench]`` of a call that gives none."""

    def __repr__(self) -> str:
        return f"Dynamics({self.model.name!r}, {self.model.n_joints} joints, fixed_base={self.fixed_base})"

    def _state_vector(self, state) -> np.ndarray:
        """The packed vector (simulation layout, :attr:`uvms.State._packed`) of a checked state."""
        if type(state) is not State or state.q.shape[0] != self._n:      # the common case decided in two tests
            checks.state(self.model, state)
        if self.fixed_base and np.any(state.nu != 0.0):
            raise checks.fail("fixed_base", "True needs a vehicle at rest (state.nu == 0): a clamped vehicle does "
                                            "not move")
        x = state._packed
        if x is None:                                   # a State.trusted of separate arrays
            x = np.concatenate((state.position, state.quaternion, state.nu, state.q, state.qd))
            x.flags.writeable = False                   # typed as a packed state is: one compiled signature
        return x

    def _inputs(self, first: np.ndarray | None, middle, ee_wrench, current, fluid_acceleration) -> np.ndarray:
        """Packed inputs: ``first`` (joint torques, or nu_dot and qdd), a 6-vector ``middle`` (body wrench) or
        nothing, the end-effector wrench; the current and fluid acceleration of the call (checked) into the
        plant's one-row water table (:meth:`_restore_water` puts the model's back)."""
        parts = [first] if first is not None else []
        if middle is not False:
            parts.append(self._zero6 if middle is None else checks.vector(middle, 6, "body_wrench", _WRENCH))
        parts.append(self._zero6 if ee_wrench is None else checks.vector(ee_wrench, 6, "ee_wrench", _WRENCH))
        self._flow.velocity[0] = self._env[0] if current is None \
            else checks.vector(current, 3, "current", " (world frame, m/s)")
        self._flow.acceleration[0] = self._env[1] if fluid_acceleration is None \
            else checks.vector(fluid_acceleration, 3, "fluid_acceleration", " (world frame, m/s^2)")
        return np.concatenate(parts)

    def _restore_water(self) -> None:
        """The model's environment back into the plant's water table (after a call with overrides)."""
        self._flow.velocity[0] = self._env[0]
        self._flow.acceleration[0] = self._env[1]

    def forward(self, state, *, joint_torques=None, body_wrench=None, ee_wrench=None, current=None,
                fluid_acceleration=None) -> Accelerations:
        """Accelerations of the vehicle and the arm by the hydrodynamic articulated-body algorithm (Eqs. 13-23).

        Args:
            joint_torques: (n,) [N m]; zero when omitted.
            body_wrench: (6,) wrench ``f_0 = [moment; force]`` on the vehicle, body axes (thrusters, Eq. 11).
            ee_wrench: (6,) spatial force on the end effector in end-effector axes (Eq. 14's ``f_ee``).
            current, fluid_acceleration: (3,) world-frame overrides of the model's environment.
        """
        x = self._state_vector(state)
        n = self._n
        tau = self._zero_n if joint_torques is None else _read(joint_torques, n, "joint_torques", _PER_JOINT)
        out = np.empty(6 + n)
        if body_wrench is None and ee_wrench is None and current is None and fluid_acceleration is None:
            wrenches = self._no_wrenches
            finite = plant_forward(self.plant, 0.0, x, tau, wrenches, self.fixed_base, out)
        else:
            try:
                wrenches = self._inputs(None, body_wrench, ee_wrench, current, fluid_acceleration)
                water = self._flow.velocity[0].copy(), self._flow.acceleration[0].copy()
                finite = plant_forward(self.plant, 0.0, x, tau, wrenches, self.fixed_base, out)
            finally:
                self._restore_water()
        if not finite:
            if not checks.finite(tau):                  # a NaN or infinity given: name it (raises)
                checks.vector(tau, n, "joint_torques", _PER_JOINT)
            current, fluid_acceleration = water if wrenches is not self._no_wrenches else self._env
            raise checks.overflow("the accelerations", {
                "state.nu": state.nu, "state.qd": state.qd, "joint_torques": tau, "body_wrench": wrenches[0:6],
                "ee_wrench": wrenches[6:12], "current": current, "fluid_acceleration": fluid_acceleration})
        return Accelerations(out[:6], out[6:])

    def inverse(self, state, *, nu_dot, qdd, ee_wrench=None, current=None,
                fluid_acceleration=None) -> tuple[np.ndarray, np.ndarray]:
        """The vehicle wrench (6,) and joint torques (n,) that produce ``nu_dot`` and ``qdd`` (RNEA)."""
        x = self._state_vector(state)
        n = self._n
        accelerations = np.concatenate((checks.vector(nu_dot, 6, "nu_dot"), checks.vector(qdd, n, "qdd", _PER_JOINT)))
        out = np.zeros(6 + n)
        try:
            u = self._inputs(accelerations, False, ee_wrench, current, fluid_acceleration)
            water = self._flow.velocity[0].copy(), self._flow.acceleration[0].copy()
            plant_inverse(self.plant, 0.0, x, u, out)
        finally:
            self._restore_water()
        total = sum(out.tolist())  # any NaN or inf makes the sum one: fast test
        if total - total != 0.0 and not checks.finite(out):
            raise checks.overflow("the wrench and torques", {
                "state.nu": state.nu, "state.qd": state.qd, "nu_dot": u[:6], "qdd": u[6:6 + n],
                "ee_wrench": u[6 + n:12 + n], "current": water[0], "fluid_acceleration": water[1]})
        return out[:6], out[6:]

    def mass_matrix(self, state) -> np.ndarray:
        """Joint-space inertia matrix ``M`` (6+n, 6+n) of ``[nu; qd]``, added mass included (CRBA)."""
        checks.state(self.model, state)
        M = np.zeros((self.model.n_dof, self.model.n_dof))
        plant_mass_matrix(self.plant, np.array(state.q, dtype=float), M)
        return M

    def vehicle_articulated_inertia(self, state, *, joint_torques=None) -> np.ndarray:
        """The vehicle's articulated inertia ``I_0^*`` (6x6, body axes: the inertia a body wrench meets with the
        arm free, paper Eq. 16) at ``state``; a copy."""
        self.forward(state, joint_torques=joint_torques)
        return np.array(self.data.work.IA[0])


def forward_dynamics(model, state, *, joint_torques=None, body_wrench=None, ee_wrench=None, fixed_base=False,
                     current=None, fluid_acceleration=None) -> Accelerations:
    """Accelerations of the vehicle and the arm (:meth:`Dynamics.forward`); ``fixed_base`` clamps the vehicle."""
    if fixed_base is not False:
        dyn = Dynamics(model, fixed_base=fixed_base) if checks.flag(fixed_base, "fixed_base") else dynamics_of(model)
    else:
        dyn = dynamics_of(model)
    if body_wrench is None and ee_wrench is None and current is None and fluid_acceleration is None:
        return dyn.forward(state, joint_torques=joint_torques)          # (fewer keywords: the common call)
    return dyn.forward(state, joint_torques=joint_torques, body_wrench=body_wrench, ee_wrench=ee_wrench,
                       current=current, fluid_acceleration=fluid_acceleration)


def inverse_dynamics(model, state, *, nu_dot, qdd, ee_wrench=None, current=None,
                     fluid_acceleration=None) -> tuple[np.ndarray, np.ndarray]:
    """The vehicle wrench (6,) and joint torques (n,) that produce ``nu_dot`` and ``qdd`` (:meth:`Dynamics.inverse`)."""
    return dynamics_of(model).inverse(state, nu_dot=nu_dot, qdd=qdd, ee_wrench=ee_wrench, current=current,
                                      fluid_acceleration=fluid_acceleration)


def mass_matrix(model, state) -> np.ndarray:
    """Joint-space inertia matrix ``M`` (6+n, 6+n) of ``[nu; qd]``, added mass included (:meth:`Dynamics.mass_matrix`)."""
    return dynamics_of(model).mass_matrix(state)


def bias_forces(model, state, *, current=None, fluid_acceleration=None) -> np.ndarray:
    """``h`` (6+n) with ``M [nu_dot; qdd] + h = [f_0; tau]``: RNEA at zero acceleration."""
    checks.state(model, state)
    f0, tau = inverse_dynamics(model, state, nu_dot=np.zeros(6), qdd=np.zeros(model.n_joints), current=current,
                               fluid_acceleration=fluid_acceleration)
    return np.concatenate([f0, tau])
