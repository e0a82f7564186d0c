"""The simulated sensors in an exported bag (``docs/ros.md``, "Sensor topics"): a station-keeping run with an IMU,
a pressure sensor, a DVL and the arm's encoders, written by ``uvms export`` and ``Result.to_mcap`` and read back
with ``rosbags`` (an independent decoder).

Two kinds of check: the bag's values are the run's sensor tables turned by the half turn written out by hand
(``bags.py``; 1e-12), and, independently of that formula, the bag is consistent with itself the way a ROS user
reads it: the noise-free gyro and DVL, turned by the sensor's ``/tf_static`` mount, are the odometry's body rates
and velocities (and the water track differs from the bottom track by the current, seen in the sensor's axes), and
the IMU at (near) rest reads +|g| up in the world (REP 145)."""

from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.spatial.transform import Rotation

import uvms
from uvms.cli import main
from uvms.errors import UvmsInputError

from .bags import H, read_bag
CURRENT = np.array([0.1, 0.0, 0.0])            # the hold6 scenario's world current (ned) [m/s]
MOUNTS = {"imu": ([0.1, -0.05, 0.08], [0.3, -0.2, 0.5]), "depth": ([-0.2, 0.0, 0.1], [0.0, 0.0, 0.0]),
          "dvl": ([0.05, 0.1, 0.15], [0.1, 0.05, 0.785])}
SENSORS = {
    "imu": {"kind": "imu", "rate": 50, "accel": {"white": 1.0e-3}, "seed": 3},          # gyro noise-free
    "depth": {"kind": "pressure", "rate": 20, "noise": 20.0, "resolution": 10.0},
    "dvl": {"kind": "dvl", "rate": 10, "water_depth": 5.0, "dropout": 0.3, "seed": 1},  # noise-free, dropouts
    "arm": {"kind": "encoders", "rate": 25, "counts_per_turn": 4096},
}
for _name, (_offset, _rpy) in MOUNTS.items():
    SENSORS[_name]["mount"] = {"offset": _offset, "rpy": _rpy}


@pytest.fixture(scope="module")
def sensed(tmp_path_factory):
    """A 2 s six-axis station keeping of the BlueROV2 Heavy + Alpha 5 (a ned model, a 0.1 m/s current) with
    four sensors; saved as ``uvms run`` saves it, exported by ``uvms export``, and written in memory by
    ``Result.to_mcap`` (full precision: the odometry is not rounded to the saved table's 10 digits)."""
    from uvms.sim.scenario import load_scenario, resolve_scenario_path, run_scenario

    folder = tmp_path_factory.mktemp("sensed")
    data = yaml.safe_load(resolve_scenario_path("bluerov2_heavy_alpha5_hold6").read_text())
    data.update(duration=2.0, sensors=SENSORS)
    (folder / "sensed.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    assert main(["run", str(folder / "sensed.yaml"), "-o", str(folder / "run")]) == 0
    assert main(["export", str(folder / "run"), "-o", str(folder / "run.mcap")]) == 0
    saved = uvms.Result.load(folder / "run")
    result = run_scenario(load_scenario(folder / "sensed.yaml"))
    model = uvms.load_model("bluerov2_heavy_alpha5")
    result.to_mcap(folder / "memory.mcap", model)
    return saved, read_bag(folder / "run.mcap"), result, read_bag(folder / "memory.mcap")


def _stamps(messages) -> np.ndarray:
    return np.array([m.header.stamp.sec + 1e-9 * m.header.stamp.nanosec for _, m in messages])


def _xyz(vectors) -> np.ndarray:
    return np.array([[v.x, v.y, v.z] for v in vectors])


def test_the_sensor_topics_and_types_are_as_documented(sensed):
    from uvms.ros import SENSOR_TOPICS

    saved, bag, _, _ = sensed
    twist = "geometry_msgs/msg/TwistWithCovarianceStamped"
    expected = {"/uvms/sensors/imu": "sensor_msgs/msg/Imu", "/uvms/sensors/depth": "sensor_msgs/msg/FluidPressure",
                "/uvms/sensors/dvl/bottom_track": twist, "/uvms/sensors/dvl/water_track": twist,
                "/uvms/sensors/arm": "sensor_msgs/msg/JointState"}
    assert {t: m for t, m in bag["types"].items() if t.startswith("/uvms/sensors/")} == expected
    assert {"/uvms/odometry", "/joint_states", "/tf", "/tf_static"} <= set(bag["types"])
    assert SENSOR_TOPICS["imu"] == {"": "sensor_msgs/msg/Imu"}
    valid = saved.sensors["dvl"]["bottom_valid"] > 0
    assert 0 < valid.sum() < valid.size                                # some dropouts: no message for those
    counts = {"imu": 101, "depth": 41, "dvl/water_track": 21, "dvl/bottom_track": int(valid.sum()), "arm": 51}
    for topic, n in counts.items():
        assert len(bag[f"/uvms/sensors/{topic}"]) == n, topic


def test_uvms_export_names_the_sensors_it_wrote(sensed, tmp_path, capsys):
    saved = sensed[0]
    assert main(["export", str(saved._directory), "-o", str(tmp_path / "again.mcap")]) == 0
    assert "of bluerov2_heavy_alpha5 and 4 sensors (imu, depth, dvl, arm) written to" in capsys.readouterr().out


def test_the_sensor_values_are_the_runs_tables_turned_to_flu(sensed):
    """Every sample at its own stamp (header and log time), in its sensor's frame; vectors ``H v``."""
    saved, bag, _, _ = sensed
    for topic, name in (("imu", "imu"), ("depth", "depth"), ("dvl/water_track", "dvl"), ("arm", "arm")):
        messages = bag[f"/uvms/sensors/{topic}"]
        np.testing.assert_allclose(_stamps(messages), saved.sensors[name].time, rtol=0, atol=1e-9)
        np.testing.assert_array_equal([t for t, _ in messages], np.round(saved.sensors[name].time * 1e9))
        assert {m.header.frame_id for _, m in messages} == ({""} if name == "arm" else {name})

    imu, record = [m for _, m in bag["/uvms/sensors/imu"]], saved.sensors["imu"]
    gyro = np.column_stack([record[f"gyro_{a}"] for a in "xyz"])
    accel = np.column_stack([record[f"accel_{a}"] for a in "xyz"])
    np.testing.assert_allclose(_xyz(m.angular_velocity for m in imu), gyro @ H, rtol=0, atol=1e-12)
    np.testing.assert_allclose(_xyz(m.linear_acceleration for m in imu), accel @ H, rtol=0, atol=1e-12)
    assert all(m.orientation_covariance[0] == -1.0 for m in imu)          # no orientation estimate

    depth = [m for _, m in bag["/uvms/sensors/depth"]]
    np.testing.assert_allclose([m.fluid_pressure for m in depth], saved.sensors["depth"]["pressure"],
                               rtol=0, atol=1e-12 * 1e5)
    assert np.all(np.array([m.fluid_pressure for m in depth]) > 1.0e5)   # absolute pressure [Pa]

    dvl = saved.sensors["dvl"]
    valid = dvl["bottom_valid"] > 0
    for track, rows in (("bottom", valid), ("water", np.ones_like(valid))):
        messages = bag[f"/uvms/sensors/dvl/{track}_track"]
        v = np.column_stack([dvl[f"{track}_{a}"] for a in "xyz"])[rows]
        np.testing.assert_allclose(_xyz(m.twist.twist.linear for _, m in messages), v @ H, rtol=0, atol=1e-12)
        np.testing.assert_allclose(_stamps(messages), dvl.time[rows], rtol=0, atol=1e-9)
        assert np.all(np.isfinite(_xyz(m.twist.twist.linear for _, m in messages)))

    model = uvms.load_model("bluerov2_heavy_alpha5")
    arm = [m for _, m in bag["/uvms/sensors/arm"]]
    assert [list(m.name) for m in arm[:1]] == [list(model.joint_names)]
    np.testing.assert_allclose([m.position for m in arm],
                               np.column_stack([saved.sensors["arm"][j] for j in model.joint_names]),
                               rtol=0, atol=1e-12)


def test_each_mount_is_a_static_transform_turned_like_a_body(sensed):
    """``base_link -> <sensor>``: ``H r`` and ``H R_bs H``, ``R_bs`` the ZYX ``rpy`` (scipy here); the encoders
    have no mount and no frame."""
    _, bag, _, _ = sensed
    static = {t.child_frame_id: t for t in bag["/tf_static"][0][1].transforms}
    assert "arm" not in static
    for name, (offset, rpy) in MOUNTS.items():
        t = static[name]
        assert t.header.frame_id == "base_link"
        p, q = t.transform.translation, t.transform.rotation
        np.testing.assert_allclose([p.x, p.y, p.z], H @ offset, rtol=0, atol=1e-12)
        R_bs = Rotation.from_euler("ZYX", rpy[::-1]).as_matrix()
        np.testing.assert_allclose(Rotation.from_quat([q.x, q.y, q.z, q.w]).as_matrix(), H @ R_bs @ H, atol=1e-12)


def _mount(bag, name):
    t = {t.child_frame_id: t for t in bag["/tf_static"][0][1].transforms}[name].transform
    return (np.array([t.translation.x, t.translation.y, t.translation.z]),
            Rotation.from_quat([t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w]).as_matrix())


def _odometry_at(bag, times):
    """(omega, v, R) of the odometry rows at ``times`` (FLU body axes, body -> world)."""
    odom = bag["/uvms/odometry"]
    index = np.searchsorted([t for t, _ in odom], np.round(np.asarray(times) * 1e9).astype(int))
    rows = [odom[i][1].twist.twist for i in index]
    q = [odom[i][1].pose.pose.orientation for i in index]
    return (_xyz(r.angular for r in rows), _xyz(r.linear for r in rows),
            Rotation.from_quat([[o.x, o.y, o.z, o.w] for o in q]).as_matrix())


def test_a_ros_reader_finds_the_gyro_and_dvl_consistent_with_the_odometry_and_tf(sensed):
    """In the bag written in memory (full precision): ``gyro = R_s^T omega``, ``bottom = R_s^T (v + omega x r)``
    and ``water - bottom = -R_s^T R^T u`` with the world current ``u`` turned to z up (``H u``), every quantity
    taken from the bag's own odometry and ``/tf_static`` (1e-12)."""
    bag = sensed[3]
    _, R_imu = _mount(bag, "imu")
    imu = bag["/uvms/sensors/imu"]
    omega, _, _ = _odometry_at(bag, _stamps(imu))
    np.testing.assert_allclose(_xyz(m.angular_velocity for _, m in imu), omega @ R_imu, rtol=0, atol=1e-12)
    assert np.abs(omega).max() > 1e-3                                  # the vehicle does turn

    r, R_s = _mount(bag, "dvl")
    water, bottom = bag["/uvms/sensors/dvl/water_track"], bag["/uvms/sensors/dvl/bottom_track"]
    omega, v, R = _odometry_at(bag, _stamps(water))
    over_ground = (v + np.cross(omega, r)) @ R_s
    u_body = np.einsum("kji,j->ki", R, H @ CURRENT)                    # R^T u
    np.testing.assert_allclose(_xyz(m.twist.twist.linear for _, m in water), over_ground - u_body @ R_s,
                               rtol=0, atol=1e-12)
    valid = np.isin(np.round(_stamps(water) * 1e9), [t for t, _ in bottom])
    np.testing.assert_allclose(_xyz(m.twist.twist.linear for _, m in bottom), over_ground[valid], rtol=0, atol=1e-12)


def test_the_imu_at_rest_reads_plus_g_up_in_the_world(sensed):
    """REP 145: the accelerometer measures the specific force, +|g| along the world's up axis for a vehicle at
    rest (station keeping: accelerations of a few cm/s^2); read through the bag's mount and odometry."""
    bag = sensed[3]
    _, R_imu = _mount(bag, "imu")
    imu = bag["/uvms/sensors/imu"]
    _, _, R = _odometry_at(bag, _stamps(imu))
    world = np.einsum("kij,jl,kl->ki", R, R_imu, _xyz(m.linear_acceleration for _, m in imu))
    g = float(np.linalg.norm(uvms.load_model("bluerov2_heavy_alpha5").gravity))
    np.testing.assert_allclose(world.mean(axis=0), [0.0, 0.0, g], atol=0.05)


def test_the_saved_and_the_in_memory_runs_write_the_same_sensor_messages(sensed):
    _, bag, _, again = sensed
    assert again["types"] == bag["types"]
    for topic in (t for t in bag["types"] if t.startswith("/uvms/sensors/")):
        assert [t for t, _ in again[topic]] == [t for t, _ in bag[topic]], topic
    a = _xyz(m.linear_acceleration for _, m in again["/uvms/sensors/imu"])
    np.testing.assert_allclose(a, _xyz(m.linear_acceleration for _, m in bag["/uvms/sensors/imu"]), rtol=0, atol=1e-12)


def test_messages_are_in_time_order(sensed, tmp_path):
    """``ros2 bag play`` plays in log-time order: the file's messages come in that order (``mcap``'s reader, in
    file order)."""
    from mcap.reader import make_reader

    path = sensed[2].to_mcap(tmp_path / "r.mcap", uvms.load_model("bluerov2_heavy_alpha5"))
    with open(path, "rb") as fh:
        times = [m.log_time for _, _, m in make_reader(fh).iter_messages(log_time_order=False)]
    assert times == sorted(times) and len(times) > 0


def test_a_sensor_named_like_a_frame_is_refused_in_one_line(sensed, tmp_path):
    from dataclasses import replace

    _, _, result, _ = sensed
    renamed = replace(result, sensors={"base_link": result.sensors["imu"]},
                      metadata={**result.metadata, "sensors": {"base_link": result.metadata["sensors"]["imu"]}})
    with pytest.raises(UvmsInputError) as info:
        renamed.to_mcap(tmp_path / "x.mcap", uvms.load_model("bluerov2_heavy_alpha5"))
    assert "rename the sensor" in str(info.value) and "\n" not in str(info.value)
    assert not (tmp_path / "x.mcap").exists()


def test_a_run_saved_without_mounts_writes_the_samples_and_no_sensor_frames(sensed, tmp_path):
    from dataclasses import replace

    _, _, result, _ = sensed
    about = {k: {f: v for f, v in d.items() if f != "mount"} for k, d in result.metadata["sensors"].items()}
    older = replace(result, metadata={**result.metadata, "sensors": about})
    bag = read_bag(older.to_mcap(tmp_path / "old.mcap", uvms.load_model("bluerov2_heavy_alpha5")))
    static = {t.child_frame_id for t in bag["/tf_static"][0][1].transforms}
    assert not static & set(MOUNTS) and len(bag["/uvms/sensors/imu"]) == 101


def test_a_z_up_models_sensors_are_written_as_they_are(tmp_path):
    """An ``enu`` model (the paper model turned z up): no turn, the table's numbers and the mount as given."""
    from uvms.sensors import Dvl, Imu, Mount, NoiseDensity

    model = uvms.load_model("paper").in_frame("enu")
    mount = Mount.of([0.1, 0.2, -0.3], [0.2, 0.1, -0.4])
    sensors = [Imu(rate=100, mount=mount, accel=NoiseDensity(white=1e-3)), Dvl(rate=50, mount=mount)]
    start = uvms.State.from_euler(model, position=[0.0, 0.0, -4.0], euler=[0.1, 0.2, 0.3],
                                  nu=[0.1, -0.2, 0.15, 0.3, 0.1, -0.1])
    result = uvms.simulate(model, start, duration=0.2, sensors=sensors, record_period=0.01,
                           joint_torques=np.linspace(1.0, -1.0, model.n_joints))
    bag = read_bag(result.to_mcap(tmp_path / "enu.mcap", model))
    imu = result.sensors["imu"]
    np.testing.assert_allclose(_xyz(m.linear_acceleration for _, m in bag["/uvms/sensors/imu"]),
                               np.column_stack([imu[f"accel_{a}"] for a in "xyz"]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(_xyz(m.angular_velocity for _, m in bag["/uvms/sensors/imu"]),
                               np.column_stack([imu[f"gyro_{a}"] for a in "xyz"]), rtol=0, atol=1e-12)
    assert np.abs(np.column_stack([imu[f"gyro_{a}"] for a in "xyz"])).max() > 1e-2    # it turns
    dvl = result.sensors["dvl"]
    np.testing.assert_allclose(_xyz(m.twist.twist.linear for _, m in bag["/uvms/sensors/dvl/bottom_track"]),
                               np.column_stack([dvl[f"bottom_{a}"] for a in "xyz"]), rtol=0, atol=1e-12)
    r, R = _mount(bag, "imu")
    np.testing.assert_allclose(r, mount.offset, atol=1e-12)
    np.testing.assert_allclose(R, mount.rotation, atol=1e-12)


def test_a_damaged_saved_sensor_table_or_mount_is_one_line_exit_2(sensed, tmp_path, capsys):
    """A saved run whose IMU table lost a column, or whose metadata's mount is not a rotation: ``uvms export``
    names the file or field in one line, exit 2, and writes nothing."""
    import json
    import shutil

    saved = sensed[0]
    for damage, message in (("column", "missing gyro_x"), ("mount", "a proper rotation matrix")):
        folder = tmp_path / damage
        shutil.copytree(saved._directory, folder)
        if damage == "column":
            table = (folder / "result.imu.csv").read_text().splitlines()
            (folder / "result.imu.csv").write_text("\n".join(",".join(row.split(",")[:1] + row.split(",")[2:])
                                                             for row in table) + "\n")
        else:
            summary = json.loads((folder / "result.json").read_text())
            summary["metadata"]["sensors"]["dvl"]["mount"]["rotation"] = [[2, 0, 0], [0, 1, 0], [0, 0, 1]]
            (folder / "result.json").write_text(json.dumps(summary))
        capsys.readouterr()
        assert main(["export", str(folder), "-o", str(tmp_path / f"{damage}.mcap")]) == 2
        err = capsys.readouterr().err
        assert message in err and len(err.strip().splitlines()) == 1, err
        assert not (tmp_path / f"{damage}.mcap").exists()


def test_docs_ros_md_tables_every_sensor_topic_with_its_type():
    """``docs/ros.md``'s topic table has a row per sensor topic of :data:`uvms.ros.SENSOR_TOPICS`, with its type."""
    import re

    from uvms.ros import SENSOR_TOPICS

    text = (Path(__file__).resolve().parents[2] / "docs" / "ros.md").read_text()
    found = re.findall(r"^\| `/uvms/sensors/<(\w+)>([\w/]*)` \| `([\w/]+)` \|", text, re.M)
    rows = {(kind, suffix): typename for kind, suffix, typename in found}
    assert len(rows) == len(found)                                     # each row once
    expected = {(kind, suffix): typename for kind, topics in SENSOR_TOPICS.items() for suffix, typename in topics.items()}
    assert rows == expected
