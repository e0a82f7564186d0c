"""Logs read from ROS bags (:mod:`uvms.logs.bag`): bags written here with ``rosbags`` (rosbag2 folders, sqlite3 and
MCAP storage) from a hand-written log (a bundled Hinsdale pool trial) and from a uvms run hold the same numbers
as the CSV files they came from, so ``uvms.replay`` gives the same comparison from either; bad topics and
fields are one line."""

from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import uvms
from tests.replays.synthetic import write_log
from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.logs.bundled import resolve_logs

TRIAL = "hinsdale_2023/traj_alt_001-0"


def _store():
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_HUMBLE)


def _header(store, t: float, frame_id: str):
    ns = int(round(t * 1e9))
    T = store.types
    return T["std_msgs/msg/Header"](stamp=T["builtin_interfaces/msg/Time"](sec=ns // 10**9, nanosec=ns % 10**9),
                                    frame_id=frame_id)


def write_bag(path: Path, streams: dict, storage: str = "sqlite3") -> Path:
    """A rosbag2 folder of ``{topic: (msgtype, [(t, message), ...])}`` written with ``rosbags``."""
    from rosbags.rosbag2 import StoragePlugin, Writer

    store = _store()
    plugin = StoragePlugin.SQLITE3 if storage == "sqlite3" else StoragePlugin.MCAP
    with Writer(path, version=8, storage_plugin=plugin) as writer:
        for topic, (msgtype, rows) in streams.items():
            connection = writer.add_connection(topic, msgtype, typestore=store)
            for t, message in rows:
                writer.write(connection, int(round(t * 1e9)), store.serialize_cdr(message, msgtype))
    return path


def _pose_messages(store, table: pd.DataFrame, columns) -> list:
    T = store.types
    x, y, z, qx, qy, qz, qw = columns
    return [(t, T["geometry_msgs/msg/PoseStamped"](
        header=_header(store, t, "world"),
        pose=T["geometry_msgs/msg/Pose"](position=T["geometry_msgs/msg/Point"](x=r[x], y=r[y], z=r[z]),
                                         orientation=T["geometry_msgs/msg/Quaternion"](x=r[qx], y=r[qy], z=r[qz],
                                                                                     w=r[qw]))))
        for t, r in zip(table.iloc[:, 0], table.to_dict("records"))]


def _joint_messages(store, table: pd.DataFrame, names: list[str], positions: list[str], rates=None) -> list:
    T = store.types
    rates = rates or []
    return [(t, T["sensor_msgs/msg/JointState"](
        header=_header(store, t, ""), name=names, position=np.array([r[c] for c in positions], dtype=float),
        velocity=np.array([r[c] for c in rates], dtype=float), effort=np.zeros(0)))
        for t, r in zip(table.iloc[:, 0], table.to_dict("records"))]


@pytest.fixture(scope="module")
def pool_bag(tmp_path_factory):
    """The bundled pool trial's motion capture and joint encoders as a rosbag2 (sqlite3) and its description."""
    folder = tmp_path_factory.mktemp("pool")
    csv = resolve_logs(TRIAL)[0].parent
    store = _store()
    mocap = pd.read_csv(csv / "traj_alt_001-0_mocap.csv")
    joints = pd.read_csv(csv / "traj_alt_001-0_joint_states.csv")
    names = ["axis_e", "axis_d", "axis_c", "axis_b"]
    write_bag(folder / "bag", {
        "/mocap": ("geometry_msgs/msg/PoseStamped",
                   _pose_messages(store, mocap, ["x_pose", "y_pose", "z_pose", "x_ori", "y_ori", "z_ori", "w_ori"])),
        "/joint_states": ("sensor_msgs/msg/JointState",
                          _joint_messages(store, joints, names, [f"{n}_pos" for n in names],
                                          [f"{n}_vel" for n in names]))})
    (folder / "trial.yaml").write_text(
        "start: 3.7\nduration: 17.3\nframe: enu\npose: {file: bag, topic: /mocap}\n"
        "joints: {file: bag, topic: /joint_states, columns: {base: axis_e, shoulder: axis_d, elbow: axis_c, "
        "wrist: axis_b}, offset: {base: -3.07, wrist: -2.879}}\n")
    return folder / "trial.yaml"


def test_a_bag_of_the_pool_trial_reads_as_its_csv_files(pool_bag):
    bag = uvms.Log.load(pool_bag)
    csv = uvms.Log.load(resolve_logs(TRIAL)[0])
    assert bag.start == csv.start and bag.duration == csv.duration
    np.testing.assert_allclose(bag.streams["pose"].time, csv.streams["pose"].time, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(bag.streams["pose"].parts["position"], csv.streams["pose"].parts["position"])
    np.testing.assert_array_equal(bag.streams["pose"].parts["quaternion"], csv.streams["pose"].parts["quaternion"])
    np.testing.assert_array_equal(bag.streams["joints"].parts["q"], csv.streams["joints"].parts["q"])


def test_a_bag_of_the_pool_trial_replays_to_the_same_comparison(pool_bag):
    model = uvms.load_model("hinsdale_bluerov2_alpha5")
    a = uvms.replay(model, pool_bag).comparison()
    b = uvms.replay(model, resolve_logs(TRIAL)[0]).comparison()
    for key, value in b.items():
        if key.endswith(("_deg", "_m")):
            assert a[key] == pytest.approx(value, rel=1e-9, abs=1e-12), key
    assert b["pitch_rmse_deg"] < b["pitch_no_skill_rmse_deg"]      # a real comparison, not a trivial one


def test_a_bag_of_a_uvms_run_replays_like_its_csv_log(tmp_path):
    """The synthetic log of ``tests/replays`` (a run of the paper model, z-up log, encoder offset and sign) as an
    MCAP-storage rosbag2 with the poses as ``nav_msgs/Odometry``: the same replay as from the CSV files."""
    model = uvms.load_model("paper")
    path, _ = write_log(tmp_path, model, log_frame="enu")
    store = _store()
    T = store.types
    mocap = pd.read_csv(tmp_path / "trial_mocap.csv")
    joints = pd.read_csv(tmp_path / "trial_joints.csv")
    poses = _pose_messages(store, mocap, ["x_pose", "y_pose", "z_pose", "x_ori", "y_ori", "z_ori", "w_ori"])
    odometry = [(t, T["nav_msgs/msg/Odometry"](
        header=m.header, child_frame_id="base_link",
        pose=T["geometry_msgs/msg/PoseWithCovariance"](pose=m.pose, covariance=np.zeros(36)),
        twist=T["geometry_msgs/msg/TwistWithCovariance"](
            twist=T["geometry_msgs/msg/Twist"](linear=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0),
                                               angular=T["geometry_msgs/msg/Vector3"](x=0.0, y=0.0, z=0.0)),
            covariance=np.zeros(36)))) for t, m in poses]
    encoders = [c for c in joints.columns if c != "time_secs"]
    write_bag(tmp_path / "run_bag", {"/odom": ("nav_msgs/msg/Odometry", odometry),
                                     "/joint_states": ("sensor_msgs/msg/JointState",
                                                       _joint_messages(store, joints, encoders, encoders))},
              storage="mcap")
    text = path.read_text()
    lines = [line for line in text.splitlines() if not line.startswith(("pose:", "joints:"))]
    joint_line = next(line for line in text.splitlines() if line.startswith("joints:"))
    joint_line = joint_line.replace("file: trial_joints.csv, time: time_secs", "file: run_bag, topic: /joint_states")
    bag_yaml = tmp_path / "bag.yaml"
    bag_yaml.write_text("\n".join(lines + ["pose: {file: run_bag, topic: /odom}", joint_line]) + "\n")
    a, b = uvms.replay(model, bag_yaml), uvms.replay(model, path)
    for name in ("roll", "pitch", "yaw", "depth"):
        np.testing.assert_allclose(a.simulated[name], b.simulated[name], rtol=0, atol=1e-9)
        np.testing.assert_allclose(a.measured[name], b.measured[name], rtol=0, atol=1e-12)


@pytest.mark.parametrize("edit, message", [
    (lambda t: t.replace("topic: /mocap", "topic: /nope"), "no topic '/nope' in the bag; its topics: /joint_states"),
    (lambda t: t.replace("wrist: axis_b}", "wrist: axis_q}"), "no 'axis_q' in the message's names (axis_e"),
    (lambda t: t.replace("pose: {file: bag, topic: /mocap}",
                         "pose: {file: bag, topic: /mocap, position: [pose.position.x, pose.position.y, pose.posit.z],"
                         " quaternion_xyzw: [pose.orientation.x, pose.orientation.y, pose.orientation.z, "
                         "pose.orientation.w]}"), "has no field 'posit'"),
    (lambda t: t.replace("topic: /mocap}", "topic: /mocap, time: stamp}"), "header.stamp, log_time"),
])
def test_bad_bag_streams_are_one_line_and_exit_2(pool_bag, tmp_path, capsys, edit, message):
    bad = pool_bag.parent / "bad.yaml"
    bad.write_text(edit(pool_bag.read_text()))
    with pytest.raises(UvmsInputError) as info:
        uvms.Log.load(bad)
    assert message in str(info.value) and "\n" not in str(info.value)
    assert main(["replay", "hinsdale_bluerov2_alpha5", str(bad), "-o", str(tmp_path / "rp")]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1 and not (tmp_path / "rp").exists()
