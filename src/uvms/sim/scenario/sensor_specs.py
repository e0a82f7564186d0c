"""The scenario file's ``sensors:`` section (``docs/sensors.md``): one entry per sensor, by name, each with its
``kind`` (``imu``, ``pressure``, ``dvl``, ``encoders``), ``rate`` [Hz], ``mount`` on the vehicle and its
parameters; built into :mod:`uvms.sensors` objects for :class:`uvms.sim.options.Recording`."""

from __future__ import annotations

import math
from typing import Annotated, Literal, Union

from pydantic import BeforeValidator, Discriminator, Field, Strict, Tag, model_validator

from uvms.errors import UvmsInputError, show
from uvms.schema_base import ZERO3, NonNegative, Positive, Spec, Vec3, fail, finite_number, numbers
from uvms.sensors.noise import DEFAULT_BAND

Seed = Annotated[int, Strict(), Field(ge=0)]


class MountSpec(Spec):
    """Where a sensor sits: ``body`` (default: the vehicle), ``offset`` in body axes [m], ``rpy`` of the
    sensor's axes in the body's (ZYX roll, pitch, yaw) [rad]."""

    body: Annotated[str, Field(min_length=1)] | None = None
    offset: Vec3 = ZERO3
    rpy: Vec3 = ZERO3


class NoiseSpec(Spec):
    """Datasheet (Allan) parameters of one inertial sensor, SI (``uvms.sensors.noise``)."""

    white: NonNegative = 0.0                      # N [unit/sqrt(Hz)]: angle / velocity random walk
    bias_instability: NonNegative = 0.0           # B [unit]; the Allan floor is 0.664 B
    band: Annotated[tuple[float, float], numbers(2, minimum=0.0)] = DEFAULT_BAND   # its correlation times [s]
    random_walk: NonNegative = 0.0                # K [unit/s/sqrt(Hz)]: bias (rate) random walk
    bias: Annotated[float, BeforeValidator(finite_number)] = 0.0   # constant bias [unit]

    @model_validator(mode="after")
    def _band(self) -> "NoiseSpec":
        if not 0 < self.band[0] <= self.band[1]:
            raise fail(f"expected 0 < T_lo <= T_hi [s], found {list(self.band)}", "band")
        return self


class _Sensor(Spec):
    rate: Positive                                # samples per second [Hz]
    mount: MountSpec = MountSpec()
    seed: Seed = 0


class ImuSpec(_Sensor):
    kind: Literal["imu"]
    gyro: NoiseSpec = NoiseSpec()                 # [rad/s] family
    accel: NoiseSpec = NoiseSpec()                # [m/s^2] family


class PressureSpec(_Sensor):
    kind: Literal["pressure"]
    noise: NonNegative = 0.0                      # standard deviation [Pa]
    resolution: NonNegative = 0.0                 # [Pa]; 0: none
    atmosphere: NonNegative = 101_325.0           # p_atm [Pa]


class DvlSpec(_Sensor):
    kind: Literal["dvl"]
    noise: NonNegative = 0.0                      # standard deviation per axis [m/s]
    water_depth: Positive | None = None           # flat bottom below the mean surface [m]; None: no bottom
    min_altitude: NonNegative = 0.0               # [m]
    max_altitude: Positive | None = None          # [m]; None: unlimited
    dropout: Annotated[float, BeforeValidator(finite_number), Field(ge=0, lt=1)] = 0.0   # probability [-]

    @model_validator(mode="after")
    def _altitudes(self) -> "DvlSpec":
        if self.max_altitude is not None and self.max_altitude < self.min_altitude:
            raise fail(f"expected max_altitude >= min_altitude ({self.min_altitude:g} m), found "
                       f"{self.max_altitude:g}", "max_altitude")
        return self


class EncodersSpec(_Sensor):
    kind: Literal["encoders"]
    joints: tuple[Annotated[str, Field(min_length=1)], ...] | None = None   # default: every joint
    counts_per_turn: Annotated[int, Strict(), Field(ge=1)] | None = None   # revolute joints; None: exact
    resolution: Positive | None = None            # prismatic joints [m]; None: exact


KIND_TAGS = ("kind=imu", "kind=pressure", "kind=dvl", "kind=encoders")
"""Tags of the sensor union (left out of error paths: no sensor name contains ``=``)."""


def _kind(value) -> str | None:
    kind = value.get("kind") if isinstance(value, dict) else getattr(value, "kind", None)
    return f"kind={kind}" if f"kind={kind}" in KIND_TAGS else None


def _known_kind(value):
    if isinstance(value, dict) and _kind(value) is None:
        raise fail(f"expected a kind of {', '.join(repr(t[5:]) for t in KIND_TAGS)}, found {show(value.get('kind'))}",
                   "kind")
    return value


SensorSpec = Annotated[Union[Annotated[ImuSpec, Tag("kind=imu")], Annotated[PressureSpec, Tag("kind=pressure")],
                             Annotated[DvlSpec, Tag("kind=dvl")], Annotated[EncodersSpec, Tag("kind=encoders")]],
                       Discriminator(_kind), BeforeValidator(_known_kind)]
SensorsSpec = dict[Annotated[str, Field(pattern=r"^[A-Za-z][A-Za-z0-9_]*$")], SensorSpec]
"""``sensors:`` name -> sensor (a name is a ROS-friendly word: it becomes the frame id and the topic)."""


def build_sensors(sensors: dict, model, source: str | None = None) -> tuple:
    """The :mod:`uvms.sensors` objects of a validated ``sensors:`` section on ``model`` (density, joints,
    bodies), in the file's order.

    Raises:
        UvmsInputError: a mount on an unknown body or on a link, an unknown joint (one line, file and field).
    """
    from uvms.sensors import Dvl, Encoders, Imu, Mount, NoiseDensity, PressureSensor

    out = []
    for name, spec in sensors.items():
        where = f"sensors.{name}"
        body = spec.mount.body
        if body is not None and body != model.body_names[0]:
            what = "a link (only the vehicle carries simulated sensors)" if body in model.body_names else \
                f"no body of model {model.name!r} (bodies: {', '.join(model.body_names)})"
            raise UvmsInputError(f"expected the vehicle body {model.body_names[0]!r}, found {show(body)}: {what}",
                                 source, f"{where}.mount.body")
        mount = Mount.of(spec.mount.offset, spec.mount.rpy)
        common = dict(name=name, rate=float(spec.rate))
        if spec.kind == "imu":
            noise = {k: NoiseDensity(**getattr(spec, k).model_dump()) for k in ("gyro", "accel")}
            out.append(Imu(**common, mount=mount, seed=spec.seed, **noise))
        elif spec.kind == "pressure":
            out.append(PressureSensor(**common, mount=mount, density=float(model.density), noise=spec.noise,
                                      resolution=spec.resolution, atmosphere=spec.atmosphere, seed=spec.seed))
        elif spec.kind == "dvl":
            out.append(Dvl(**common, mount=mount, noise=spec.noise, seed=spec.seed, dropout=spec.dropout,
                           water_depth=math.inf if spec.water_depth is None else spec.water_depth,
                           min_altitude=spec.min_altitude,
                           max_altitude=math.inf if spec.max_altitude is None else spec.max_altitude))
        else:
            joints = spec.joints if spec.joints is not None else tuple(model.joint_names)
            for k, joint in enumerate(joints):
                if joint not in model.joint_names:
                    raise UvmsInputError(f"model {model.name!r} has no joint {show(joint)}; joints: "
                                         f"{', '.join(model.joint_names)}", source, f"{where}.joints[{k}]")
            index = tuple(model.joint_names.index(j) for j in joints)
            kinds = [model.joint_type[i] for i in index]
            res = tuple((2 * math.pi / spec.counts_per_turn if spec.counts_per_turn else 0.0) if kind != "prismatic"
                        else (spec.resolution or 0.0) for kind in kinds)
            out.append(Encoders(**common, joints=tuple(joints), indices=index, resolutions=res))
    return tuple(out)
