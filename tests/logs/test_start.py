"""The state at a log's start: pose interpolated, body velocities from the local fit, joints with offset and
sign, the frame of the model; against a synthetic motion whose values are known in closed form."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import uvms
from uvms.errors import UvmsInputError
from uvms.logs import Log

from .files import POSE_HEADER, POSE_XYZW, pose_rows, write_csv

V_WORLD = np.array([0.3, -0.2, 0.1])      # constant world velocity [m/s]
OMEGA = np.array([0.1, -0.2, 0.3])        # constant body angular velocity [rad/s]
P0 = np.array([1.0, 2.0, -3.0])
R0 = Rotation.from_euler("ZYX", [0.7, -0.2, 0.1])
T0 = 1.005                                 # the replay's start, between two rows


def _attitude(t):
    """``R(t) = R0 exp(omega t)``: a constant body rate (scipy composes ``R0 * R(omega t)``)."""
    return R0 * Rotation.from_rotvec(np.outer(t, OMEGA))


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("paper")


def _write_motion(folder, *, imu_rates=None):
    t = np.arange(0.0, 2.0 + 1e-9, 0.01)             # 100 Hz
    write_csv(folder / "pose.csv", POSE_HEADER,
              pose_rows(t, P0 + np.outer(t, V_WORLD), _attitude(t).as_quat()))
    write_csv(folder / "joints.csv", ["t", "a", "b", "b_rate"], [[x, 0.2 + 0.5 * x, -x, 7.0] for x in t])
    description = {"frame": "ned", "start": T0, "duration": 0.5, "pose": {"file": "pose.csv", **POSE_XYZW},
                   "joints": {"file": "joints.csv", "time": "t", "columns": {"joint1": "a", "joint3": "b"},
                              "rates": {"joint3": "b_rate"}, "sign": {"joint1": -1}, "offset": {"joint1": 1.0}}}
    if imu_rates is not None:
        write_csv(folder / "imu.csv", ["t", "p", "q", "r"], [[x, *imu_rates] for x in (0.0, 2.0)])
        description["imu"] = {"file": "imu.csv", "time": "t", "angular_velocity": ["p", "q", "r"]}
    return Log.from_dict(description, base_dir=folder)


def test_constant_velocity_and_rate_give_the_exact_start_state(tmp_path, model):
    """Position ``P0 + v t0``, attitude ``R0 exp(omega t0)``, ``nu = [omega; R(t0)^T v]``; joint1 ``-(0.2 + 0.5
    t0) + 1`` with rate ``-0.5`` (fitted), joint3 ``-t0`` with its logged rate 7, joint2 (not logged) zero."""
    state = _write_motion(tmp_path).initial_state(model)
    assert state.position == pytest.approx(P0 + T0 * V_WORLD, abs=1e-13)
    expected = _attitude([T0])[0].as_quat()                       # x, y, z, w
    q = state.quaternion * np.sign(state.quaternion[0] * expected[3])
    assert q == pytest.approx([expected[3], *expected[:3]], abs=1e-13)
    body_velocity = _attitude([T0])[0].inv().apply(V_WORLD)
    assert state.nu[:3] == pytest.approx(OMEGA, abs=1e-10)
    assert state.nu[3:] == pytest.approx(body_velocity, abs=1e-12)
    assert state.q == pytest.approx([-(0.2 + 0.5 * T0) + 1.0, 0.0, -T0], abs=1e-13)
    assert state.qd == pytest.approx([-0.5, 0.0, 7.0], abs=1e-11)


def test_the_start_state_in_the_other_frame(tmp_path, model):
    """The same motion asked for in enu: ``H p``, ``[w, x, -y, -z]``, ``H omega``, ``H v``; joints unchanged."""
    log = _write_motion(tmp_path)
    ned, enu = log.initial_state(model), log.initial_state(model, frame="enu")
    flip = np.array([1.0, -1.0, -1.0])
    assert enu.position == pytest.approx(flip * ned.position, abs=1e-15)
    assert enu.quaternion == pytest.approx(np.r_[1.0, flip] * ned.quaternion, abs=1e-15)
    assert enu.nu == pytest.approx(np.r_[flip, flip] * ned.nu, abs=1e-15)
    assert enu.q == pytest.approx(ned.q, abs=0) and enu.qd == pytest.approx(ned.qd, abs=0)
    assert log.in_frame("enu").initial_state(model).nu == pytest.approx(ned.nu, abs=1e-12)   # model is ned


def test_omega_from_the_imu(tmp_path, model):
    state = _write_motion(tmp_path, imu_rates=[0.4, 0.0, -0.1]).initial_state(model, omega_from="imu")
    assert state.nu[:3] == pytest.approx([0.4, 0.0, -0.1], abs=1e-15)


def test_a_joint_the_model_lacks_is_one_line_listing_the_models_joints(tmp_path, model):
    log = _write_motion(tmp_path)
    renamed = Log.from_dict(log.spec.model_dump() | {"joints": log.spec.joints.model_dump() | {
        "columns": {"elbow": "a"}, "rates": {}, "sign": {}, "offset": {}}}, base_dir=tmp_path, source="log.yaml")
    with pytest.raises(UvmsInputError) as error:
        renamed.initial_state(model)
    assert str(error.value) == ("log.yaml: joints.columns: model 'paper' has no joint 'elbow'; its joints: joint1, "
                                "joint2, joint3")


def test_a_window_with_too_few_rows_and_imu_rates_that_are_not_there(tmp_path, model):
    log = _write_motion(tmp_path)
    with pytest.raises(UvmsInputError, match=r"window: pose: 2 rows within 0.006 s of the start, a degree-2 fit "
                                             r"needs 3"):
        log.initial_state(model, window=0.003)   # widened 4 times: rows at 1.00 and 1.01 s only
    widened = log.initial_state(model, window=0.012)     # 2 rows, widened to 0.024 s: 3 rows
    np.testing.assert_array_equal(widened.nu, log.initial_state(model, window=0.024).nu)
    with pytest.raises(UvmsInputError, match="omega_from='imu' needs an imu stream"):
        log.initial_state(model, omega_from="imu")
