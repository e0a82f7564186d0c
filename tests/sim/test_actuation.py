"""Thrusters inside the simulation: states integrate at the default step, the commanded wrench is delivered,
what a layout cannot produce is reported (issue 5)."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.base import ControlOutput
from uvms.sim.run import Actuation, simulate
from uvms.thrusters.healey import healey_thrust_torque


class ConstantWrench:
    """A stand-in controller commanding a fixed body wrench."""

    period = 0.01

    def __init__(self, wrench):
        self.wrench = np.array(wrench, dtype=float)

    def reset(self):
        pass

    def update(self, measurement):
        return ControlOutput(wrench=self.wrench)


@pytest.fixture(scope="module")
def paper():
    return uvms.load_model("paper")


def test_healey_thrusters_deliver_the_commanded_surge_force(paper):
    """20 N surge at the default 1 ms step: each surge thruster settles at 10 N (steady-state inverse of the
    voltage), the others at 0; the states stay finite and smooth."""
    act = Actuation.named("model", paper)
    r = simulate(paper, duration=1.0, step=1e-3, fixed_base=True, controller=ConstantWrench([0, 0, 0, 20.0, 0, 0]),
                 actuation=act, record_period=0.01)
    assert r.complete
    p = act.thrusters[0].parameters.as_array()
    states = r.actuator[-1].reshape(-1, 2)                     # (Omega, U) per thruster
    thrust = np.array([healey_thrust_torque(p, w, u)[0] for w, u in states])
    np.testing.assert_allclose(thrust, [10.0, 10.0, 0.0, 0.0], atol=0.05)
    assert np.isclose(r.signals["unachieved_X"][-1], 0.0, atol=1e-9)
    # the 63 % rise of the thrust happens in tens of milliseconds, not in one step
    early = np.array([healey_thrust_torque(p, *r.actuator[k].reshape(-1, 2)[0])[0] for k in range(1, 4)])
    assert np.all(early < 9.0) and np.all(np.diff(early) > 0)


def test_paper_layout_reports_the_sway_force_it_cannot_produce(paper):
    act = Actuation.named("paper")
    r = simulate(paper, duration=0.05, step=1e-3, fixed_base=True,
                 controller=ConstantWrench([0, 0, 0, 0, 15.0, 0]), actuation=act)
    np.testing.assert_allclose(r.signals["unachieved_Y"], 15.0, atol=1e-9)
    assert np.allclose(r.actuator, 0.0)                         # nothing is commanded to any thruster


def test_first_order_thrusters_follow_their_time_constant(paper):
    from uvms.thrusters.first_order import FirstOrderParameters
    from uvms.thrusters.layouts import Thruster

    thrusters = (Thruster("surge", (0.0, 0.0, 0.0), (1.0, 0.0, 0.0), "first_order",
                          FirstOrderParameters(time_constant=0.05, max_thrust=50.0)),)
    r = simulate(paper, duration=0.2, step=1e-3, fixed_base=True, controller=ConstantWrench([0, 0, 0, 30.0, 0, 0]),
                 actuation=Actuation(thrusters), record_period=0.001)
    # T(t) = 30 (1 - exp(-t / tau)) from the first update on (closed form, RK4 at 1 ms)
    np.testing.assert_allclose(r.actuator[:, 0], 30.0 * (1 - np.exp(-r.time / 0.05)), atol=1e-6)
