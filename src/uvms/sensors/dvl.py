"""A Doppler velocity log on the vehicle: bottom track and water track, in its own axes.

At a mount ``r`` with axes ``R_bs`` (sensor to body), from the true ``nu = [omega; v]``, the body-to-world
rotation ``R`` and the water's velocity ``u_f`` at the mount's world point (:func:`uvms.hydro.flow.fluid_at`,
the same water the dynamics see: current table, depth profile, field, waves)::

    bottom = R_bs^T (v + omega x r)                        + e_b     velocity over the ground   [m/s]
    water  = R_bs^T (v + omega x r - R^T u_f(p + R r, t))  + e_w     velocity through the water [m/s]

(Brokloff, "Matrix algorithm for Doppler sonar navigation", OCEANS 1994; the lever arm as in Kinsey, Eustice
and Whitcomb, "A survey of underwater vehicle navigation", IFAC MCMC 2006, sec. 3.2). The bottom is flat, at
``water_depth`` below the mean surface; bottom track is valid when the mount's altitude
``water_depth - depth`` lies in ``[min_altitude, max_altitude]`` and the sample is not a dropout (each sample
independently with probability ``dropout``, seeded); an invalid sample reads NaN and ``bottom_valid`` 0.
``e`` white noise of standard deviation ``noise`` [m/s] per axis.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from uvms.sensors.base import Mount, SensorRecord, Truth, depth_of, mount_point, rotate_rows, stream

BOTTOM_COLUMNS = ("bottom_x", "bottom_y", "bottom_z")
WATER_COLUMNS = ("water_x", "water_y", "water_z")


def water_velocity(flow, times: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(K, 3) the water's velocity (world) at ``points[k]`` and ``times[k]`` (``flow``: a compiled
    :class:`uvms.hydro.flow.FlowData`, or ``None`` for still water)."""
    if flow is None:
        return np.zeros_like(points)
    from uvms.hydro.flow import fluid_at_points

    u, a, grad = np.zeros((1, 3)), np.zeros((1, 3)), np.zeros((1, 3, 3))
    out = np.empty_like(points)
    for k in range(points.shape[0]):
        fluid_at_points(flow, float(times[k]), np.ascontiguousarray(points[k:k + 1]), u, a, grad)
        out[k] = u[0]
    return out


@dataclass(frozen=True)
class Dvl:
    """``rate`` [Hz], ``mount``, ``noise`` [m/s], ``water_depth`` [m] (``inf``: no bottom in reach unless
    ``max_altitude`` is ``inf`` too), ``min_altitude``, ``max_altitude`` [m], ``dropout`` [-], ``seed``."""

    name: str = "dvl"
    rate: float = 5.0
    mount: Mount = field(default_factory=Mount)
    noise: float = 0.0
    water_depth: float = float("inf")
    min_altitude: float = 0.0
    max_altitude: float = float("inf")
    dropout: float = 0.0
    seed: int = 0
    kind = "dvl"

    def true_values(self, truth: Truth, flow=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(bottom, water, altitude)``: (K, 3), (K, 3) without noise and the mount's altitude (K,)."""
        omega, v = truth.nu[:, :3], truth.nu[:, 3:]
        v_mount = v + np.cross(omega, np.broadcast_to(self.mount.offset, omega.shape))
        points = mount_point(truth, self.mount)
        u_body = np.einsum("kji,kj->ki", truth.rotation, water_velocity(flow, truth.time, points))   # R^T u_f
        to_sensor = self.mount.rotation.T
        altitude = self.water_depth - depth_of(truth, points)
        return rotate_rows(to_sensor, v_mount), rotate_rows(to_sensor, v_mount - u_body), altitude

    def errors(self, n_samples: int) -> dict[str, np.ndarray]:
        """The seeded draws of the first ``n_samples`` samples: noise ``bottom``, ``water`` (K, 3) [m/s] and the
        dropout draws ``dropout`` (K,) uniform in [0, 1) (each part left out when switched off)."""
        K = int(n_samples)
        out = {}
        if self.noise > 0:
            out["bottom"] = stream(self.seed, 0).standard_normal((K, 3)) * self.noise
            out["water"] = stream(self.seed, 1).standard_normal((K, 3)) * self.noise
        if self.dropout > 0:
            out["dropout"] = stream(self.seed, 2).random(K)
        return out

    def reading(self, truth: Truth, errors: dict[str, np.ndarray], flow=None) -> SensorRecord:
        """The samples at ``truth.time`` with ``errors`` (rows of :meth:`errors`, one per sample)."""
        bottom, water, altitude = self.true_values(truth, flow)
        if "bottom" in errors:
            bottom = bottom + errors["bottom"]
            water = water + errors["water"]
        valid = (altitude >= self.min_altitude) & (altitude <= self.max_altitude)
        if "dropout" in errors:
            valid &= errors["dropout"] >= self.dropout
        bottom = np.where(valid[:, None], bottom, np.nan)
        columns = {**dict(zip(BOTTOM_COLUMNS, bottom.T)), "bottom_valid": valid.astype(float),
                   "altitude": altitude, **dict(zip(WATER_COLUMNS, water.T))}
        return SensorRecord(self.name, self.kind, self.name, truth.time,
                            {k: np.ascontiguousarray(c) for k, c in columns.items()})

    def measure(self, truth: Truth, flow=None) -> SensorRecord:
        return self.reading(truth, self.errors(truth.time.shape[0]), flow)
