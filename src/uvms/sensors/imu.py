"""An inertial measurement unit on the vehicle: a three-axis gyro and a three-axis accelerometer.

At a mount ``r`` (body axes) with sensor axes ``R_bs`` (sensor to body), from the true ``nu = [omega; v]``,
``nu_dot`` and body-to-world rotation ``R`` (Titterton and Weston, *Strapdown Inertial Navigation Technology*,
2nd ed., 2004, sec. 3.2 and eq. 3.8; the accelerometer measures the specific force, gravity included)::

    gyro   = R_bs^T omega                                                      + e_gyro    [rad/s]
    accel  = R_bs^T (v_dot + omega x v + omega_dot x r + omega x (omega x r) - R^T g) + e_accel   [m/s^2]

``v_dot + omega x v`` is the inertial acceleration of the body origin in body axes, the other two terms carry
it to the mount (the lever arm); ``g`` is the model's gravity in world axes, so a vehicle at rest in a z-down
world reads ``-g`` along its z axis. The errors ``e`` are the datasheet noise of :mod:`uvms.sensors.noise`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from uvms.sensors.base import Mount, SensorRecord, Truth, rotate_rows
from uvms.sensors.noise import NoiseDensity, axis_noise

GYRO_COLUMNS = ("gyro_x", "gyro_y", "gyro_z")
ACCEL_COLUMNS = ("accel_x", "accel_y", "accel_z")


@dataclass(frozen=True)
class Imu:
    """An IMU's parameters: ``rate`` [Hz], ``mount``, the gyro's and the accelerometer's noise, ``seed``."""

    name: str = "imu"
    rate: float = 100.0
    mount: Mount = field(default_factory=Mount)
    gyro: NoiseDensity = NoiseDensity()
    accel: NoiseDensity = NoiseDensity()
    seed: int = 0
    kind = "imu"

    def true_values(self, truth: Truth) -> tuple[np.ndarray, np.ndarray]:
        """``(gyro, accel)`` (K, 3) without noise (module docstring), in sensor axes."""
        omega, v = truth.nu[:, :3], truth.nu[:, 3:]
        omega_dot, v_dot = truth.nu_dot[:, :3], truth.nu_dot[:, 3:]
        r = np.broadcast_to(self.mount.offset, omega.shape)
        gravity_body = np.einsum("kji,j->ki", truth.rotation, truth.gravity)     # R^T g
        a = v_dot + np.cross(omega, v) + np.cross(omega_dot, r) + np.cross(omega, np.cross(omega, r))
        to_sensor = self.mount.rotation.T
        return rotate_rows(to_sensor, omega), rotate_rows(to_sensor, a - gravity_body)

    def errors(self, n_samples: int) -> dict[str, np.ndarray]:
        """The seeded errors of the first ``n_samples`` samples: ``gyro``, ``accel`` (K, 3) (a part left out
        when its noise is zero). Sample ``k``'s errors are the same whatever ``n_samples`` (> k)."""
        dt, K = 1.0 / self.rate, int(n_samples)
        out = {}
        if not self.gyro.is_zero:
            out["gyro"] = axis_noise(self.gyro, dt, K, 3, self.seed, 0)
        if not self.accel.is_zero:
            out["accel"] = axis_noise(self.accel, dt, K, 3, self.seed, 1)
        return out

    def reading(self, truth: Truth, errors: dict[str, np.ndarray]) -> SensorRecord:
        """The samples at ``truth.time``: true values plus ``errors`` (rows of :meth:`errors`, one per sample)."""
        gyro, accel = self.true_values(truth)
        if "gyro" in errors:
            gyro = gyro + errors["gyro"]
        if "accel" in errors:
            accel = accel + errors["accel"]
        columns = {**dict(zip(GYRO_COLUMNS, gyro.T)), **dict(zip(ACCEL_COLUMNS, accel.T))}
        return SensorRecord(self.name, self.kind, self.name, truth.time, {k: np.ascontiguousarray(c)
                                                                          for k, c in columns.items()})

    def measure(self, truth: Truth) -> SensorRecord:
        """The samples at ``truth.time`` (taken every ``1 / rate``): true values plus seeded noise."""
        return self.reading(truth, self.errors(truth.time.shape[0]))
