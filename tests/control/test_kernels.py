"""The compiled controllers and arm trackers (issue 14) against the Python laws they replace
(:mod:`tests.control.reference_laws`), update by update on the states of a real closed-loop run of the paper
model (case 3: released vehicle, the paper's torque schedule, ``smc-ab`` every 10 ms).

Tolerance 1e-12 relative (1e-12 absolute for values below 1): the compiled update and the reference do the
same arithmetic except (i) the reference's rotation is normalised as ``State.rotation`` does (``q * (1/|q|)``)
while the controller's is ``q / |q|``, (ii) the reference reaches the accelerations through the Python API and
takes ``b_hat`` with ``b_source = model`` from the response to a unit wrench, not from the articulated inertia,
(iii) numpy's vectorised cross products and LAPACK solves against scalar loops; each moves the last bits only.
"""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.arm import (
    ComputedTorqueArm,
    JointTrajectory,
    PdArm,
    arm_torques,
    constant_arm,
    schedule_arm,
)
from uvms.control.kernels import controller_update, no_controller
from uvms.control.registry import make_controller
from uvms.sim.inputs import paper_torques
from uvms.sim.integrate import unpack
from uvms.sim.run import simulate

from .reference_laws import (
    ReferencePid,
    ReferenceSlidingMode,
    computed_torque,
    desired,
    pd_torque,
    schedule_torque,
)

PERIOD = 0.01
KNOTS = ([0.0, 2.0, 4.0, 6.0], [[0, 0, 0], [1.5, 0.5, -0.5], [2.5, -0.3, 0.8], [3.0, 0, 0]])


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("paper")


@pytest.fixture(scope="module")
def recorded(model):
    """(t, x, tau, nu_dot) at every controller update of 3 s of the paper's case 3 under ``smc-ab``."""
    controller = make_controller("smc-ab", model, period=PERIOD)
    result = simulate(model, duration=3.0, step=1e-3, joint_torques=paper_torques(), controller=controller,
                      record_period=PERIOD)
    assert result.complete
    n = model.n_joints
    rows = []
    for t, x, tau in zip(result.time[:-1], result.states[:-1], result.joint_torques[:-1]):
        state = unpack(x, n)
        nu_dot = uvms.forward_dynamics(model, state, joint_torques=tau).nu_dot
        rows.append((float(t), np.array(x[:13 + 2 * n]), np.array(tau), nu_dot))
    assert len(rows) == 300 and np.ptp([r[1][7:13] for r in rows], axis=0).max() > 1e-3      # the vehicle moves
    return rows


def close(actual, expected, what):
    actual, expected = np.asarray(actual, dtype=float), np.asarray(expected, dtype=float)
    tol = 1e-12 * np.maximum(1.0, np.abs(expected))
    bad = np.abs(actual - expected) > tol
    assert not bad.any(), f"{what}: {actual[bad]} != {expected[bad]}"


CASES = [
    ("smc-ab", {}),
    ("smc-ab", {"hydro_scale": 1.0, "surface": "error_rate"}),
    ("smc-ab", {"b_source": "model", "desired_position": [0.01, -0.02, 0.0], "desired_yaw": 0.05}),
    ("smc-vehicle", {}),
    ("smc-vehicle", {"b_source": "model", "surface": "error_rate"}),
    ("smc-ne", {}),
    ("smc-ne", {"imu_noise": 0.05, "imu_bias": [0.01, 0, -0.02, 0.1, 0, 0.03], "imu_delay": 2, "imu_seed": 7}),
    ("smc-ne", {"imu_mode": "finite_difference", "imu_delay": 1, "b_source": "model"}),
    # six axes (issue 16): per-axis gains, bounds or the model's b, level attitude, waypoints, both surfaces
    ("smc-ab", {"axes": "all", "bandwidth": [3.0, 3.1, 2.0, 4.0, 4.5, 3.14], "b_heave": [30.0, 50.0]}),
    ("smc-ab", {"axes": ["pitch", "heave", "roll"], "surface": "error_rate", "desired_roll": 0.01,
                "waypoints": [[0.5, 0.0, 0.0, 0.02, 0.0, 0.01, 0.0], [2.2, 0.01, 0.0, -0.01, 0.02, -0.01, 0.1]]}),
    ("smc-vehicle", {"axes": "all", "surface": "error_rate", "uncertainty": [0.5, 0.5, 1.0, 0.8, 0.8, 0.5],
                     "boundary_layer": [0.02, 0.02, 0.03, 0.01, 0.01, 0.02]}),
    ("smc-ne", {"axes": ["yaw", "heave", "pitch"], "imu_noise": 0.02, "imu_delay": 1, "eta": [0.4, 0.5, 0.6]}),
]


@pytest.mark.parametrize("name, parameters", CASES)
def test_compiled_sliding_mode_equals_the_python_law(model, recorded, name, parameters):
    """Wrench and every logged signal, 300 updates, compiled == reference (both from fresh memory)."""
    controller = make_controller(name, model, period=PERIOD, parameters=parameters)
    reference = ReferenceSlidingMode({"smc-ab": "ab", "smc-vehicle": "vehicle", "smc-ne": "ne"}[name], model,
                                     controller.parameters, PERIOD)
    data = controller.compiled(len(recorded))
    assert data.needs_acceleration == (name == "smc-ne" and parameters.get("imu_mode") != "finite_difference")
    names = controller.signal_names
    wrench = np.zeros(6)
    for t, x, tau, nu_dot in recorded:
        controller_update(data, t, x, tau, nu_dot, wrench)
        expected_wrench, expected_signals = reference.update(t, unpack(x, model.n_joints), tau, nu_dot)
        assert tuple(expected_signals) == names
        close(wrench, expected_wrench, f"wrench at t = {t}")
        close(data.signals, list(expected_signals.values()), f"signals at t = {t}")


def test_pid_equals_the_python_law(model, recorded):
    """With a set point away from the recorded path, so that the output saturates and the anti-windup acts."""
    parameters = {"limit": [20.0, 20.0, 2.0], "desired_position": [0.05, -0.04, 0.0], "desired_yaw": 0.02}
    controller = make_controller("pid", model, period=PERIOD, parameters=parameters)
    reference = ReferencePid(controller.parameters, PERIOD)
    data = controller.compiled(len(recorded))
    wrench = np.zeros(6)
    clamped = 0
    for t, x, tau, nu_dot in recorded:
        controller_update(data, t, x, tau, nu_dot, wrench)
        expected_wrench, expected_signals = reference.update(t, unpack(x, model.n_joints))
        close(wrench, expected_wrench, f"wrench at t = {t}")
        close(data.signals, list(expected_signals.values()), f"signals at t = {t}")
        clamped += int(np.any(np.abs(wrench[[3, 4, 2]]) >= [20.0, 20.0, 2.0]))
    assert clamped > 10


@pytest.mark.parametrize("parameters", [
    {"axes": "all", "ki": [100.0, 100.0, 200.0, 5.0, 5.0, 5.0], "limit": 20.0},
    {"axes": ["heave", "pitch"], "waypoints": [[1.0, 0.0, 0.0, 0.03, 0.0, 0.05, 0.0]], "limit": [15.0, 1.0]},
])
def test_six_axis_pid_equals_the_python_law(model, recorded, parameters):
    controller = make_controller("pid", model, period=PERIOD, parameters=parameters)
    reference = ReferencePid(controller.parameters, PERIOD)
    data = controller.compiled(len(recorded))
    wrench = np.zeros(6)
    for t, x, tau, nu_dot in recorded:
        controller_update(data, t, x, tau, nu_dot, wrench)
        expected_wrench, expected_signals = reference.update(t, unpack(x, model.n_joints))
        assert tuple(expected_signals) == controller.signal_names
        close(wrench, expected_wrench, f"wrench at t = {t}")
        close(data.signals, list(expected_signals.values()), f"signals at t = {t}")


def test_python_update_is_the_kernel_and_reset_forgets(model, recorded):
    """The class's update() (user protocol) gives the kernel's numbers; reset() and compiled() start afresh;
    the IMU's Python noise table grows past its first block with the same seeded sequence."""
    from uvms.control.base import Measurement

    parameters = {"imu_noise": 0.1, "imu_seed": 3}
    controller = make_controller("smc-ne", model, period=PERIOD, parameters=parameters)
    for _ in range(2):
        controller.reset()
        data = controller.compiled(len(recorded))
        wrench = np.zeros(6)
        for t, x, tau, nu_dot in recorded:
            out = controller.update(Measurement(time=t, state=unpack(x, model.n_joints), joint_torques=tau,
                                                nu_dot=nu_dot))
            controller_update(data, t, x, tau, nu_dot, wrench)
            np.testing.assert_array_equal(out.wrench, wrench)
            np.testing.assert_array_equal(list(out.signals.values()), data.signals)
    assert len(recorded) > controller.PYTHON_UPDATES


def test_compiled_update_flag(model):
    from uvms.control.smc_ab import ArticulatedBodySMC

    assert all(make_controller(name, model).compiled_update for name in ("smc-ab", "smc-vehicle", "smc-ne", "pid"))

    class Custom(ArticulatedBodySMC):
        def update(self, measurement):
            return super().update(measurement)

    assert not Custom(model).compiled_update


def test_no_controller_writes_zero():
    data = no_controller()
    wrench = np.ones(6)
    controller_update(data, 0.0, np.zeros(13), np.zeros(0), np.zeros(6), wrench)
    assert np.all(wrench == 0.0) and data.signals.size == 0


# ------------------------------------------------------------------------------------------------ arm


@pytest.mark.parametrize("base", ["fixed", "moving"])
def test_computed_torque_equals_the_python_law(model, recorded, base):
    """scipy's spline and the Python RNEA against the compiled spline and RNEA, at every recorded state,
    including a knot (t = 2 s) and times past the last knot."""
    trajectory = JointTrajectory(*KNOTS)
    arm = ComputedTorqueArm(model, trajectory, kp=[90.0, 100.0, 110.0], kd=20.0, base=base)
    data = arm.compiled()
    tau = np.zeros(model.n_joints)
    for t, x, _, _ in recorded:
        for when in (t, t + 4.0):
            arm_torques(data, when, x, tau)
            expected = computed_torque(model, trajectory._spline, trajectory.times, trajectory.angles, arm.kp,
                                       arm.kd, base, when, unpack(x, model.n_joints))
            close(tau, expected, f"tau at t = {when}")
            close(arm(when, unpack(x, model.n_joints)), expected, f"Python torques at t = {when}")


def test_pd_and_schedule_and_constant_equal_the_python_laws(model, recorded):
    trajectory = JointTrajectory(*KNOTS)
    pd = PdArm(trajectory, kp=[20.0, 25.0, 30.0], kd=5.0)
    data = pd.compiled()
    schedule = paper_torques()
    step = 1e-3
    sched = schedule_arm(schedule, step)
    const = constant_arm([1.0, -2.0, 0.5])
    tau = np.zeros(model.n_joints)
    for t, x, _, _ in recorded:
        state = unpack(x, model.n_joints)
        arm_torques(data, t, x, tau)
        close(tau, pd_torque(trajectory._spline, trajectory.times, trajectory.angles, pd.kp, pd.kd, t, state),
              f"PD at t = {t}")
        for when in (t, 2.0 - 0.5 * step - 1e-12, 2.0 - 0.5 * step, 2.0 - step, 2.0):
            arm_torques(sched, when, x, tau)
            np.testing.assert_array_equal(tau, schedule_torque(schedule.times, schedule.torques, when, step))
            np.testing.assert_array_equal(tau, schedule(when + 0.5 * step))
        arm_torques(const, t, x, tau)
        np.testing.assert_array_equal(tau, [1.0, -2.0, 0.5])
    single = JointTrajectory([0.0], [[0.1, 0.2, 0.3]])
    q_d, qd_d, qdd_d = single(5.0)
    np.testing.assert_array_equal(q_d, [0.1, 0.2, 0.3])
    assert not qd_d.any() and not qdd_d.any()
    for t in np.linspace(0.0, 7.0, 701):                 # the compiled spline is scipy's, bit for bit
        for mine, scipy_value in zip(trajectory(t), desired(trajectory._spline, trajectory.times,
                                                            trajectory.angles, t)):
            np.testing.assert_array_equal(mine, scipy_value)
