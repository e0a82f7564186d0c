"""Ideal thruster: the thrust equals the command, clipped to the thrust limits (no dynamics, no state)::

    T = clip(T_cmd, -T_max, T_max)

The default ``T_max`` = 51.8 N is the default Healey thruster's steady thrust at 24 V. (Body-wrench
actuation with no thrusters at all is the layout ``"ideal"`` of :mod:`uvms.thrusters.layouts`.)
The compiled kernel takes :meth:`IdealParameters.as_array` = ``[T_max]``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

P_MAX_THRUST = 0
N_PARAMETERS = 1


@dataclass(frozen=True)
class IdealParameters:
    """Parameters of an ideal thruster.

    Attributes:
        max_thrust: ``T_max`` [N], > 0 (``inf`` allowed: no limit).
    """

    max_thrust: float = 51.8

    def __post_init__(self) -> None:
        if not self.max_thrust > 0:
            raise ValueError(f"IdealParameters.max_thrust must be positive, got {self.max_thrust}")

    def as_array(self) -> np.ndarray:
        """(1,) ``[T_max]`` for the kernel."""
        return np.array([self.max_thrust], dtype=np.float64)


@njit(cache=True)
def ideal_thrust(p: np.ndarray, T_cmd: float) -> float:
    """Delivered thrust [N]: the command ``T_cmd`` [N] clipped to ``+/-T_max``."""
    T_max = p[P_MAX_THRUST]
    return min(max(T_cmd, -T_max), T_max)
