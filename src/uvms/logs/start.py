"""The state a replay starts from: a log's pose, velocities and joints at its start time (``docs/logs.md``,
"The start state").

- Position: the pose stream linearly interpolated at ``start``; attitude: Slerp between the two rows around it.
- Linear velocity: the derivative at ``start`` of the least-squares polynomial of degree ``degree`` (default 2)
  through the position rows within ``start +/- window / 2`` (default 0.2 s: 20 rows of 100 Hz motion capture),
  a world vector, turned into body axes by ``R(start)^T``.
- Angular velocity (``omega_from="pose"``, the default): the same fit of the rotation vectors
  ``r_k = log(R(start)^T R_k)`` of the rows in the window, differentiated at ``start``. At ``start`` the
  rotation vector is zero and the derivative of the log map there is the identity, so ``dr/dt(start)`` is the
  body angular velocity exactly (``omega = 2 vec(q* (x) q_dot)`` written without differentiating quaternion
  components); a constant body rate gives ``r_k = omega (t_k - start)``, which any degree fits exactly.
  ``omega_from="imu"`` takes the IMU's rates (linearly interpolated at ``start``, body axes) instead.
- Joints: angles interpolated at ``start`` (model convention, ``q = sign q_log + offset``); rates from the
  joint's rate column when described, else the same local fit of its angles. Model joints the log does not
  describe start at 0 rad and 0 rad/s.

Everything is computed in the log's frame and converted at the end to ``frame`` (default: the model's
convention, :attr:`uvms.model.Model.convention`) with :mod:`uvms.frames`.
"""

from __future__ import annotations

import numpy as np

from uvms import checks, frames
from uvms.errors import UvmsInputError, show
from uvms.logs import interpolate
from uvms.state import State

FIT_WINDOW = 0.2
"""[s] Width of the window of rows the velocities are fitted over, centred on the start (cut by the log's ends)."""

FIT_DEGREE = 2
"""Degree of the local least-squares polynomial."""

OMEGA_SOURCES = ("pose", "imu")
"""Where the start's angular velocity comes from."""


def local_fit(t: np.ndarray, y: np.ndarray, t0: float, window: float, degree: int,
              what: str, source: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Value and first derivative at ``t0`` of the least-squares polynomial of ``degree`` through the rows
    ``(t_k, y_k)`` with ``|t_k - t0| <= window / 2`` (``y`` (K, m)). A window holding fewer than ``degree + 1``
    rows (a stream that begins at the start, or a gap in it) is widened twice, to 2 and 4 times ``window``;
    then ``what`` (the stream) and ``source`` (the log) are named in the message."""
    for widen in (1.0, 2.0, 4.0):
        half = widen * window / 2.0
        near = np.abs(t - t0) <= half * (1.0 + 1e-12)
        if near.sum() >= degree + 1:
            break
    else:
        raise UvmsInputError(f"{what}: {near.sum()} rows within {half:g} s of the start, a degree-{degree} fit "
                             f"needs {degree + 1} (give a wider window)", source, "window")
    tau = (t[near] - t0) / half
    coefficients = np.linalg.lstsq(np.vander(tau, degree + 1, increasing=True), y[near], rcond=None)[0]
    return coefficients[0], coefficients[1] / half


def _model_joints(log, model) -> None:
    names = tuple(model.joint_names)
    for joint in log.joint_names:
        if joint not in names:
            raise UvmsInputError(f"model {model.name!r} has no joint {show(joint)}; its joints: "
                                 f"{', '.join(names) or '(none)'}", log.source, "joints.columns")


def initial_state(log, model, *, frame: str | None = None, window: float = FIT_WINDOW, degree: int = FIT_DEGREE,
                  omega_from: str = "pose") -> State:
    """The :class:`uvms.State` of ``model`` at ``log``'s replay start (see the module docstring), in ``frame``.

    Raises:
        UvmsInputError: a joint the model does not have (naming the log file and the model's joints), a window
            with too few rows, ``omega_from="imu"`` without IMU rates.
    """
    checks.model(model)
    target = frames.check_frame(frame if frame is not None else model.convention, "frame")
    window = checks.number(window, "window", positive=True, unit="s")
    degree = checks.count(degree, "degree", minimum=1)
    if omega_from not in OMEGA_SOURCES:
        raise UvmsInputError(f"expected one of {', '.join(OMEGA_SOURCES)}, found {show(omega_from)}",
                             path="omega_from")
    _model_joints(log, model)
    t0 = np.array([log.start])
    pose = log.streams["pose"]
    position = interpolate.values(pose.time, pose.parts["position"], t0)[0]
    quaternion = interpolate.slerp(pose.time, pose.parts["quaternion"], t0)[0]
    attitude = interpolate.rotations(quaternion)
    velocity_world = local_fit(pose.time, pose.parts["position"], log.start, window, degree, "pose", log.source)[1]
    velocity = attitude.inv().apply(velocity_world)[0]
    if omega_from == "imu":
        imu = log.streams.get("imu")
        if imu is None or "angular_velocity" not in imu.parts:
            raise UvmsInputError("omega_from='imu' needs an imu stream with angular_velocity columns", log.source,
                                 "imu.angular_velocity")
        omega = interpolate.values(imu.time, imu.parts["angular_velocity"], t0)[0]
    else:
        relative = (attitude.inv() * interpolate.rotations(pose.parts["quaternion"])).as_rotvec()
        omega = local_fit(pose.time, relative, log.start, window, degree, "pose", log.source)[1]
    q, qd = np.zeros(model.n_joints), np.zeros(model.n_joints)
    if "joints" in log.streams:
        joints = log.streams["joints"]
        angles = interpolate.values(joints.time, joints.parts["q"], t0)[0]
        fitted = [j for j in joints.names if j not in joints.rate_names]
        rates = local_fit(joints.time, joints.parts["q"], log.start, window, degree, "joints",
                           log.source)[1] if fitted else []
        logged = interpolate.values(joints.time, joints.parts["qd"], t0)[0] if joints.rate_names else []
        for k, joint in enumerate(joints.names):
            i = model.joint_names.index(joint)
            q[i] = angles[k]
            qd[i] = logged[joints.rate_names.index(joint)] if joint in joints.rate_names else rates[k]
    return State(position=frames.convert_vectors(position, log.frame, target),
                 quaternion=frames.convert_quaternions(quaternion, log.frame, target),
                 nu=frames.convert_twists(np.concatenate([omega, velocity]), log.frame, target), q=q, qd=qd)
