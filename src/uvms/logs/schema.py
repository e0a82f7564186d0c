"""The log description file's schema: which CSV files hold which streams, in which frame, over which interval.

Validated like every uvms input file (:mod:`uvms.schema_base`: pydantic v2, unknown keys refused by name, one-line
errors naming the file and the dotted field path); ``docs/logs.md`` documents every key. This module holds the
file's content only: reading the CSV files is :mod:`uvms.logs.read`'s, the streams' use :mod:`uvms.logs.log`'s.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

from pydantic import BeforeValidator, Field, model_validator

from uvms.schema_base import Number, Positive, Spec, fail, is_number, show

Column = Annotated[str, BeforeValidator(lambda v: _column(v))]
"""A CSV column name: a non-empty string, at most 200 characters."""


def _column(value: Any) -> str:
    if isinstance(value, str) and 0 < len(value) <= 200:
        return value
    raise fail(f"expected a column name (a non-empty string of at most 200 characters), found {show(value)}")


def _three_columns(value: Any) -> tuple[str, str, str]:
    if isinstance(value, (list, tuple)) and len(value) == 3:
        return tuple(_column(v) for v in value)  # type: ignore[return-value]
    raise fail(f"expected a list of 3 column names (x, y, z), found {show(value)}")


def _four_columns(value: Any) -> tuple[str, str, str, str]:
    if isinstance(value, (list, tuple)) and len(value) == 4:
        return tuple(_column(v) for v in value)  # type: ignore[return-value]
    raise fail(f"expected a list of 4 column names, found {show(value)}")


Columns3 = Annotated[tuple[str, str, str], BeforeValidator(_three_columns)]
Columns4 = Annotated[tuple[str, str, str, str], BeforeValidator(_four_columns)]


def _sign(value: Any) -> float:
    if is_number(value) and value in (1, -1):
        return float(value)
    raise fail(f"expected 1 or -1, found {show(value)}")


Sign = Annotated[float, BeforeValidator(_sign)]


class StreamSpec(Spec):
    """What every stream has: its CSV file or ROS bag (relative to the description's folder; a bag with the
    ``topic`` to read, :mod:`uvms.logs.bag`) and its time column (a bag's: ``header.stamp`` or ``log_time``)."""

    file: Annotated[str, Field(min_length=1, max_length=4096)]
    topic: Annotated[str, Field(min_length=1, max_length=500)] | None = None   # a bag's topic (then columns are fields)
    time: Column | None = None                     # the time column [s, after time_scale]; a bag: header.stamp
    time_scale: Positive = 1.0                     # multiplies the time column to give seconds (1e-9 for ns)
    time_offset: Number = 0.0                      # added (after time_scale) to put the stream on the log clock [s]

    @model_validator(mode="after")
    def _time_of_a_csv(self):
        if self.topic is None and self.time is None:
            raise fail("expected the time column's name (time: ...); a bag stream gives topic: instead", "time")
        return self


class QuaternionColumns(Spec):
    """A quaternion given by four columns in one of the two orders (exactly one of the keys)."""

    quaternion_xyzw: Columns4 | None = None        # scalar last (ROS)
    quaternion_wxyz: Columns4 | None = None        # scalar first (uvms)

    def quaternion_columns(self) -> tuple[str, str, str, str] | None:
        """The columns in uvms's order ``(w, x, y, z)``, or ``None``."""
        if self.quaternion_wxyz is not None:
            return self.quaternion_wxyz
        if self.quaternion_xyzw is not None:
            x, y, z, w = self.quaternion_xyzw
            return (w, x, y, z)
        return None

    @model_validator(mode="after")
    def _one_order(self):
        if self.quaternion_xyzw is not None and self.quaternion_wxyz is not None:
            raise fail("give quaternion_xyzw or quaternion_wxyz, not both")
        return self


class PoseSpec(StreamSpec, QuaternionColumns):
    """The vehicle's pose in the world: position and body-to-world quaternion (motion capture, a navigation
    filter)."""

    position: Columns3 | None = None               # x, y, z [m, after scale]; a bag: its message type's fields
    scale: Positive = 1.0                          # multiplies the position columns to give metres (0.001 for mm)

    @model_validator(mode="after")
    def _has_quaternion(self):
        if self.topic is not None:                 # a bag: the message type's fields by default
            return self
        if self.position is None:
            raise fail("expected position: the 3 position columns (x, y, z)", "position")
        if self.quaternion_columns() is None:
            raise fail("expected quaternion_xyzw or quaternion_wxyz (the body-to-world attitude's 4 columns)")
        return self


class ImuSpec(StreamSpec, QuaternionColumns):
    """An IMU in body axes: its own attitude estimate, angular rates [rad/s], specific force [m/s^2]."""

    angular_velocity: Columns3 | None = None       # body rates p, q, r [rad/s]
    linear_acceleration: Columns3 | None = None    # accelerometer, body axes [m/s^2]

    @model_validator(mode="after")
    def _has_something(self):
        if self.topic is None and (self.quaternion_columns() is None and self.angular_velocity is None
                and self.linear_acceleration is None):
            raise fail("expected at least one of quaternion_xyzw, quaternion_wxyz, angular_velocity, "
                       "linear_acceleration")
        return self


class JointsSpec(StreamSpec):
    """Joint states: one angle column per model joint, optional rate columns, per-joint ``sign`` and ``offset``
    (``q_model = sign * q_log + offset``, ``qd_model = sign * qd_log``)."""

    columns: dict[Annotated[str, Field(min_length=1, max_length=200)], Column]
    rates: dict[Annotated[str, Field(min_length=1, max_length=200)], Column] = {}
    offset: dict[Annotated[str, Field(min_length=1, max_length=200)], Number] = {}
    sign: dict[Annotated[str, Field(min_length=1, max_length=200)], Sign] = {}

    @model_validator(mode="after")
    def _names_known(self):
        if not self.columns:
            raise fail("expected at least one joint: columns {joint name: column}", "columns")
        if len(self.columns) > 1000:
            raise fail(f"at most 1000 joints, found {len(self.columns)}", "columns")
        for key in ("rates", "offset", "sign"):
            for name in getattr(self, key):
                if name not in self.columns:
                    raise fail(f"joint {show(name)} has no angle column; joints in columns: "
                               f"{', '.join(self.columns)}", key)
        return self


class ThrustersSpec(StreamSpec):
    """Thruster commands, one column per thruster (the unit is the log's: a PWM, a voltage, a thrust)."""

    columns: dict[Annotated[str, Field(min_length=1, max_length=200)], Column]

    @model_validator(mode="after")
    def _some(self):
        if not self.columns or len(self.columns) > 1000:
            raise fail(f"expected 1 to 1000 thrusters {{name: column}}, found {len(self.columns)}", "columns")
        return self


class LogSpec(Spec):
    """A log description: the streams, the frame of their numbers, the replay's interval."""

    name: Annotated[str, Field(min_length=1, max_length=100)] | None = None
    frame: Literal["ned", "enu"]                   # the frame of the log's numbers (required: no guess)
    start: Number | None = None                    # log time where the replay starts [s]; default first common sample
    duration: Positive | None = None               # [s]; default to the end of the shortest stream
    pose: PoseSpec
    imu: ImuSpec | None = None
    joints: JointsSpec | None = None
    thrusters: ThrustersSpec | None = None

    def streams(self) -> dict[str, StreamSpec]:
        """The streams given, by key (``pose`` first)."""
        return {key: getattr(self, key) for key in STREAMS if getattr(self, key) is not None}


STREAMS = ("pose", "imu", "joints", "thrusters")
"""The stream keys, in the order the streams are read and reported."""
