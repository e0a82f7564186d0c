"""Bundled controllers fed measurements (``feedback: measured``, :mod:`uvms.control.estimator`).

- The compiled readings are the sensors' numpy models (:mod:`uvms.sensors`, checked against closed forms in
  ``tests/sensors``) with the same seeded errors: the estimator's rates, velocity, depth and joints, driven
  along a recorded trajectory, equal those models' samples mapped to body axes by hand.
- The dead reckoning is the trapezoid written out again here (attitude by the exact rotation of the mean rate,
  position by the trapezoid of ``R v``), and with ideal sensors its error is second order in the sample period.
- Closed loop: with ideal sensors the measured-feedback run converges to the true-state run at that order;
  noise changes the run; a seed reproduces it; the default feedback (the true state) is unchanged by sensors.
"""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.estimator import sensing_data, sense
from uvms.control.registry import make_controller
from uvms.errors import UvmsInputError
from uvms.rotations import rotation_from_euler, rotations_from_quaternions
from uvms.sensors import Dvl, Encoders, Imu, Mount, NoiseDensity, PressureSensor
from uvms.sim.inputs import paper_torques
from uvms.state import JOINTS, NU, POSITION, QUATERNION

H = 1e-3
OFFSET, RPY = np.array([0.3, -0.1, 0.12]), np.array([0.2, -0.1, 0.6])
RESOLUTION = 2 * np.pi / 4096


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("paper")


def _start(model):
    return uvms.State.from_euler(model, position=[1.0, -2.0, 5.0], euler=[0.1, 0.2, 0.3],
                                 nu=[0.1, -0.2, 0.15, 0.3, 0.1, -0.1], q=0.2 * np.ones(model.n_joints))


def _sensors(noisy: bool, rate: float = 100.0, seed: int = 0, mount=Mount.of(OFFSET, RPY)):
    return [Imu(rate=rate, mount=mount, seed=seed,
                gyro=NoiseDensity(white=2e-3, bias_instability=1e-3, random_walk=1e-4) if noisy else NoiseDensity()),
            PressureSensor(rate=rate / 5, mount=mount, noise=50.0 if noisy else 0.0,
                           resolution=5.0 if noisy else 0.0, seed=seed + 1),
            Dvl(rate=rate / 4, mount=mount, noise=0.02 if noisy else 0.0, water_depth=30.0, max_altitude=40.0,
                dropout=0.3 if noisy else 0.0, seed=seed + 2),
            Encoders(rate=rate / 2, joints=("a", "b", "c"), indices=(0, 1, 2),
                     resolutions=(RESOLUTION if noisy else 0.0,) * 3)]


def _true_run(model, duration=0.4, sensors=None):
    """A run whose every step is recorded (the trajectory the estimator is driven along)."""
    return uvms.simulate(model, _start(model), duration=duration, step=H, sensors=sensors,
                         joint_torques=np.linspace(1.0, -1.0, model.n_joints), record_period=H)


def _drive(model, result, sensors):
    """The compiled estimator's estimate after each recorded step (sampled as the loop samples it)."""
    s = sensing_data(sensors, model, result.states[0], h=H, n_total=result.time.size - 1)
    estimates = np.empty_like(result.states)
    for done, x in enumerate(result.states):
        sense(s, np.ascontiguousarray(x), done)
        estimates[done] = s.x_hat
    return estimates


def _quaternion_product(a, b):
    aw, av, bw, bv = a[0], a[1:], b[0], b[1:]
    return np.concatenate([[aw * bw - av @ bv], aw * bv + bw * av + np.cross(av, bv)])


def _rotation(qv):
    return rotations_from_quaternions(qv[None] / np.linalg.norm(qv))[0]


def test_the_compiled_readings_are_the_sensor_models(model):
    """Noisy sensors: at each sample the estimate's omega is ``R_bs`` times the IMU model's gyro sample, v is
    ``R_bs`` bottom - omega x r of the last valid DVL sample, the joints are the encoders' samples and their
    differences, z is the pressure model's depth carried to the body origin with the estimated attitude."""
    sensors = _sensors(noisy=True)
    result = _true_run(model, sensors=sensors)
    est = _drive(model, result, sensors)
    imu, dvl, enc, depth = (result.sensors[k] for k in ("imu", "dvl", "encoders", "pressure"))
    B = rotation_from_euler(RPY)
    steps = np.round(result.time / H).astype(int)
    omega = None
    for done in steps[1:]:
        k_imu = done // 10
        omega = B @ np.array([imu[c][k_imu] for c in ("gyro_x", "gyro_y", "gyro_z")])
        np.testing.assert_allclose(est[done, NU:NU + 3], omega, rtol=0, atol=1e-14)
        valid = np.flatnonzero(dvl["bottom_valid"][:done // 40 + 1] > 0)
        if valid.size and valid[-1] > 0:
            k = valid[-1]
            omega_then = B @ np.array([imu[c][k * 4] for c in ("gyro_x", "gyro_y", "gyro_z")])
            v = B @ np.array([dvl[c][k] for c in ("bottom_x", "bottom_y", "bottom_z")]) - np.cross(omega_then, OFFSET)
            np.testing.assert_allclose(est[done, NU + 3:JOINTS], v, rtol=0, atol=1e-14)
        k_enc = done // 20
        q = np.array([enc[c][k_enc] for c in ("a", "b", "c")])
        np.testing.assert_allclose(est[done, JOINTS:JOINTS + 3], q, rtol=0, atol=1e-15)
        if k_enc > 0:
            q_before = np.array([enc[c][k_enc - 1] for c in ("a", "b", "c")])
            np.testing.assert_allclose(est[done, JOINTS + 3:JOINTS + 6], (q - q_before) / 0.02, rtol=1e-12)
        if done % 50 == 0:
            lever = (_rotation(est[done, QUATERNION:NU]) @ OFFSET)[2]
            np.testing.assert_allclose(est[done, POSITION + 2], depth["depth"][done // 50] - lever, rtol=0,
                                       atol=1e-12)
    assert np.any(dvl["bottom_valid"] == 0)           # dropouts happened and were held across


def test_the_dead_reckoning_is_the_trapezoid_and_second_order(model):
    """Ideal sensors at one rate: the compiled attitude and position equal the trapezoid written out in numpy
    from the IMU's and the DVL's samples; the error against the true pose falls by 4 when the rate doubles."""
    errors = []
    for rate in (125.0, 250.0, 500.0):
        sensors = [Imu(rate=rate), PressureSensor(rate=rate), Dvl(rate=rate), Encoders(rate=rate, joints=("a", "b", "c"),
                                                                                    indices=(0, 1, 2),
                                                                                    resolutions=(0.0,) * 3)]
        result = _true_run(model, duration=0.4, sensors=sensors)
        est = _drive(model, result, sensors)
        every = int(round(1 / (rate * H)))
        imu, dvl = result.sensors["imu"], result.sensors["dvl"]
        qv, p = result.states[0, QUATERNION:NU].copy(), result.states[0, POSITION:QUATERNION].copy()
        qv /= np.linalg.norm(qv)
        w_prev = np.array([imu[c][0] for c in ("gyro_x", "gyro_y", "gyro_z")])
        v_prev = np.array([dvl[c][0] for c in ("bottom_x", "bottom_y", "bottom_z")])
        dt = every * H
        for k in range(1, imu.time.size):
            w = np.array([imu[c][k] for c in ("gyro_x", "gyro_y", "gyro_z")])
            v = np.array([dvl[c][k] for c in ("bottom_x", "bottom_y", "bottom_z")])
            wm = 0.5 * (w_prev + w)
            angle = np.linalg.norm(wm) * dt
            dq = np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * wm / np.linalg.norm(wm)])
            R0 = _rotation(qv)
            qv = _quaternion_product(qv, dq)
            qv /= np.linalg.norm(qv)
            p = p + 0.5 * dt * (R0 @ v_prev + _rotation(qv) @ v)
            w_prev, v_prev = w, v
            row = k * every
            np.testing.assert_allclose(est[row, QUATERNION:NU], qv, rtol=0, atol=1e-13)
            np.testing.assert_allclose(est[row, POSITION:POSITION + 2], p[:2], rtol=0, atol=1e-13)
        end = result.states[-1]
        errors.append(max(np.max(np.abs(est[-1, POSITION:QUATERNION] - end[POSITION:QUATERNION])),
                          np.max(np.abs(_rotation(est[-1, QUATERNION:NU]) - _rotation(end[QUATERNION:NU])))))
        np.testing.assert_allclose(est[-1, NU:JOINTS], end[NU:JOINTS], rtol=0, atol=1e-14)    # rates exact
        np.testing.assert_array_equal(est[-1, JOINTS:JOINTS + 3], end[JOINTS:JOINTS + 3])     # joints exact
    ratios = np.array(errors[:-1]) / np.array(errors[1:])
    assert np.all((ratios > 3.0) & (ratios < 5.5)), (errors, ratios)


def _closed_loop(model, feedback, sensors, name="pid", duration=3.0):
    controller = make_controller(name, model, period=0.01, parameters={"feedback": feedback})
    start = uvms.State.from_euler(model, position=[0.0, 0.0, 5.0], euler=[0.0, 0.0, 0.2])
    return uvms.simulate(model, start, duration=duration, step=H, controller=controller, sensors=sensors,
                         joint_torques=paper_torques(), record_period=H)


def test_ideal_sensors_give_the_true_state_run_to_the_dead_reckoning_error(model):
    """PID station keeping through the paper's arm motion, ideal sensors sampling at every controller update
    (100, 200, 500 Hz; the controller at 100 Hz): rates, depth and joints are exact, so the measured run differs
    from the true-state run only by the dead reckoning's error in attitude and x, y, second order in the sample
    period: the difference falls as ``T^2`` (by 4, then 6.25) and is below 1e-6 m at 500 Hz. (A sensor whose
    samples fall between updates adds the staleness of its last sample, first order: not tested here.)"""
    truth = _closed_loop(model, "true_state", None)
    gaps = []
    for rate in (100.0, 200.0, 500.0):
        sensors = [Imu(rate=rate), PressureSensor(rate=rate), Dvl(rate=rate),
                   Encoders(rate=rate, joints=("a", "b", "c"), indices=(0, 1, 2), resolutions=(0.0,) * 3)]
        measured = _closed_loop(model, "measured", sensors)
        assert measured.complete
        gaps.append(np.max(np.abs(measured.position - truth.position)))
    ratios = np.array(gaps[:-1]) / np.array(gaps[1:]) / np.array([4.0, 6.25])
    assert np.all((ratios > 0.75) & (ratios < 1.35)), (gaps, ratios)
    assert gaps[-1] < 1e-6, gaps


@pytest.mark.parametrize("name", ["smc-vehicle", "smc-ne"])
def test_every_sliding_mode_controller_fed_ideal_sensors_follows_its_true_state_run(model, name):
    """The other two controllers that take ``feedback`` (``smc-ab`` and ``pid`` above): ideal sensors at 500 Hz,
    the controller at 100 Hz. The measured run differs from the true-state run by the dead reckoning's error
    only, which the PID case bounds at 1e-6 m: a controller that ignored the estimate, or read it wrongly, would
    drift by millimetres or more (the noisy case above moves by over 1e-4 m)."""
    truth = _closed_loop(model, "true_state", None, name=name, duration=1.0)
    sensors = [Imu(rate=500.0), PressureSensor(rate=500.0), Dvl(rate=500.0),
               Encoders(rate=500.0, joints=("a", "b", "c"), indices=(0, 1, 2), resolutions=(0.0,) * 3)]
    measured = _closed_loop(model, "measured", sensors, name=name, duration=1.0)
    assert measured.complete and truth.complete
    gap = np.max(np.abs(measured.position - truth.position))
    assert 0.0 < gap < 1e-6, gap
    noisy = _closed_loop(model, "measured", _sensors(noisy=True, mount=Mount()), name=name, duration=1.0)
    assert np.max(np.abs(noisy.position - truth.position)) > 1e-5


def test_noisy_sensors_change_the_run_and_a_seed_reproduces_it(model):
    truth = _closed_loop(model, "true_state", _sensors(noisy=True, mount=Mount()), name="smc-ab", duration=2.0)
    one = _closed_loop(model, "measured", _sensors(noisy=True, mount=Mount()), name="smc-ab", duration=2.0)
    again = _closed_loop(model, "measured", _sensors(noisy=True, mount=Mount()), name="smc-ab", duration=2.0)
    other = _closed_loop(model, "measured", _sensors(noisy=True, seed=7, mount=Mount()), name="smc-ab", duration=2.0)
    assert one.complete and other.complete
    np.testing.assert_array_equal(one.states, again.states)
    assert np.max(np.abs(one.position - truth.position)) > 1e-4
    assert np.max(np.abs(one.position - other.position)) > 1e-5
    assert np.max(np.abs(one.position - truth.position)) < 0.2          # still holding station
    for name in truth.sensors:                                          # the recorded samples are the same sensors'
        assert truth.sensors[name].time.size == one.sensors[name].time.size


def test_the_true_state_default_is_unchanged_by_declared_sensors(model):
    plain = _closed_loop(model, "true_state", None, name="smc-ab", duration=1.0)
    sensed = _closed_loop(model, "true_state", _sensors(noisy=True), name="smc-ab", duration=1.0)
    np.testing.assert_array_equal(plain.states, sensed.states)
    assert make_controller("smc-ab", model).parameters.feedback == "true_state"


def test_measured_feedback_without_the_sensors_it_needs_is_one_line(model):
    with pytest.raises(UvmsInputError, match="dvl, encoders") as error:
        _closed_loop(model, "measured", [Imu(rate=100.0), PressureSensor(rate=20.0)], duration=0.1)
    assert error.value.path == "controller.parameters.feedback"
    with pytest.raises(UvmsInputError, match="feedback"):
        make_controller("pid", model, parameters={"feedback": "estimated"})


def test_sampling_past_the_errors_drawn_for_the_run_raises(model):
    """The errors are drawn for ``n_total`` steps; a sample past them is refused, not read out of bounds."""
    result = _true_run(model, duration=0.02, sensors=_sensors(noisy=True))
    s = sensing_data(_sensors(noisy=True), model, result.states[0], h=H, n_total=20)
    x = np.ascontiguousarray(result.states[-1])
    sense(s, x, 20)
    with pytest.raises(ValueError, match="exhausted"):
        sense(s, x, 30)


def _scenario_file(tmp_path, sensors):
    import yaml

    data = {"model": "paper", "duration": 0.1, "step": 0.001, "initial_state": {"position": [0, 0, 5.0]},
            "controller": {"name": "pid", "period": 0.01, "parameters": {"feedback": "measured"}},
            "outputs": {"record_period": 0.005}, "sensors": sensors}
    path = tmp_path / "measured.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_a_scenario_feeds_its_controller_measurements_and_a_missing_sensor_is_exit_2(tmp_path, capsys):
    """The docs' scenario (``docs/sensors.md``): it runs; without its DVL one line names the field, exit 2."""
    from uvms.cli import main
    from uvms.sim.scenario import load_scenario, run_scenario

    sensors = {"imu": {"kind": "imu", "rate": 200, "gyro": {"white": 3.0e-5, "bias_instability": 2.0e-5}},
               "depth": {"kind": "pressure", "rate": 20, "noise": 100.0, "resolution": 10.0},
               "dvl": {"kind": "dvl", "rate": 5, "noise": 0.01, "water_depth": 30.0, "max_altitude": 50.0,
                       "dropout": 0.05},
               "encoders": {"kind": "encoders", "rate": 100, "counts_per_turn": 4096}}
    result = run_scenario(load_scenario(_scenario_file(tmp_path, sensors)))
    assert result.complete
    assert set(result.sensors) == set(sensors)
    del sensors["dvl"]
    assert main(["run", str(_scenario_file(tmp_path, sensors)), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("uvms: error: controller.parameters.feedback: expected the run's sensors to include "
                              "dvl"), err


def test_the_loop_with_events_in_python_feeds_the_same_measurements(model):
    """A user's Python arm puts the run's events in Python (``uvms.sim.loop``); the compiled controller fed
    noisy measurements there gives the rows of the compiled loop (the sensing is the same kernel, sampled in
    ``event_start``)."""
    from uvms.sim.compiled_loop import compilable
    from uvms.sim.run import prepare

    tau = np.linspace(1.0, -1.0, model.n_joints)

    class PythonArm:
        def __call__(self, t, state):
            return tau

    rows = []
    for arm in (tau, PythonArm()):
        controller = make_controller("pid", model, period=0.01, parameters={"feedback": "measured"})
        kw = dict(duration=0.5, step=H, controller=controller, sensors=_sensors(noisy=True), joint_torques=arm,
                  record_period=H)
        assert compilable(prepare(model, _start(model), **kw)) is (arm is tau)
        rows.append(uvms.simulate(model, _start(model), **kw))
    np.testing.assert_allclose(rows[1].states, rows[0].states, rtol=1e-12, atol=1e-12)
    truth = uvms.simulate(model, _start(model), duration=0.5, step=H, joint_torques=tau, record_period=H,
                          controller=make_controller("pid", model, period=0.01))
    assert np.max(np.abs(rows[0].position - truth.position)) > 1e-6          # the measurements did act
