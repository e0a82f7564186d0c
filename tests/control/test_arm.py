"""Arm commands: joint trajectories, computed torque (error dynamics), PD, and an arm task on a held vehicle."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.arm import ComputedTorqueArm, JointTrajectory, PdArm
from uvms.control.compare import axis_series
from uvms.control.registry import make_controller
from uvms.errors import UvmsInputError
from uvms.sim.run import simulate
from uvms.state import State

KNOTS = ([0.0, 2.0, 4.0, 6.0], [[0, 0, 0], [1.5, 0.5, -0.5], [2.5, -0.3, 0.8], [3.0, 0, 0]])


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("paper")


def test_trajectory_passes_through_knots_starts_and_ends_at_rest():
    traj = JointTrajectory(*KNOTS)
    for t, q in zip(*KNOTS):
        np.testing.assert_allclose(traj(t)[0], q, atol=1e-12)
    for t in (0.0, 6.0, 7.5):
        np.testing.assert_allclose(traj(t)[1], 0.0, atol=1e-12)
    np.testing.assert_allclose(traj(9.0)[0], KNOTS[1][-1])
    h = 1e-5                                    # velocity and acceleration are derivatives of the angles
    np.testing.assert_allclose((traj(3.0 + h)[0] - traj(3.0 - h)[0]) / (2 * h), traj(3.0)[1], rtol=1e-6)
    np.testing.assert_allclose((traj(3.0 + h)[1] - traj(3.0 - h)[1]) / (2 * h), traj(3.0)[2], rtol=1e-5)
    single = JointTrajectory([0.0], [[0.1, 0.2, 0.3]])
    np.testing.assert_allclose(single(5.0)[0], [0.1, 0.2, 0.3])


@pytest.mark.parametrize("times, angles", [([0.0, 1.0], [[0, 0, 0]]), ([1.0, 0.0], [[0, 0, 0], [1, 1, 1]]),
                                           ([0.0, 1.0], [[0, 0, 0], [np.nan, 0, 0]])])
def test_trajectory_rejects_bad_knots(times, angles):
    with pytest.raises(UvmsInputError, match="arm.trajectory"):
        JointTrajectory(times, angles)


def test_computed_torque_gives_the_designed_error_dynamics(model):
    """Fixed base, plant model, 1 ms updates: a 0.1 rad error on joint 2 decays as the critically damped
    e(t) = e0 (1 + w t) exp(-w t), w = 10 rad/s, with the arm's hydrodynamics cancelled by the RNEA."""
    hold = JointTrajectory([0.0], [[0.0, 0.0, 0.0]])
    arm = ComputedTorqueArm(model, hold, kp=100.0, kd=20.0, period=1e-3)
    start = State.from_euler(model, q=[0.0, 0.1, 0.0])
    result = simulate(model, start, duration=1.0, step=1e-3, fixed_base=True, joint_torques=arm, control_period=1e-3)
    t = result.time
    expected = 0.1 * (1 + 10 * t) * np.exp(-10 * t)
    assert np.abs(result.q[:, 1] - expected).max() < 2e-3
    assert np.abs(result.q[:, [0, 2]]).max() < 1e-3


def test_computed_torque_tracks_far_better_than_pd(model):
    traj = JointTrajectory(*KNOTS)
    errors = {}
    for label, arm in (("computed torque", ComputedTorqueArm(model, traj)), ("pd", PdArm(traj))):
        result = simulate(model, duration=6.0, step=1e-3, fixed_base=True, joint_torques=arm, control_period=1e-3)
        desired = np.array([traj(t)[0] for t in result.time])
        errors[label] = np.abs(result.q - desired).max()
    assert errors["computed torque"] < 1e-3            # measured 5e-5 rad
    assert errors["pd"] > 10 * errors["computed torque"]


@pytest.mark.slow
def test_arm_task_on_a_released_vehicle_held_by_smc_ab(model):
    """The arm tracks a 3 rad sweep with the vehicle's measured velocity in its model while smc-ab keeps the
    vehicle within Phi / lambda."""
    traj = JointTrajectory(*KNOTS)
    arm = ComputedTorqueArm(model, traj, base="moving")
    controller = make_controller("smc-ab", model)
    result = simulate(model, duration=6.0, step=1e-3, joint_torques=arm, controller=controller)
    desired = np.array([traj(t)[0] for t in result.time])
    assert np.abs(result.q - desired).max() < 5e-3
    assert np.abs(axis_series(result)["s"]).max() <= 0.02
    err = result.body_frame_error()
    assert np.hypot(err[:, 0], err[:, 1]).max() <= 0.02 / 3.14


def test_arm_commands_check_their_inputs(model):
    with pytest.raises(UvmsInputError, match="arm.trajectory"):
        ComputedTorqueArm(model, JointTrajectory([0.0], [[0.0, 0.0]]))
    with pytest.raises(UvmsInputError, match="arm.base"):
        ComputedTorqueArm(model, JointTrajectory(*KNOTS), base="floating")
    with pytest.raises(UvmsInputError, match="arm.kp"):
        PdArm(JointTrajectory(*KNOTS), kp=[-1.0, 1.0, 1.0])
    arm = PdArm(JointTrajectory(*KNOTS), kp=2.0, kd=0.0)
    assert arm(2.0, State.zero(model)) == pytest.approx(2.0 * np.array(KNOTS[1][1]))
