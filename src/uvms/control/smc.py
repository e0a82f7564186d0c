"""Slotine's per-axis sliding-mode law (paper Section 5, Eqs. 24-30; Slotine & Li 1991), shared by the
``smc-ab``, ``smc-ne`` and ``smc-vehicle`` controllers, which differ only in how they predict ``f_hat``.

Axes: the paper's surge, sway, yaw by default (``docs/conventions.md``, "Sliding-mode controller"); any subset
of the six with ``axes`` (``docs/conventions.md``, "Six-axis station keeping": heave like surge and sway, roll
and pitch like yaw with their Euler rates; :func:`uvms.control.sliding_kernels.pose_kinematics_into`). For a
constant desired pose
``(p_d, psi_d)``, the errors and their exact time derivatives (from ``R_dot = R [omega x]`` and Eq. 1's
``T2``) are::

    e = R^T (p - p_d)          e_dot = v - omega x e                         (3,) body axes; x, y used
    e_psi = wrap(psi - psi_d)  psi_dot = (sin(phi) q + cos(phi) r) / cos(theta)

Sliding surface (``surface = "body_velocity"``, the default; the paper's Eq. 26 with the body velocity)::

    s = vel + lambda e,   vel = (u, v, r)                 its derivative: vel_dot = (u_dot, v_dot, r_dot)

``f_hat`` is then exactly the axis' component of ``nu_dot`` predicted by the controller's own model at
``f_0 = 0`` (Eqs. 24-25: with spatial accelerations ``nu_dot`` already is Eq. 24's ``a``, the ``omega x v``
term is inside it), and a command enters ``vel_dot`` with gain ``1/b``. Because ``vel`` is not exactly
``e_dot``, ``u_hat`` uses the exact error rate::

    s_dot = vel_dot + lambda e_dot   =>   u_hat = -f_hat - lambda e_dot          (station keeping)

so ``s_dot = (f - f_hat) + (1 - b_hat/b)(-u_hat) - (b_hat/b) k sat(s/Phi)`` as in the scalar theory. On
``s = 0`` the error norm still decays as ``exp(-lambda t)``: ``e . e_dot = e . v = -lambda |e|^2`` since
``e . (omega x e) = 0`` (up to the roll/pitch-rate coupling with the uncontrolled heave error and
``psi_dot != r`` at non-zero roll/pitch), and ``|s| <= Phi`` gives ``|e| <= Phi / lambda`` (Eq. 30).

The alternative ``surface = "error_rate"`` uses ``vel = (e_dot_x, e_dot_y, psi_dot)``, so that
``s = (d/dt + lambda) e`` literally, with the second derivatives::

    e_ddot   = v_dot - omega_dot x e - omega x e_dot
    psi_ddot = (sin(phi) q_dot + cos(phi) r_dot) / cos(theta) + phi_dot theta_dot / cos(theta)
               + theta_dot tan(theta) psi_dot

and the yaw moment divided by ``cos(phi)/cos(theta)``. Its drawback: ``omega_dot x e`` makes the yaw
command act on the surge and sway surfaces in proportion to the position error, a coupling ``f_hat`` (at
``f_0 = 0``) cannot see; far from the set point (1.4 m and 1 rad) it breaks the sliding condition on sway,
which the default surface keeps.

Per axis (Eqs. 27-29 as corrected in the conventions)::

    u_hat = -f_hat + acc_d - lambda e_dot
    b_hat = sqrt(b_min b_max)      beta = sqrt(b_max / b_min)
    k     = beta (F + eta) + (beta - 1) |u_hat|
    f     = b_hat (u_hat - k sat(s / Phi))                    [N or N m]

``b`` is the axis' effective mass or inertia [kg, kg m^2]: fixed bounds (the paper's), or ``b_hat`` from the
controller model's inertia at the current configuration (``b_source = "model"``) with ``beta = b_margin``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uvms.control import sliding_kernels as kernels
from uvms.control.axes import PAPER_AXES, axis_list, expand, per_axis, slots, waypoint_rows
from uvms.control.base import ControlOutput, Measurement
from uvms.control.registry import (
    at_least_one,
    bounds,
    choice,
    non_negative,
    number,
    optional,
    parameter,
    positive,
    vector,
)
from uvms.errors import UvmsInputError

AXES: tuple[str, ...] = PAPER_AXES
"""The paper's controlled axes (the default of ``axes``), in the order of :meth:`SlidingModeParameters.b_limits`."""

PAPER_B_TRANSLATION = (36.0, 44.44)
"""Paper's bounds of the surge and sway effective mass [kg]."""
PAPER_B_YAW = (1.287, 1.5889)
"""Paper's bounds of the yaw effective inertia [kg m^2]."""


# ---------------------------------------------------------------------------------------------- the law


@dataclass(frozen=True)
class AxisCommand:
    """One axis' update: sliding variable ``s``, gain ``k``, model-based part ``u_hat`` and the command
    ``b_hat (u_hat - k sat(s / Phi))`` [N or N m] (before the yaw axis' Euler-angle factor)."""

    s: float
    k: float
    u_hat: float
    command: float


_LAW_REQUIRED = ("bandwidth", "eta", "boundary_layer", "uncertainty", "b_hat", "beta")
_LAW_OPTIONAL = {"rate_desired": 0.0, "acc_desired": 0.0, "error_rate": None}


def slotine_law(error: float, rate: float, f_hat: float, **law: float) -> AxisCommand:
    """Slotine's law for one axis whose velocity variable obeys ``rate_dot = f + command / b`` (Eqs. 26-29;
    the compiled :func:`uvms.control.sliding_kernels.slotine`).

    Args:
        error: ``e = x - x_d``.  rate: the surface's velocity variable ``vel``.
        f_hat: model estimate of ``rate_dot`` at zero command.
        law: the gains, as keywords: ``bandwidth`` (``lambda`` [1/s]), ``eta`` (reaching rate),
            ``boundary_layer`` (``Phi``), ``uncertainty`` (``F``, bound on ``|f - f_hat|``), ``b_hat``
            (``sqrt(b_min b_max)``), ``beta`` (``sqrt(b_max / b_min) >= 1``); optionally ``rate_desired``,
            ``acc_desired`` (desired ``vel`` and its derivative, 0 for station keeping) and ``error_rate`` (the
            exact ``de/dt`` when it differs from ``rate - rate_desired``, module docstring).
    """
    missing = [name for name in _LAW_REQUIRED if name not in law]
    unknown = sorted(set(law) - set(_LAW_REQUIRED) - set(_LAW_OPTIONAL))
    if missing or unknown:
        raise TypeError(f"slotine_law() needs {', '.join(_LAW_REQUIRED)} and accepts {', '.join(_LAW_OPTIONAL)}; "
                        f"missing {missing}, unknown {unknown}")
    g = {**_LAW_OPTIONAL, **law}
    e_dot = rate - g["rate_desired"] if g["error_rate"] is None else g["error_rate"]
    s, k, u_hat, command = kernels.slotine(float(error), float(rate), float(f_hat), float(g["bandwidth"]),
                                           float(g["eta"]), float(g["boundary_layer"]), float(g["uncertainty"]),
                                           float(g["b_hat"]), float(g["beta"]), float(g["rate_desired"]),
                                           float(g["acc_desired"]), float(e_dot))
    return AxisCommand(s=s, k=k, u_hat=u_hat, command=command)


# --------------------------------------------------------------------------------------- body-frame errors


@dataclass(frozen=True)
class AxisKinematics:
    """The surge, sway and yaw errors, their exact rates, the body velocities (rows of the compiled
    :func:`uvms.control.sliding_kernels.axis_kinematics_into`).

    ``error`` (3,): ``e_x, e_y`` [m], ``e_psi`` [rad]; ``error_rate`` (3,): their time derivatives
    ``(e_dot_x, e_dot_y, psi_dot)``; ``velocity`` (3,): the body velocities ``(u, v, r)`` [m/s, rad/s].
    """

    table: np.ndarray           # (7, 3), rows as in uvms.control.sliding_kernels

    @property
    def error(self) -> np.ndarray:
        return self.table[kernels.ERROR]

    @property
    def error_rate(self) -> np.ndarray:
        return self.table[kernels.ERROR_RATE]

    @property
    def velocity(self) -> np.ndarray:
        return self.table[kernels.VELOCITY]

    @property
    def euler(self) -> np.ndarray:
        """``(phi, theta, psi)`` [rad]."""
        return self.table[kernels.EULER]

    def rates(self, surface: str) -> np.ndarray:
        """The ``vel`` of ``s = vel + lambda e``: ``velocity`` (``"body_velocity"``) or ``error_rate``."""
        return self.velocity if surface == "body_velocity" else self.error_rate

    def accelerations(self, nu_dot: np.ndarray, surface: str) -> np.ndarray:
        """Time derivatives of :meth:`rates` for a body acceleration ``nu_dot = [omega_dot; v_dot]`` (6,):
        ``(u_dot, v_dot, r_dot)``, or ``(e_ddot_x, e_ddot_y, psi_ddot)`` (module docstring)."""
        out = np.zeros(3)
        kernels.axis_accelerations(self.table, np.array(nu_dot, dtype=float), surface == "body_velocity", out)
        return out


def axis_kinematics(state, position_desired: np.ndarray, yaw_desired: float) -> AxisKinematics:
    """Errors, rates and velocities of the surge, sway and yaw axes for a constant desired pose."""
    R, table = kernels.kinematics_buffers()
    # the desired position copied (writeable even when the caller's is read-only, a state's position): one
    # compiled signature, the one precompiled (uvms.precompile); nu_dot likewise in accelerations()
    kernels.axis_kinematics_into(state.quaternion, state.position, state.nu,
                                 np.array(position_desired, dtype=float), float(yaw_desired), R, table)
    table.flags.writeable = False
    return AxisKinematics(table)


# ------------------------------------------------------------------------------------------ parameters


@dataclass(frozen=True)
class SlidingModeParameters:
    """Parameters of the sliding-mode controllers (defaults: the paper's values, ``docs/conventions.md``)."""

    axes: tuple[str, ...] = parameter(PAPER_AXES, axis_list,
                                      "controlled axes, any of surge, sway, heave, roll, pitch, yaw (or all)")
    bandwidth: tuple[float, ...] = parameter(3.14, per_axis(positive),
                                             "lambda [1/s] of s = vel + lambda e (one, or one per axis)")
    eta: tuple[float, ...] = parameter(0.5, per_axis(positive),
                                       "reaching rate eta [m/s^2, rad/s^2]: d|s|/dt <= -eta outside the layer")
    boundary_layer: tuple[float, ...] = parameter(0.02, per_axis(positive),
                                                  "Phi [m/s, rad/s]: boundary-layer thickness (one, or per axis)")
    uncertainty: tuple[float, ...] = parameter(
        0.5, per_axis(non_negative), "F [m/s^2, rad/s^2]: bound on |f - f_hat| (one, or one per axis)")
    b_surge: tuple[float, float] = parameter(PAPER_B_TRANSLATION, bounds, "[b_min, b_max] surge mass [kg]")
    b_sway: tuple[float, float] = parameter(PAPER_B_TRANSLATION, bounds, "[b_min, b_max] sway mass [kg]")
    b_yaw: tuple[float, float] = parameter(PAPER_B_YAW, bounds, "[b_min, b_max] yaw inertia [kg m^2]")
    b_heave: tuple[float, float] | None = parameter(None, optional(bounds), "[b_min, b_max] heave mass [kg] "
                                                    "(default: b_hat from the controller's model, beta = b_margin)")
    b_roll: tuple[float, float] | None = parameter(None, optional(bounds), "[b_min, b_max] roll inertia [kg m^2] "
                                                   "(default: from the controller's model)")
    b_pitch: tuple[float, float] | None = parameter(None, optional(bounds), "[b_min, b_max] pitch inertia "
                                                    "[kg m^2] (default: from the controller's model)")
    b_source: str = parameter("fixed", choice("fixed", "model"),
                              "fixed: b from b_surge/b_sway/b_yaw; model: b_hat from the controller's model")
    b_margin: float = parameter(math.sqrt(PAPER_B_TRANSLATION[1] / PAPER_B_TRANSLATION[0]), at_least_one,
                                "beta used with b_source = model (default: the paper's sqrt(44.44/36))")
    surface: str = parameter("body_velocity", choice("body_velocity", "error_rate"),
                             "vel of s = vel + lambda e: body velocities (u, v, r) or the error rates")
    hydro_scale: float = parameter(0.4, non_negative,
                                   "controller model's added mass and drag = hydro_scale x the plant's (paper: 0.4)")
    desired_position: tuple[float, float, float] | None = parameter(
        None, optional(vector(3)), "world position to hold [m] (default: the position at the first update)")
    desired_yaw: float | None = parameter(None, optional(number),
                                          "yaw to hold [rad] (default: the yaw at the first update)")
    desired_roll: float = parameter(0.0, number, "roll to hold [rad] (default: level)")
    desired_pitch: float = parameter(0.0, number, "pitch to hold [rad] (default: level)")
    waypoints: tuple[tuple[float, ...], ...] = parameter(
        (), waypoint_rows, "later set points: rows [t, x, y, z, roll, pitch, yaw], each held from its time t [s] on")
    feedback: str = parameter("true_state", choice("true_state", "measured"),
                              "true_state: the controller reads the true state; measured: the state estimated from "
                              "the run's sensors (an IMU, a pressure sensor, a DVL, encoders; docs/sensors.md)")

    def __post_init__(self) -> None:
        for name in ("bandwidth", "eta", "boundary_layer", "uncertainty"):
            object.__setattr__(self, name, expand(getattr(self, name), self.axes, name))

    def b_limits(self) -> tuple[tuple[float, float], ...]:
        """The paper axes' bounds (surge, sway, yaw)."""
        return (self.b_surge, self.b_sway, self.b_yaw)

    def b_bounds(self, axis: str) -> tuple[float, float] | None:
        """``[b_min, b_max]`` of an axis, or ``None``: ``b_hat`` from the controller's model."""
        return getattr(self, f"b_{axis}")

    def targets(self) -> np.ndarray:
        """The (K, 7) set-point table of :func:`uvms.control.kernels.targets_table`."""
        from uvms.control.kernels import targets_table

        return targets_table(self.desired_position, (self.desired_roll, self.desired_pitch, self.desired_yaw),
                             self.waypoints)


# ------------------------------------------------------------------------------------------ the b bounds' fit


def fixed_bound_axes(parameters: SlidingModeParameters) -> tuple[str, ...]:
    """The controlled axes whose ``b`` comes from fixed ``[b_min, b_max]`` bounds (``b_source = "fixed"`` and
    bounds given): the axes whose guarantee (Eqs. 27-29) assumes the plant's effective inertia inside them."""
    if parameters.b_source != "fixed":
        return ()
    return tuple(a for a in parameters.axes if parameters.b_bounds(a) is not None)


def b_bounds_misses(parameters: SlidingModeParameters, inertia) -> str:
    """``"surge effective mass 21.19 kg outside [36, 44.44] kg, ..."`` for every axis of :func:`fixed_bound_axes` whose
    effective mass or inertia (``inertia``: (6,) in :data:`uvms.dynamics.axes.AXES` order, kg and kg m^2) lies
    outside its bounds; ``""`` when none does."""
    from uvms.dynamics.axes import AXES as INERTIA_AXES
    from uvms.dynamics.axes import INERTIA_UNITS

    misses = []
    for axis in fixed_bound_axes(parameters):
        j = INERTIA_AXES.index(axis)
        (lo, hi), value, unit = parameters.b_bounds(axis), float(inertia[j]), INERTIA_UNITS[j]
        if not lo <= value <= hi:
            kind = "mass" if unit == "kg" else "inertia"
            misses.append(f"{axis} effective {kind} {value:.4g} {unit} outside [{lo:.6g}, {hi:.6g}] {unit}")
    return ", ".join(misses)


def warn_b_bounds(model, parameters: SlidingModeParameters) -> str | None:
    """Warn (one :class:`UserWarning` line) when the controller relies on fixed ``b`` bounds that miss the
    plant's effective mass or inertia (:func:`uvms.dynamics.axes.effective_inertia`, arm at ``q = 0``); the
    text names no controller, so the three sliding-mode controllers of one comparison warn once (Python's
    default filter shows a warning once per text and place). Returns the
    line, or ``None`` (every bound contains the plant, or no axis uses fixed bounds: ``pid`` and ``lqr`` never
    call this)."""
    if model is None or not fixed_bound_axes(parameters):
        return None
    import warnings

    from uvms.dynamics.axes import effective_inertia

    misses = b_bounds_misses(parameters, effective_inertia(model, np.zeros(model.n_joints)))
    if not misses:
        return None
    line = (f"sliding-mode controller: its b bounds miss model {model.name!r} (arm at q = 0): {misses} (paper "
            "Eqs. 27-29 assume it inside); give controller.parameters.b_<axis> bounds that contain it, or "
            "b_source: model")
    warnings.warn(line, UserWarning, stacklevel=2)
    return line


def warn_controller_b_bounds(controller) -> str | None:
    """:func:`warn_b_bounds` for a controller about to be used (``uvms run`` after its inputs are checked,
    every case of :func:`uvms.control.compare.run_case`): only a sliding-mode controller can warn; any other
    (``pid``, ``lqr``, a user's) or ``None`` returns ``None``. A sweep's workers do not call it (their runs are
    counted in the sweep's table, not on the terminal)."""
    if not isinstance(controller, SlidingModeController):
        return None
    return warn_b_bounds(controller.plant, controller.parameters)


# ------------------------------------------------------------------------------------------ the controller


def state_vector(state) -> np.ndarray:
    """``[p | quat | nu | q | qd]`` of a :class:`~uvms.state.State` (the layout of :mod:`uvms.state`)."""
    return np.concatenate([state.position, state.quaternion, state.nu, state.q, state.qd]).astype(float)


class CompiledController:
    """The Python face of a compiled controller: ``update(measurement)`` runs :func:`uvms.control.kernels.controller_update`
    on the controller's own :class:`~uvms.control.kernels.ControllerData` (built by :meth:`compiled`)."""

    PYTHON_UPDATES = 256
    """``n_updates`` of the data used by the Python :meth:`update` (tables grow as needed)."""

    _data = None

    def compiled(self, n_updates: int):
        """A fresh :class:`~uvms.control.kernels.ControllerData` (memory reset) for ``n_updates`` updates."""
        raise NotImplementedError

    @property
    def signal_names(self) -> tuple[str, ...]:
        """Names of :attr:`ControllerData.signals`, the logged values of an update."""
        raise NotImplementedError

    @property
    def compiled_update(self) -> bool:
        """True when :meth:`update` is the compiled kernel's (a subclass overriding ``update`` runs in Python,
        through the :class:`~uvms.control.base.Controller` protocol)."""
        return type(self).update is CompiledController.update

    def reset(self) -> None:
        """Forget the memory (captured set point, integrators, IMU): the next update starts afresh."""
        self._data = None

    def _before_update(self, data):
        return data

    def update(self, measurement: Measurement) -> ControlOutput:
        from uvms.control.kernels import controller_update

        if self._data is None:
            self._data = self.compiled(self.PYTHON_UPDATES)
            self._names = self.signal_names
            self._wrench = np.zeros(6)
        data = self._data = self._before_update(self._data)
        nu_dot = (np.asarray(measurement.nu_dot, dtype=float) if data.needs_acceleration else data.zero6)
        controller_update(data, float(measurement.time), state_vector(measurement.state),
                          np.asarray(measurement.joint_torques, dtype=float), nu_dot, self._wrench)
        return ControlOutput(wrench=self._wrench.copy(), signals=dict(zip(self._names, data.signals.tolist())))


class SlidingModeController(CompiledController):
    """Sliding-mode station keeping on the chosen axes (default: surge, sway, yaw); subclasses choose the model
    that predicts ``f_hat`` (:meth:`model_options`).

    Logged signals per controlled axis ``a``: ``s_a``, ``k_a``, ``f_hat_a``, ``command_a``, ``e_a`` (and
    ``b_hat_a`` with ``b_source = "model"``), plus ``Phi``.
    """

    name = "smc"
    Parameters = SlidingModeParameters

    def __init__(self, model, parameters: SlidingModeParameters | None = None, *, period: float = 0.01) -> None:
        if not period > 0:
            raise UvmsInputError(f"expected a period > 0 [s], found {period!r}", path="controller.period")
        self._parameters = parameters or self.Parameters()
        self.period = float(period)
        self.plant = model
        self.axes = self.parameters.axes

    @property
    def parameters(self) -> SlidingModeParameters:
        """The parameters, fixed at construction (the controller's model and gains are derived from them once;
        build a new controller to change them)."""
        return self._parameters

    @property
    def signal_names(self) -> tuple[str, ...]:
        columns = ("s", "k", "f_hat", "command", "e") + (("b_hat",) if self.parameters.b_source == "model" else ())
        return tuple(f"{c}_{a}" for a in self.axes for c in columns) + ("Phi",)

    def model_options(self, n_updates: int) -> dict:
        """The :class:`~uvms.control.kernels.ControllerData` fields of the controller's model (``predictor``,
        ``system``, ``vehicle``, ``current``, ``fluid_acceleration``, ...)."""
        raise NotImplementedError

    def gain_table(self) -> np.ndarray:
        """(6, N_GAINS) per axis slot: lambda, eta, Phi, F, and from ``[b_min, b_max]``
        ``b_hat = sqrt(b_min b_max)`` (Eq. 28), ``beta = sqrt(b_max / b_min)`` (Eq. 29); axes without bounds
        take ``b_hat`` from the controller's model (column ``B_MODEL``)."""
        from uvms.control import kernels as ck

        par = self.parameters
        gains = np.zeros((6, ck.N_GAINS))
        for j, (axis, slot) in enumerate(zip(par.axes, slots(par.axes))):
            gains[slot, ck.BANDWIDTH] = par.bandwidth[j]
            gains[slot, ck.ETA] = par.eta[j]
            gains[slot, ck.PHI] = par.boundary_layer[j]
            gains[slot, ck.UNCERTAINTY] = par.uncertainty[j]
            b = par.b_bounds(axis)
            if b is None:
                gains[slot, ck.B_MODEL] = 1.0
            else:
                gains[slot, ck.B_HAT] = math.sqrt(b[0] * b[1])
                gains[slot, ck.BETA] = math.sqrt(b[1] / b[0])
        return gains

    def compiled(self, n_updates: int):
        from uvms.control import kernels as ck
        from uvms.control.kinds import SLIDING

        par = self.parameters
        return ck.controller_data(kind=SLIDING, n_joints=self.plant.n_joints, period=self.period,
                                  axes=slots(self.axes), gains=self.gain_table(), targets=par.targets(),
                                  n_signals=len(self.signal_names),
                                  body_velocity=par.surface == "body_velocity", b_from_model=par.b_source == "model",
                                  beta_model=float(par.b_margin), log_b_hat=par.b_source == "model",
                                  **self.model_options(n_updates))
