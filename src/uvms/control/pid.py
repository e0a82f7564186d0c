"""``pid``: a PID baseline on the same surge, sway and yaw errors as the sliding-mode controllers.

Per axis, with ``e`` and ``e_dot`` from :func:`uvms.control.smc.axis_kinematics` (body-frame position error
and its exact rate, yaw error and Euler yaw rate)::

    f = -(kp e + ki z + kd e_dot)    clipped to +/- limit         z = integral of e

Anti-windup by clamping (conditional integration): ``z`` is not advanced while the output is saturated and
``e`` would drive it further into saturation; ``|ki z|`` is also kept within the output limit.

Default gains place the three closed-loop poles of ``b e_ddot = f`` at ``-omega`` (triple pole):
``kd = 3 omega b``, ``kp = 3 omega^2 b``, ``ki = omega^3 b``, with ``omega = pi`` rad/s (the sliding-mode
bandwidth ``lambda``) and ``b`` the paper's nominal ``b_hat`` (40 kg surge and sway, 1.43 kg m^2 yaw).
Output limits 200 N and 50 N m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uvms.control.base import ControlOutput, Measurement
from uvms.control.registry import non_negative, number, optional, parameter, positive, register, vector
from uvms.control.smc import AXES, PAPER_B_TRANSLATION, PAPER_B_YAW, WRENCH_INDEX, axis_kinematics
from uvms.errors import UvmsInputError

_OMEGA = math.pi
_B = (math.sqrt(PAPER_B_TRANSLATION[0] * PAPER_B_TRANSLATION[1]),) * 2 + (math.sqrt(PAPER_B_YAW[0] * PAPER_B_YAW[1]),)


def _rounded(values) -> tuple[float, float, float]:
    a, b, c = (float(f"{v:.4g}") for v in values)
    return a, b, c


DEFAULT_KP = _rounded(3 * _OMEGA**2 * b for b in _B)
"""Default proportional gains (surge, sway, yaw) [N/m, N/m, N m/rad]."""
DEFAULT_KI = _rounded(_OMEGA**3 * b for b in _B)
"""Default integral gains [N/(m s), N/(m s), N m/(rad s)]."""
DEFAULT_KD = _rounded(3 * _OMEGA * b for b in _B)
"""Default derivative gains [N s/m, N s/m, N m s/rad]."""


@dataclass(frozen=True)
class PidParameters:
    """Gains and limits per axis (surge, sway, yaw); a single number applies to all three axes."""

    kp: tuple[float, float, float] = parameter(DEFAULT_KP, vector(3, non_negative, scalar=True),
                                               "proportional gains [N/m, N/m, N m/rad]")
    ki: tuple[float, float, float] = parameter(DEFAULT_KI, vector(3, non_negative, scalar=True),
                                               "integral gains [N/(m s), N/(m s), N m/(rad s)]")
    kd: tuple[float, float, float] = parameter(DEFAULT_KD, vector(3, non_negative, scalar=True),
                                               "derivative gains [N s/m, N s/m, N m s/rad]")
    limit: tuple[float, float, float] = parameter((200.0, 200.0, 50.0), vector(3, positive, scalar=True),
                                                  "output limits [N, N, N m]")
    desired_position: tuple[float, float, float] | None = parameter(
        None, optional(vector(3)), "world position to hold [m] (default: the position at the first update)")
    desired_yaw: float | None = parameter(None, optional(number),
                                          "yaw to hold [rad] (default: the yaw at the first update)")


@register("pid")
class PidController:
    """PID station keeping on the body-frame surge and sway errors and the yaw error, with clamping anti-windup.

    Logs per axis ``e_<axis>``, ``integral_<axis>``, ``command_<axis>``.
    """

    Parameters = PidParameters

    def __init__(self, model=None, parameters: PidParameters | None = None, *, period: float = 0.01) -> None:
        if not period > 0:
            raise UvmsInputError(f"expected a period > 0 [s], found {period!r}", path="controller.period")
        self.parameters = parameters or PidParameters()
        self.period = float(period)
        self.reset()

    def reset(self) -> None:
        """Zero the integrators and forget the captured desired pose."""
        self._integral = np.zeros(3)
        self._position_desired: np.ndarray | None = None
        self._yaw_desired = 0.0

    def update(self, measurement: Measurement) -> ControlOutput:
        par = self.parameters
        state = measurement.state
        if self._position_desired is None:
            self._position_desired = (np.array(par.desired_position, dtype=float) if par.desired_position is not None
                                      else np.array(state.position, dtype=float))
            self._yaw_desired = par.desired_yaw if par.desired_yaw is not None else float(state.euler[2])
        kin = axis_kinematics(state, self._position_desired, self._yaw_desired)
        kp, ki, kd, limit = (np.array(x) for x in (par.kp, par.ki, par.kd, par.limit))
        e, e_dot = kin.error, kin.error_rate
        unclamped = -(kp * e + ki * self._integral + kd * e_dot)
        saturated = np.abs(unclamped) >= limit
        pushing = np.sign(unclamped) == -np.sign(e)          # integrating e moves the output that way
        advance = ~(saturated & pushing)
        self._integral = np.where(advance, self._integral + e * self.period, self._integral)
        with np.errstate(divide="ignore", invalid="ignore"):
            cap = np.where(ki > 0, limit / ki, np.inf)
        self._integral = np.clip(self._integral, -cap, cap)
        force = np.clip(-(kp * e + ki * self._integral + kd * e_dot), -limit, limit)
        wrench = np.zeros(6)
        signals: dict[str, float] = {}
        for j, axis in enumerate(AXES):
            wrench[WRENCH_INDEX[j]] = force[j]
            signals[f"e_{axis}"] = float(e[j])
            signals[f"integral_{axis}"] = float(self._integral[j])
            signals[f"command_{axis}"] = float(force[j])
        return ControlOutput(wrench=wrench, signals=signals)
