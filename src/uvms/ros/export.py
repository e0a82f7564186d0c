"""A run as an MCAP file of ROS 2 messages (``docs/ros.md``), written with ``mcap`` + ``mcap-ros2-support`` and no ROS.

Conventions (REP 103, REP 105): the world is z up and bodies are forward-left-up; a run of a ``ned`` model
(z down, bodies forward-right-down) is converted by uvms's half turn about x (:mod:`uvms.frames`,
``docs/conventions.md``, "Frames": world points and body vectors ``(x, y, z) -> (x, -y, -z)``, quaternions
``[w, x, y, z] -> [w, x, -y, -z]``), which keeps the world's x axis and the vehicle's forward axis; an ``enu``
model's numbers are written as they are. Quaternions are ROS's ``(x, y, z, w)``. Stamps are the run's time
(``t = 0`` at the epoch, a simulated clock), the same in each message's header and as the MCAP log time.

Topics (:data:`TOPICS`):

- ``/uvms/odometry`` ``nav_msgs/msg/Odometry``: the true pose of the vehicle (``header.frame_id`` the world,
  ``child_frame_id`` the vehicle's body name) and its body velocity (``twist`` in the vehicle's axes, as REP 105
  and ``nav_msgs/Odometry`` say: linear ``v``, angular ``omega``);
- ``/joint_states`` ``sensor_msgs/msg/JointState``: ``q``, ``qd`` and the joint torques as ``effort``;
- ``/uvms/wrench/commanded`` and ``/uvms/wrench/achieved`` ``geometry_msgs/msg/WrenchStamped``: the body wrench
  the controller asked for (the ``command_K..command_Z`` signals) and the part the thrust allocation achieved
  (the command minus ``unachieved_K..Z``), in the vehicle's axes about its origin; only in runs with those signals;
- ``/uvms/thrusters/<name>`` ``WrenchStamped``: each thruster's commanded thrust ``T`` (``thrust_cmd_<name>``) as
  the wrench it puts on the vehicle, ``f = T d``, ``m = r x T d`` (mount ``r``, direction ``d``, vehicle axes);
- ``/tf`` ``tf2_msgs/msg/TFMessage``: world -> vehicle and every joint's parent body -> child body, per row;
  ``/tf_static``: each named frame of the model (:attr:`uvms.model.Model.frames`) in its body, and each simulated
  sensor's mount in the vehicle, once at ``t = 0``;
- ``/uvms/sensors/<name>`` (:data:`SENSOR_TOPICS`): each simulated sensor of the run (``Result.sensors``), at
  its own sample times: an IMU as ``sensor_msgs/msg/Imu`` (no orientation: ``orientation_covariance[0] = -1``),
  a pressure sensor as ``sensor_msgs/msg/FluidPressure`` [Pa], a DVL as two
  ``geometry_msgs/msg/TwistWithCovarianceStamped`` topics, ``<name>/bottom_track`` (a sample whose bottom track
  is invalid, out of range or a dropout, is not written) and ``<name>/water_track``, and encoders as
  ``sensor_msgs/msg/JointState``. A sensor's ``frame_id`` is its name (encoders: ``""``, as ``/joint_states``).
  The sensor's axes are turned like the vehicle's (``H R_bs H``, mount ``H r``): a sensor mounted with ``rpy``
  zero has the axes of the vehicle's ``base_link`` in the bag too, and its vectors map by ``H``, so an IMU at
  rest reads ``+|g|`` along its z axis (REP 145). Covariances are zero: "unknown" in these messages.
"""

from __future__ import annotations

import heapq
import os
import tempfile
from pathlib import Path

import numpy as np

from uvms import frames
from uvms.errors import UvmsInputError

WORLD_FRAME = "world"
"""``frame_id`` of the world in every message (REP 105's fixed frame of a simulation's ground truth)."""

TOPICS = {
    "/uvms/odometry": "nav_msgs/msg/Odometry",
    "/joint_states": "sensor_msgs/msg/JointState",
    "/uvms/wrench/commanded": "geometry_msgs/msg/WrenchStamped",
    "/uvms/wrench/achieved": "geometry_msgs/msg/WrenchStamped",
    "/uvms/thrusters/<name>": "geometry_msgs/msg/WrenchStamped",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/tf_static": "tf2_msgs/msg/TFMessage",
}
"""Every topic :func:`write_mcap` may write and its message type (the sensors': :data:`SENSOR_TOPICS`)."""

SENSOR_PREFIX = "/uvms/sensors/"
"""A simulated sensor's topics are ``SENSOR_PREFIX + <its name> + <suffix>``."""

SENSOR_TOPICS = {
    "imu": {"": "sensor_msgs/msg/Imu"},
    "pressure": {"": "sensor_msgs/msg/FluidPressure"},
    "dvl": {"/bottom_track": "geometry_msgs/msg/TwistWithCovarianceStamped",
            "/water_track": "geometry_msgs/msg/TwistWithCovarianceStamped"},
    "encoders": {"": "sensor_msgs/msg/JointState"},
}
"""Each sensor kind's topic suffixes and message types."""

WRENCH_LABELS = ("K", "M", "N", "X", "Y", "Z")


def _need_ros():
    try:
        from mcap_ros2.writer import Writer
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise UvmsInputError("writing ROS 2 bags needs the optional extra: pip install 'uvms[ros]' (mcap, "
                             "mcap-ros2-support, rosbags)") from None
    return Writer, get_typestore(Stores.ROS2_HUMBLE)


def _stamp(t: float) -> dict:
    ns = int(round(t * 1e9))
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def _vector(v) -> dict:
    return {"x": float(v[0]), "y": float(v[1]), "z": float(v[2])}


def _quaternion(q) -> dict:
    """``[w, x, y, z]`` as ROS's ``(x, y, z, w)`` fields."""
    return {"x": float(q[1]), "y": float(q[2]), "z": float(q[3]), "w": float(q[0])}


def _transform(t: float, parent: str, child: str, p, q) -> dict:
    return {"header": {"stamp": _stamp(t), "frame_id": parent}, "child_frame_id": child,
            "transform": {"translation": _vector(p), "rotation": _quaternion(q)}}


def _wrench(t: float, frame_id: str, w) -> dict:
    """``[moment; force]`` as ``geometry_msgs/Wrench`` (``force``, ``torque``)."""
    return {"header": {"stamp": _stamp(t), "frame_id": frame_id},
            "wrench": {"force": _vector(w[3:]), "torque": _vector(w[:3])}}


def _quaternions_of(R: np.ndarray) -> np.ndarray:
    """(..., 4) ``[w, x, y, z]`` of rotation matrices (scipy), ``w >= 0``."""
    from scipy.spatial.transform import Rotation

    q = Rotation.from_matrix(R.reshape(-1, 3, 3)).as_quat(canonical=True)
    return frames.quaternion_wxyz(q)


def _body_poses(model, result) -> tuple[np.ndarray, np.ndarray]:
    """(K, nb, 3, 3) and (K, nb, 3): each body's world pose per row (forward kinematics of ``model``)."""
    from uvms.dynamics.poses import forward_kinematics

    nb = model.n_bodies
    R = np.zeros((len(result.time), nb, 3, 3))
    p = np.zeros((len(result.time), nb, 3))
    for k in range(len(result.time)):
        poses = forward_kinematics(model, result.state(k))
        R[k], p[k] = poses.rotation[:nb], poses.position[:nb]
    return R, p


def _relative(R_p, p_p, R_c, p_c) -> tuple[np.ndarray, np.ndarray]:
    """Child pose in the parent's frame: ``R = R_p^T R_c``, ``p = R_p^T (p_c - p_p)``."""
    return R_p.T @ R_c, R_p.T @ (p_c - p_p)


def sensor_topics(result) -> dict[str, str]:
    """The topics of ``result``'s simulated sensors (:data:`SENSOR_TOPICS`) and their message types, in the
    run's sensor order (a DVL's ``bottom_track`` is absent from a file when none of its samples is valid)."""
    from uvms.sensors.dvl import BOTTOM_COLUMNS, WATER_COLUMNS
    from uvms.sensors.imu import ACCEL_COLUMNS, GYRO_COLUMNS

    needs = {"imu": GYRO_COLUMNS + ACCEL_COLUMNS, "pressure": ("pressure",),
             "dvl": BOTTOM_COLUMNS + ("bottom_valid",) + WATER_COLUMNS, "encoders": ()}
    folder = getattr(result, "_directory", None)
    topics = {}
    for name, record in (result.sensors or {}).items():
        if record.kind not in SENSOR_TOPICS:
            raise UvmsInputError(f"expected a sensor kind of {', '.join(SENSOR_TOPICS)}, found {record.kind!r}",
                                 None if folder is None else str(folder / "result.json"),
                                 f"metadata.sensors.{name}.kind")
        missing = [c for c in needs[record.kind] if c not in record.columns]
        if missing:
            table = None if folder is None else str(folder / f"result.{name}.csv")
            raise UvmsInputError(f"expected the {record.kind} columns {', '.join(needs[record.kind])}; missing "
                                 f"{', '.join(missing)}", table, f"sensors.{name}")
        topics.update({SENSOR_PREFIX + name + suffix: t for suffix, t in SENSOR_TOPICS[record.kind].items()})
    return topics


def sensor_mounts(result, convention: str) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each mounted sensor's ``(r, R_bs)`` in the bag's axes, ``(H r, H R_bs H)`` from a ``ned`` run (module
    docstring), read from the run's ``metadata["sensors"][name]["mount"]`` (``offset_m``, ``rotation``: sensor
    to body axes). A sensor without one (encoders, a run saved before mounts were recorded) has no entry.

    Raises:
        UvmsInputError: a mount that is not 3 finite numbers and a proper rotation (1e-9).
    """
    about = (result.metadata or {}).get("sensors") or {}
    about = about if isinstance(about, dict) else {}
    turn = frames.HALF_TURN if frames.check_frame(convention) == "ned" else np.eye(3)
    mounts = {}
    for name in result.sensors or {}:
        mount = about.get(name, {}).get("mount") if isinstance(about.get(name), dict) else None
        if mount is None:
            continue
        where = f"metadata.sensors.{name}.mount"
        try:
            r = np.asarray(mount["offset_m"], dtype=float).reshape(3)
            R = np.asarray(mount["rotation"], dtype=float).reshape(3, 3)
        except (KeyError, TypeError, ValueError):
            raise UvmsInputError("expected offset_m (3 numbers) and rotation (3 x 3)", None, where) from None
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(R)) and np.allclose(R.T @ R, np.eye(3), atol=1e-9)
                and np.linalg.det(R) > 0):
            raise UvmsInputError("expected a finite offset and a proper rotation matrix", None, where)
        mounts[name] = (turn @ r, turn @ R @ turn)
    return mounts


def _covariance(n: int) -> list[float]:
    return [0.0] * n


def _sensor_messages(name: str, record, convention: str):
    """``(ns, topic, type, message, sequence)`` of each sample of sensor ``name``'s ``record``, in time order
    (module docstring): vectors in the bag's axes, ``H v`` from a ``ned`` run."""
    from uvms.sensors.dvl import BOTTOM_COLUMNS, WATER_COLUMNS
    from uvms.sensors.imu import ACCEL_COLUMNS, GYRO_COLUMNS

    def vectors(columns) -> np.ndarray:
        return frames.convert_vectors(np.column_stack([record[c] for c in columns]), convention, "enu")

    topic = SENSOR_PREFIX + name
    types = SENSOR_TOPICS[record.kind]
    kind = record.kind
    frame_id = "" if kind == "encoders" else name
    if kind == "imu":
        gyro, accel = vectors(GYRO_COLUMNS), vectors(ACCEL_COLUMNS)
    elif kind == "dvl":
        bottom, water = vectors(BOTTOM_COLUMNS), vectors(WATER_COLUMNS)
        valid = (record["bottom_valid"] > 0) & np.all(np.isfinite(bottom), axis=1)
    for k, t in enumerate(record.time):
        t = float(t)
        ns = int(round(t * 1e9))
        header = {"stamp": _stamp(t), "frame_id": frame_id}
        if kind == "imu":
            yield ns, topic, types[""], {
                "header": header, "orientation": {"x": 0.0, "y": 0.0, "z": 0.0, "w": 1.0},
                "orientation_covariance": [-1.0] + _covariance(8),
                "angular_velocity": _vector(gyro[k]), "angular_velocity_covariance": _covariance(9),
                "linear_acceleration": _vector(accel[k]), "linear_acceleration_covariance": _covariance(9)}, k
        elif kind == "pressure":
            yield ns, topic, types[""], {"header": header, "fluid_pressure": float(record["pressure"][k]),
                                         "variance": 0.0}, k
        elif kind == "dvl":
            for suffix, v, ok in (("/bottom_track", bottom[k], valid[k]), ("/water_track", water[k], True)):
                if ok and np.all(np.isfinite(v)):
                    yield ns, topic + suffix, types[suffix], {
                        "header": header, "twist": {"twist": {"linear": _vector(v), "angular": _vector((0, 0, 0))},
                                                    "covariance": _covariance(36)}}, k
        else:
            yield ns, topic, types[""], {"header": header, "name": list(record.columns),
                                         "position": [float(record[c][k]) for c in record.columns],
                                         "velocity": [], "effort": []}, k


def write_mcap(result, path, *, model, thrusters=None) -> Path:
    """Write ``result`` (a run of ``model``, in the model's convention) to ``path`` as MCAP (module docstring);
    ``thrusters`` (default: the model's) give the per-thruster topics their mounts. Written through a temporary
    sibling and a rename: a failed write leaves no file. Returns the path.

    Raises:
        UvmsInputError: the ``uvms[ros]`` extra is not installed, or the run and the model disagree.
    """
    Writer, store = _need_ros()
    if model.n_joints != result.n_joints:
        raise UvmsInputError(f"the run has {result.n_joints} joints, model {model.name!r} has {model.n_joints}")
    enu = model.in_frame("enu")
    run = _in_enu(result, model.convention)
    thrusters = tuple(model.thrusters if thrusters is None else thrusters)
    names = list(model.joint_names)
    bodies = list(enu.body_names)
    vehicle = bodies[0]
    sensor_topics(result)                          # every kind known before anything is written
    mounts = sensor_mounts(result, model.convention)
    taken = {WORLD_FRAME, *bodies, *(f.name for f in (enu.frames or ()))}
    for name, record in (result.sensors or {}).items():
        if record.kind != "encoders" and name in taken:
            raise UvmsInputError(f"sensor {name!r} has the name of a frame of model {model.name!r} (or 'world'); "
                                 f"its frame id would be ambiguous in /tf: rename the sensor", None,
                                 f"sensors.{name}")
    R, p = _body_poses(enu, run)
    quats = _quaternions_of(R).reshape(len(run.time), len(bodies), 4)
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    try:
        with os.fdopen(fd, "wb") as fh:
            writer = Writer(fh)
            schemas = {}

            def schema(typename: str):
                if typename not in schemas:
                    schemas[typename] = writer.register_msgdef(typename, store.generate_msgdef(typename,
                                                                                               ros_version=2)[0])
                return schemas[typename]

            def write(topic: str, typename: str, t: float, message: dict, sequence: int, ns: int | None = None) -> None:
                ns = int(round(t * 1e9)) if ns is None else ns
                writer.write_message(topic, schema(typename), message, log_time=ns, publish_time=ns,
                                     sequence=sequence)

            static = [_transform(0.0, bodies[f.body], f.name, enu.frame(f.name).position,
                                 _quaternions_of(enu.frame(f.name).rotation)[0]) for f in (enu.frames or ())]
            static += [_transform(0.0, vehicle, name, r, _quaternions_of(R)[0]) for name, (r, R) in mounts.items()]
            if static:
                write("/tf_static", TOPICS["/tf_static"], 0.0, {"transforms": static}, 0)
            commanded = _signal_rows(run, "command_")
            unachieved = _signal_rows(run, "unachieved_")
            thrust = {th.name: run.signals.get(f"thrust_cmd_{th.name}") for th in thrusters}
            samples = heapq.merge(*(_sensor_messages(name, record, model.convention)
                                    for name, record in (result.sensors or {}).items()), key=lambda m: m[0])
            pending = next(samples, None)
            for k, t in enumerate(run.time):
                t = float(t)
                while pending is not None and pending[0] <= int(round(t * 1e9)):   # in time order
                    ns, topic, typename, message, sequence = pending
                    write(topic, typename, 0.0, message, sequence, ns)
                    pending = next(samples, None)
                state = run.state(k)
                write("/uvms/odometry", TOPICS["/uvms/odometry"], t, {
                    "header": {"stamp": _stamp(t), "frame_id": WORLD_FRAME}, "child_frame_id": vehicle,
                    "pose": {"pose": {"position": _vector(state.position), "orientation": _quaternion(state.quaternion)},
                             "covariance": [0.0] * 36},
                    "twist": {"twist": {"linear": _vector(state.nu[3:]), "angular": _vector(state.nu[:3])},
                              "covariance": [0.0] * 36}}, k)
                write("/joint_states", TOPICS["/joint_states"], t, {
                    "header": {"stamp": _stamp(t), "frame_id": ""}, "name": names,
                    "position": [float(x) for x in state.q], "velocity": [float(x) for x in state.qd],
                    "effort": [float(x) for x in run.joint_torques[k]]}, k)
                transforms = [_transform(t, WORLD_FRAME, vehicle, p[k, 0], quats[k, 0])]
                for j in range(len(names)):
                    parent, child = int(model.joint_parent[j]), j + 1
                    Rr, pr = _relative(R[k, parent], p[k, parent], R[k, child], p[k, child])
                    transforms.append(_transform(t, bodies[parent], bodies[child], pr, _quaternions_of(Rr)[0]))
                write("/tf", TOPICS["/tf"], t, {"transforms": transforms}, k)
                if commanded is not None:
                    write("/uvms/wrench/commanded", TOPICS["/uvms/wrench/commanded"], t,
                          _wrench(t, vehicle, commanded[k]), k)
                    if unachieved is not None:
                        write("/uvms/wrench/achieved", TOPICS["/uvms/wrench/achieved"], t,
                              _wrench(t, vehicle, commanded[k] - unachieved[k]), k)
                for th in thrusters:
                    if thrust[th.name] is None:
                        continue
                    r, d = frames.convert_vectors(np.array([th.position, th.direction]), model.convention, "enu")
                    f = float(thrust[th.name][k]) * d
                    write(f"/uvms/thrusters/{th.name}", TOPICS["/uvms/thrusters/<name>"], t,
                          _wrench(t, vehicle, np.concatenate([np.cross(r, f), f])), k)
            while pending is not None:                                             # samples after the last row
                ns, topic, typename, message, sequence = pending
                write(topic, typename, 0.0, message, sequence, ns)
                pending = next(samples, None)
            writer.finish()
        from uvms.output import publish

        publish(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def _signal_rows(result, prefix: str) -> np.ndarray | None:
    """(K, 6) the ``<prefix>K .. <prefix>Z`` signals (already in the export's frame), or ``None``."""
    columns = [result.signals.get(prefix + label) for label in WRENCH_LABELS]
    if any(c is None for c in columns):
        return None
    return np.column_stack(columns)


def _in_enu(result, convention: str):
    """``result`` with its states and body-wrench signals in ``enu`` (the half turn; joint values unchanged)."""
    from dataclasses import replace

    from uvms.state import NU, POSITION, QUATERNION

    if convention == "enu":
        return result
    states = np.array(result.states, dtype=float, copy=True)
    states[:, POSITION:POSITION + 3] = frames.convert_vectors(states[:, POSITION:POSITION + 3], convention, "enu")
    states[:, QUATERNION:QUATERNION + 4] = frames.convert_quaternions(states[:, QUATERNION:QUATERNION + 4],
                                                                      convention, "enu")
    states[:, NU:NU + 6] = frames.convert_twists(states[:, NU:NU + 6], convention, "enu")
    signals = dict(result.signals)
    for prefix in ("command_", "unachieved_"):
        rows = _signal_rows(result, prefix)
        if rows is not None:
            converted = frames.convert_twists(rows, convention, "enu")       # wrenches map as twists: H6
            signals.update({prefix + label: converted[:, i] for i, label in enumerate(WRENCH_LABELS)})
    return replace(result, states=states, signals=signals)
