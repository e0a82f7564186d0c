"""Scalar metrics of a run, by name: a few named ones, and ``<statistic>_<series>`` for any recorded series.

Named metrics (errors relative to the initial pose, the paper's Figures 5-6):

| name | definition |
| --- | --- |
| ``peak_body_error_xy_m`` | ``max_t |[R^T (p - p0)]_xy|`` [m] |
| ``final_body_error_xy_m`` | the same at the last sample [m] |
| ``rms_body_error_xy_m`` | its root mean square over the samples [m] |
| ``peak_abs_roll_rad``, ``peak_abs_pitch_rad``, ``peak_abs_yaw_rad`` | ``max_t |angle - angle0|`` [rad] (yaw unwrapped) |
| ``peak_displacement_m`` | ``max_t |p - p0|`` [m] |
| ``simulated_time_s`` | the last sample's time [s] |

``max_abs_X``, ``rms_X``, ``mean_X``, ``final_X`` apply to a series ``X``: a column of
:meth:`Result.columns <uvms.sim.result.Result.columns>` (``x_m``, ``yaw_rad``, ``u_m_s``, ``q1_rad``, ``tau1_Nm``,
``ee_x_m`` ...) or a controller signal (``s_surge``, ``command_X``, ``e_yaw`` ...). NaN samples (a signal before
the controller's first update) are ignored; a series the run does not have gives NaN.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable

import numpy as np

STATISTICS: dict[str, Callable[[np.ndarray], float]] = {
    "max_abs": lambda v: float(np.nanmax(np.abs(v))),
    "rms": lambda v: float(np.sqrt(np.nanmean(np.square(v)))),
    "mean": lambda v: float(np.nanmean(v)),
    "final": lambda v: float(v[np.isfinite(v)][-1]),
}
"""Statistics of a series, by the prefix of the metric name."""

NAMED: tuple[str, ...] = ("peak_body_error_xy_m", "final_body_error_xy_m", "rms_body_error_xy_m",
                          "peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad", "peak_displacement_m",
                          "simulated_time_s")

_SERIES = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def default_metrics(*, controlled: bool) -> tuple[str, ...]:
    """The metrics recorded when a sweep names none (command metrics only with a controller)."""
    names = ("peak_body_error_xy_m", "final_body_error_xy_m", "rms_body_error_xy_m", "peak_abs_yaw_rad")
    if controlled:
        names += ("max_abs_command_X", "max_abs_command_Y", "max_abs_command_N", "rms_command_X", "rms_command_Y",
                  "rms_command_N")
    return names


def check_metric(name: str) -> None:
    """Raise ``ValueError`` (one line) unless ``name`` is a named metric or ``<statistic>_<series>``."""
    if name in NAMED:
        return
    for prefix in STATISTICS:
        if name.startswith(prefix + "_") and _SERIES.fullmatch(name[len(prefix) + 1:]):
            return
    raise ValueError(f"unknown metric {name!r}; expected one of {', '.join(NAMED)}, or "
                     f"{'/'.join(STATISTICS)}_<series> (e.g. max_abs_s_surge, rms_command_X)")


def compute_metrics(result, names: tuple[str, ...] | list[str]) -> dict[str, float]:
    """The metrics ``names`` of a :class:`~uvms.sim.result.Result` (NaN where a series is missing or empty)."""
    series = _Series(result)
    values: dict[str, float] = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices: the metric is NaN, as documented
        for name in names:
            try:
                values[name] = series.metric(name)
            except (KeyError, IndexError, ValueError):
                values[name] = float("nan")
    return values


class _Series:
    """Series of a result by name, derived series computed once."""

    def __init__(self, result) -> None:
        self.result = result
        self._cache: dict[str, np.ndarray] = {}

    def euler(self) -> np.ndarray:
        """(K, 3) ZYX Euler angles (roll, pitch, yaw) [rad], yaw unwrapped."""
        if "euler" not in self._cache:
            self._cache["euler"] = self.result.euler
        return self._cache["euler"]

    def body_error_xy(self) -> np.ndarray:
        """(K,) ``|[R^T (p - p0)]_xy|`` [m]."""
        if "body_xy" not in self._cache:
            d = self.result.body_frame_error()
            self._cache["body_xy"] = np.hypot(d[:, 0], d[:, 1])
        return self._cache["body_xy"]

    def get(self, name: str) -> np.ndarray:
        """A series by its :meth:`Result.columns` name or signal name (``KeyError`` if the run has none)."""
        r = self.result
        if name in r.signals:
            return np.asarray(r.signals[name], dtype=float)
        fixed = {"t_s": lambda: r.time}
        for k, a in enumerate("xyz"):
            fixed[f"{a}_m"] = lambda k=k: r.position[:, k]
            fixed[f"ee_{a}_m"] = lambda k=k: r.end_effector[:, k]
        for k, a in enumerate(("roll", "pitch", "yaw")):
            fixed[f"{a}_rad"] = lambda k=k: self.euler()[:, k]
        for k, a in enumerate("pqr"):
            fixed[f"{a}_rad_s"] = lambda k=k: r.nu[:, k]
        for k, a in enumerate("uvw"):
            fixed[f"{a}_m_s"] = lambda k=k: r.nu[:, 3 + k]
        if name in fixed:
            return np.asarray(fixed[name](), dtype=float)
        match = re.fullmatch(r"(q|qd|tau)(\d+)_(rad|rad_s|Nm)", name)
        if match and {"q": "rad", "qd": "rad_s", "tau": "Nm"}[match[1]] == match[3]:
            j = int(match[2]) - 1
            if 0 <= j < r.n_joints:
                return np.asarray({"q": r.q, "qd": r.qd, "tau": r.joint_torques}[match[1]][:, j], dtype=float)
        match = re.fullmatch(r"actuator(\d+)", name)
        if match and int(match[1]) < r.actuator.shape[1]:
            return np.asarray(r.actuator[:, int(match[1])], dtype=float)
        raise KeyError(name)

    def metric(self, name: str) -> float:
        r = self.result
        if name == "peak_body_error_xy_m":
            return float(self.body_error_xy().max())
        if name == "final_body_error_xy_m":
            return float(self.body_error_xy()[-1])
        if name == "rms_body_error_xy_m":
            return float(np.sqrt(np.mean(np.square(self.body_error_xy()))))
        if name in ("peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad"):
            k = ("peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad").index(name)
            e = self.euler()[:, k]
            return float(np.abs(e - e[0]).max())
        if name == "peak_displacement_m":
            p = np.asarray(r.position, dtype=float)
            return float(np.linalg.norm(p - p[0], axis=1).max())
        if name == "simulated_time_s":
            return float(r.time[-1])
        for prefix, statistic in STATISTICS.items():
            if name.startswith(prefix + "_"):
                return statistic(self.get(name[len(prefix) + 1:]))
        raise KeyError(name)
