"""The two world/body frame conventions uvms supports, and the one map between them (``docs/conventions.md``,
"Frames").

- ``"ned"`` (the default, Fossen's marine convention): world z down (x north, y east), body x forward, y right,
  z down (FRD).
- ``"enu"`` (ROS REP 103): world z up (x east, y north), body x forward, y left, z up (FLU).

A pool, a motion-capture hall or a Gazebo world has no north, so uvms maps between the two by a **half turn about
x**, applied to the world and to every body frame alike: a point or vector ``(x, y, z)`` becomes ``(x, -y, -z)``
(ROS REP 103 names this map for FRD <-> FLU bodies; it is *not* the geographic NED <-> ENU swap
``(y, x, -z)``, which also exchanges north and east). The map is its own inverse. With ``H = diag(1, -1, -1)``:

- a world point ``p`` and a body vector ``v`` (rates, velocities, forces, moments, in body axes) go to ``H p``
  and ``H v``;
- a body-to-world rotation ``R`` goes to ``H R H`` and the unit quaternion ``[w, x, y, z]`` to
  ``[w, x, -y, -z]`` (the half-turn quaternion ``[0, 1, 0, 0]`` conjugating it);
- ZYX Euler angles ``(roll, pitch, yaw)`` go to ``(roll, -pitch, -yaw)``;
- a spatial inertia ``I`` (``[angular; linear]``) goes to ``H6 I H6`` with ``H6 = diag(H, H)``.

Quaternions in ROS messages and most logs are ordered ``(x, y, z, w)``; uvms stores ``(w, x, y, z)``
(:func:`quaternion_wxyz`).

Ground floor (``docs/architecture.md``): this module imports nothing of uvms but :mod:`uvms.errors`.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from uvms.errors import UvmsInputError

Frame = Literal["ned", "enu"]
FRAMES: tuple[str, ...] = ("ned", "enu")
"""The frame names, the default first."""

HALF_TURN = np.diag([1.0, -1.0, -1.0])
"""``H``: the rotation by pi about x that maps one convention's coordinates onto the other's (its own inverse)."""

UP = {"ned": np.array([0.0, 0.0, -1.0]), "enu": np.array([0.0, 0.0, 1.0])}
"""The world's up direction in each convention's coordinates."""

GRAVITY_DIRECTION = {"ned": np.array([0.0, 0.0, 1.0]), "enu": np.array([0.0, 0.0, -1.0])}
"""The direction gravity points in each convention (``-UP``): gravity is ``g * GRAVITY_DIRECTION[frame]``."""


def check_frame(frame: str, where: str = "frame") -> str:
    """``frame`` if it names a convention, else a one-line :class:`~uvms.errors.UvmsInputError`."""
    if frame not in FRAMES:
        raise UvmsInputError(f"{where}: expected one of {', '.join(FRAMES)} (ned: world z down, body "
                             f"forward-right-down; enu: world z up, body forward-left-up), got {frame!r}")
    return frame


def _same(source: str, target: str) -> bool:
    return check_frame(source, "source frame") == check_frame(target, "target frame")


def convert_vectors(v, source: str, target: str) -> np.ndarray:
    """World points or body vectors (``(..., 3)``) from ``source``'s coordinates to ``target``'s: ``H v``."""
    v = np.array(v, dtype=float)
    if not _same(source, target):
        v[..., 1:3] *= -1.0
    return v


def convert_quaternions(q, source: str, target: str) -> np.ndarray:
    """Body-to-world unit quaternions ``[w, x, y, z]`` (``(..., 4)``) from ``source`` to ``target``:
    ``[w, x, -y, -z]`` (the rotation ``H R H``)."""
    q = np.array(q, dtype=float)
    if not _same(source, target):
        q[..., 2:4] *= -1.0
    return q


def convert_euler(euler, source: str, target: str) -> np.ndarray:
    """ZYX Euler angles ``(roll, pitch, yaw)`` (``(..., 3)``) from ``source`` to ``target``: ``(roll, -pitch,
    -yaw)`` (the Euler angles of ``H R H``)."""
    return convert_vectors(euler, source, target)


def convert_twists(nu, source: str, target: str) -> np.ndarray:
    """Body twists or wrenches ``[angular; linear]`` (``(..., 6)``) from ``source`` to ``target``: ``H6 nu``."""
    nu = np.array(nu, dtype=float)
    if not _same(source, target):
        nu[..., [1, 2, 4, 5]] *= -1.0
    return nu


def convert_spatial_matrix(M, source: str, target: str) -> np.ndarray:
    """A 6x6 body matrix in ``[angular; linear]`` coordinates (spatial inertia, added mass, damping):
    ``H6 M H6``."""
    M = np.array(M, dtype=float)
    if not _same(source, target):
        h = np.array([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
        M = h[:, None] * M * h[None, :]
    return M


def convert_damping_tensor(C, source: str, target: str) -> np.ndarray:
    """A body's mixed quadratic damping ``C`` (2, 6, 6, 6), ``f_i -= C[0, i, j, k] nu_j |nu_k| +
    C[1, i, j, k] nu_j nu_k`` (:attr:`uvms.model.model.Model.damping_cross`): each index takes the sign ``h``
    of ``H6``, except the one under ``| |`` (``|h nu_k| = |nu_k|``)."""
    C = np.array(C, dtype=float)
    if not _same(source, target):
        h = np.array([1.0, -1.0, -1.0, 1.0, -1.0, -1.0])
        C[0] = C[0] * h[:, None, None] * h[None, :, None]
        C[1] = C[1] * h[:, None, None] * h[None, :, None] * h[None, None, :]
    return C


def quaternion_wxyz(q_xyzw) -> np.ndarray:
    """A quaternion (or ``(..., 4)`` rows) ordered ``(x, y, z, w)`` (ROS) reordered to uvms's ``(w, x, y, z)``."""
    q = np.asarray(q_xyzw, dtype=float)
    return np.concatenate([q[..., 3:4], q[..., 0:3]], axis=-1)


def convert_frame_rotations(R, source: str, target: str) -> np.ndarray:
    """Rotations ``(..., 3, 3)`` from a frame fixed in the vehicle (a link mount, a shape, a sensor) to the
    vehicle's body axes, from ``source`` to ``target``: ``H R``. The fixed frame itself is not renamed (a link's
    frame is the model's own: DH rows or URDF joint origins); only the vehicle axes it is written in change."""
    R = np.array(R, dtype=float)
    if not _same(source, target):
        R[..., 1:3, :] *= -1.0
    return R


def default_gravity(frame: str, g: float = 9.81) -> np.ndarray:
    """Gravity ``g * GRAVITY_DIRECTION[frame]`` [m/s^2]: ``[0, 0, g]`` in ned, ``[0, 0, -g]`` in enu."""
    return g * GRAVITY_DIRECTION[check_frame(frame)]


def check_gravity(gravity, frame: str, source: str | None = None, path: str = "environment.gravity") -> np.ndarray:
    """``gravity`` as an array if it points down in ``frame`` (a positive component along
    ``GRAVITY_DIRECTION[frame]``) or is zero (no gravity); else a one-line :class:`~uvms.errors.UvmsInputError`.

    Refused rather than warned: a gravity pointing up is a model loaded upside down (a z-down file without
    ``frame: ned`` or a z-up one without ``frame: enu``), and every number after it would be wrong."""
    g = np.array(gravity, dtype=float).reshape(3)
    norm = float(np.linalg.norm(g))
    if norm > 0.0 and not float(g @ GRAVITY_DIRECTION[check_frame(frame)]) > 0.0:
        world = "z down" if frame == "ned" else "z up"
        expected = ", ".join(f"{v:g}" for v in default_gravity(frame, norm))
        raise UvmsInputError(f"expected gravity pointing down in frame {frame} (world {world}), e.g. "
                             f"[{expected}], got [{', '.join(f'{v:g}' for v in g)}] (set 'frame: "
                             f"{'enu' if frame == 'ned' else 'ned'}' if the file is written "
                             f"{'z up' if frame == 'ned' else 'z down'})", source, path)
    return g


def convert_state(state, source: str, target: str):
    """A :class:`uvms.state.State` (or anything with ``position``, ``quaternion``, ``nu`` and ``replace``) from
    ``source``'s convention to ``target``'s: ``H p``, ``[w, x, -y, -z]``, ``H6 nu``; the joint angles and rates
    and the actuator states (motor speeds, duct flows, thrusts along each thruster's own direction) are the
    same in both."""
    if _same(source, target):
        return state
    return state.replace(position=convert_vectors(state.position, source, target),
                         quaternion=convert_quaternions(state.quaternion, source, target),
                         nu=convert_twists(state.nu, source, target))


VEHICLE_AXES = {"ned": "x fwd, y stbd, z down", "enu": "x fwd, y port, z up"}
"""The vehicle's body axes in words (report and trim headers)."""

WORLD_AXES = {"ned": ("x north", "y east", "z down"), "enu": ("x", "y", "z up")}
"""The world axes' labels (3-D views, plots). The enu world of the half-turn map has x along the ned world's x,
which need not be east: its horizontal axes are not named after compass points."""


def depth(z, frame: str):
    """Depth [m] (positive down) of world heights or z coordinates ``z``: ``z`` in ned, ``-z`` in enu."""
    return z if check_frame(frame) == "ned" else -np.asarray(z)
