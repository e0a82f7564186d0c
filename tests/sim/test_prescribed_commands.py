"""Thruster commands from a table in the prescribed-motion loop (``Inputs(thruster_commands=...)``): the held
commands reach the vehicle as the thrust map ``B u`` written out here (ideal thrusters: the wrench of each
thrust at its mount), row by row at the table's times; a first-order thruster's thrust follows its closed-form
lag; the result records the commands; bad tables are refused in one line."""

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.sim.inputs import CommandSchedule
from uvms.sim.options import Actuation
from uvms.thrusters.first_order import FirstOrderParameters
from uvms.thrusters.layouts import Thruster

MOUNTS = [((0.3, 0.1, 0.05), (1.0, 0.0, 0.0)), ((-0.3, -0.1, 0.0), (0.0, 1.0, 0.0)),
          ((0.0, 0.2, -0.1), (0.0, 0.0, 1.0)), ((0.1, -0.2, 0.1), (0.6, 0.0, 0.8))]


def _thrusters(model="ideal", parameters=None):
    return tuple(Thruster(name=f"u{k}", position=np.array(p), direction=np.array(d), model=model,
                          parameters=parameters) for k, (p, d) in enumerate(MOUNTS))


def _thrust_map() -> np.ndarray:
    """(6, m) body wrench ``[r x d; d]`` of a unit thrust of each thruster, ``[moment; force]``."""
    return np.column_stack([np.concatenate([np.cross(p, d), d]) for p, d in
                            ((np.array(p), np.array(d) / np.linalg.norm(d)) for p, d in MOUNTS)])


@pytest.fixture(scope="module")
def setup():
    model = uvms.load_model("paper")
    q = np.array([0.3, -0.4, 0.5])[:model.n_joints]
    motion = uvms.JointMotion.from_arrays(np.array([0.0, 0.5, 1.0]), np.tile(q, (3, 1)), joints=model.joint_names)
    start = uvms.State.zero(model).replace(q=q, nu=np.array([0.02, -0.01, 0.03, 0.1, 0.0, -0.05]))
    return model, motion, start


def test_held_commands_act_as_the_thrust_map_row_by_row(setup):
    """Two rows (switch at 0.5 s) against two chained runs with the body wrench ``B u`` of each row: the same
    state to rounding."""
    model, motion, start = setup
    u = np.array([[10.0, -5.0, 3.0, 8.0], [-4.0, 6.0, -2.0, 1.0]])
    table = CommandSchedule(np.array([0.0, 0.5]), u[:, ::-1], names=("u3", "u2", "u1", "u0"))
    run = uvms.simulate(model, start, duration=1.0, step=0.005, actuation=Actuation(_thrusters()),
                        inputs=uvms.Inputs(joint_motion=motion, thruster_commands=table))
    B = _thrust_map()
    first = uvms.simulate(model, start, duration=0.5, step=0.005,
                          inputs=uvms.Inputs(joint_motion=motion, body_wrench=B @ u[0]))
    second = uvms.simulate(model, first.state(-1), duration=0.5, step=0.005,
                           inputs=uvms.Inputs(joint_motion=motion, body_wrench=B @ u[1]))
    half = int(np.argmin(np.abs(run.time - 0.5)))
    np.testing.assert_allclose(run.states[half], first.states[-1], rtol=0, atol=1e-12)
    np.testing.assert_allclose(run.states[-1], second.states[-1], rtol=0, atol=1e-12)
    assert np.abs(run.nu[-1] - start.nu).max() > 0.05                       # the commands moved it
    for k in range(4):                                                        # the held commands are recorded
        expected = np.where(run.time < 0.5 - 1e-9, u[0, k], u[1, k])
        np.testing.assert_array_equal(run.signals[f"thruster_command_u{k}"], expected)


def test_a_first_order_thruster_lags_its_step_command(setup):
    """``T(t) = T_cmd (1 - exp(-t / tau))`` for a step at ``t = 0`` (RK4 at 1 ms, tau = 50 ms)."""
    model, motion, start = setup
    tau = 0.05
    thrusters = _thrusters("first_order", FirstOrderParameters(time_constant=tau, max_thrust=100.0))
    table = CommandSchedule(np.array([0.0]), np.array([[20.0, 0.0, 0.0, 0.0]]))
    run = uvms.simulate(model, start, duration=0.3, step=0.001, actuation=Actuation(thrusters),
                        inputs=uvms.Inputs(joint_motion=motion, thruster_commands=table))
    thrust = run.states[:, -4]
    np.testing.assert_allclose(thrust, 20.0 * (1.0 - np.exp(-run.time / tau)), rtol=0, atol=1e-8)


@pytest.mark.parametrize("make, message", [
    (lambda m: dict(inputs=uvms.Inputs(thruster_commands=CommandSchedule([0.0], [[1.0] * 4]))),
     "expected a joint_motion with thruster_commands"),
    (lambda m: dict(inputs=uvms.Inputs(joint_motion=m, thruster_commands=CommandSchedule([0.0], [[1.0] * 4]))),
     "the actuation has none"),
    (lambda m: dict(actuation=Actuation(_thrusters()),
                    inputs=uvms.Inputs(joint_motion=m, thruster_commands=CommandSchedule([0.0], [[1.0] * 3],
                                                                                         names=("u0", "u1", "x")))),
     "missing u2, u3; not a thruster: x"),
    (lambda m: dict(actuation=Actuation(_thrusters()),
                    inputs=uvms.Inputs(joint_motion=m, thruster_commands=[[1.0] * 4])),
     "CommandSchedule"),
])
def test_bad_command_tables_are_refused_in_one_line(setup, make, message):
    model, motion, start = setup
    with pytest.raises(UvmsInputError, match="thruster_commands") as info:
        uvms.simulate(model, start, duration=0.1, step=0.005, **make(motion))
    assert message in str(info.value) and "\n" not in str(info.value)


def test_a_schedule_starts_at_zero_and_increases():
    with pytest.raises(UvmsInputError, match="start at 0"):
        CommandSchedule([0.1, 0.2], [[1.0], [2.0]])
    with pytest.raises(UvmsInputError, match="distinct thruster names"):
        CommandSchedule([0.0], [[1.0, 2.0]], names=("a", "a"))
    table = CommandSchedule([0.0, 1.0], [[1.0], [2.0]])
    assert table(0.999)[0] == 1.0 and table(1.0)[0] == 2.0 and table(5.0)[0] == 2.0
