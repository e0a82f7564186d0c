"""Sensors sampled on a run: with the noise off they give the true values, checked against hand-computed
kinematics (the lever-arm formula written out, and a finite-difference second derivative of the mount's world
path), the hydrostatic pressure rho g z, the joint angles, and the water velocity evaluated by hand (uniform
current, a linear depth profile, one deep-water Airy wave: DNV-RP-C205 eq. 3.2.2 ff.)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import uvms
from uvms.errors import UvmsInputError
from uvms.hydro.currents import CurrentProfile
from uvms.hydro.flow import Flow
from uvms.hydro.waves import WaveComponents
from uvms.rotations import rotation_from_euler, rotations_from_quaternions
from uvms.sensors import Dvl, Encoders, Imu, Mount, NoiseDensity, PressureSensor
from uvms.state import JOINTS, NU, QUATERNION

OFFSET, RPY = np.array([0.3, -0.1, 0.12]), np.array([0.2, -0.1, 0.6])


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("paper")


def _start(model):
    return uvms.State.from_euler(model, position=[1.0, -2.0, 5.0], euler=[0.1, 0.2, 0.3],
                                 nu=[0.1, -0.2, 0.15, 0.3, 0.1, -0.1], q=0.2 * np.ones(model.n_joints))


def _run(model, sensors, duration=0.2, **options):
    return uvms.simulate(model, _start(model), duration=duration, step=1e-3, sensors=sensors,
                         joint_torques=np.linspace(1.0, -1.0, model.n_joints), **options)


def _rows(result, times):
    index = np.round(result.time / 1e-3).astype(int)
    return np.searchsorted(index, np.round(np.asarray(times) / 1e-3).astype(int))


def test_imu_without_noise_is_the_specific_force_and_rate_at_its_mount(model):
    """gyro = R_bs^T omega; accel = R_bs^T (v_dot + omega x v + omega_dot x r + omega x (omega x r) - R^T g), with
    nu_dot from uvms.Dynamics.forward at each sampled state (Titterton and Weston 2004, eq. 3.8); and the
    specific force equals R_bs^T R^T (d^2/dt^2 (p + R r) - g) by central differences of every-step rows."""
    imu = Imu(rate=100.0, mount=Mount.of(OFFSET, RPY))
    current = np.array([0.1, 0.2, 0.0])
    result = _run(model, [imu], current=current, record_period=1e-3)
    record = result.sensors["imu"]
    np.testing.assert_allclose(record.time, np.arange(21) * 0.01, atol=1e-12)
    dynamics = uvms.Dynamics(model)
    R_bs = rotation_from_euler(RPY)
    tau = np.linspace(1.0, -1.0, model.n_joints)
    for k, r in enumerate(_rows(result, record.time)):
        x = result.states[r]
        state = result.state(r)
        nu_dot = dynamics.forward(state, joint_torques=tau, current=current).nu_dot
        omega, v, omega_dot, v_dot = x[NU:NU + 3], x[NU + 3:JOINTS], nu_dot[:3], nu_dot[3:]
        R = rotations_from_quaternions(x[None, QUATERNION:NU] / np.linalg.norm(x[QUATERNION:NU]))[0]
        a = v_dot + np.cross(omega, v) + np.cross(omega_dot, OFFSET) + np.cross(omega, np.cross(omega, OFFSET))
        expected_f = R_bs.T @ (a - R.T @ model.gravity)
        got_f = [record[c][k] for c in ("accel_x", "accel_y", "accel_z")]
        got_w = [record[c][k] for c in ("gyro_x", "gyro_y", "gyro_z")]
        np.testing.assert_allclose(got_w, R_bs.T @ omega, rtol=0, atol=1e-12)
        np.testing.assert_allclose(got_f, expected_f, rtol=0, atol=1e-11)
    # finite differences of the mount's world path (independent of the formula), interior samples
    R_all = rotations_from_quaternions(result.quaternion / np.linalg.norm(result.quaternion, axis=1)[:, None])
    mount = result.position + R_all @ OFFSET
    h = 1e-3
    for k in range(1, 20):
        r = _rows(result, [record.time[k]])[0]
        a_world = (mount[r + 1] - 2 * mount[r] + mount[r - 1]) / h ** 2
        expected = R_bs.T @ R_all[r].T @ (a_world - model.gravity)
        got = np.array([record[c][k] for c in ("accel_x", "accel_y", "accel_z")])
        np.testing.assert_allclose(got, expected, rtol=0, atol=2e-4)


def test_pressure_encoders_and_rates(model):
    """p = p_atm + rho |g| z at the mount (z down from the surface at 0); encoders at resolution 0 are the joint
    angles and at 2 pi / 4096 their nearest count; each sensor samples at k / rate."""
    n = model.n_joints
    pressure = PressureSensor(rate=20.0, mount=Mount.of(OFFSET), density=1025.0, atmosphere=1.0e5)
    exact = Encoders(name="exact", rate=50.0, joints=tuple(model.joint_names), indices=tuple(range(n)),
                     resolutions=(0.0,) * n)
    counts = Encoders(name="counts", rate=25.0, joints=tuple(model.joint_names), indices=tuple(range(n)),
                      resolutions=(2 * math.pi / 4096,) * n)
    result = _run(model, [pressure, exact, counts], record_period=0.01)
    p = result.sensors["pressure"]
    np.testing.assert_allclose(p.time, np.arange(5) * 0.05, atol=1e-12)
    rows = _rows(result, p.time)
    R = rotations_from_quaternions(result.quaternion[rows] / np.linalg.norm(result.quaternion[rows], axis=1)[:, None])
    z = result.position[rows, 2] + (R @ OFFSET)[:, 2]
    np.testing.assert_allclose(p["pressure"], 1.0e5 + 1025.0 * np.linalg.norm(model.gravity) * z, rtol=1e-15)
    np.testing.assert_allclose(p["depth"], z, atol=1e-10)
    e = result.sensors["exact"]
    np.testing.assert_allclose(e.time, np.arange(11) * 0.02, atol=1e-12)
    q = result.states[_rows(result, e.time), JOINTS:JOINTS + n]
    for j, name in enumerate(model.joint_names):
        np.testing.assert_array_equal(e[name], q[:, j])
    c = result.sensors["counts"]
    np.testing.assert_allclose(c.time, np.arange(6) * 0.04, atol=1e-12)
    q = result.states[_rows(result, c.time), JOINTS:JOINTS + n]
    res = 2 * math.pi / 4096
    for j, name in enumerate(model.joint_names):
        assert np.all(np.abs(c[name] - q[:, j]) <= res / 2 + 1e-15)
        np.testing.assert_allclose(c[name] / res, np.round(c[name] / res), atol=1e-9)
    assert result.metadata["sensors"]["counts"] == {"kind": "encoders", "rate_hz": 25.0, "frame_id": "counts"}


def _water_track(result, record, rows, u_world):
    R_bs = rotation_from_euler(RPY)
    x = result.states[rows]
    R = rotations_from_quaternions(x[:, QUATERNION:NU] / np.linalg.norm(x[:, QUATERNION:NU], axis=1)[:, None])
    omega, v = x[:, NU:NU + 3], x[:, NU + 3:JOINTS]
    v_mount = v + np.cross(omega, OFFSET)
    bottom = v_mount @ R_bs
    water = np.einsum("ij,ki->kj", R_bs, v_mount - np.einsum("kji,kj->ki", R, u_world))
    return bottom, water, R


def test_dvl_water_track_is_velocity_through_a_uniform_current(model):
    """water = R_bs^T (v + omega x r - R^T u) to 1e-12, bottom = R_bs^T (v + omega x r), noise off."""
    dvl = Dvl(rate=10.0, mount=Mount.of(OFFSET, RPY))
    current = np.array([0.3, -0.2, 0.05])
    result = _run(model, [dvl], current=current, record_period=0.01)
    record = result.sensors["dvl"]
    rows = _rows(result, record.time)
    bottom, water, _ = _water_track(result, record, rows, np.tile(current, (rows.size, 1)))
    got_w = np.stack([record[c] for c in ("water_x", "water_y", "water_z")], 1)
    got_b = np.stack([record[c] for c in ("bottom_x", "bottom_y", "bottom_z")], 1)
    np.testing.assert_allclose(got_w, water, rtol=0, atol=1e-12)
    np.testing.assert_allclose(got_b, bottom, rtol=0, atol=1e-12)
    assert np.all(record["bottom_valid"] == 1.0)


def test_dvl_water_track_in_a_depth_profile_and_a_wave(model):
    """The water at the mount by hand: linear interpolation of the profile at the mount's depth plus one
    deep-water Airy component, u_h = a w e^{k zeta} cos theta along b, u_up = a w e^{k zeta} sin theta,
    theta = k (x cos b + y sin b) - w t + phi, zeta = -z (world z down, surface at 0)."""
    depth, velocity = np.array([0.0, 4.0, 8.0]), np.array([[0.5, 0.0, 0.0], [0.2, 0.1, 0.0], [0.0, 0.3, 0.02]])
    a, w, b, phi = 0.3, 0.9, 0.4, 0.7
    k = w * w / 9.81
    flow = Flow([0.0], [[0.05, 0.0, 0.0]], [[0.0, 0.0, 0.0]], profile=CurrentProfile(depth, velocity),
                waves=WaveComponents(np.array([a]), np.array([w]), np.array([k]), np.array([b]), np.array([phi]),
                                     math.inf))
    dvl = Dvl(rate=10.0, mount=Mount.of(OFFSET, RPY))
    result = _run(model, [dvl], flow=flow, record_period=0.01)
    record = result.sensors["dvl"]
    rows = _rows(result, record.time)
    R = rotations_from_quaternions(result.quaternion[rows] / np.linalg.norm(result.quaternion[rows], axis=1)[:, None])
    point = result.position[rows] + R @ OFFSET
    u = np.tile([0.05, 0.0, 0.0], (rows.size, 1))
    u += np.stack([np.interp(point[:, 2], depth, velocity[:, i]) for i in range(3)], 1)
    zeta = -point[:, 2]
    theta = k * (point[:, 0] * np.cos(b) + point[:, 1] * np.sin(b)) - w * record.time + phi
    amp = a * w * np.exp(k * zeta)
    u += np.stack([amp * np.cos(theta) * np.cos(b), amp * np.cos(theta) * np.sin(b), -amp * np.sin(theta)], 1)
    _, water, _ = _water_track(result, record, rows, u)
    got = np.stack([record[c] for c in ("water_x", "water_y", "water_z")], 1)
    np.testing.assert_allclose(got, water, rtol=0, atol=1e-12)


def test_noisy_sensors_are_seeded_and_reproducible(model):
    """The same seed gives the same samples, another seed others; the noise-free run differs by the noise."""
    def sensors(seed):
        return [Imu(rate=100.0, gyro=NoiseDensity(white=1e-3, bias_instability=1e-4), accel=NoiseDensity(white=1e-2),
                    seed=seed), PressureSensor(rate=20.0, noise=50.0, resolution=10.0, seed=seed),
                Dvl(rate=10.0, noise=0.01, dropout=0.3, seed=seed)]
    a, b, c = (_run(model, sensors(s), duration=0.1, record_period=0.01) for s in (1, 1, 2))
    for name in ("imu", "pressure", "dvl"):
        for col in a.sensors[name].columns:
            np.testing.assert_array_equal(a.sensors[name][col], b.sensors[name][col])
    assert not np.allclose(a.sensors["imu"]["gyro_x"], c.sensors["imu"]["gyro_x"])
    p = a.sensors["pressure"]["pressure"]
    np.testing.assert_allclose(p / 10.0, np.round(p / 10.0), atol=1e-9)


def test_a_sensor_period_off_the_record_grid_is_refused(model):
    with pytest.raises(UvmsInputError, match=r"sensors\.dvl\.rate: .*whole multiple of the record period"):
        _run(model, [Dvl(rate=8.0)], duration=0.1, record_period=0.01)
    with pytest.raises(UvmsInputError, match=r"sensors\.imu\.rate"):
        _run(model, [Imu(rate=-1.0)], duration=0.1)
    result = _run(model, [Dvl(rate=8.0), Imu(rate=100.0)], duration=0.25)      # no record_period: the gcd
    np.testing.assert_allclose(result.sensors["dvl"].time, [0.0, 0.125, 0.25], atol=1e-12)
