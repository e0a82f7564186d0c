"""Reading a log: quaternion orders, frames, offsets and signs, slicing, alignment and resampling, each against
values worked out by hand (``docs/logs.md``)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import uvms
from uvms.errors import UvmsInputError
from uvms.logs import Log

from .files import POSE_HEADER, POSE_XYZW, pose_rows, write_csv, write_log

C15, S15 = math.cos(math.radians(15)), math.sin(math.radians(15))   # the half angles of a 30 deg yaw


def _yaw_log(tmp_path, frame="enu", **extra):
    """Three pose rows, yaw 0, 30, 60 deg about z at t = 0, 1, 2 s, moving along (1, 2, 3) m/s."""
    quats = [[0, 0, 0, 1], [0, 0, S15, C15], [0, 0, 0.5, math.sqrt(3) / 2]]
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 1, 2], [[0, 0, 0], [1, 2, 3], [2, 4, 6]], quats))
    return Log.load(write_log(tmp_path, {"frame": frame, "pose": {"file": "pose.csv", **POSE_XYZW}, **extra}))


def test_uvms_log_is_the_package_class():
    assert uvms.Log is Log


def test_the_two_quaternion_orders_give_the_same_attitude(tmp_path):
    """One 30 deg yaw written scalar last (x, y, z, w) and scalar first (w, x, y, z), in shuffled columns."""
    write_csv(tmp_path / "a.csv", ["t", "x", "y", "z", "i", "j", "k", "r"],
              [[0, 0, 0, 0, 0, 0, S15, C15], [1, 0, 0, 0, 0, 0, S15, C15]])
    write_csv(tmp_path / "b.csv", ["r", "t", "k", "j", "i", "x", "y", "z"],
              [[C15, 0, S15, 0, 0, 0, 0, 0], [C15, 1, S15, 0, 0, 0, 0, 0]])
    common = {"time": "t", "position": ["x", "y", "z"]}
    a = Log.from_dict({"frame": "ned", "pose": {"file": "a.csv", **common, "quaternion_xyzw": ["i", "j", "k", "r"]}},
                      base_dir=tmp_path)
    b = Log.from_dict({"frame": "ned", "pose": {"file": "b.csv", **common, "quaternion_wxyz": ["r", "i", "j", "k"]}},
                      base_dir=tmp_path)
    expected = [C15, 0.0, 0.0, S15]
    for log in (a, b):
        assert log.pose[["qw", "qx", "qy", "qz"]].to_numpy() == pytest.approx(np.array([expected, expected]),
                                                                              abs=1e-15)
        assert np.degrees(log.attitude().to_numpy()[0]) == pytest.approx([0.0, 0.0, 30.0], abs=1e-12)


def test_enu_numbers_in_ned_flip_y_z_pitch_and_yaw(tmp_path):
    """A 30 deg yaw in enu is -30 deg in ned; position (1, 2, 3) is (1, -2, -3); depth is -z in enu, z in ned."""
    log = _yaw_log(tmp_path)
    ned = log.in_frame("ned")
    assert ned.frame == "ned" and log.frame == "enu" and ned.pose.attrs["frame"] == "ned"
    assert np.degrees(log.attitude()["yaw_rad"].to_numpy()) == pytest.approx([0, 30, 60], abs=1e-12)
    assert np.degrees(ned.attitude()["yaw_rad"].to_numpy()) == pytest.approx([0, -30, -60], abs=1e-12)
    assert ned.pose.loc[1.0, ["x_m", "y_m", "z_m"]].to_list() == [1.0, -2.0, -3.0]
    assert log.resample([1.0])["depth_m"].item() == -3.0
    assert ned.resample([1.0])["depth_m"].item() == -3.0
    assert ned.in_frame("enu").pose.to_numpy() == pytest.approx(log.pose.to_numpy(), abs=1e-15)


def test_roll_pitch_yaw_in_enu_become_roll_minus_pitch_minus_yaw_in_ned(tmp_path):
    """R = Rz(40) Ry(20) Rx(10) deg written as a quaternion by scipy (an independent source)."""
    xyzw = Rotation.from_euler("ZYX", [40, 20, 10], degrees=True).as_quat()
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 1], [[0, 0, 0]] * 2, [xyzw] * 2))
    log = Log.from_dict({"frame": "enu", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    assert np.degrees(log.attitude().to_numpy()[0]) == pytest.approx([10, 20, 40], abs=1e-12)
    assert np.degrees(log.in_frame("ned").attitude().to_numpy()[0]) == pytest.approx([10, -20, -40], abs=1e-12)


def test_imu_body_vectors_change_frame_and_keep_their_units(tmp_path):
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 1], [[0, 0, 0]] * 2, [[0, 0, 0, 1]] * 2))
    write_csv(tmp_path / "imu.csv", ["time", "p", "q", "r", "ax", "ay", "az"],
              [[0, 0.1, 0.2, 0.3, 1.0, 2.0, 9.81], [1, 0.1, 0.2, 0.3, 1.0, 2.0, 9.81]])
    log = Log.from_dict({"frame": "enu", "pose": {"file": "pose.csv", **POSE_XYZW},
                         "imu": {"file": "imu.csv", "time": "time", "angular_velocity": ["p", "q", "r"],
                                 "linear_acceleration": ["ax", "ay", "az"]}}, base_dir=tmp_path)
    imu = log.in_frame("ned").imu
    assert list(imu.columns) == ["p_rad_s", "q_rad_s", "r_rad_s", "ax_m_s2", "ay_m_s2", "az_m_s2"]
    assert imu.iloc[0].to_list() == [0.1, -0.2, -0.3, 1.0, -2.0, -9.81]
    assert log.resample([0.5])[["imu_p_rad_s", "imu_az_m_s2"]].iloc[0].to_list() == [0.1, 9.81]


def test_joint_offsets_and_signs(tmp_path):
    """``q_model = sign * q_log + offset``, ``qd_model = sign * qd_log``."""
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 1], [[0, 0, 0]] * 2, [[0, 0, 0, 1]] * 2))
    write_csv(tmp_path / "joints.csv", ["t", "e_pos", "b_pos", "d_pos", "e_vel"],
              [[0, 1.0, 2.0, 3.0, 0.25], [1, 1.5, 2.5, 3.5, 0.25]])
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW},
                         "joints": {"file": "joints.csv", "time": "t",
                                    "columns": {"base": "e_pos", "wrist": "b_pos", "shoulder": "d_pos"},
                                    "rates": {"base": "e_vel"},
                                    "offset": {"base": -3.0, "wrist": 0.5}, "sign": {"base": -1}}},
                        base_dir=tmp_path)
    assert log.joint_names == ("base", "wrist", "shoulder")
    joints = log.joints
    assert list(joints.columns) == ["q_base_rad", "q_wrist_rad", "q_shoulder_rad", "qd_base_rad_s"]
    assert joints.iloc[0].to_list() == [-1.0 * 1.0 - 3.0, 2.0 + 0.5, 3.0, -0.25]
    assert joints.iloc[1].to_list() == [-1.5 - 3.0, 2.5 + 0.5, 3.5, -0.25]
    assert log.joint_angles([0.5]).iloc[0].to_list() == [-1.25 - 3.0, 2.25 + 0.5, 3.25]


def test_linear_data_resample_exactly_and_cubic_data_with_the_cubic_spline(tmp_path):
    t = np.array([0.0, 0.3, 0.7, 1.5, 2.0, 3.1])
    linear = np.stack([2 * t + 1, -t, 0.5 * t], axis=1)
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows(t, linear, [[0, 0, 0, 1]] * t.size))
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    at = np.array([0.0, 0.1, 1.0, 2.55, 3.1])
    assert log.resample(at)[["x_m", "y_m", "z_m"]].to_numpy() == pytest.approx(
        np.stack([2 * at + 1, -at, 0.5 * at], axis=1), abs=1e-14)
    cubic = np.stack([t ** 3 - 2 * t, t ** 2, 1 + 0 * t], axis=1)
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows(t, cubic, [[0, 0, 0, 1]] * t.size))
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    assert log.resample(at, position="cubic")[["x_m", "y_m", "z_m"]].to_numpy() == pytest.approx(
        np.stack([at ** 3 - 2 * at, at ** 2, 1 + 0 * at], axis=1), abs=1e-12)


def test_slerp_halfway_between_two_attitudes(tmp_path):
    """Halfway between yaw 0 and yaw 90 deg is yaw 45 deg: ``[cos 22.5, 0, 0, sin 22.5]``; a quarter of the way
    between roll 0 and roll 60 deg is roll 15 deg."""
    h = math.sqrt(0.5)
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 2], [[0, 0, 0]] * 2, [[0, 0, 0, 1], [0, 0, h, h]]))
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    row = log.resample([1.0]).iloc[0]
    c, s = math.cos(math.radians(22.5)), math.sin(math.radians(22.5))
    assert [row.qw, row.qx, row.qy, row.qz] == pytest.approx([c, 0, 0, s], abs=1e-15)
    assert math.degrees(row.yaw_rad) == pytest.approx(45.0, abs=1e-12)
    write_csv(tmp_path / "pose.csv", POSE_HEADER,
              pose_rows([0, 2], [[0, 0, 0]] * 2, [[0, 0, 0, 1], [0.5, 0, 0, math.sqrt(3) / 2]]))
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    assert np.degrees(log.attitude([0.5]).to_numpy()[0]) == pytest.approx([15, 0, 0], abs=1e-12)


def test_start_and_duration_slice_every_stream_and_put_zero_at_start(tmp_path):
    t = np.arange(0.0, 5.0, 0.5)
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows(t, [[x, 0, 0] for x in t], [[0, 0, 0, 1]] * t.size))
    write_csv(tmp_path / "joints.csv", ["t", "a"], [[x, 10 * x] for x in t])
    log = Log.from_dict({"frame": "ned", "start": 1.0, "duration": 2.0,
                         "pose": {"file": "pose.csv", **POSE_XYZW},
                         "joints": {"file": "joints.csv", "time": "t", "columns": {"j": "a"}}}, base_dir=tmp_path)
    assert (log.start, log.duration) == (1.0, 2.0)
    assert log.pose.index.to_list() == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert log.pose["x_m"].to_list() == [1.0, 1.5, 2.0, 2.5, 3.0]
    assert log.joints["q_j_rad"].to_list() == [10.0, 15.0, 20.0, 25.0, 30.0]
    assert log.resample([0.25])["x_m"].item() == 1.25


def test_the_default_start_is_the_first_common_sample_and_the_duration_the_shortest_stream(tmp_path):
    """Pose 0..4 s, joints 0.5..3.5 s, thrusters 0.2..5 s: the replay runs 0.5..3.5 s."""
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 2, 4], [[0, 0, 0]] * 3, [[0, 0, 0, 1]] * 3))
    write_csv(tmp_path / "joints.csv", ["t", "a"], [[0.5, 0], [3.5, 1]])
    write_csv(tmp_path / "thrust.csv", ["t", "left", "right"], [[0.2, 1, -1], [1.5, 2, -2], [5.0, 3, -3]])
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW},
                         "joints": {"file": "joints.csv", "time": "t", "columns": {"j": "a"}},
                         "thrusters": {"file": "thrust.csv", "time": "t",
                                       "columns": {"port": "left", "starboard": "right"}}}, base_dir=tmp_path)
    assert (log.start, log.duration) == (0.5, 3.0)
    assert log.thrusters.index.to_list() == [1.0]                 # the row at 1.5 s of log time
    held = log.resample([0.0, 0.9, 1.0, 3.0])
    assert held["thrust_port"].to_list() == [1.0, 1.0, 2.0, 2.0]   # commands held from row to row
    assert held["thrust_starboard"].to_list() == [-1.0, -1.0, -2.0, -2.0]


def test_time_scale_offset_and_position_scale(tmp_path):
    """Times in ms (``time_scale: 0.001``) shifted by 10 s, positions in mm (``scale: 0.001``)."""
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows([0, 1000], [[0, 0, 0], [1000, 2000, -500]],
                                                          [[0, 0, 0, 1]] * 2))
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW, "time_scale": 0.001,
                                                  "time_offset": 10.0, "scale": 0.001}}, base_dir=tmp_path)
    assert (log.start, log.duration) == (10.0, 1.0)
    assert log.pose.loc[1.0, ["x_m", "y_m", "z_m"]].to_list() == [1.0, 2.0, -0.5]


def test_exact_repetitions_of_a_row_are_dropped_with_a_note(tmp_path):
    rows = pose_rows([0, 1, 1, 2], [[0, 0, 0], [1, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 0, 0, 1]] * 4)
    write_csv(tmp_path / "pose.csv", POSE_HEADER, rows)
    log = Log.from_dict({"frame": "ned", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    assert log.pose.index.to_list() == [0.0, 1.0, 2.0]
    assert log.notes == (f"{tmp_path / 'pose.csv'}: dropped 1 exact repetition of a row",)


def test_the_grid_ends_at_the_duration(tmp_path):
    log = _yaw_log(tmp_path)
    assert log.grid(0.75).tolist() == [0.0, 0.75, 1.5, 2.0]
    assert log.grid(0.5).tolist() == [0.0, 0.5, 1.0, 1.5, 2.0]
    assert log.on_grid(1.0)["x_m"].to_list() == [0.0, 1.0, 2.0]
    for step in (0.0, 2.5, float("nan")):
        with pytest.raises(UvmsInputError, match=r": grid step: expected a number in \(0, 2\] s \(the log's "
                           r"duration\), found "):
            log.grid(step)


def test_a_real_trial_reads_when_the_data_is_at_hand(tmp_path):
    """traj003-0 of the Hinsdale 2023 trials (Kolano et al., MIT licence), if a copy is found: the description of
    ``docs/logs.md`` reads it, from the metadata's 3.75 s start."""
    import os
    import subprocess

    repo = os.environ.get("UVMS_HINSDALE_REPO", "/work/.mirror/hkolano+UVMS-SysID-with-EAs/repo")
    if not os.path.isdir(repo):
        pytest.skip("no copy of the Hinsdale trials")
    for stream in ("mocap", "joint_states"):
        name = f"traj003-0_{stream}.csv"
        text = subprocess.run(["git", "-C", repo, "show", f"HEAD:data/hinsdale-data-2023/{name}"],
                              capture_output=True, check=True).stdout
        (tmp_path / name).write_bytes(text)
    log = Log.from_dict({
        "start": 3.75, "duration": 15.0, "frame": "enu",
        "pose": {"file": "traj003-0_mocap.csv", "time": "time_secs", "position": ["x_pose", "y_pose", "z_pose"],
                 "quaternion_xyzw": ["x_ori", "y_ori", "z_ori", "w_ori"]},
        "joints": {"file": "traj003-0_joint_states.csv", "time": "time_secs",
                   "columns": {"base": "axis_e_pos", "shoulder": "axis_d_pos", "elbow": "axis_c_pos",
                               "wrist": "axis_b_pos"}, "offset": {"base": -3.07, "wrist": -2.879}}},
        base_dir=tmp_path)
    import pandas as pd

    mocap = pd.read_csv(tmp_path / "traj003-0_mocap.csv")
    row = mocap[mocap.time_secs >= 3.75].iloc[0]           # the file's own roll, pitch, yaw columns (enu)
    attitude = log.attitude([row.time_secs - 3.75]).iloc[0]
    assert [attitude.roll_rad, attitude.pitch_rad, attitude.yaw_rad] == pytest.approx(
        [row.roll, row.pitch, row.yaw], abs=1e-6)
    assert log.pose.index[0] >= 0.0 and log.pose.index[-1] <= 15.0
