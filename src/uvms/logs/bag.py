"""Reading one stream of a log from a ROS bag: one topic's messages, the fields a description names, checked as data
(``docs/ros.md``, "Bags in"; ``docs/logs.md``).

A bag is an MCAP file (``.mcap``, as ``uvms export`` or Foxglove write it), a rosbag2 folder (``metadata.yaml``
beside ``.db3`` sqlite3 or ``.mcap`` files) or a single ``.db3`` file's folder; it is read with ``rosbags``
(the optional extra ``uvms[ros]``), which decodes each message with the definitions stored in the bag.

A *field* names a value in a message by its path: ``pose.pose.position.x``; a list element by its index,
``data[2]``, or, in a message with a ``name`` list beside the list (``sensor_msgs/JointState``), by that name:
``position[axis_e]``. The time of a row is the message's ``header.stamp`` (default) or the bag's receive time
(``time: log_time``). :data:`DEFAULT_FIELDS` gives the pose and IMU fields of the common message types, so a
description needs only the topic. The result is the :class:`uvms.logs.read.Table` a CSV stream gives, and the
same rules apply: at most :data:`uvms.logs.read.MAX_FILE_BYTES` of bag and :data:`uvms.logs.read.MAX_ROWS`
messages, finite values, time increasing, an exact repetition dropped.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from uvms.errors import UvmsInputError, show
from uvms.logs.read import MAX_FILE_BYTES, MAX_ROWS, Table, checked_rows

BAG_SUFFIXES = (".mcap", ".db3")
"""File suffixes read as bags (a folder with a ``metadata.yaml`` is a rosbag2 bag too)."""

TIME_FIELDS = ("header.stamp", "log_time")
"""The two clocks a bag stream may use."""

DEFAULT_FIELDS = {
    "nav_msgs/msg/Odometry": {"position": ("pose.pose.position.x", "pose.pose.position.y", "pose.pose.position.z"),
                              "quaternion_xyzw": ("pose.pose.orientation.x", "pose.pose.orientation.y",
                                                  "pose.pose.orientation.z", "pose.pose.orientation.w")},
    "geometry_msgs/msg/PoseStamped": {"position": ("pose.position.x", "pose.position.y", "pose.position.z"),
                                      "quaternion_xyzw": ("pose.orientation.x", "pose.orientation.y",
                                                          "pose.orientation.z", "pose.orientation.w")},
    "geometry_msgs/msg/PoseWithCovarianceStamped": {
        "position": ("pose.pose.position.x", "pose.pose.position.y", "pose.pose.position.z"),
        "quaternion_xyzw": ("pose.pose.orientation.x", "pose.pose.orientation.y", "pose.pose.orientation.z",
                            "pose.pose.orientation.w")},
    "sensor_msgs/msg/Imu": {"quaternion_xyzw": ("orientation.x", "orientation.y", "orientation.z", "orientation.w"),
                            "angular_velocity": ("angular_velocity.x", "angular_velocity.y", "angular_velocity.z"),
                            "linear_acceleration": ("linear_acceleration.x", "linear_acceleration.y",
                                                    "linear_acceleration.z")},
}
"""Pose and IMU fields of the common message types (a description's own fields replace them)."""

JOINT_STATE = "sensor_msgs/msg/JointState"
"""Joint streams from this type name their columns by the message's joint names: ``position[<name>]`` and
``velocity[<name>]``."""

_PART = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)(?:\[([^\]]+)\])?$")


def is_bag(path: Path) -> bool:
    """Whether a stream's ``file`` is a bag (by its suffix, or a folder holding ``metadata.yaml``)."""
    return path.suffix.lower() in BAG_SUFFIXES or (path.is_dir() and (path / "metadata.yaml").is_file())


def _reader(path: Path, source: str):
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError:
        raise UvmsInputError("reading ROS bags needs the optional extra: pip install 'uvms[ros]'", source) from None
    if not path.exists():
        raise UvmsInputError("no such file", source)
    size = path.stat().st_size if path.is_file() else sum(p.stat().st_size for p in path.rglob("*") if p.is_file())
    if size > MAX_FILE_BYTES:
        raise UvmsInputError(f"refused: {size / 2**20:.0f} MiB is larger than the {MAX_FILE_BYTES // 2**20} MiB a "
                             "log file may be", source)
    bag = path.parent if path.suffix.lower() == ".db3" else path
    return AnyReader([bag], default_typestore=get_typestore(Stores.ROS2_HUMBLE))


def _open(reader, source: str):
    try:
        reader.open()
    except Exception as exc:                       # rosbags' own errors: a damaged or foreign file
        raise UvmsInputError(f"not a readable ROS bag: {show(str(exc).splitlines()[0] if str(exc) else exc, 120)}",
                             source) from None


def topic_type(path: Path, topic: str, source: str, field: str) -> str:
    """The message type of ``topic`` in the bag, or one line listing the bag's topics."""
    reader = _reader(path, source)
    _open(reader, source)
    try:
        types = {c.topic: c.msgtype for c in reader.connections}
    finally:
        reader.close()
    if topic not in types:
        listed = ", ".join(f"{t} ({m})" for t, m in sorted(types.items())) or "none"
        raise UvmsInputError(f"no topic {show(topic)} in the bag; its topics: {listed}", source, field)
    return types[topic]


def _getter(path_text: str, msgtype: str, source: str, where: str):
    """A function ``message -> float`` of a field path (module docstring)."""
    parts = []
    for piece in path_text.split("."):
        m = _PART.match(piece)
        if not m:
            raise UvmsInputError(f"expected a field path such as pose.position.x or position[joint], found "
                                 f"{show(path_text)}", source, where)
        parts.append((m.group(1), m.group(2)))

    def get(message):
        value = message
        for name, index in parts:
            owner = value
            if not hasattr(owner, name):
                raise UvmsInputError(f"{msgtype} has no field {show(name)} (in {show(path_text)})", source, where)
            value = getattr(owner, name)
            if index is None:
                continue
            if index.lstrip("-").isdigit():
                k = int(index)
            else:
                labels = list(getattr(owner, "name", None) or [])
                if index not in labels:
                    listed = ", ".join(labels) if labels else "none"
                    raise UvmsInputError(f"no {show(index)} in the message's names ({listed})", source, where)
                k = labels.index(index)
            try:
                value = value[k]
            except (IndexError, TypeError):
                raise UvmsInputError(f"{show(path_text)}: no element {k} in the message's {name}", source,
                                     where) from None
        try:
            return float(value)
        except (TypeError, ValueError):
            raise UvmsInputError(f"{show(path_text)} is not a number in {msgtype}", source, where) from None

    return get


def _stamp(message) -> float:
    stamp = message.header.stamp
    return float(stamp.sec) + 1e-9 * float(stamp.nanosec)


def read_bag_table(path: Path, topic: str, time: str, fields: dict[str, str], *, time_scale: float = 1.0,
                   time_offset: float = 0.0) -> Table:
    """Read ``topic``'s messages: the ``time`` clock (:data:`TIME_FIELDS`) and ``fields`` (``{field path: the
    description key that names it}``) as the columns of a :class:`~uvms.logs.read.Table` (``lines`` are message
    numbers, the first 1).

    Raises:
        UvmsInputError: one line naming the bag and the topic, field or message.
    """
    source = str(path)
    where = f"topic {topic}"
    if time not in TIME_FIELDS:
        raise UvmsInputError(f"expected the time of a bag stream to be one of {', '.join(TIME_FIELDS)}, found "
                             f"{show(time)}", source, where)
    reader = _reader(path, source)
    _open(reader, source)
    try:
        connections = [c for c in reader.connections if c.topic == topic]
        if not connections:
            listed = ", ".join(sorted({c.topic for c in reader.connections})) or "none"
            raise UvmsInputError(f"no such topic; the bag's topics: {listed}", source, where)
        msgtype = connections[0].msgtype
        getters = {f: _getter(f, msgtype, source, f"{where}, field {f} ({key})") for f, key in fields.items()}
        times, rows = [], []
        for count, (connection, log_time, raw) in enumerate(reader.messages(connections=connections), 1):
            if count > MAX_ROWS:
                raise UvmsInputError(f"refused: more than {MAX_ROWS:,} messages", source, where)
            message = reader.deserialize(raw, connection.msgtype)
            if time == "log_time":
                times.append(1e-9 * log_time)
            else:
                if not hasattr(message, "header"):
                    raise UvmsInputError(f"{msgtype} has no header: give time: log_time", source, where)
                times.append(_stamp(message))
            rows.append([get(message) for get in getters.values()])
    finally:
        reader.close()
    t = np.asarray(times, dtype=float) * time_scale + time_offset
    values = {f: np.asarray([r[i] for r in rows], dtype=float) for i, f in enumerate(getters)}
    for f, v in values.items():
        bad = np.flatnonzero(~np.isfinite(v))
        if bad.size:
            raise UvmsInputError(f"expected a finite number, found {v[bad[0]]}", source,
                                 f"{where}, message {int(bad[0]) + 1}, field {f}")
    return checked_rows(source, t, values, np.arange(1, t.size + 1), time_name=f"{where} ({time})", line="message")
