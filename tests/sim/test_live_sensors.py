"""A Python controller's ``Measurement.sensors``: the latest reading of each sensor at every update, labelled by
sensor and channel, checked against the sensors' own models evaluated independently on the recorded states
(the gyro and the pressure written out by hand, the rest through the after-run tables that
``tests/sensors`` checks against closed forms), noise included: sample ``k`` carries the recorded sample's
errors."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.control.base import ControlOutput
from uvms.rotations import rotation_from_euler, rotations_from_quaternions
from uvms.sensors import Dvl, Encoders, Imu, Mount, NoiseDensity, PressureSensor, Reading
from uvms.state import JOINTS, NU, QUATERNION

H = 1e-3
OFFSET, RPY = np.array([0.3, -0.1, 0.12]), np.array([0.2, -0.1, 0.6])
WRENCH = np.array([0.5, -0.3, 0.2, 4.0, -3.0, 2.0])


class Recorder:
    """A Python controller: a constant wrench, and a copy of every measurement's sensors."""

    def __init__(self, period: float) -> None:
        self.period = period
        self.seen: list = []

    def reset(self) -> None:
        self.seen = []

    def update(self, measurement) -> ControlOutput:
        self.seen.append((measurement.time, dict(measurement.sensors)))
        return ControlOutput(wrench=WRENCH)


def _sensors():
    return [Imu(name="imu", rate=200.0, mount=Mount.of(OFFSET, RPY), gyro=NoiseDensity(white=2e-3, bias=1e-3),
                accel=NoiseDensity(white=5e-3, random_walk=1e-3), seed=4),
            PressureSensor(name="depth", rate=20.0, mount=Mount.of(OFFSET), noise=30.0, resolution=2.0, seed=5),
            Dvl(name="dvl", rate=25.0, mount=Mount.of(OFFSET, RPY), noise=0.01, water_depth=30.0,
                max_altitude=40.0, dropout=0.3, seed=6),
            Encoders(name="arm", rate=50.0, joints=("j1", "j2", "j3"), indices=(0, 1, 2),
                     resolutions=(2 * np.pi / 4096,) * 3)]


@pytest.fixture(scope="module")
def run():
    model = uvms.load_model("paper")
    start = uvms.State.from_euler(model, position=[1.0, -2.0, 5.0], euler=[0.1, 0.2, 0.3],
                                  nu=[0.1, -0.2, 0.15, 0.3, 0.1, -0.1], q=0.2 * np.ones(model.n_joints))
    controller = Recorder(period=0.03)
    sensors = _sensors()
    result = uvms.simulate(model, start, duration=0.3, step=H, controller=controller, sensors=sensors,
                           joint_torques=np.linspace(1.0, -1.0, model.n_joints), record_period=H)
    return model, controller, sensors, result


def _row(result, t):
    return int(np.searchsorted(np.round(result.time / H).astype(int), int(round(t / H))))


def test_every_update_sees_the_latest_sample_of_each_sensor(run):
    _, controller, sensors, result = run
    assert len(controller.seen) == 10
    for t, readings in controller.seen:
        assert list(readings) == [s.name for s in sensors]
        for s in sensors:
            reading = readings[s.name]
            assert isinstance(reading, Reading) and reading.kind == s.kind and reading.frame_id == s.name
            period = round(1.0 / (s.rate * H))
            assert round(reading.time / H) == (round(t / H) // period) * period     # at or before the update
            assert set(reading.values) == set(result.sensors[s.name].columns)


def test_the_readings_are_the_sensor_models_with_the_recorded_noise(run):
    """Gyro ``R_bs^T omega + e_k`` and pressure ``p_atm + rho |g| depth + e_k`` (rounded) by hand from the
    recorded state, ``e_k`` the sensor's own seeded errors; every channel equals the after-run table's sample of
    the same time (the accelerometer at ``t > 0``: at ``t = 0`` no input is held yet, neither the first command
    nor the first joint torques, so the specific force is the one with none, written out from ``uvms.Dynamics``)."""
    model, controller, sensors, result = run
    imu, pressure = sensors[0], sensors[1]
    R_bs = rotation_from_euler(RPY)
    gyro_errors = imu.errors(61)["gyro"]
    p_errors = pressure.errors(7)["pressure"]
    g = np.linalg.norm(model.gravity)
    for t, readings in controller.seen:
        for s in sensors:
            reading, table = readings[s.name], result.sensors[s.name]
            k = int(np.flatnonzero(np.isclose(table.time, reading.time, rtol=0, atol=1e-12))[0])
            for channel, value in reading.values.items():
                if s.kind == "imu" and channel.startswith("accel") and reading.time == 0.0:
                    continue
                np.testing.assert_array_equal(value, table[channel][k], err_msg=f"{s.name}.{channel} at {t}")
        x = result.states[_row(result, readings["imu"].time)]
        k = int(round(readings["imu"].time / 0.005))
        np.testing.assert_allclose([readings["imu"][c] for c in ("gyro_x", "gyro_y", "gyro_z")],
                                   R_bs.T @ x[NU:NU + 3] + gyro_errors[k], rtol=0, atol=1e-12)
        x = result.states[_row(result, readings["depth"].time)]
        R = rotations_from_quaternions(x[None, QUATERNION:NU] / np.linalg.norm(x[QUATERNION:NU]))[0]
        depth = x[2] + (R @ OFFSET)[2]
        k = int(round(readings["depth"].time / 0.05))
        expected = 2.0 * np.round((101_325.0 + 1000.0 * g * depth + p_errors[k]) / 2.0)
        assert readings["depth"]["pressure"] == pytest.approx(expected, abs=1e-9)
    first = controller.seen[0][1]["imu"]
    start = result.state(0)
    nu_dot = uvms.Dynamics(model).forward(start, joint_torques=np.zeros(model.n_joints)).nu_dot
    x = result.states[0]
    omega, v, omega_dot, v_dot = x[NU:NU + 3], x[NU + 3:JOINTS], nu_dot[:3], nu_dot[3:]
    R = rotations_from_quaternions(x[None, QUATERNION:NU] / np.linalg.norm(x[QUATERNION:NU]))[0]
    a = v_dot + np.cross(omega, v) + np.cross(omega_dot, OFFSET) + np.cross(omega, np.cross(omega, OFFSET))
    expected = R_bs.T @ (a - R.T @ model.gravity) + imu.errors(1)["accel"][0]
    np.testing.assert_allclose([first[c] for c in ("accel_x", "accel_y", "accel_z")], expected, rtol=0, atol=1e-10)


def test_without_sensors_a_measurement_has_none():
    model = uvms.load_model("paper")
    controller = Recorder(period=0.05)
    uvms.simulate(model, duration=0.1, step=H, controller=controller)
    assert controller.seen and all(readings == {} for _, readings in controller.seen)
