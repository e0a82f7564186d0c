"""Sampling a stream between its rows: linear or cubic values, Slerp attitudes, held commands (``docs/logs.md``,
"Resampling").

Every function takes the stream's strictly increasing times ``t`` (K,), its rows ``y`` (K, m) and the times
``at`` (N,) to sample, all inside ``[t[0], t[-1]]`` (the caller checks), and returns (N, m).
"""

from __future__ import annotations

import numpy as np

from uvms.frames import quaternion_wxyz

METHODS = ("linear", "cubic")
"""How positions, rates and joint angles are interpolated: piecewise linear, or a not-a-knot cubic spline."""


def values(t: np.ndarray, y: np.ndarray, at: np.ndarray, method: str = "linear") -> np.ndarray:
    """``y`` at ``at``: piecewise linear (:func:`numpy.interp` per column) or a not-a-knot cubic spline
    (:class:`scipy.interpolate.CubicSpline`; linear when the stream has fewer than 4 rows)."""
    if method == "cubic" and t.size >= 4:
        from scipy.interpolate import CubicSpline

        return CubicSpline(t, y, axis=0)(at)
    return np.array([np.interp(at, t, column) for column in y.T]).T.reshape(at.size, y.shape[1])


def held(t: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """``y`` held from each row to the next (zero-order hold: the last row at or before each time), as a
    command is held until the next one."""
    index = np.clip(np.searchsorted(t, at, side="right") - 1, 0, t.size - 1)
    return y[index]


def slerp(t: np.ndarray, q: np.ndarray, at: np.ndarray) -> np.ndarray:
    """Unit quaternions ``[w, x, y, z]`` at ``at`` by spherical linear interpolation between the rows
    (:class:`scipy.spatial.transform.Slerp`: constant angular velocity along the shorter arc), with ``w >= 0``."""
    from scipy.spatial.transform import Rotation, Slerp

    rotations = Rotation.from_quat(q[:, [1, 2, 3, 0]])     # scipy orders (x, y, z, w)
    return quaternion_wxyz(Slerp(t, rotations)(at).as_quat(canonical=True))


def rotations(q: np.ndarray):
    """``[w, x, y, z]`` rows as a :class:`scipy.spatial.transform.Rotation` (body to world)."""
    from scipy.spatial.transform import Rotation

    return Rotation.from_quat(np.asarray(q, dtype=float).reshape(-1, 4)[:, [1, 2, 3, 0]])
