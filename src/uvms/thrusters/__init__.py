"""Thrusters: dynamic models (Healey, first-order lag, ideal), layouts and thrust allocation (paper Eqs. 9-12)."""

from uvms.thrusters.allocation import (
    AllocationResult,
    allocate,
    allocate_pinv,
    allocation_matrix,
    unachievable_directions,
    unachievable_part,
)
from uvms.thrusters.first_order import FirstOrderParameters, first_order_derivative
from uvms.thrusters.healey import (
    RECOMMENDED_MAX_STEP,
    RK4_STABILITY_LIMIT,
    HealeyParameters,
    StepResponse,
    healey_bank_derivatives,
    healey_derivatives,
    healey_thrust_torque,
    healey_voltage_for_thrust,
    rise_time,
    steady_coefficients,
    steady_state,
    step_response,
    voltage_for_thrust,
)
from uvms.thrusters.ideal import IdealParameters, ideal_thrust
from uvms.thrusters.layouts import (
    DEFAULT_LAYOUT,
    Thruster,
    layout,
    layout_matrix,
    layout_names,
    thrust_limits,
)

__all__ = [
    "DEFAULT_LAYOUT",
    "RECOMMENDED_MAX_STEP",
    "RK4_STABILITY_LIMIT",
    "AllocationResult",
    "FirstOrderParameters",
    "HealeyParameters",
    "IdealParameters",
    "StepResponse",
    "Thruster",
    "allocate",
    "allocate_pinv",
    "allocation_matrix",
    "first_order_derivative",
    "healey_bank_derivatives",
    "healey_derivatives",
    "healey_thrust_torque",
    "healey_voltage_for_thrust",
    "ideal_thrust",
    "layout",
    "layout_matrix",
    "layout_names",
    "rise_time",
    "steady_coefficients",
    "steady_state",
    "step_response",
    "thrust_limits",
    "unachievable_directions",
    "unachievable_part",
    "voltage_for_thrust",
]
