"""First-order lag and ideal thruster: kernels against exact solutions, clipping, and the default's match to
the Healey thruster."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uvms.thrusters.first_order import (
    FirstOrderParameters,
    first_order_derivative,
    first_order_exact,
    first_order_rk4_step,
)
from uvms.thrusters.healey import HealeyParameters, rise_time, step_response
from uvms.thrusters.ideal import IdealParameters, ideal_thrust

PARAMS = FirstOrderParameters()
P = PARAMS.as_array()


def test_derivative_is_the_lag_equation():
    assert first_order_derivative(P, 10.0, 20.0) == pytest.approx((20.0 - 10.0) / PARAMS.time_constant)
    assert first_order_derivative(P, 0.0, 1e6) == pytest.approx(PARAMS.max_thrust / PARAMS.time_constant)
    assert first_order_derivative(P, 0.0, -1e6) == pytest.approx(-PARAMS.max_thrust / PARAMS.time_constant)


@pytest.mark.parametrize("command", [30.0, -45.0, 200.0])
def test_rk4_matches_exact_solution(command):
    h, T = 1e-3, 5.0
    times = np.arange(1, 201) * h
    numeric = []
    for _ in times:
        T = first_order_rk4_step(P, T, command, h)
        numeric.append(T)
    np.testing.assert_allclose(numeric, first_order_exact(PARAMS, 5.0, command, times), rtol=0, atol=1e-6)


def test_rise_time_is_tau_and_close_to_healey():
    t = np.linspace(0.0, 0.5, 50_001)
    T = first_order_exact(PARAMS, 0.0, 51.8, t)
    tau = rise_time(t, T, 1 - math.exp(-1), final=51.8)
    assert tau == pytest.approx(PARAMS.time_constant, rel=1e-6)
    healey = step_response(HealeyParameters(), 24.0, 0.5, 1e-4)
    assert rise_time(healey.time, healey.thrust) == pytest.approx(tau, rel=0.02)
    assert HealeyParameters().max_thrust == pytest.approx(PARAMS.max_thrust, rel=1e-3)


def test_ideal_thrust_clips():
    p = IdealParameters(max_thrust=10.0).as_array()
    assert ideal_thrust(p, 3.5) == 3.5
    assert ideal_thrust(p, 11.0) == 10.0
    assert ideal_thrust(p, -11.0) == -10.0


def test_parameters_validate():
    with pytest.raises(ValueError):
        FirstOrderParameters(time_constant=0.0)
    with pytest.raises(ValueError):
        IdealParameters(max_thrust=-1.0)
