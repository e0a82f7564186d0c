"""Measured feedback for the bundled controllers (``feedback: measured``): the run's sensors read in compiled
form at their own rates, and the baseline estimator that builds, from their readings alone, the state the
controller sees instead of the truth (``docs/sensors.md``, "Controllers fed measurements"; decisions in
``docs/conventions.md``).

The readings are the sensors' own models (:mod:`uvms.sensors`) evaluated on the state at the sample step, with
the errors each sensor draws for itself (:meth:`~uvms.sensors.Imu.errors`, ... drawn once for the whole run,
sample ``k`` taking row ``k``), so a compiled reading equals the numpy model's to rounding:

    gyro   = R_bs^T omega + e_k                                       (uvms.sensors.imu)
    bottom = R_bs^T (v + omega x r) + e_k, valid if the altitude is in range and not a dropout   (uvms.sensors.dvl)
    p      = round(p_atm + rho |g| depth(p + R r) + e_k), depth = (p - p_atm) / (rho |g|)        (uvms.sensors.pressure)
    q_enc  = round(q)                                                  (uvms.sensors.encoders)

The estimator, started from the true initial state (the pose a vehicle is launched from is known), at each
sample step ``t_k`` (a step where any of the sensors samples; ``dt = t_k - t_{k-1}``)::

    omega_hat = R_bs gyro                                  the latest gyro reading, in body axes
    v_hat     = R_bs bottom - omega_hat x r                the latest valid bottom-track reading (held across
                                                           dropouts and out-of-range samples)
    quat_hat <- quat_hat (x) exp(omega_bar dt / 2),        omega_bar = (omega_hat_{k-1} + omega_hat_k) / 2
    p_hat    <- p_hat + dt / 2 (R_hat_{k-1} v_hat_{k-1} + R_hat_k v_hat_k)     dead reckoning (trapezoid)
    z_hat     = surface + depth - (R_hat r)_z              at each pressure sample (z up: surface - depth - ...)
    q_hat     = q_enc,  qd_hat = (q_enc,k - q_enc,k-1) / (t_k - t_k-1)        at each encoder sample

Attitude and ``x, y`` are dead reckoned (no magnetometer or position fix is simulated): their error grows with
the gyro's and the DVL's errors; with ideal sensors it is the trapezoid's, second order in the sample period
(tested). Joint rates are the encoders' backward differences (the true initial ones before the second
sample). The controller reads only the pose, ``nu``, ``q`` and ``qd`` of the estimate (:attr:`SensingData.x_hat`,
the state vector's layout of :mod:`uvms.state`; its actuator entries stay at their initial values).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from uvms.jit import kernel
from uvms.kinematics import normalised_rotation
from uvms.state import JOINTS, NU, POSITION, QUATERNION

IMU, PRESSURE, DVL, ENCODERS = range(4)
"""Slots of :attr:`SensingData.every`."""


class SensingData(NamedTuple):
    """The compiled sensors of a measured-feedback controller and its estimator's memory (module docstring)."""

    active: bool
    h: float                    # [s] the integration step
    every: np.ndarray           # (4,) int64 steps between samples of the IMU, pressure, DVL, encoders
    started: np.ndarray         # (1,) int64: 1 once the first sample is taken
    gyro_rotation: np.ndarray   # (3, 3) R_bs of the IMU
    gyro_noisy: bool
    gyro_noise: np.ndarray      # (K, 3) [rad/s]
    pressure_offset: np.ndarray  # (3,) mount [m]
    pressure_values: np.ndarray  # (3,) rho |g| [Pa/m], p_atm [Pa], resolution [Pa]
    pressure_noisy: bool
    pressure_noise: np.ndarray  # (K,) [Pa]
    surface: float              # world z of the mean free surface [m]
    z_down: bool                # world z down (ned) or up (enu)
    dvl_offset: np.ndarray      # (3,) mount [m]
    dvl_rotation: np.ndarray    # (3, 3) R_bs of the DVL
    dvl_limits: np.ndarray      # (4,) water depth, min altitude, max altitude [m], dropout probability
    dvl_noisy: bool
    dvl_noise: np.ndarray       # (K, 3) [m/s]
    dvl_dropping: bool
    dvl_draws: np.ndarray       # (K,) uniform draws of the dropouts
    encoder_index: np.ndarray   # (n,) int64 index into q of the joint read as joint j (the identity today)
    encoder_resolution: np.ndarray  # (n,) [rad or m]
    x_hat: np.ndarray           # (N,) the estimated state (what the controller reads)
    omega: np.ndarray           # (3,) omega_hat now
    v: np.ndarray               # (3,) v_hat now
    omega_prev: np.ndarray      # (3,) at the previous sample step
    v_prev: np.ndarray          # (3,)
    times: np.ndarray           # (2,) the previous sample step's time and the previous encoder sample's [s]
    q_prev: np.ndarray          # (n,) the previous encoder readings
    R: np.ndarray               # (3, 3) scratch
    R_prev: np.ndarray          # (3, 3) scratch
    reading: np.ndarray         # (3,) scratch


def no_sensing(n_state: int = 13) -> SensingData:
    """The placeholder of a run whose controller reads the true state (never sampled)."""
    z3, e3 = np.zeros(3), np.eye(3)
    return SensingData(active=False, h=1.0, every=np.zeros(4, dtype=np.int64), started=np.zeros(1, dtype=np.int64),
                       gyro_rotation=e3.copy(), gyro_noisy=False, gyro_noise=np.zeros((1, 3)),
                       pressure_offset=z3.copy(), pressure_values=np.array([1.0, 0.0, 0.0]), pressure_noisy=False,
                       pressure_noise=np.zeros(1), surface=0.0, z_down=True, dvl_offset=z3.copy(),
                       dvl_rotation=e3.copy(), dvl_limits=np.array([np.inf, 0.0, np.inf, 0.0]), dvl_noisy=False,
                       dvl_noise=np.zeros((1, 3)), dvl_dropping=False, dvl_draws=np.zeros(1),
                       encoder_index=np.zeros(0, dtype=np.int64), encoder_resolution=np.zeros(0),
                       x_hat=np.zeros(n_state), omega=z3.copy(), v=z3.copy(), omega_prev=z3.copy(),
                       v_prev=z3.copy(), times=np.zeros(2), q_prev=np.zeros(0), R=np.zeros((3, 3)),
                       R_prev=np.zeros((3, 3)), reading=z3.copy())


def sensing_data(sensors, model, x0: np.ndarray, *, h: float, n_total: int, surface: float = 0.0,
                 path: str = "controller.parameters.feedback") -> SensingData:
    """The :class:`SensingData` of a run's ``sensors`` (a tuple of :mod:`uvms.sensors` objects) on the plant
    ``model`` (its joints, gravity and world convention): the first IMU, pressure sensor and DVL, and encoders
    covering every joint (an arm's), each required; their errors for the ``n_total`` steps of ``h`` seconds; the
    estimate starting at the initial state vector ``x0``; ``surface`` the world z of the mean free surface."""
    from uvms.errors import UvmsInputError

    n_joints, gravity, convention = model.n_joints, model.gravity, model.convention
    first = {}
    for s in sensors:
        first.setdefault(s.kind, s)
    needed = ["imu", "pressure", "dvl"] + (["encoders"] if n_joints else [])
    missing = [k for k in needed if k not in first]
    if missing:
        raise UvmsInputError(f"expected the run's sensors to include {', '.join(missing)} for measured feedback "
                             f"(declare them in the scenario's sensors: section), found "
                             f"{', '.join(s.kind for s in sensors) or 'none'}", path=path)
    index = np.zeros(n_joints, dtype=np.int64)
    resolution = np.zeros(n_joints)
    if n_joints:
        enc = first["encoders"]
        covered = dict(zip(enc.indices, enc.resolutions))
        if set(covered) != set(range(n_joints)):
            raise UvmsInputError(f"expected the encoders {enc.name!r} to read every joint for measured feedback, "
                                 f"found {len(covered)} of {n_joints}", path=path)
        index = np.arange(n_joints, dtype=np.int64)
        resolution = np.array([covered[j] for j in range(n_joints)], dtype=float)
    every = np.zeros(4, dtype=np.int64)
    for slot, kind in enumerate(("imu", "pressure", "dvl", "encoders")):
        if kind in first:
            every[slot] = max(1, int(round(1.0 / (first[kind].rate * h))))
    counts = [int(n_total) // int(k) + 1 if k > 0 else 0 for k in every]
    from uvms.checks import MAX_RECORDED_VALUES

    if 3 * sum(counts) > MAX_RECORDED_VALUES:        # the errors are drawn before the run: bound them
        raise UvmsInputError(f"expected at most {MAX_RECORDED_VALUES // 3:.3g} sensor samples for measured feedback "
                             f"(their errors are drawn before the run), found {sum(counts):.3g}: a shorter run or "
                             f"slower sensors", path="duration")
    imu, pressure, dvl = first["imu"], first["pressure"], first["dvl"]
    gyro = imu.errors(counts[IMU]).get("gyro") if not imu.gyro.is_zero else None
    p_noise = pressure.errors(counts[PRESSURE]).get("pressure")
    dvl_errors = dvl.errors(counts[DVL])
    g = float(np.linalg.norm(np.asarray(gravity, dtype=float)))
    x0 = np.asarray(x0, dtype=float)
    sensing = no_sensing(x0.size)._replace(
        active=True, h=float(h), every=every,
        gyro_rotation=np.ascontiguousarray(imu.mount.rotation, dtype=float), gyro_noisy=gyro is not None,
        gyro_noise=np.ascontiguousarray(gyro) if gyro is not None else np.zeros((1, 3)),
        pressure_offset=np.ascontiguousarray(pressure.mount.offset, dtype=float),
        pressure_values=np.array([pressure.density * g, pressure.atmosphere, pressure.resolution], dtype=float),
        pressure_noisy=p_noise is not None, pressure_noise=p_noise if p_noise is not None else np.zeros(1),
        surface=float(surface), z_down=convention == "ned",
        dvl_offset=np.ascontiguousarray(dvl.mount.offset, dtype=float),
        dvl_rotation=np.ascontiguousarray(dvl.mount.rotation, dtype=float),
        dvl_limits=np.array([dvl.water_depth, dvl.min_altitude, dvl.max_altitude, dvl.dropout], dtype=float),
        dvl_noisy="bottom" in dvl_errors, dvl_noise=dvl_errors.get("bottom", np.zeros((1, 3))),
        dvl_dropping="dropout" in dvl_errors, dvl_draws=dvl_errors.get("dropout", np.zeros(1)),
        encoder_index=index, encoder_resolution=resolution, x_hat=x0.copy(), q_prev=np.zeros(n_joints))
    return sensing


@kernel
def _quantised(value, resolution):
    """``value`` rounded to a multiple of ``resolution`` (0: unchanged; :func:`uvms.sensors.base.quantised`)."""
    return value if resolution == 0.0 else np.rint(value / resolution) * resolution


@kernel
def _mount_depth(s, x, offset):
    """The depth below the mean surface [m] of the world point ``p + R r`` (``s.R``: the true ``R``)."""
    z = x[POSITION + 2] + s.R[2, 0] * offset[0] + s.R[2, 1] * offset[1] + s.R[2, 2] * offset[2]
    return z - s.surface if s.z_down else s.surface - z


@kernel
def _rotate_quaternion(qv, w0, w1, w2, dt):
    """``qv <- qv (x) exp([w] dt / 2)``: the exact rotation by a constant body rate ``w`` over ``dt``, then
    renormalised."""
    rate = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    half = 0.5 * rate * dt
    c = math.cos(half)
    k = math.sin(half) / rate if rate > 0.0 else 0.5 * dt
    dw, dx, dy, dz = c, k * w0, k * w1, k * w2
    aw, ax, ay, az = qv[0], qv[1], qv[2], qv[3]
    qw = aw * dw - ax * dx - ay * dy - az * dz
    qx = aw * dx + ax * dw + ay * dz - az * dy
    qy = aw * dy - ax * dz + ay * dw + az * dx
    qz = aw * dz + ax * dy - ay * dx + az * dw
    norm = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    qv[0] = qw / norm
    qv[1] = qx / norm
    qv[2] = qy / norm
    qv[3] = qz / norm


@kernel
def sample_due(s, done):
    """Whether any sensor of ``s`` samples at step ``done``."""
    if not s.active:
        return False
    for slot in range(4):
        if s.every[slot] > 0 and done % s.every[slot] == 0:
            return True
    return False


@kernel
def next_sample(s, done, nxt):
    """``min(nxt, the first sample step after done)``."""
    if s.active:
        for slot in range(4):
            k = s.every[slot]
            if k > 0:
                nxt = min(nxt, (done // k + 1) * k)
    return nxt


@kernel
def sense(s, x, done):
    """The samples at step ``done`` of the true state ``x`` and the estimator's update (module docstring) into
    ``s.x_hat``. Call before the step's arm and controller updates; a step where no sensor samples is a no-op.
    Raises past the end of the errors drawn for the run (:func:`sensing_data`'s ``n_total`` steps)."""
    if not sample_due(s, done):
        return
    every = s.every
    if ((s.gyro_noisy and done // max(every[IMU], 1) >= s.gyro_noise.shape[0])
            or (s.pressure_noisy and done // max(every[PRESSURE], 1) >= s.pressure_noise.shape[0])
            or (s.dvl_noisy and done // max(every[DVL], 1) >= s.dvl_noise.shape[0])
            or (s.dvl_dropping and done // max(every[DVL], 1) >= s.dvl_draws.shape[0])):
        raise ValueError("the sensors' pre-drawn errors are exhausted (the run is longer than its sensing was "
                         "built for)")
    t = done * s.h
    first = s.started[0] == 0
    n = s.encoder_index.shape[0]
    if first:
        for i in range(x.shape[0]):
            s.x_hat[i] = x[i]
        for j in range(3):
            s.omega[j] = x[NU + j]
            s.v[j] = x[NU + 3 + j]
    normalised_rotation(x[QUATERNION:NU], s.R)                   # the true R: where the mounts are
    if every[IMU] > 0 and done % every[IMU] == 0:
        k = done // every[IMU]
        B = s.gyro_rotation
        for i in range(3):
            g = B[0, i] * x[NU] + B[1, i] * x[NU + 1] + B[2, i] * x[NU + 2]
            if s.gyro_noisy:
                g += s.gyro_noise[k, i]
            s.reading[i] = g
        for i in range(3):
            s.omega[i] = B[i, 0] * s.reading[0] + B[i, 1] * s.reading[1] + B[i, 2] * s.reading[2]
    if every[DVL] > 0 and done % every[DVL] == 0:
        k = done // every[DVL]
        r, B, lim = s.dvl_offset, s.dvl_rotation, s.dvl_limits
        altitude = lim[0] - _mount_depth(s, x, r)
        valid = altitude >= lim[1] and altitude <= lim[2]
        if s.dvl_dropping and s.dvl_draws[k] < lim[3]:
            valid = False
        if valid:
            w0, w1, w2 = x[NU], x[NU + 1], x[NU + 2]
            m0 = x[NU + 3] + w1 * r[2] - w2 * r[1]                 # v + omega x r
            m1 = x[NU + 4] + w2 * r[0] - w0 * r[2]
            m2 = x[NU + 5] + w0 * r[1] - w1 * r[0]
            for i in range(3):
                b = B[0, i] * m0 + B[1, i] * m1 + B[2, i] * m2
                if s.dvl_noisy:
                    b += s.dvl_noise[k, i]
                s.reading[i] = b
            o = s.omega
            for i in range(3):
                s.v[i] = B[i, 0] * s.reading[0] + B[i, 1] * s.reading[1] + B[i, 2] * s.reading[2]
            s.v[0] -= o[1] * r[2] - o[2] * r[1]
            s.v[1] -= o[2] * r[0] - o[0] * r[2]
            s.v[2] -= o[0] * r[1] - o[1] * r[0]
    qv = s.x_hat[QUATERNION:NU]
    if not first:
        dt = t - s.times[0]
        normalised_rotation(qv, s.R_prev)
        _rotate_quaternion(qv, 0.5 * (s.omega_prev[0] + s.omega[0]), 0.5 * (s.omega_prev[1] + s.omega[1]),
                           0.5 * (s.omega_prev[2] + s.omega[2]), dt)
        normalised_rotation(qv, s.R)                           # now R_hat (the true R is no longer needed)
        for i in range(3):
            step = 0.0
            for j in range(3):
                step += s.R_prev[i, j] * s.v_prev[j] + s.R[i, j] * s.v[j]
            s.x_hat[POSITION + i] += 0.5 * dt * step
    else:
        normalised_rotation(qv, s.R)
    for j in range(3):
        s.omega_prev[j] = s.omega[j]
        s.v_prev[j] = s.v[j]
    s.times[0] = t
    if every[PRESSURE] > 0 and done % every[PRESSURE] == 0:
        k = done // every[PRESSURE]
        r, values = s.pressure_offset, s.pressure_values
        normalised_rotation(x[QUATERNION:NU], s.R_prev)          # the true R, for the true depth
        z = x[POSITION + 2] + s.R_prev[2, 0] * r[0] + s.R_prev[2, 1] * r[1] + s.R_prev[2, 2] * r[2]
        depth = z - s.surface if s.z_down else s.surface - z
        p = values[1] + values[0] * depth
        if s.pressure_noisy:
            p += s.pressure_noise[k]
        p = _quantised(p, values[2])
        measured = (p - values[1]) / values[0]
        lever = s.R[2, 0] * r[0] + s.R[2, 1] * r[1] + s.R[2, 2] * r[2]   # (R_hat r)_z
        s.x_hat[POSITION + 2] = (s.surface + measured if s.z_down else s.surface - measured) - lever
    if n > 0 and every[ENCODERS] > 0 and done % every[ENCODERS] == 0:
        for j in range(n):
            q = _quantised(x[JOINTS + s.encoder_index[j]], s.encoder_resolution[j])
            s.x_hat[JOINTS + j] = q
            if s.times[1] < t and not first:
                s.x_hat[JOINTS + n + j] = (q - s.q_prev[j]) / (t - s.times[1])
            s.q_prev[j] = q
        s.times[1] = t
    for j in range(3):
        s.x_hat[NU + j] = s.omega[j]
        s.x_hat[NU + 3 + j] = s.v[j]
    s.started[0] = 1
