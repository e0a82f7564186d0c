"""Actuators inside the compiled loop: body-wrench (ideal) actuation or a thruster layout (paper Eqs. 9-12).

A thruster layout has ``m`` thrusters of kinds (:mod:`uvms.thrusters.kinds`) ideal (thrust = clipped command,
no state), first-order lag (state: thrust), Healey (states: propeller speed ``Omega`` and inflow ``U``) or table
(datasheet lookup with a first-order lag, :mod:`uvms.thrusters.table`; state: thrust). The body wrench is
``f_0 = Lambda T`` (Eq. 11). Commands held by the zero-order hold are thrusts [N] for ideal and first-order
thrusters, voltages [V] for Healey thrusters and the table's command (e.g. ESC pulse width [us]) for table
thrusters; with no thrusters the command is the body wrench itself.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from uvms.jit import kernel
from uvms.thrusters import first_order, healey, ideal
from uvms.thrusters.kinds import N_STATES, kind_of, thruster_rates
from uvms.thrusters.layouts import layout_matrix

N_PARAMETERS = max(healey.N_PARAMETERS, first_order.N_PARAMETERS, ideal.N_PARAMETERS)


class ActuatorKernel(NamedTuple):
    """Flat arrays of a thruster layout for the kernels (``m = 0``: ideal body-wrench actuation)."""

    kind: np.ndarray          # (m,) int64 thruster kinds (uvms.thrusters.kinds)
    allocation: np.ndarray    # (6, m) Lambda, columns [r x e; e]
    params: np.ndarray        # (m, max(N_PARAMETERS, longest table array))
    offset: np.ndarray        # (m,) index of each thruster's first state in the actuator state vector


def actuator_kernel(thrusters) -> ActuatorKernel:
    """Kernel arrays of a layout (a tuple of :class:`~uvms.thrusters.layouts.Thruster`)."""
    m = len(thrusters)
    kind = np.array([kind_of(t.model) for t in thrusters], dtype=np.int64)
    arrays = [t.parameters.as_array() for t in thrusters]
    params = np.zeros((m, max([N_PARAMETERS] + [p.size for p in arrays])))
    offset = np.zeros(m, dtype=np.int64)
    k = 0
    for j, t in enumerate(thrusters):
        p = arrays[j]
        params[j, : p.size] = p
        offset[j] = k
        k += N_STATES[int(kind[j])]
    return ActuatorKernel(kind=kind, allocation=np.ascontiguousarray(layout_matrix(tuple(thrusters))),
                          params=params, offset=offset)


def n_actuator_states(act: ActuatorKernel) -> int:
    """Size of the actuator state vector."""
    return int(sum(N_STATES[int(k)] for k in act.kind))


@kernel
def actuator_rates(act, states, command, f_body, rates, thrust):
    """Body wrench ``f_body = Lambda T`` (6), state rates and thrusts ``T`` (m) for the held commands."""
    m = act.kind.shape[0]
    if m == 0:
        for k in range(6):
            f_body[k] = command[k]
        return
    for j in range(m):
        thrust[j] = thruster_rates(act.kind[j], act.params[j], states, act.offset[j], command[j], rates)
    for k in range(6):
        s = 0.0
        for j in range(m):
            s += act.allocation[k, j] * thrust[j]
        f_body[k] = s
