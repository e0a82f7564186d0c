"""Slotine's per-axis sliding-mode law (paper Section 5, Eqs. 24-30; Slotine & Li 1991), shared by the
``smc-ab``, ``smc-ne`` and ``smc-vehicle`` controllers, which differ only in how they predict ``f_hat``.

Axes: surge, sway, yaw (``shared/conventions.md``, "Sliding-mode controller"). For a constant desired pose
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
from uvms.rotations import wrap_angle

AXES: tuple[str, ...] = ("surge", "sway", "yaw")
"""The controlled axes, in this order everywhere (errors, gains, logged signals)."""
SIGNAL_NAMES = tuple(tuple(f"{kind}_{axis}" for kind in ("s", "k", "f_hat", "command", "e", "b_hat")) for axis in AXES)
"""Logged signal names per axis (built once)."""

WRENCH_INDEX: tuple[int, ...] = (3, 4, 2)
"""Where each axis' command goes in the body wrench ``[K, M, N, X, Y, Z]``: X (surge), Y (sway), N (yaw)."""

PAPER_B_TRANSLATION = (36.0, 44.44)
"""Paper's bounds of the surge and sway effective mass [kg]."""
PAPER_B_YAW = (1.287, 1.5889)
"""Paper's bounds of the yaw effective inertia [kg m^2]."""


def sat(x: float) -> float:
    """The saturation function: ``x`` clipped to [-1, 1]."""
    return min(1.0, max(-1.0, x))


# ---------------------------------------------------------------------------------------------- the law


@dataclass(frozen=True)
class AxisCommand:
    """One axis' update: sliding variable ``s``, gain ``k``, model-based part ``u_hat`` and the command
    ``b_hat (u_hat - k sat(s / Phi))`` [N or N m] (before the yaw axis' Euler-angle factor)."""

    s: float
    k: float
    u_hat: float
    command: float


def slotine_law(error: float, rate: float, f_hat: float, *, bandwidth: float, eta: float, boundary_layer: float,
                uncertainty: float, b_hat: float, beta: float, rate_desired: float = 0.0,
                acc_desired: float = 0.0, error_rate: float | None = None) -> AxisCommand:
    """Slotine's law for one axis whose velocity variable obeys ``rate_dot = f + command / b`` (Eqs. 26-29).

    Args:
        error: ``e = x - x_d``.  rate: the surface's velocity variable ``vel``.
        f_hat: model estimate of ``rate_dot`` at zero command.
        bandwidth: ``lambda`` [1/s].  eta: reaching rate.  boundary_layer: ``Phi``.
        uncertainty: ``F``, bound on ``|f - f_hat|``.
        b_hat: ``sqrt(b_min b_max)``.  beta: ``sqrt(b_max / b_min) >= 1``.
        rate_desired, acc_desired: desired ``vel`` and its derivative (0 for station keeping).
        error_rate: the exact ``de/dt`` when it differs from ``rate - rate_desired`` (module docstring).
    """
    rate_error = rate - rate_desired
    s = rate_error + bandwidth * error
    u_hat = -f_hat + acc_desired - bandwidth * (rate_error if error_rate is None else error_rate)
    k = beta * (uncertainty + eta) + (beta - 1.0) * abs(u_hat)
    return AxisCommand(s=s, k=k, u_hat=u_hat, command=b_hat * (u_hat - k * sat(s / boundary_layer)))


# --------------------------------------------------------------------------------------- body-frame errors


@dataclass(frozen=True)
class AxisKinematics:
    """The surge, sway and yaw errors, their exact rates, the body velocities, and their accelerations.

    ``error`` (3,): ``e_x, e_y`` [m], ``e_psi`` [rad]; ``error_rate`` (3,): their time derivatives
    ``(e_dot_x, e_dot_y, psi_dot)``; ``velocity`` (3,): the body velocities ``(u, v, r)`` [m/s, rad/s].
    """

    error: np.ndarray
    error_rate: np.ndarray
    velocity: np.ndarray
    error3: np.ndarray          # full body-frame position error e (3,) [m]
    rate3: np.ndarray           # e_dot (3,) [m/s]
    omega: np.ndarray           # (3,) body angular velocity [rad/s]
    euler: np.ndarray           # (phi, theta, psi) [rad]

    def rates(self, surface: str) -> np.ndarray:
        """The ``vel`` of ``s = vel + lambda e``: ``velocity`` (``"body_velocity"``) or ``error_rate``."""
        return self.velocity if surface == "body_velocity" else self.error_rate

    def accelerations(self, nu_dot: np.ndarray, surface: str) -> np.ndarray:
        """Time derivatives of :meth:`rates` for a body acceleration ``nu_dot = [omega_dot; v_dot]`` (6,):
        ``(u_dot, v_dot, r_dot)``, or ``(e_ddot_x, e_ddot_y, psi_ddot)`` (module docstring)."""
        if surface == "body_velocity":
            return np.array([nu_dot[3], nu_dot[4], nu_dot[2]])
        omega_dot = nu_dot[:3]
        e_ddot = nu_dot[3:] - _cross(omega_dot, self.error3) - _cross(self.omega, self.rate3)
        phi, theta, _ = self.euler
        p, q, r = self.omega
        sp, cp, ct, tt = math.sin(phi), math.cos(phi), math.cos(theta), math.tan(theta)
        psi_dot = self.error_rate[2]
        theta_dot = cp * q - sp * r
        phi_dot = p + psi_dot * math.sin(theta)
        psi_ddot = ((sp * omega_dot[1] + cp * omega_dot[2]) / ct + phi_dot * theta_dot / ct
                    + theta_dot * tt * psi_dot)
        return np.array([e_ddot[0], e_ddot[1], psi_ddot])

    def input_gain(self, surface: str) -> np.ndarray:
        """How each axis' acceleration responds to its command per unit of ``command / b``: 1, except
        ``cos(phi) / cos(theta)`` for ``psi_ddot`` on the ``"error_rate"`` surface."""
        if surface == "body_velocity":
            return np.ones(3)
        phi, theta, _ = self.euler
        return np.array([1.0, 1.0, math.cos(phi) / math.cos(theta)])


def _cross(a, b) -> np.ndarray:
    """3-vector cross product without numpy's general-axis machinery (this runs every control update)."""
    return np.array([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]])


def axis_kinematics(state, position_desired: np.ndarray, yaw_desired: float) -> AxisKinematics:
    """Errors, rates and velocities of the surge, sway and yaw axes for a constant desired pose.

    Written with scalar math (it runs at every control update)."""
    R = state.rotation
    p0, p1, p2, q0, q1, q2, r0, r1, r2 = R.ravel().tolist()
    d0, d1, d2 = (state.position - position_desired).tolist()
    w0, w1, w2, u, v, w = state.nu.tolist()
    e0 = p0 * d0 + q0 * d1 + r0 * d2                  # e = R^T (p - p_d)
    e1 = p1 * d0 + q1 * d1 + r1 * d2
    e2 = p2 * d0 + q2 * d1 + r2 * d2
    ed0 = u - (w1 * e2 - w2 * e1)                      # e_dot = v - omega x e
    ed1 = v - (w2 * e0 - w0 * e2)
    ed2 = w - (w0 * e1 - w1 * e0)
    theta = -math.asin(min(max(r0, -1.0), 1.0))        # ZYX Euler angles of R (r0 = R[2, 0])
    phi = math.atan2(r1, r2)
    psi = math.atan2(q0, p0)
    psi_dot = (math.sin(phi) * w1 + math.cos(phi) * w2) / math.cos(theta)
    return AxisKinematics(
        error=np.array([e0, e1, wrap_angle(psi - yaw_desired)]),
        error_rate=np.array([ed0, ed1, psi_dot]),
        velocity=np.array([u, v, w2]),
        error3=np.array([e0, e1, e2]), rate3=np.array([ed0, ed1, ed2]), omega=np.array([w0, w1, w2]),
        euler=np.array([phi, theta, psi]),
    )


# ------------------------------------------------------------------------------------------ parameters


@dataclass(frozen=True)
class SlidingModeParameters:
    """Parameters of the sliding-mode controllers (defaults: the paper's values, ``shared/conventions.md``)."""

    bandwidth: float = parameter(3.14, positive, "lambda [1/s]: the sliding surface s = vel + lambda e")
    eta: float = parameter(0.5, positive, "reaching rate eta [m/s^2, rad/s^2]: d|s|/dt <= -eta outside the layer")
    boundary_layer: float = parameter(0.02, positive, "Phi [m/s, rad/s]: boundary-layer thickness")
    uncertainty: tuple[float, float, float] = parameter(
        (0.5, 0.5, 0.5), vector(3, non_negative, scalar=True),
        "F (surge, sway, yaw) [m/s^2, m/s^2, rad/s^2]: bound on |f - f_hat|")
    b_surge: tuple[float, float] = parameter(PAPER_B_TRANSLATION, bounds, "[b_min, b_max] surge mass [kg]")
    b_sway: tuple[float, float] = parameter(PAPER_B_TRANSLATION, bounds, "[b_min, b_max] sway mass [kg]")
    b_yaw: tuple[float, float] = parameter(PAPER_B_YAW, bounds, "[b_min, b_max] yaw inertia [kg m^2]")
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

    def b_limits(self) -> tuple[tuple[float, float], ...]:
        return (self.b_surge, self.b_sway, self.b_yaw)


# ------------------------------------------------------------------------------------------ the models


def effective_inertia(inertia: np.ndarray) -> np.ndarray:
    """Per axis (surge, sway, yaw), ``1 / (I^-1)_jj`` of a 6x6 inertia mapping a body wrench to ``nu_dot``:
    the mass or inertia a force on that axis meets when every other axis is free [kg, kg, kg m^2]."""
    inverse = np.linalg.inv(inertia)
    return np.array([1.0 / inverse[j, j] for j in WRENCH_INDEX])


# ------------------------------------------------------------------------------------------ the controller


class SlidingModeController:
    """Surge, sway and yaw sliding-mode station keeping; subclasses implement :meth:`predict`.

    Logged signals per axis ``a`` in (surge, sway, yaw): ``s_a``, ``k_a``, ``f_hat_a``, ``command_a``, ``e_a``
    (and ``b_hat_a`` with ``b_source = "model"``), plus ``Phi``.
    """

    name = "smc"
    Parameters = SlidingModeParameters

    def __init__(self, model, parameters: SlidingModeParameters | None = None, *, period: float = 0.01) -> None:
        if not period > 0:
            raise UvmsInputError(f"expected a period > 0 [s], found {period!r}", path="controller.period")
        self.parameters = parameters or self.Parameters()
        self.period = float(period)
        self.plant = model
        self._position_desired: np.ndarray | None = None
        self._yaw_desired = 0.0

    def reset(self) -> None:
        """Forget the captured desired pose (taken again at the next update unless given)."""
        self._position_desired = None

    def predict(self, measurement: Measurement) -> tuple[np.ndarray, np.ndarray]:
        """The controller model's ``nu_dot`` (6,) at ``f_0 = 0`` and the 6x6 inertia that maps a body
        wrench to ``nu_dot`` in that model (for ``b_source = "model"``)."""
        raise NotImplementedError

    @property
    def _fixed_b(self) -> tuple[np.ndarray, np.ndarray]:
        """``b_hat = sqrt(b_min b_max)`` and ``beta = sqrt(b_max / b_min)`` per axis from the fixed bounds (Eq. 28-29)."""
        cached = self.__dict__.get("_fixed_b_cache")
        if cached is None:
            limits = np.array(self.parameters.b_limits())
            cached = (np.sqrt(limits[:, 0] * limits[:, 1]), np.sqrt(limits[:, 1] / limits[:, 0]))
            self.__dict__["_fixed_b_cache"] = cached
        return cached

    def _desired(self, state) -> tuple[np.ndarray, float]:
        if self._position_desired is None:
            par = self.parameters
            self._position_desired = (np.array(par.desired_position, dtype=float) if par.desired_position is not None
                                      else np.array(state.position, dtype=float))
            self._yaw_desired = par.desired_yaw if par.desired_yaw is not None else float(state.euler[2])
        return self._position_desired, self._yaw_desired

    def update(self, measurement: Measurement) -> ControlOutput:
        par = self.parameters
        position_d, yaw_d = self._desired(measurement.state)
        kin = axis_kinematics(measurement.state, position_d, yaw_d)
        nu_dot_hat, inertia = self.predict(measurement)
        rates = kin.rates(par.surface)
        f_hat = kin.accelerations(nu_dot_hat, par.surface)
        gain = kin.input_gain(par.surface)
        if par.b_source == "model":
            b_hat = effective_inertia(inertia)
            beta = np.full(3, par.b_margin)
        else:
            b_hat, beta = self._fixed_b
        wrench = np.zeros(6)
        signals: dict[str, float] = {"Phi": par.boundary_layer}
        error, rate, fh, error_rate = kin.error.tolist(), rates.tolist(), f_hat.tolist(), kin.error_rate.tolist()
        bh, bt = b_hat.tolist(), beta.tolist()
        for j, names in enumerate(SIGNAL_NAMES):
            cmd = slotine_law(error[j], rate[j], fh[j], bandwidth=par.bandwidth, eta=par.eta,
                              boundary_layer=par.boundary_layer, uncertainty=par.uncertainty[j], b_hat=bh[j],
                              beta=bt[j], error_rate=error_rate[j])
            force = cmd.command / float(gain[j])
            wrench[WRENCH_INDEX[j]] = force
            s_name, k_name, f_name, c_name, e_name, b_name = names
            signals[s_name] = cmd.s
            signals[k_name] = cmd.k
            signals[f_name] = fh[j]
            signals[c_name] = force
            signals[e_name] = error[j]
            if par.b_source == "model":
                signals[b_name] = bh[j]
        return ControlOutput(wrench=wrench, signals=signals)
