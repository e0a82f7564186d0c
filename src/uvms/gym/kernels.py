"""Compiled helpers of the Gymnasium environments."""

from __future__ import annotations

from numba import njit

from uvms.thrusters.command import HEALEY, TABLE
from uvms.thrusters.healey import healey_voltage_for_thrust
from uvms.thrusters.table import table_command


@njit(cache=True, nogil=True)
def thrust_commands(kind, params, coefficients, thrusts, out):
    """``out[k, h]``: the command of thruster ``h`` for the steady thrust ``thrusts[k, h]`` [N] (Healey's
    steady-state voltage, a table thruster's inverse table, or the thrust itself), as the last stage of
    :func:`uvms.thrusters.command.allocate_command` (``kind``, ``params``, ``coefficients``: the fields of its
    :class:`~uvms.thrusters.command.ThrustCommand`)."""
    for k in range(thrusts.shape[0]):
        for h in range(thrusts.shape[1]):
            T = thrusts[k, h]
            if kind[h] == HEALEY:
                out[k, h] = healey_voltage_for_thrust(params[h], coefficients[h], T)
            elif kind[h] == TABLE:
                out[k, h] = table_command(params[h], T)
            else:
                out[k, h] = T
