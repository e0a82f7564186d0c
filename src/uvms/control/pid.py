"""``pid``: a PID baseline on the same surge, sway and yaw errors as the sliding-mode controllers.

Per axis, with ``e`` and ``e_dot`` from :func:`uvms.control.sliding_kernels.pose_kinematics_into` (body-frame position error
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

from uvms.control.registry import choice, non_negative, number, optional, parameter, positive, register, vector
from uvms.control.axes import PAPER_AXES, TRANSLATIONS, axis_list, expand, per_axis, slots, waypoint_rows
from uvms.control.smc import PAPER_B_TRANSLATION, PAPER_B_YAW, CompiledController
from uvms.errors import UvmsInputError

_OMEGA = math.pi
_B = (math.sqrt(PAPER_B_TRANSLATION[0] * PAPER_B_TRANSLATION[1]),) * 2 + (math.sqrt(PAPER_B_YAW[0] * PAPER_B_YAW[1]),)


def default_gain(name: str, axis: str) -> float:
    """Default ``kp``, ``ki``, ``kd`` or ``limit`` of an axis: the triple pole at ``-pi`` rad/s for the paper's
    nominal ``b`` (40 kg on translations, 1.43 kg m^2 on rotations), limits 200 N and 50 N m."""
    translation = axis in TRANSLATIONS
    if name == "limit":
        return 200.0 if translation else 50.0
    b = _B[0] if translation else _B[2]
    value = {"kp": 3 * _OMEGA**2 * b, "ki": _OMEGA**3 * b, "kd": 3 * _OMEGA * b}[name]
    return float(f"{value:.4g}")


@dataclass(frozen=True)
class PidParameters:
    """Gains and limits per axis; one number applies to every axis (default: :func:`default_gain`)."""

    axes: tuple[str, ...] = parameter(PAPER_AXES, axis_list,
                                      "controlled axes, any of surge, sway, heave, roll, pitch, yaw (or all)")
    kp: tuple[float, ...] | None = parameter(None, optional(per_axis(non_negative)),
                                             "proportional gains [N/m, N m/rad] (default: triple pole at -pi)")
    ki: tuple[float, ...] | None = parameter(None, optional(per_axis(non_negative)),
                                             "integral gains [N/(m s), N m/(rad s)]")
    kd: tuple[float, ...] | None = parameter(None, optional(per_axis(non_negative)),
                                             "derivative gains [N s/m, N m s/rad]")
    limit: tuple[float, ...] | None = parameter(None, optional(per_axis(positive)),
                                                "output limits [N, N m] (default 200 N, 50 N m)")
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
        for name in ("kp", "ki", "kd", "limit"):
            object.__setattr__(self, name, expand(getattr(self, name), self.axes, name,
                                                  lambda axis, name=name: default_gain(name, axis)))

    def targets(self) -> np.ndarray:
        """The (K, 7) set-point table of :func:`uvms.control.kernels.targets_table`."""
        from uvms.control.kernels import targets_table

        return targets_table(self.desired_position, (self.desired_roll, self.desired_pitch, self.desired_yaw),
                             self.waypoints)


@register("pid")
class PidController(CompiledController):
    """PID station keeping on the body-frame surge and sway errors and the yaw error, with clamping anti-windup.

    Logs per axis ``e_<axis>``, ``integral_<axis>``, ``command_<axis>``. The update is
    :func:`uvms.control.kernels.controller_update` (kind ``PID``).
    """

    Parameters = PidParameters

    def __init__(self, model=None, parameters: PidParameters | None = None, *, period: float = 0.01) -> None:
        if not period > 0:
            raise UvmsInputError(f"expected a period > 0 [s], found {period!r}", path="controller.period")
        self.parameters = parameters or PidParameters()
        self.period = float(period)
        self.plant = model
        self.axes = self.parameters.axes
        self.reset()

    @property
    def signal_names(self) -> tuple[str, ...]:
        return tuple(f"{c}_{a}" for a in self.axes for c in ("e", "integral", "command"))

    def gain_table(self) -> np.ndarray:
        """(6, N_GAINS) with kp, ki, kd and the output limit per axis slot."""
        from uvms.control import kernels as ck

        par = self.parameters
        gains = np.zeros((6, ck.N_GAINS))
        for j, slot in enumerate(slots(par.axes)):
            gains[slot, [ck.KP, ck.KI, ck.KD, ck.LIMIT]] = par.kp[j], par.ki[j], par.kd[j], par.limit[j]
        return gains

    def compiled(self, n_updates: int):
        from uvms.control import kernels as ck
        from uvms.control.kinds import PID

        par = self.parameters
        n = 0 if self.plant is None else self.plant.n_joints
        return ck.controller_data(kind=PID, n_joints=n, period=self.period,
                                  axes=slots(self.axes), gains=self.gain_table(), targets=par.targets(),
                                  n_signals=len(self.signal_names))
