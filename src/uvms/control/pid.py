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

from uvms.control.registry import non_negative, number, optional, parameter, positive, register, vector
from uvms.control.sliding_kernels import AXIS_NAMES
from uvms.control.smc import AXES, PAPER_B_TRANSLATION, PAPER_B_YAW, CompiledController
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
        self.axes = AXES
        self.reset()

    @property
    def signal_names(self) -> tuple[str, ...]:
        return tuple(f"{c}_{a}" for a in self.axes for c in ("e", "integral", "command"))

    def gain_table(self) -> np.ndarray:
        """(6, N_GAINS) with kp, ki, kd and the output limit per axis slot."""
        from uvms.control import kernels as ck

        par = self.parameters
        gains = np.zeros((6, ck.N_GAINS))
        for j, a in enumerate(AXES):
            slot = AXIS_NAMES.index(a)
            gains[slot, [ck.KP, ck.KI, ck.KD, ck.LIMIT]] = par.kp[j], par.ki[j], par.kd[j], par.limit[j]
        return gains

    def compiled(self, n_updates: int):
        from uvms.control import kernels as ck

        par = self.parameters
        n = 0 if self.plant is None else self.plant.n_joints
        return ck.controller_data(kind=ck.PID, n_joints=n, period=self.period,
                                  axes=[AXIS_NAMES.index(a) for a in self.axes], gains=self.gain_table(),
                                  targets=ck.targets_table(par.desired_position, (None, None, par.desired_yaw)),
                                  n_signals=len(self.signal_names))
