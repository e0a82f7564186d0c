"""Actuators inside the compiled loop: body-wrench (ideal) actuation or a thruster layout (paper Eqs. 9-12).

A thruster layout has ``m`` thrusters of kinds ideal (thrust = clipped command, no state), first-order lag
(state: thrust), Healey (states: propeller speed ``Omega`` and inflow ``U``) or table (datasheet lookup with a
first-order lag, :mod:`uvms.thrusters.table`; state: thrust). The body wrench is
``f_0 = Lambda T`` (Eq. 11). Commands held by the zero-order hold are thrusts [N] for ideal and first-order
thrusters, voltages [V] for Healey thrusters and the table's command (e.g. ESC pulse width [us]) for table
thrusters; with no thrusters the command is the body wrench itself.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from uvms.jit import kernel
from uvms.thrusters import first_order, healey, ideal, table
from uvms.thrusters.layouts import layout_matrix

KIND_IDEAL, KIND_FIRST_ORDER, KIND_HEALEY, KIND_TABLE = 0, 1, 2, 3
_KINDS = {"ideal": KIND_IDEAL, "first_order": KIND_FIRST_ORDER, "healey": KIND_HEALEY, "table": KIND_TABLE}
_N_STATES = {KIND_IDEAL: 0, KIND_FIRST_ORDER: 1, KIND_HEALEY: 2, KIND_TABLE: 1}
N_PARAMETERS = max(healey.N_PARAMETERS, first_order.N_PARAMETERS, ideal.N_PARAMETERS)


class ActuatorKernel(NamedTuple):
    """Flat arrays of a thruster layout for the kernels (``m = 0``: ideal body-wrench actuation)."""

    kind: np.ndarray          # (m,) int64
    allocation: np.ndarray    # (6, m) Lambda, columns [r x e; e]
    params: np.ndarray        # (m, max(N_PARAMETERS, longest table array))
    offset: np.ndarray        # (m,) index of each thruster's first state in the actuator state vector


def actuator_kernel(thrusters) -> ActuatorKernel:
    """Kernel arrays of a layout (a tuple of :class:`~uvms.thrusters.layouts.Thruster`)."""
    m = len(thrusters)
    kind = np.array([_KINDS[t.model] for t in thrusters], dtype=np.int64)
    arrays = [t.parameters.as_array() for t in thrusters]
    params = np.zeros((m, max([N_PARAMETERS] + [p.size for p in arrays])))
    offset = np.zeros(m, dtype=np.int64)
    k = 0
    for j, t in enumerate(thrusters):
        p = arrays[j]
        params[j, : p.size] = p
        offset[j] = k
        k += _N_STATES[int(kind[j])]
    return ActuatorKernel(kind=kind, allocation=np.ascontiguousarray(layout_matrix(tuple(thrusters))),
                          params=params, offset=offset)


def n_actuator_states(act: ActuatorKernel) -> int:
    """Size of the actuator state vector."""
    return int(sum(_N_STATES[int(k)] for k in act.kind))


@kernel
def actuator_rates(act, states, command, f_body, rates, thrust):
    """Body wrench ``f_body = Lambda T`` (6), state rates and thrusts ``T`` (m) for the held commands."""
    m = act.kind.shape[0]
    if m == 0:
        for k in range(6):
            f_body[k] = command[k]
        return
    for j in range(m):
        o = act.offset[j]
        p = act.params[j]
        kind = act.kind[j]
        if kind == KIND_IDEAL:
            thrust[j] = ideal.ideal_thrust(p, command[j])
        elif kind == KIND_FIRST_ORDER:
            thrust[j] = states[o]
            rates[o] = first_order.first_order_derivative(p, states[o], command[j])
        elif kind == KIND_TABLE:
            thrust[j] = states[o]
            rates[o] = table.table_derivative(p, states[o], command[j])
        else:
            T, _ = healey.healey_thrust_torque(p, states[o], states[o + 1])
            thrust[j] = T
            dW, dU = healey.healey_derivatives(p, states[o], states[o + 1], command[j])
            rates[o] = dW
            rates[o + 1] = dU
    for k in range(6):
        s = 0.0
        for j in range(m):
            s += act.allocation[k, j] * thrust[j]
        f_body[k] = s
