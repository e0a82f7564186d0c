"""First-order thrust lag: a thruster whose thrust follows the command with one time constant.

State: thrust ``T`` [N]; input: commanded thrust ``T_cmd`` [N], clipped to ``+/-T_max``::

    dT/dt = (clip(T_cmd, -T_max, T_max) - T) / tau

A cheap stand-in for :mod:`uvms.thrusters.healey`: the default ``tau`` = 31 ms matches the Healey thruster's
63 % rise time at full voltage and ``T_max`` = 51.8 N its steady thrust at 24 V, but the lag is the same at
every thrust (the Healey thruster is slower near zero thrust). Explicit RK4 is stable for steps up to
``2.785 tau`` (86 ms at the default).

The compiled kernels take the flat array of :meth:`FirstOrderParameters.as_array`
(``[tau, T_max]``, indices ``P_TIME_CONSTANT``, ``P_MAX_THRUST``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

P_TIME_CONSTANT, P_MAX_THRUST = 0, 1
N_PARAMETERS = 2


@dataclass(frozen=True)
class FirstOrderParameters:
    """Parameters of a first-order thrust lag.

    Attributes:
        time_constant: ``tau`` [s], > 0.
        max_thrust: ``T_max`` [N], > 0; commands are clipped to ``+/-T_max``.
    """

    time_constant: float = 0.031
    max_thrust: float = 51.8

    def __post_init__(self) -> None:
        if not (math.isfinite(self.time_constant) and self.time_constant > 0):
            raise ValueError(f"FirstOrderParameters.time_constant must be positive, got {self.time_constant}")
        if not self.max_thrust > 0:
            raise ValueError(f"FirstOrderParameters.max_thrust must be positive, got {self.max_thrust}")

    def as_array(self) -> np.ndarray:
        """(2,) ``[tau, T_max]`` for the kernels."""
        return np.array([self.time_constant, self.max_thrust], dtype=np.float64)


@njit(cache=True)
def first_order_derivative(p: np.ndarray, T: float, T_cmd: float) -> float:
    """``dT/dt`` [N/s] of the lag at thrust ``T`` [N] and command ``T_cmd`` [N] (clipped to ``+/-T_max``)."""
    T_max = p[P_MAX_THRUST]
    target = min(max(T_cmd, -T_max), T_max)
    return (target - T) / p[P_TIME_CONSTANT]


@njit(cache=True)
def first_order_rk4_step(p: np.ndarray, T: float, T_cmd: float, h: float) -> float:
    """One classical RK4 step of length ``h`` [s] at constant command; returns the new thrust [N]."""
    k1 = first_order_derivative(p, T, T_cmd)
    k2 = first_order_derivative(p, T + 0.5 * h * k1, T_cmd)
    k3 = first_order_derivative(p, T + 0.5 * h * k2, T_cmd)
    k4 = first_order_derivative(p, T + h * k3, T_cmd)
    return T + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)


def first_order_exact(params: FirstOrderParameters, T0: float, T_cmd: float, t: float | np.ndarray):
    """Exact response ``T(t)`` [N] from ``T0`` to a constant command (for tests and plots)."""
    target = min(max(T_cmd, -params.max_thrust), params.max_thrust)
    return target + (T0 - target) * np.exp(-np.asarray(t, dtype=float) / params.time_constant)
