"""``lqr``: the gain against the closed-form LQR of a double integrator, closed-loop stability, station keeping of a
vehicle against a current the controller does not know (the steady offset against the linear model's prediction,
and a stated bound), the feedforward holding a vehicle level that rests tilted, axis subsets and bad parameters."""

from __future__ import annotations

import math

import numpy as np
import pytest

import uvms
from uvms.control.base import Measurement
from uvms.control.lqr import DEFAULT_Q_POSE, DEFAULT_Q_VELOCITY, DEFAULT_R_WRENCH, VELOCITY_INDEX, pose_error
from uvms.control.registry import controller_names, make_controller
from uvms.errors import UvmsInputError


@pytest.fixture(scope="module")
def vehicle():
    """The paper's vehicle alone with ideal actuation."""
    return uvms.load_model("paper").vehicle_only().replace(thrusters=())


def measurement(state, n=0):
    return Measurement(time=0.0, state=state, joint_torques=np.zeros(n), nu_dot=np.zeros(6))


def test_registered():
    assert "lqr" in controller_names()


def test_gain_is_the_double_integrator_closed_form(vehicle):
    """No gravity, buoyancy or drag, CoM at the origin, diagonal inertia and added mass: each axis is
    ``m_j x'' = u`` decoupled. The continuous LQR of ``[x; x']`` with ``Q = diag(q1, q2)``, ``R = r`` solves the
    Riccati equation by hand: ``K = [sqrt(q1 / r), sqrt((2 m_j sqrt(q1 r) + q2) / r)]``."""
    free = vehicle.with_effects(gravity=False, buoyancy=False, drag=False)
    controller = make_controller("lqr", free, parameters={"design": "continuous"})
    design = controller.design(uvms.State.zero(free))
    masses = np.diag(free.inertia_com[0]).tolist() + [float(free.mass[0])] * 3
    masses = np.array(masses) + np.diag(free.added_mass[0])          # [K M N X Y Z] order
    for j, axis in enumerate(("surge", "sway", "heave", "roll", "pitch", "yaw")):
        m = masses[VELOCITY_INDEX[j]]
        q1, q2, r = DEFAULT_Q_POSE[j], DEFAULT_Q_VELOCITY[j], DEFAULT_R_WRENCH[j]
        expected = np.zeros(12)
        expected[j], expected[6 + j] = math.sqrt(q1 / r), math.sqrt((2 * m * math.sqrt(q1 * r) + q2) / r)
        np.testing.assert_allclose(design.gain[j], expected, rtol=1e-7, atol=1e-6, err_msg=axis)
    assert np.all(design.closed_loop.real < 0)


@pytest.mark.parametrize("name", ["paper", "bluerov2_heavy_alpha5"])
def test_closed_loop_is_stable_with_the_arm(name):
    model = uvms.load_model(name)
    state = uvms.State.from_euler(model, q=np.full(model.n_joints, 0.3))
    for design in ("discrete", "continuous"):
        d = make_controller("lqr", model, parameters={"design": design}).design(state)
        if design == "discrete":
            assert np.max(np.abs(d.closed_loop)) < 1.0
            # the same gain in continuous time: eigenvalues of A - B K in the left half plane too
            assert np.all(np.linalg.eigvals(d.A - d.B @ d.gain).real < 0)
        else:
            assert np.all(d.closed_loop.real < 0)
        assert d.gain.shape == (6, 12) and d.input_names == ("X", "Y", "Z", "K", "M", "N")


def test_holds_against_a_current_it_does_not_know(vehicle):
    """Released 0.2 m and 0.2 rad away, in a 0.3 m/s current unknown to the controller (its model has none):
    after 30 s the vehicle is at rest within 1 cm and 0.03 rad of the target (the current's Munk moment on the
    unequal added masses tilts it). The offset is the pose error ``e`` at which the held command
    ``u_ff - K [e; 0]`` balances the current: ``forward_dynamics = 0`` there, solved by root finding (to 1e-6
    rad); the linear closed loop under the current's wrench at the target, ``(I - Ad + Bd K)^-1 Bd w``,
    predicts it to 10 % (the current's wrench changes with the tilt)."""
    from scipy.optimize import fsolve
    from scipy.spatial.transform import Rotation

    current = np.array([0.3, -0.2, 0.1])
    controller = make_controller("lqr", vehicle, period=0.01,
                                 parameters={"desired_position": [0.0, 0.0, 0.0], "desired_attitude": [0, 0, 0.5]})
    start = uvms.State.from_euler(vehicle, position=[0.2, -0.1, 0.15], euler=[0.2, -0.15, 0.3])
    result = uvms.simulate(vehicle, start, duration=30.0, step=2e-3, controller=controller, current=current,
                           record_period=0.5)
    assert result.complete
    final = result.state(-1)
    d = controller.current_design
    R_d = d.hold_state.rotation
    e = pose_error(final, np.zeros(3), R_d)
    assert np.linalg.norm(e[:3]) < 0.01 and np.linalg.norm(e[3:]) < 0.03
    assert np.max(np.abs(final.nu)) < 1e-6
    inputs = [VELOCITY_INDEX[j] for j in range(6)]          # design input order -> [K M N X Y Z]

    def pose(err):
        x, y, z, w = Rotation.from_matrix(R_d @ Rotation.from_rotvec(err[3:]).as_matrix()).as_quat()
        return uvms.State(position=R_d @ err[:3], quaternion=[w, x, y, z], nu=np.zeros(6), q=[], qd=[])

    def residual(err):
        wrench = np.zeros(6)
        wrench[inputs] = d.feedforward - d.gain[:, :6] @ err
        return uvms.forward_dynamics(vehicle, pose(err), body_wrench=wrench, current=current).nu_dot

    steady = fsolve(residual, np.zeros(6), xtol=1e-13)
    np.testing.assert_allclose(residual(steady), 0.0, atol=1e-10)
    np.testing.assert_allclose(e, steady, rtol=0, atol=1e-6)
    hold = d.hold_state
    lin = uvms.linearize(vehicle, hold)
    acc = uvms.forward_dynamics(vehicle, hold, current=current).nu_dot
    w = np.linalg.solve(lin.B[6:12, :6], acc - lin.drift[6:12])     # the current's wrench at the target
    predicted = np.linalg.solve(np.eye(12) - d.Ad + d.Bd @ d.gain, d.Bd @ w[inputs])[:6]
    assert np.linalg.norm(predicted) > 1e-3                          # a visible offset
    np.testing.assert_allclose(e, predicted, rtol=0, atol=0.1 * np.abs(predicted).max())


def test_integral_action_removes_the_offset(vehicle):
    """The same run with integrators on all six pose errors: the closed loop of the augmented design is stable
    and after 40 s the offset of the unknown current is gone (below 1e-5 m and rad; without them it is about
    3.5 mm and 0.02 rad, previous test)."""
    current = np.array([0.3, -0.2, 0.1])
    controller = make_controller("lqr", vehicle, period=0.01,
                                 parameters={"desired_position": [0.0, 0.0, 0.0], "desired_attitude": [0, 0, 0.5],
                                             "q_integral": [100.0, 100.0, 100.0, 100.0, 100.0, 100.0]})
    start = uvms.State.from_euler(vehicle, position=[0.2, -0.1, 0.15], euler=[0.2, -0.15, 0.3])
    result = uvms.simulate(vehicle, start, duration=40.0, step=2e-3, controller=controller, current=current,
                           record_period=0.5)
    d = controller.current_design
    assert d.gain.shape == (6, 18) and d.state_names[-1] == "integral_yaw"
    assert np.max(np.abs(d.closed_loop)) < 1.0
    e = pose_error(result.state(-1), np.zeros(3), d.hold_state.rotation)
    assert np.max(np.abs(e)) < 1e-5
    assert abs(result.signals["integral_roll"][-1]) > 1e-3          # the integrator carries the current's moment


def test_feedforward_holds_a_tilted_vehicle_level(vehicle):
    """A nose-heavy vehicle (CoM 1 cm ahead of the origin, CoB 2.54 cm above it) rests at
    ``-atan(0.01 / 0.0254)`` = -21.5 deg of pitch; holding level needs a steady pitch moment, which the feedforward
    provides: level to 1e-6 rad after 10 s. Without it the pitch offset is the linear closed loop's under the
    static moment (the restoring moment of the tilt is in ``A``)."""
    model = vehicle.replace(com=np.array([[0.01, 0.0, 0.0]]))
    assert uvms.trim(model).pitch_rad == pytest.approx(-math.atan(0.01 / 0.0254), rel=1e-12)
    start = uvms.State.zero(model)
    pitches = {}
    for feedforward in (True, False):
        controller = make_controller("lqr", model, parameters={"feedforward": feedforward})
        result = uvms.simulate(model, start, duration=10.0, step=1e-3, controller=controller, record_period=0.5)
        pitches[feedforward] = result.state(-1).euler[1]
    assert abs(pitches[True]) < 1e-6
    d = controller.current_design
    lin = uvms.linearize(model, d.hold_state)
    static = np.linalg.solve(lin.B[6:12, :6], lin.drift[6:12])       # the wrench of B_v^-1 nu_dot_0
    inputs = [VELOCITY_INDEX[j] for j in range(6)]
    predicted = np.linalg.solve(np.eye(12) - d.Ad + d.Bd @ d.gain, d.Bd @ static[inputs])
    assert pitches[False] == pytest.approx(predicted[4], rel=0.02)
    assert pitches[False] < -1e-3


def test_axis_subset_commands_only_those_axes(vehicle):
    controller = make_controller("lqr", vehicle, parameters={"axes": ["surge", "sway", "yaw"], "limit": 5.0})
    state = uvms.State.from_euler(vehicle, position=[1.0, 0.0, 0.5], euler=[0.1, 0.1, 0.0])
    controller.update(measurement(state))      # captures the hold pose at this state
    moved = uvms.State.from_euler(vehicle, position=[1.5, 0.2, 0.9], euler=[0.3, 0.2, -0.2], nu=[0.1] * 6)
    out = controller.update(measurement(moved))
    assert set(out.signals) == {"e_surge", "e_sway", "e_yaw", "command_surge", "command_sway", "command_yaw"}
    assert out.wrench[0] == out.wrench[1] == out.wrench[5] == 0.0          # roll, pitch, heave left alone
    assert np.all(np.abs(out.wrench[[2, 3, 4]]) <= 5.0) and abs(out.wrench[3]) == 5.0   # clipped
    assert controller.current_design.gain.shape == (3, 6)


@pytest.mark.parametrize("parameters, message", [
    ({"axes": ["surge", "surge"]}, "axis 'surge' is named twice"),
    ({"axes": ["surge", "up"]}, "unknown axis 'up'"),
    ({"axes": []}, "expected a non-empty list of axes"),
    ({"q_pose": [1.0, 2.0]}, "expected a number or a list of 6 numbers"),
    ({"r_wrench": -1.0}, "expected a number > 0"),
    ({"design": "hinf"}, "expected one of discrete, continuous"),
])
def test_bad_parameters_are_one_line(vehicle, parameters, message):
    with pytest.raises(UvmsInputError, match=message) as info:
        make_controller("lqr", vehicle, parameters=parameters)
    key = next(iter(parameters))
    assert info.value.path == f"controller.parameters.{key}" and "\n" not in str(info.value)


@pytest.mark.slow
def test_holds_depth_and_attitude_while_the_bundled_arm_reaches():
    """The bundled reach scenario (BlueROV2 Heavy, eight T200 thrusters, the Alpha 5 reaching forward and down by
    computed torque) with ``lqr`` on all six axes instead of the 3-axis PID: depth within 1 mm, roll and pitch
    within 1 deg, horizontal position within 5 mm; the 3-axis PID leaves pitch to the righting moment (about 11
    deg, the arm's moment against ``m_f g h``)."""
    import yaml

    from uvms.sim.scenario import resolve_scenario_path, run_scenario, scenario_from_data

    data = yaml.safe_load(resolve_scenario_path("bluerov2_heavy_alpha5_reach").read_text())
    peaks = {}
    for name in ("lqr", "pid"):
        data["controller"] = {"name": name, "period": 0.01}
        data["outputs"] = {"record_period": 0.05}
        result = run_scenario(scenario_from_data(data, default_name=f"reach-{name}"))
        assert result.complete
        p = result.position - result.position[0]
        peaks[name] = (np.abs(p[:, 2]).max(), np.degrees(np.abs(result.euler[:, :2]).max()), np.abs(p[:, :2]).max())
    depth, tilt, horizontal = peaks["lqr"]
    assert depth < 1e-3 and tilt < 1.0 and horizontal < 5e-3
    assert peaks["pid"][1] > 5.0
