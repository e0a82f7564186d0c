"""The one numbering of thruster models and the compiled dispatch on it (paper Eqs. 9-12).

A thruster's ``model`` in a layout (:class:`~uvms.thrusters.layouts.Thruster`) is a name; the kernels see it as
an int64 kind (:data:`KINDS`), one per thruster, in the kernel arrays of the actuators
(:class:`uvms.thrusters.actuation.ActuatorKernel`) and of the allocation
(:class:`uvms.thrusters.command.ThrustCommand`). Two dispatchers switch on it, one per question:

- :func:`thruster_rates`: a thruster's delivered thrust [N] and its state rates at a held command (what the
  integrator asks, :func:`uvms.thrusters.actuation.actuator_rates`);
- :func:`command_for_thrust`: the held command that makes a thruster deliver a steady thrust (the last stage of
  the allocation, :func:`uvms.thrusters.command.allocate_command`, and of the Gymnasium environments).

==============  =====  =========================================  =====================================
kind            state  command                                    module
==============  =====  =========================================  =====================================
``IDEAL``       none   thrust [N], clipped                        :mod:`uvms.thrusters.ideal`
``FIRST_ORDER`` T      thrust [N], first-order lag                :mod:`uvms.thrusters.first_order`
``HEALEY``      W, U   voltage [V] (steady-state inverse)         :mod:`uvms.thrusters.healey`
``TABLE``       T      the table's command (e.g. ESC pulse [us])  :mod:`uvms.thrusters.table`
==============  =====  =========================================  =====================================
"""

from __future__ import annotations

from uvms.jit import block
from uvms.thrusters import first_order, healey, ideal, table

IDEAL, FIRST_ORDER, HEALEY, TABLE = 0, 1, 2, 3
"""Thruster kinds (the int64 the kernels switch on)."""
KINDS = {"ideal": IDEAL, "first_order": FIRST_ORDER, "healey": HEALEY, "table": TABLE}
"""Kind of each thruster ``model`` name."""
N_STATES = {IDEAL: 0, FIRST_ORDER: 1, HEALEY: 2, TABLE: 1}
"""Number of actuator states of each kind (their order: the table above)."""


def kind_of(model: str) -> int:
    """The kind of a thruster ``model`` name (:data:`KINDS`)."""
    return KINDS[model]


@block
def thruster_rates(kind, p, states, o, command, rates):
    """The thrust [N] one thruster of ``kind`` delivers at the held ``command``; its state rates into
    ``rates[o:o + N_STATES[kind]]`` (its states are ``states[o:o + N_STATES[kind]]``; ``p``: its kernel
    parameters, the parameters' ``as_array()``)."""
    if kind == IDEAL:
        return ideal.ideal_thrust(p, command)
    if kind == FIRST_ORDER:
        rates[o] = first_order.first_order_derivative(p, states[o], command)
        return states[o]
    if kind == TABLE:
        rates[o] = table.table_derivative(p, states[o], command)
        return states[o]
    T, _ = healey.healey_thrust_torque(p, states[o], states[o + 1])
    dW, dU = healey.healey_derivatives(p, states[o], states[o + 1], command)
    rates[o] = dW
    rates[o + 1] = dU
    return T


@block
def command_for_thrust(kind, p, coefficients, T):
    """The held command that makes one thruster of ``kind`` deliver the steady thrust ``T`` [N]: Healey's
    steady-state voltage (:func:`~uvms.thrusters.healey.healey_voltage_for_thrust`, ``coefficients`` its
    :func:`~uvms.thrusters.healey.steady_coefficients`), a table thruster's inverse table
    (:func:`~uvms.thrusters.table.table_command`), or the thrust itself (ideal and first-order thrusters)."""
    if kind == HEALEY:
        return healey.healey_voltage_for_thrust(p, coefficients, T)
    if kind == TABLE:
        return table.table_command(p, T)
    return T
