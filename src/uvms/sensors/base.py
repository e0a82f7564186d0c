"""What every sensor shares: where it sits (:class:`Mount`), the true quantities it measures (:class:`Truth`),
what it returns (:class:`SensorRecord`), and its seeded noise streams (:func:`stream`).

A sensor model is a function of true quantities only: the simulator (:mod:`uvms.sim.sensing`) evaluates the
truth at the sensor's sample times and hands it in, so the models sit on the physics floor and a controller
(or a user's script, from any state history) can call them too.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from uvms.rotations import rotation_from_euler


@dataclass(frozen=True)
class Mount:
    """A sensor's place on the vehicle body.

    Attributes:
        offset: (3,) the sensor's origin in body axes, from the body's origin [m] (the lever arm ``r``).
        rotation: (3, 3) sensor axes to body axes, ``R_bs`` (from ``rpy`` = ZYX roll, pitch, yaw [rad]).
    """

    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rotation: np.ndarray = field(default_factory=lambda: np.eye(3))

    @classmethod
    def of(cls, offset=(0.0, 0.0, 0.0), rpy=(0.0, 0.0, 0.0)) -> "Mount":
        return cls(np.asarray(offset, dtype=float).reshape(3).copy(), rotation_from_euler(np.asarray(rpy, float)))


class Truth(NamedTuple):
    """True quantities at a sensor's K sample times (world frame of ``convention``; body axes of the vehicle).

    ``nu = [omega; v]`` and ``nu_dot`` its time derivative in body axes (the dynamics' ``nu_dot``, so the
    inertial acceleration of the body origin in body axes is ``v_dot + omega x v``)."""

    time: np.ndarray            # (K,) [s]
    position: np.ndarray        # (K, 3) body origin, world [m]
    rotation: np.ndarray        # (K, 3, 3) body to world
    nu: np.ndarray              # (K, 6) [rad/s, m/s]
    nu_dot: np.ndarray          # (K, 6) [rad/s^2, m/s^2]
    q: np.ndarray               # (K, n) joint positions [rad or m]
    gravity: np.ndarray         # (3,) world [m/s^2]
    convention: str = "ned"     # "ned" (world z down) or "enu" (z up)
    surface: float = 0.0        # world z of the mean free surface [m]


@dataclass(frozen=True)
class SensorRecord:
    """A sensor's samples: ``columns[name]`` (K,) at ``time`` (K,), in the sensor's frame ``frame_id``."""

    name: str
    kind: str
    frame_id: str
    time: np.ndarray
    columns: dict[str, np.ndarray]

    def __getitem__(self, column: str) -> np.ndarray:
        return self.columns[column]


@dataclass(frozen=True)
class Reading:
    """One sample of one sensor, as a controller receives it (:attr:`uvms.control.base.Measurement.sensors`):
    ``values[channel]`` (a float) taken at ``time`` [s], in the sensor's frame ``frame_id``. The channels and
    their units are the sensor's :class:`SensorRecord` columns (``docs/sensors.md``): ``gyro_*`` [rad/s],
    ``accel_*`` [m/s^2], ``pressure`` [Pa], ``depth`` [m], ``bottom_*``, ``water_*`` [m/s], ``bottom_valid``
    (1 or 0), ``altitude`` [m], an encoder's joint [rad or m]."""

    name: str
    kind: str
    frame_id: str
    time: float
    values: dict[str, float]

    def __getitem__(self, channel: str) -> float:
        return self.values[channel]

    @classmethod
    def of(cls, record: "SensorRecord", row: int = 0) -> "Reading":
        """Row ``row`` of a :class:`SensorRecord`."""
        return cls(record.name, record.kind, record.frame_id, float(record.time[row]),
                   {k: float(c[row]) for k, c in record.columns.items()})


def stream(seed: int, *key: int) -> np.random.Generator:
    """The noise generator of one noise part of one sensor: ``numpy.random.default_rng([seed, *key])``. Each
    part (a gyro's white noise, its bias...) draws from its own stream, so the first K samples of a part are
    the same whatever the record's length and whichever other parts are switched on."""
    return np.random.default_rng([int(seed), *(int(k) for k in key)])


def mount_point(truth: Truth, mount: Mount) -> np.ndarray:
    """(K, 3) the mount's world position ``p + R r``."""
    return truth.position + np.einsum("kij,j->ki", truth.rotation, mount.offset)


def rotate_rows(R: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """(K, 3) ``R v_k`` for each row ``v_k`` of ``vectors`` (K, 3), i.e. ``vectors @ R.T``, as three elementwise
    products and two sums per element: the same rounding for every row whatever ``K``. A BLAS product's
    rounding depends on the matrix sizes and the CPU (its kernels, FMA or not), and a live sample of one row
    must equal the after-run table's row bit for bit (``tests/sim/test_live_sensors.py``; seen to differ by an
    ulp on an AVX2 machine with ``@``)."""
    return vectors[:, 0:1] * R[:, 0] + vectors[:, 1:2] * R[:, 1] + vectors[:, 2:3] * R[:, 2]


def depth_of(truth: Truth, points: np.ndarray) -> np.ndarray:
    """(K,) depth below the mean free surface [m] of world points (K, 3): ``z - surface`` in ``ned``,
    ``surface - z`` in ``enu``."""
    z = points[:, 2]
    return z - truth.surface if truth.convention == "ned" else truth.surface - z


def quantised(value: np.ndarray, resolution: float) -> np.ndarray:
    """``value`` rounded to the nearest multiple of ``resolution`` (0: unchanged)."""
    return value if resolution == 0 else np.round(value / resolution) * resolution
