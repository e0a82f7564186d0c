"""``uvms export`` / ``Result.to_mcap``: a run written as ROS 2 messages with ``mcap`` and read back with
``rosbags``, an independent reader that decodes with the definitions stored in the file: the topics and types
documented, and every value the run's, converted to z up and forward-left-up by the half turn written out by hand
(``bags.py``; 1e-12)."""

import numpy as np
import pytest

import uvms
from uvms.cli import main

from .bags import H, read_bag


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    """A 2 s station-keeping run of the BlueROV2 Heavy + Alpha 5 (a ned model; eight thrusters, a controller)
    saved by ``uvms run`` and exported by ``uvms export``."""
    folder = tmp_path_factory.mktemp("export")
    from uvms.sim.scenario import resolve_scenario_path

    text = resolve_scenario_path("bluerov2_heavy_alpha5_hold6").read_text()
    text = "\n".join("duration: 2.0" if line.startswith("duration:") else line for line in text.splitlines())
    (folder / "hold.yaml").write_text(text + "\n")
    assert main(["run", str(folder / "hold.yaml"), "-o", str(folder / "run")]) == 0
    assert main(["export", str(folder / "run"), "-o", str(folder / "run.mcap")]) == 0
    result = uvms.Result.load(folder / "run")
    return result, read_bag(folder / "run.mcap"), folder


def test_the_topics_and_types_are_as_documented(exported):
    from uvms.ros import TOPICS

    result, bag, _ = exported
    model = uvms.load_model("bluerov2_heavy_alpha5")
    expected = {t: m for t, m in TOPICS.items() if "<name>" not in t}
    expected.update({f"/uvms/thrusters/{th.name}": TOPICS["/uvms/thrusters/<name>"] for th in model.thrusters})
    assert bag["types"] == expected
    for topic in expected:
        if topic != "/tf_static":
            assert len(bag[topic]) == len(result.time), topic


def test_odometry_joint_states_and_wrenches_are_the_runs_values_in_enu_flu(exported):
    result, bag, _ = exported
    model = uvms.load_model("bluerov2_heavy_alpha5")
    odom = [m for _, m in bag["/uvms/odometry"]]
    stamps = np.array([m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for m in odom])
    np.testing.assert_allclose(stamps, result.time, rtol=0, atol=1e-9)
    np.testing.assert_array_equal([t for t, _ in bag["/uvms/odometry"]], np.round(result.time * 1e9).astype(int))
    assert {m.header.frame_id for m in odom} == {"world"} and {m.child_frame_id for m in odom} == {"base_link"}
    p = np.array([[m.pose.pose.position.x, m.pose.pose.position.y, m.pose.pose.position.z] for m in odom])
    np.testing.assert_allclose(p, result.position @ H, rtol=0, atol=1e-12)
    xyzw = np.array([[o.x, o.y, o.z, o.w] for o in (m.pose.pose.orientation for m in odom)])
    w, x, y, z = result.quaternion.T                                  # [w, x, -y, -z] in ROS's x, y, z, w order
    np.testing.assert_allclose(xyzw, np.column_stack([x, -y, -z, w]), rtol=0, atol=1e-12)
    twist = np.array([[m.twist.twist.angular.x, m.twist.twist.angular.y, m.twist.twist.angular.z,
                       m.twist.twist.linear.x, m.twist.twist.linear.y, m.twist.twist.linear.z] for m in odom])
    np.testing.assert_allclose(twist, result.nu @ np.kron(np.eye(2), H), rtol=0, atol=1e-12)

    joints = [m for _, m in bag["/joint_states"]]
    assert list(joints[0].name) == list(model.joint_names)
    np.testing.assert_allclose([m.position for m in joints], result.q, rtol=0, atol=1e-12)
    np.testing.assert_allclose([m.velocity for m in joints], result.qd, rtol=0, atol=1e-12)
    np.testing.assert_allclose([m.effort for m in joints], result.joint_torques, rtol=0, atol=1e-12)

    def wrenches(topic):
        return np.array([[w.wrench.torque.x, w.wrench.torque.y, w.wrench.torque.z, w.wrench.force.x,
                          w.wrench.force.y, w.wrench.force.z] for _, w in bag[topic]])

    labels = ("K", "M", "N", "X", "Y", "Z")
    commanded = np.column_stack([result.signals[f"command_{a}"] for a in labels])
    unachieved = np.column_stack([result.signals[f"unachieved_{a}"] for a in labels])
    H6 = np.kron(np.eye(2), H)
    np.testing.assert_allclose(wrenches("/uvms/wrench/commanded"), commanded @ H6, rtol=0, atol=1e-12)
    np.testing.assert_allclose(wrenches("/uvms/wrench/achieved"), (commanded - unachieved) @ H6, rtol=0, atol=1e-12)
    assert np.abs(commanded).max() > 0.01                             # the controller commanded something
    for th in model.thrusters:                                        # f = T d, m = r x f, in FLU axes
        r, d = H @ np.asarray(th.position), H @ np.asarray(th.direction) / np.linalg.norm(th.direction)
        f = result.signals[f"thrust_cmd_{th.name}"][:, None] * d
        np.testing.assert_allclose(wrenches(f"/uvms/thrusters/{th.name}"),
                                   np.column_stack([np.cross(r, f), f]), rtol=0, atol=1e-12)


def test_the_tf_tree_composes_to_each_links_pose(exported):
    """world -> base_link -> ... -> each link, composed from the transforms, is the link's world pose of the
    z-up model (forward kinematics of ``Model.in_frame("enu")``); the vehicle's transform is the odometry's."""
    from scipy.spatial.transform import Rotation

    from uvms.dynamics.poses import forward_kinematics
    from uvms.frames import convert_state

    result, bag, _ = exported
    model = uvms.load_model("bluerov2_heavy_alpha5")
    enu = model.in_frame("enu")
    for k in (0, len(result.time) // 2, len(result.time) - 1):
        tf = bag["/tf"][k][1].transforms
        pose = {"world": (np.eye(3), np.zeros(3))}
        for t in tf:                                                   # parents come first
            Rp, pp = pose[t.header.frame_id]
            r = t.transform.rotation
            R = Rotation.from_quat([r.x, r.y, r.z, r.w]).as_matrix()
            p = np.array([t.transform.translation.x, t.transform.translation.y, t.transform.translation.z])
            pose[t.child_frame_id] = (Rp @ R, Rp @ p + pp)
        fk = forward_kinematics(enu, convert_state(result.state(k), "ned", "enu"))
        for b, name in enumerate(enu.body_names):
            np.testing.assert_allclose(pose[name][0], fk.rotation[b], atol=1e-12)
            np.testing.assert_allclose(pose[name][1], fk.position[b], atol=1e-12)
        odom = bag["/uvms/odometry"][k][1].pose.pose.position
        np.testing.assert_allclose(pose["base_link"][1], [odom.x, odom.y, odom.z], atol=1e-12)


def test_named_frames_are_static_transforms(exported):
    _, bag, _ = exported
    model = uvms.load_model("bluerov2_heavy_alpha5").in_frame("enu")
    static = {t.child_frame_id: t for t in bag["/tf_static"][0][1].transforms}
    assert set(static) == {f.name for f in model.frames}
    f = model.frames[0]
    t = static[f.name].transform.translation
    assert static[f.name].header.frame_id == model.body_names[f.body]
    np.testing.assert_allclose([t.x, t.y, t.z], f.position, atol=1e-12)


def test_result_to_mcap_writes_the_same_messages(exported, tmp_path):
    result, bag, _ = exported
    path = result.to_mcap(tmp_path / "again.mcap", uvms.load_model("bluerov2_heavy_alpha5"))
    again = read_bag(path)
    assert again["types"] == bag["types"]
    a = [m.pose.pose.position.x for _, m in again["/uvms/odometry"]]
    np.testing.assert_array_equal(a, [m.pose.pose.position.x for _, m in bag["/uvms/odometry"]])


@pytest.mark.parametrize("args, message", [(["-o", "x.csv"], "expected a .mcap file name"),
                                           (["--model", "no_such_model"], "no_such_model")])
def test_bad_exports_exit_2_in_one_line(exported, tmp_path, capsys, args, message):
    _, _, folder = exported
    assert main(["export", str(folder / "run"), *[str(tmp_path / a) if a.endswith(".csv") else a for a in args]]) == 2
    err = capsys.readouterr().err
    assert message in err and len(err.strip().splitlines()) == 1


def test_the_file_is_an_indexed_mcap_of_cdr_messages_with_ros2msg_schemas(exported):
    """What Foxglove and ``ros2 bag info`` (the rosbag2 MCAP storage plugin) read: ``cdr`` channels with
    ``ros2msg`` schemas named by their ROS 2 types, and a summary with message counts per channel and the
    time span (read with ``mcap``'s own reader)."""
    from mcap.reader import make_reader

    result, bag, folder = exported
    with open(folder / "run.mcap", "rb") as fh:
        summary = make_reader(fh).get_summary()
    assert summary is not None and summary.statistics is not None
    assert {c.message_encoding for c in summary.channels.values()} == {"cdr"}
    assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
    names = {summary.channels[i].topic: summary.schemas[summary.channels[i].schema_id].name
             for i in summary.channels}
    assert names == bag["types"]
    counts = {summary.channels[i].topic: n for i, n in summary.statistics.channel_message_counts.items()}
    assert counts["/uvms/odometry"] == len(result.time) and counts["/tf_static"] == 1
    assert summary.statistics.message_start_time == 0
    assert summary.statistics.message_end_time == int(round(result.time[-1] * 1e9))
