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
  ``/tf_static``: each named frame of the model (:attr:`uvms.model.Model.frames`) in its body, once at ``t = 0``.
"""

from __future__ import annotations

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
"""Every topic :func:`write_mcap` may write and its message type."""

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

            def write(topic: str, typename: str, t: float, message: dict, sequence: int) -> None:
                ns = int(round(t * 1e9))
                writer.write_message(topic, schema(typename), message, log_time=ns, publish_time=ns,
                                     sequence=sequence)

            static = [_transform(0.0, bodies[f.body], f.name, enu.frame(f.name).position,
                                 _quaternions_of(enu.frame(f.name).rotation)[0]) for f in (enu.frames or ())]
            if static:
                write("/tf_static", TOPICS["/tf_static"], 0.0, {"transforms": static}, 0)
            commanded = _signal_rows(run, "command_")
            unachieved = _signal_rows(run, "unachieved_")
            thrust = {th.name: run.signals.get(f"thrust_cmd_{th.name}") for th in thrusters}
            for k, t in enumerate(run.time):
                t = float(t)
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
