"""One numbering of thruster models and one dispatcher per question (:mod:`uvms.thrusters.kinds`): the actuators,
the allocation and the Gymnasium environments see the same kinds and the same per-kind arithmetic."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from numba import njit

from uvms.thrusters import first_order, healey, ideal, kinds, table
from uvms.thrusters.actuation import actuator_kernel, n_actuator_states
from uvms.thrusters.command import thrust_command
from uvms.thrusters.first_order import FirstOrderParameters
from uvms.thrusters.ideal import IdealParameters
from uvms.thrusters.layouts import Thruster
from uvms.thrusters.table import t200_table

SRC = Path(__file__).resolve().parents[2] / "src" / "uvms"


def mixed_layout():
    return (Thruster("a", (0.0, -0.15, 0.0), (1.0, 0.0, 0.0), "first_order", FirstOrderParameters(0.05, 50.0)),
            Thruster("b", (0.0, 0.15, 0.0), (1.0, 0.0, 0.0), "ideal", IdealParameters(40.0)),
            Thruster("c", (0.0, 0.0, 0.0), (0.0, 1.0, 0.0), "healey"),
            Thruster("d", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), "table", t200_table(0.02)))


def test_the_actuators_and_the_allocation_number_the_kinds_alike():
    layout = mixed_layout()
    expected = [kinds.FIRST_ORDER, kinds.IDEAL, kinds.HEALEY, kinds.TABLE]
    np.testing.assert_array_equal(actuator_kernel(layout).kind, expected)
    np.testing.assert_array_equal(thrust_command(layout).kind, expected)
    assert n_actuator_states(actuator_kernel(layout)) == 1 + 0 + 2 + 1
    assert sorted(kinds.KINDS) == ["first_order", "healey", "ideal", "table"]
    assert len(set(kinds.KINDS.values())) == 4


@njit(cache=True)
def _rates(kind, p, states, o, command, rates):
    return kinds.thruster_rates(kind, p, states, o, command, rates)


@njit(cache=True)
def _command(kind, p, coefficients, T):
    return kinds.command_for_thrust(kind, p, coefficients, T)


@pytest.mark.parametrize("j", range(4))
def test_the_rate_dispatcher_is_each_models_own_arithmetic(j):
    thruster = mixed_layout()[j]
    act = actuator_kernel((thruster,))
    p = act.params[0]
    states, rates = np.array([0.0, 120.0, 0.4, 0.0]), np.zeros(4)
    command = {kinds.HEALEY: 12.0, kinds.TABLE: 1700.0}.get(int(act.kind[0]), 20.0)
    thrust = _rates(act.kind[0], p, states, 1, command, rates)
    if thruster.model == "ideal":
        assert thrust == ideal.ideal_thrust(p, command) and not rates.any()
    elif thruster.model == "first_order":
        assert thrust == 120.0 and rates[1] == first_order.first_order_derivative(p, 120.0, command)
    elif thruster.model == "table":
        assert thrust == 120.0 and rates[1] == table.table_derivative(p, 120.0, command)
    else:
        assert thrust == healey.healey_thrust_torque(p, 120.0, 0.4)[0]
        assert (rates[1], rates[2]) == healey.healey_derivatives(p, 120.0, 0.4, command)
    assert not rates[0] and not rates[3]


@pytest.mark.parametrize("j", range(4))
def test_the_command_dispatcher_inverts_each_model(j):
    alloc = thrust_command(mixed_layout())
    p, c, T = alloc.params[j], alloc.coefficients[j], 7.5
    expected = {kinds.HEALEY: lambda: healey.healey_voltage_for_thrust(p, c, T),
                kinds.TABLE: lambda: table.table_command(p, T)}.get(int(alloc.kind[j]), lambda: T)()
    assert _command(alloc.kind[j], p, c, T) == expected


def test_no_other_module_numbers_or_dispatches_thruster_kinds():
    """The kinds are numbered once and each dispatch is written once: no module but :mod:`uvms.thrusters.kinds`
    assigns a thruster kind number or compares with one."""
    names = r"(KIND_(IDEAL|FIRST_ORDER|HEALEY|TABLE)|HEALEY|TABLE|THRUST|IDEAL|FIRST_ORDER)\b"
    number = re.compile(r"^\s*" + names + r"[\w, ]*=\s*\d")
    compare = re.compile(r"==\s*" + names)
    offending = []
    for path in sorted(SRC.rglob("*.py")):
        if path.name == "kinds.py" and path.parent.name == "thrusters":
            continue
        for n, line in enumerate(path.read_text().splitlines(), 1):
            if number.search(line) or compare.search(line):
                offending.append(f"{path.relative_to(SRC)}:{n}: {line.strip()}")
    assert not offending, offending
