"""``uvms.Log``: a recorded run read from a log description (``docs/logs.md``), its streams labelled and aligned.

A description (YAML, or the same mapping from Python) names the CSV files of up to four streams (``pose``,
``imu``, ``joints``, ``thrusters``), the frame their numbers are in (``ned`` or ``enu``, :mod:`uvms.frames`) and the
replay's interval (``start``, ``duration``). :class:`Log` reads and checks them (:mod:`uvms.logs.read`), applies
the description's conversions once (positions times ``scale``; quaternions to ``[w, x, y, z]`` and unit norm;
joint angles ``q_model = sign * q_log + offset``, rates ``qd_model = sign * qd_log``), and puts ``t = 0`` at
``start``. Tables are pandas DataFrames indexed by ``t_s`` with units in their column names, tagged with their
frame (``table.attrs["frame"]``).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
from pydantic import ValidationError

from uvms import frames
from uvms.errors import UvmsInputError, show
from uvms.input_paths import data_file
from uvms.logs import interpolate
from uvms.logs.read import read_table
from uvms.logs.schema import LogSpec, StreamSpec
from uvms.logs.score import ReplayScores, score
from uvms.logs.start import initial_state
from uvms.rotations import euler_from_rotations, rotations_from_quaternions
from uvms.safe_yaml import read_yaml_mapping
from uvms.schema_base import validation_input_error

QUATERNION_NORM_TOLERANCE = 1e-3
"""A logged quaternion's norm may differ from 1 by at most this (rounding in a CSV file), then it is normalised;
a larger difference is refused: the columns are probably not a quaternion, or not in the order given."""

TIME_TOLERANCE = 1e-9
"""[s] Times this close to an end of the interval count as inside it (round-off of ``start + duration``)."""

_VECTORS = ("position", "angular_velocity", "linear_acceleration")
"""The parts that are world points or body vectors: ``(x, y, z) -> (x, -y, -z)`` between the frames."""


@dataclass(frozen=True, eq=False)
class Stream:
    """One stream as read, in the frame of its :class:`Log`.

    Attributes:
        key: ``pose``, ``imu``, ``joints`` or ``thrusters``.
        source: its CSV file.
        time: (K,) log clock [s], strictly increasing (the whole file, not only the replay's interval).
        parts: ``{part: (K, m) array}``: ``position`` [m], ``quaternion`` ``[w, x, y, z]`` (body to world),
            ``angular_velocity`` [rad/s] and ``linear_acceleration`` [m/s^2] in body axes, ``q`` (model
            convention), ``qd`` (the joints in :attr:`rate_names`), ``commands``.
        names: the joints of ``q`` or the thrusters of ``commands``, in column order.
        rate_names: the joints of ``qd``.
        dropped: exact repetitions of a row dropped when read.
    """

    key: str
    source: str
    time: np.ndarray
    parts: dict[str, np.ndarray]
    names: tuple[str, ...] = ()
    rate_names: tuple[str, ...] = ()
    dropped: int = 0


def _unit_quaternions(q: np.ndarray, lines: np.ndarray, columns: tuple[str, ...], source: str) -> np.ndarray:
    norm = np.linalg.norm(q, axis=1)
    bad = np.flatnonzero(np.abs(norm - 1.0) > QUATERNION_NORM_TOLERANCE)
    if bad.size:
        k = int(bad[0])
        raise UvmsInputError(f"expected a unit quaternion (norm within {QUATERNION_NORM_TOLERANCE:g} of 1), found "
                             f"norm {norm[k]:.6g}", source, f"line {lines[k]}, columns {', '.join(columns)}")
    return q / norm[:, None]


def _read_bag_stream(key: str, spec: StreamSpec, path: Path, wanted: dict, described: dict):
    """The table of a stream read from a bag's topic (:mod:`uvms.logs.bag`) and its parts' fields: the message
    type's default pose and IMU fields where the description gives none, a joint state's ``position[<name>]``
    and ``velocity[<name>]`` for the joints' columns."""
    from uvms.logs import bag

    source = str(path)
    msgtype = bag.topic_type(path, spec.topic, source, f"{key}.topic")
    defaults = dict(bag.DEFAULT_FIELDS.get(msgtype, {}))
    if "quaternion_xyzw" in defaults:
        x, y, z, w = defaults.pop("quaternion_xyzw")
        defaults["quaternion"] = (w, x, y, z)
    wanted = dict(wanted)
    parts = {"pose": ("position", "quaternion"),
             "imu": ("quaternion", "angular_velocity", "linear_acceleration")}.get(key, ())
    for part in parts:
        if part not in wanted and part in defaults:
            wanted[part] = defaults[part]
            described.update({f: f"{key}.topic ({msgtype})" for f in defaults[part]})
    if key == "pose" and not {"position", "quaternion"} <= set(wanted):
        raise UvmsInputError(f"a pose from {msgtype} needs its fields: position: [x, y, z] and quaternion_xyzw: "
                             f"[x, y, z, w] (field paths such as pose.position.x)", source, "pose.topic")
    if key == "joints" and msgtype == bag.JOINT_STATE:
        for part, field in (("q", "position"), ("qd", "velocity")):
            fields = tuple(f"{field}[{c}]" for c in wanted[part])
            described.update({f: f"joints.{'columns' if part == 'q' else 'rates'}" for f in fields})
            wanted[part] = fields
    fields = {f: described[f] for columns in wanted.values() for f in columns}
    table = bag.read_bag_table(path, spec.topic, spec.time or "header.stamp", fields,
                               time_scale=spec.time_scale, time_offset=spec.time_offset)
    return table, wanted


def _read_stream(key: str, spec: StreamSpec, base_dir: Path, source: str | None) -> Stream:
    """Read one stream's CSV file (inside ``base_dir``, :func:`uvms.input_paths.data_file`) and apply its
    description's conversions."""
    wanted: dict[str, tuple[str, ...]] = {}                  # part -> columns
    quaternion = getattr(spec, "quaternion_columns", lambda: None)()
    for part in _VECTORS[:1] + ("quaternion",) + _VECTORS[1:]:         # position, attitude, rates, accelerations
        columns = quaternion if part == "quaternion" else getattr(spec, part, None)
        if columns is not None:
            wanted[part] = columns
    names: tuple[str, ...] = ()
    rate_names: tuple[str, ...] = ()
    if key == "joints":
        names, rate_names = tuple(spec.columns), tuple(spec.rates)
        wanted["q"], wanted["qd"] = tuple(spec.columns.values()), tuple(spec.rates.values())
    elif key == "thrusters":
        names = tuple(spec.columns)
        wanted["commands"] = tuple(spec.columns.values())
    described = {}
    for part, columns in wanted.items():
        label = {"quaternion": "quaternion_xyzw" if getattr(spec, "quaternion_xyzw", None) else "quaternion_wxyz",
                 "q": "columns", "qd": "rates", "commands": "columns"}.get(part, part)
        described.update({c: f"{key}.{label}" for c in columns if c not in described})
    path = data_file(spec.file, base_dir, source, f"{key}.file")
    if spec.topic is not None:
        table, wanted = _read_bag_stream(key, spec, path, wanted, described)
    else:
        table = read_table(path, spec.time, described,
                           time_scale=spec.time_scale, time_offset=spec.time_offset)
    parts = {part: np.array([table.values[c] for c in columns]).T.reshape(table.time.size, len(columns))
             for part, columns in wanted.items()}
    if "quaternion" in parts:
        parts["quaternion"] = _unit_quaternions(parts["quaternion"], table.lines, wanted["quaternion"],
                                                table.source)
    if key == "pose":
        parts["position"] = parts["position"] * spec.scale
    if key == "joints":
        sign = np.array([spec.sign.get(j, 1.0) for j in names])
        offset = np.array([spec.offset.get(j, 0.0) for j in names])
        parts["q"] = sign * parts["q"] + offset
        parts["qd"] = np.array([spec.sign.get(j, 1.0) for j in rate_names]) * parts["qd"]
    return Stream(key=key, source=table.source, time=table.time, parts=parts, names=names, rate_names=rate_names,
                  dropped=table.dropped)


def _interval(spec: LogSpec, streams: dict[str, Stream], source: str | None) -> tuple[float, float]:
    """The replay's start (log clock) and duration [s], checked against every stream."""
    start = spec.start if spec.start is not None else max(s.time[0] for s in streams.values())
    for key, s in streams.items():
        if s.time[0] > start + TIME_TOLERANCE:
            raise UvmsInputError(f"stream {key} ({s.source}) starts at {s.time[0]:.9g} s of log time, after the "
                                 f"replay's start {start:.9g} s", source, "start")
    if spec.duration is None:
        key, s = min(streams.items(), key=lambda item: item[1].time[-1])
        duration = s.time[-1] - start
        if duration <= 0:
            raise UvmsInputError(f"stream {key} ({s.source}) ends at {s.time[-1]:.9g} s of log time, at or before "
                                 f"the replay's start {start:.9g} s", source, "start")
        return float(start), float(duration)
    for key, s in streams.items():
        if s.time[-1] < start + spec.duration - TIME_TOLERANCE:
            raise UvmsInputError(f"log shorter than asked: stream {key} ({s.source}) ends at {s.time[-1]:.9g} s of "
                                 f"log time, before start + duration = {start + spec.duration:.9g} s", source,
                                 "duration")
    return float(start), float(spec.duration)


def _table(t: np.ndarray, columns: dict[str, np.ndarray], frame: str, source: str | None):
    import pandas as pd

    table = pd.DataFrame({name: np.asarray(v, dtype=float) for name, v in columns.items()},
                         index=pd.Index(np.asarray(t, dtype=float), name="t_s"))
    table.attrs.update(frame=frame, source=source)
    return table


@dataclass(frozen=True, eq=False)
class Log:
    """A recorded run: its streams in :attr:`frame`, the replay's interval ``[start, start + duration]`` of log
    time; ``t = 0`` at ``start`` in every table and time argument.

    Build one with :meth:`load` (a YAML file) or :meth:`from_dict`; ``docs/logs.md`` describes the file.

    Attributes:
        spec: the validated description.
        source: the description file (``None`` for a mapping given from Python).
        frame: ``"ned"`` or ``"enu"``, the frame of every number this log returns (:meth:`in_frame`).
        start: the replay's start on the log clock [s].
        duration: the replay's length [s].
        streams: ``{key: Stream}``, ``pose`` always, ``imu``, ``joints``, ``thrusters`` when described.
    """

    spec: LogSpec
    source: str | None
    frame: str
    start: float
    duration: float
    streams: dict[str, Stream]

    # ------------------------------------------------------------------------------------------ building

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "Log":
        """Read a log description file; its CSV paths are relative to its folder.

        Raises:
            UvmsInputError: one line naming the file (the description or a CSV file) and the key, column or line.
        """
        path = Path(path)
        data = read_yaml_mapping(path, "log description fields")
        return cls.from_dict(data, base_dir=path.parent, source=str(path))

    @classmethod
    def from_dict(cls, data: Any, *, base_dir: str | os.PathLike[str] | None = None,
                  source: str | None = None) -> "Log":
        """A log from a description mapping (the YAML file's content); CSV paths relative to ``base_dir``
        (default: the working folder); ``source`` names the description in messages."""
        if not isinstance(data, dict):
            raise UvmsInputError(f"expected a mapping of log description fields, found {show(data)}", source)
        try:
            spec = LogSpec.model_validate(data)
        except ValidationError as exc:
            raise validation_input_error(exc, source, schema=LogSpec) from None
        base = Path(base_dir) if base_dir is not None else Path.cwd()
        streams = {key: _read_stream(key, stream, base, source) for key, stream in spec.streams().items()}
        start, duration = _interval(spec, streams, source)
        return cls(spec=spec, source=source, frame=spec.frame, start=start, duration=duration, streams=streams)

    def in_frame(self, frame: str) -> "Log":
        """This log with its numbers in ``frame`` (:mod:`uvms.frames`: positions and body vectors ``H v``,
        quaternions ``[w, x, -y, -z]``; joint angles and commands unchanged)."""
        frames.check_frame(frame, "frame")
        streams = {}
        for key, s in self.streams.items():
            parts = dict(s.parts)
            for part in _VECTORS:
                if part in parts:
                    parts[part] = frames.convert_vectors(parts[part], self.frame, frame)
            if "quaternion" in parts:
                parts["quaternion"] = frames.convert_quaternions(parts["quaternion"], self.frame, frame)
            streams[key] = replace(s, parts=parts)
        return replace(self, frame=frame, streams=streams)

    # ------------------------------------------------------------------------------------------ reading

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The joints the log describes (model names), in the description's order."""
        return self.streams["joints"].names if "joints" in self.streams else ()

    @property
    def notes(self) -> tuple[str, ...]:
        """What reading changed, one line each (exact repetitions of rows dropped)."""
        return tuple(f"{s.source}: dropped {s.dropped} exact repetition{'s' if s.dropped > 1 else ''} of a row"
                     for s in self.streams.values() if s.dropped)

    def _rows(self, key: str) -> tuple[Stream, np.ndarray]:
        s = self.streams[key]
        inside = (s.time >= self.start - TIME_TOLERANCE) & (s.time <= self.start + self.duration + TIME_TOLERANCE)
        return s, inside

    def _stream_table(self, key: str):
        if key not in self.streams:
            return None
        s, inside = self._rows(key)
        return _table(s.time[inside] - self.start, self._columns(s, inside), self.frame, s.source)

    def _columns(self, s: Stream, rows) -> dict[str, np.ndarray]:
        """The labelled columns of stream ``s`` at ``rows`` (an index or a mask)."""
        return self._labelled(s, {part: v[rows] for part, v in s.parts.items()})

    @staticmethod
    def _labelled(s: Stream, parts: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        out: dict[str, np.ndarray] = {}
        labels = {"position": ("x_m", "y_m", "z_m"), "quaternion": ("qw", "qx", "qy", "qz"),
                  "angular_velocity": ("p_rad_s", "q_rad_s", "r_rad_s"),
                  "linear_acceleration": ("ax_m_s2", "ay_m_s2", "az_m_s2"),
                  "q": tuple(f"q_{j}_rad" for j in s.names), "qd": tuple(f"qd_{j}_rad_s" for j in s.rate_names),
                  "commands": s.names}
        for part, v in parts.items():
            out.update(zip(labels[part], v.T))
        return out

    @property
    def pose(self):
        """The pose stream's rows in the replay's interval: ``x_m, y_m, z_m, qw, qx, qy, qz`` by ``t_s``."""
        return self._stream_table("pose")

    @property
    def imu(self):
        """The IMU's rows in the interval (``qw..qz``, ``p_rad_s, q_rad_s, r_rad_s``, ``ax_m_s2..az_m_s2``, those
        described), or ``None``."""
        return self._stream_table("imu")

    @property
    def joints(self):
        """The joint states' rows in the interval (``q_<joint>_rad``, ``qd_<joint>_rad_s``), or ``None``."""
        return self._stream_table("joints")

    @property
    def thrusters(self):
        """The thruster commands' rows in the interval (one column per thruster name), or ``None``."""
        return self._stream_table("thrusters")

    def check_times(self, times, name: str = "times") -> np.ndarray:
        """``times`` [s from start] as a float array, if finite and inside ``[0, duration]``."""
        t = np.atleast_1d(np.asarray(times, dtype=float))
        if t.ndim != 1 or t.size == 0 or not np.all(np.isfinite(t)):
            raise UvmsInputError(f"expected a non-empty list of finite times [s from the replay's start], found "
                                 f"shape {t.shape}", path=name)
        if t.min() < -TIME_TOLERANCE or t.max() > self.duration + TIME_TOLERANCE:
            raise UvmsInputError(f"expected times within the replay's [0, {self.duration:.9g}] s, found "
                                 f"{t.min():.9g} to {t.max():.9g} s", path=name)
        return np.clip(t, 0.0, self.duration)

    def _at(self, key: str, t: np.ndarray, position: str = "linear") -> dict[str, np.ndarray]:
        """Stream ``key``'s parts at replay times ``t`` (checked)."""
        s = self.streams[key]
        at = t + self.start
        parts = {}
        for part, v in s.parts.items():
            if part == "quaternion":
                parts[part] = interpolate.slerp(s.time, v, at)
            elif part == "commands":
                parts[part] = interpolate.held(s.time, v, at)
            else:
                parts[part] = interpolate.values(s.time, v, at, position if part == "position" else "linear")
        return parts

    def quaternions(self, times=None) -> np.ndarray:
        """(N, 4) body-to-world ``[w, x, y, z]`` of the pose stream at ``times`` [s from start] (Slerp), or at its
        own rows in the interval."""
        if times is None:
            s, inside = self._rows("pose")
            return s.parts["quaternion"][inside]
        return self._at("pose", self.check_times(times))["quaternion"]

    def attitude(self, times=None):
        """ZYX Euler angles ``roll_rad, pitch_rad, yaw_rad`` of the pose stream (:func:`uvms.rotations.euler_zyx`)
        at ``times`` [s from start], or at its own rows in the interval."""
        t = self.pose.index.to_numpy() if times is None else self.check_times(times)
        euler = euler_from_rotations(rotations_from_quaternions(self.quaternions(times)))
        return _table(t, dict(zip(("roll_rad", "pitch_rad", "yaw_rad"), euler.T)), self.frame, self.source)

    def joint_angles(self, times=None):
        """``q_<joint>_rad`` (model convention) at ``times`` [s from start] (linear), or at the joint stream's
        rows in the interval."""
        if "joints" not in self.streams:
            raise UvmsInputError("the log describes no joints", self.source, "joints")
        if times is None:
            table = self.joints
            return table[[c for c in table.columns if c.startswith("q_")]]
        t = self.check_times(times)
        s = self.streams["joints"]
        return _table(t, self._labelled(s, {"q": self._at("joints", t)["q"]}), self.frame, s.source)

    def resample(self, times, *, position: str = "linear"):
        """Every stream at ``times`` [s from start] in one table: the pose (``x_m..z_m`` linear, or ``cubic``
        with ``position="cubic"``; ``qw..qz`` by Slerp), its ``roll_rad, pitch_rad, yaw_rad`` and ``depth_m``
        (positive down), the joints (linear), the IMU (``imu_qw..imu_qz`` by Slerp, ``imu_p_rad_s..`` and
        ``imu_ax_m_s2..`` linear) and the thruster commands (``thrust_<name>``, held)."""
        if position not in interpolate.METHODS:
            raise UvmsInputError(f"expected one of {', '.join(interpolate.METHODS)}, found {show(position)}",
                                 path="position")
        t = self.check_times(times)
        columns: dict[str, np.ndarray] = {}
        for key, s in self.streams.items():
            prefix = {"imu": "imu_", "thrusters": "thrust_"}.get(key, "")
            for name, v in self._labelled(s, self._at(key, t, position)).items():
                columns[prefix + name] = v
            if key == "pose":
                euler = euler_from_rotations(rotations_from_quaternions(self._at(key, t)["quaternion"]))
                columns.update(zip(("roll_rad", "pitch_rad", "yaw_rad"), euler.T))
                columns["depth_m"] = -columns["z_m"] * frames.UP[self.frame][2]
        return _table(t, columns, self.frame, self.source)

    def grid(self, step: float) -> np.ndarray:
        """``0, step, 2 step, ...`` up to ``duration``, and ``duration`` itself when ``step`` does not divide it."""
        if not (isinstance(step, (int, float)) and not isinstance(step, bool) and 0 < step <= self.duration):
            raise UvmsInputError(f"expected a number in (0, {self.duration:.9g}] s (the log's duration), "
                                 f"found {show(step)}", self.source, "grid step")
        k = np.arange(int(np.floor(self.duration / step + 1e-9)) + 1)
        t = k * step
        return t if self.duration - t[-1] <= TIME_TOLERANCE else np.append(t, self.duration)

    def on_grid(self, step: float, *, position: str = "linear"):
        """:meth:`resample` on :meth:`grid` ``(step)``."""
        return self.resample(self.grid(step), position=position)

    # ------------------------------------------------------------------------------------------ using

    def initial_state(self, model, *, frame: str | None = None, window: float = 0.2, degree: int = 2,
                      omega_from: str = "pose"):
        """The :class:`uvms.State` at the replay's start (:func:`uvms.logs.start.initial_state`)."""
        return initial_state(self, model, frame=frame, window=window, degree=degree, omega_from=omega_from)

    def score(self, times, *, roll, pitch, yaw, depth, frame: str | None = None) -> ReplayScores:
        """A simulation's attitude and depth against this log (:func:`uvms.logs.score.score`)."""
        return score(self, times, roll=roll, pitch=pitch, yaw=yaw, depth=depth, frame=frame)
