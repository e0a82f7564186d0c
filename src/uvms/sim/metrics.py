"""Scalar metrics of a run, by name: the one place a metric of a :class:`~uvms.sim.result.Result` is defined.

``Result.summary``, sweep tables (:mod:`uvms.sweep`), ``uvms compare`` (:func:`uvms.control.compare.metrics`)
and ``uvms reproduce`` (:func:`uvms.reproduce.case_metrics`) all compute their numbers here.

Named metrics (errors relative to the initial pose, the paper's Figures 5-6; attitude absolute):

| name | definition |
| --- | --- |
| ``peak_body_error_xy_m`` | ``max_t |[R^T (p - p0)]_xy|`` [m] |
| ``final_body_error_xy_m`` | the same at the last sample [m] |
| ``rms_body_error_xy_m`` | its root mean square over the samples [m] |
| ``peak_abs_x_m``, ``peak_abs_y_m``, ``peak_abs_z_m`` | ``max_t |p_i - p0_i|`` [m] |
| ``peak_abs_roll_rad``, ``peak_abs_pitch_rad``, ``peak_abs_yaw_rad`` | ``max_t |angle - angle0|`` [rad] (yaw unwrapped) |
| ``peak_yaw_error_rad`` | ``max_t |wrap(psi - psi0)|`` [rad] (wrapped to (-pi, pi]: the controllers' yaw error) |
| ``peak_displacement_m`` | ``max_t |p - p0|`` [m] |
| ``peak_world_error_xy_m`` | ``max_t |(p - p0)_xy|`` [m] (world-frame horizontal error: six-axis station keeping) |
| ``peak_depth_error_m`` | ``max_t |z - z0|`` [m] (the depth error; the same number as ``peak_abs_z_m``) |
| ``peak_roll_error_rad``, ``peak_pitch_error_rad`` | ``max_t |wrap(angle)|`` [rad]: from level (the six-axis controllers' default set point) |
| ``simulated_time_s`` | the last sample's time [s] |
| ``healthy`` | 1 for a healthy run, 0 for an unhealthy one (:mod:`uvms.sim.health`) |
| ``max_saturated_fraction`` | the largest fraction of time any thruster spends at a thrust limit [-] (0 without thrusters) |
| ``peak_unachieved_force_N``, ``peak_unachieved_moment_Nm`` | ``max_t`` of the norm of the force / moment the thrusters could not produce |
| ``peak_station_departure_m`` | how far the vehicle left its station [m] (:mod:`uvms.sim.health`; NaN without a controller holding a position) |
| ``unproduced_force_share``, ``unproduced_moment_share`` | the share of the commanded force / moment not produced [-] (:mod:`uvms.sim.health`; NaN without thrusters) |

``<statistic>_<series>`` applies a statistic (``max_abs``, ``rms``, ``mean``, ``final``, ``sign_changes``) to
a series: a column of :meth:`Result.columns <uvms.sim.result.Result.columns>` (``x_m``, ``yaw_rad``, ``u_m_s``,
``q_joint1_rad``, ``tau_joint1_Nm``, ``ee_x_m`` ...: joints by name, :mod:`uvms.sim.columns`; an older file's
``q1_rad`` also works), a logged signal (``s_surge``, ``command_X``, ``thrust_cmd_sway``,
``unachieved_N`` ...), or a derived series: ``axis_error_<axis>`` and ``surface_<axis>`` for ``axis`` in
surge, sway, yaw (:meth:`Result.axis_errors <uvms.sim.result.Result.axis_errors>` and the sliding variable
``s = vel + lambda e`` of the paper's Eq. 24 with the paper's lambda, computed from the states for any
controller). ``max_abs_roll_rad`` and ``max_abs_pitch_rad`` are the largest absolute attitude angles. NaN
samples (a signal before the controller's first update) are ignored; a series the run does not have gives NaN.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable, Sequence

import numpy as np

AXES: tuple[str, ...] = ("surge", "sway", "yaw")
"""The axes of :meth:`Result.axis_errors`, in its column order."""


def paper_bandwidth() -> float:
    """The paper's sliding-surface bandwidth ``lambda`` [1/s]: the default of
    :class:`~uvms.control.smc.SlidingModeParameters` (its one definition)."""
    from uvms.control.smc import SlidingModeParameters

    return float(SlidingModeParameters().bandwidth[0])    # the same on every paper axis


def sign_changes(values: np.ndarray, relative_tolerance: float = 1e-6) -> int:
    """Sign changes of the first difference of ``values`` (NaN samples dropped); differences within
    ``relative_tolerance`` times ``max |values|`` (held samples, rounding noise) are skipped. A smooth signal
    has few, chatter many."""
    x = np.asarray(values, dtype=float)
    x = x[np.isfinite(x)]
    if x.size < 3:
        return 0
    d = np.diff(x)
    d = d[np.abs(d) > relative_tolerance * max(np.abs(x).max(), 1e-300)]
    return int(np.count_nonzero(np.diff(np.sign(d)) != 0))


STATISTICS: dict[str, Callable[[np.ndarray], float]] = {
    "max_abs": lambda v: float(np.nanmax(np.abs(v))),
    "rms": lambda v: float(np.sqrt(np.nanmean(np.square(v)))),
    "mean": lambda v: float(np.nanmean(v)),
    "final": lambda v: float(v[np.isfinite(v)][-1]),
    "sign_changes": lambda v: float(sign_changes(v)),
}
"""Statistics of a series, by the prefix of the metric name."""

NAMED: tuple[str, ...] = ("peak_body_error_xy_m", "final_body_error_xy_m", "rms_body_error_xy_m",
                          "peak_abs_x_m", "peak_abs_y_m", "peak_abs_z_m",
                          "peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad", "peak_yaw_error_rad",
                          "peak_displacement_m", "peak_world_error_xy_m", "peak_depth_error_m",
                          "peak_roll_error_rad", "peak_pitch_error_rad", "simulated_time_s",
                          "healthy", "max_saturated_fraction", "peak_unachieved_force_N", "peak_unachieved_moment_Nm",
                          "peak_station_departure_m", "unproduced_force_share", "unproduced_moment_share")

HEALTH_METRICS: tuple[str, ...] = ("healthy", "max_abs_roll_rad", "max_abs_pitch_rad", "max_saturated_fraction",
                                   "peak_unachieved_force_N", "peak_unachieved_moment_Nm")
"""Run health (:mod:`uvms.sim.health`) as sweep-table columns: part of every default metric set."""

_POSITION_COMPONENT = {"peak_abs_x_m": 0, "peak_abs_y_m": 1, "peak_abs_z_m": 2, "peak_depth_error_m": 2}
"""Metrics ``max_t |p_i - p0_i|`` and their component ``i`` (z is down: the depth)."""

_HEALTH_OPTIONAL = {"peak_station_departure_m": "station_departure", "unproduced_force_share": "unproduced_share_force",
                    "unproduced_moment_share": "unproduced_share_moment"}
"""Health metrics a run may not have (:class:`uvms.sim.health.RunHealth` field ``None``: NaN)."""

_SERIES = re.compile(r"[A-Za-z][A-Za-z0-9_]*")


def default_metrics(*, controlled: bool) -> tuple[str, ...]:
    """The metrics recorded when a sweep names none (command metrics only with a controller), run health
    (:data:`HEALTH_METRICS`) always."""
    names = ("peak_body_error_xy_m", "final_body_error_xy_m", "rms_body_error_xy_m", "peak_abs_yaw_rad")
    if controlled:
        names += ("max_abs_command_X", "max_abs_command_Y", "max_abs_command_N", "rms_command_X", "rms_command_Y",
                  "rms_command_N")
    return names + HEALTH_METRICS


def check_metric(name: str) -> None:
    """Raise ``ValueError`` (one line) unless ``name`` is a named metric or ``<statistic>_<series>``."""
    if name in NAMED:
        return
    for prefix in STATISTICS:
        if name.startswith(prefix + "_") and _SERIES.fullmatch(name[len(prefix) + 1:]):
            return
    raise ValueError(f"unknown metric {name!r}; expected one of {', '.join(NAMED)}, or "
                     f"{'/'.join(STATISTICS)}_<series> (e.g. max_abs_s_surge, rms_command_X)")


def compute_metrics(result, names: Sequence[str]) -> dict[str, float]:
    """The metrics ``names`` of a :class:`~uvms.sim.result.Result` (NaN where a series is missing or empty)."""
    series = Series(result)
    return {name: series.metric(name) for name in names}


class Series:
    """Series and metrics of one result by name; derived series (Euler angles, axis errors, health) are
    computed once. ``bandwidth`` is the ``lambda`` of the ``surface_<axis>`` series (default: the paper's)."""

    def __init__(self, result, *, bandwidth: float | None = None) -> None:
        self.result = result
        self.bandwidth = paper_bandwidth() if bandwidth is None else float(bandwidth)
        self._cache: dict[str, object] = {}

    def _once(self, key: str, compute: Callable[[], object]):
        if key not in self._cache:
            self._cache[key] = compute()
        return self._cache[key]

    def euler(self) -> np.ndarray:
        """(K, 3) ZYX Euler angles (roll, pitch, yaw) [rad], yaw unwrapped."""
        return self._once("euler", lambda: self.result.euler)

    def body_error_xy(self) -> np.ndarray:
        """(K,) ``|[R^T (p - p0)]_xy|`` [m]."""
        def compute():
            d = self.result.body_frame_error()
            return np.hypot(d[:, 0], d[:, 1])

        return self._once("body_xy", compute)

    def axis(self) -> dict[str, np.ndarray]:
        """``error`` and ``s`` (K, 3) of :meth:`Result.axis_errors` (surge, sway, yaw; initial pose held; body
        velocity surface, ``lambda = self.bandwidth``)."""
        def compute():
            axes = self.result.axis_errors()
            return {"error": axes.error, "s": axes.velocity + self.bandwidth * axes.error}

        return self._once("axis", compute)

    def health(self):
        """:class:`uvms.sim.health.RunHealth` of the run (limits from its metadata, else the defaults)."""
        from uvms.sim.health import run_health

        return self._once("health", lambda: run_health(self.result))

    def _joint_series(self, name: str) -> np.ndarray | None:
        """A joint column by its name (``q_<joint>_rad`` ..., :mod:`uvms.sim.columns`) or by an older file's
        numbered name (``q1_rad``, joint order), else ``None``."""
        from uvms.sim.columns import legacy_alias

        r = self.result
        values = {"q": r.q, "qd": r.qd, "tau": r.joint_torques}
        for kind, labels in zip(("q", "qd", "tau"), r.joint_columns()):
            if name in labels:
                return np.asarray(values[kind][:, labels.index(name)], dtype=float)
        alias = legacy_alias(name, r.n_joints)
        return None if alias is None else np.asarray(values[alias[0]][:, alias[1]], dtype=float)

    def get(self, name: str) -> np.ndarray:
        """A series by its :meth:`Result.columns` name, signal name or derived name (``KeyError`` if none)."""
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
        for k, a in enumerate(AXES):
            fixed[f"axis_error_{a}"] = lambda k=k: self.axis()["error"][:, k]
            fixed[f"surface_{a}"] = lambda k=k: self.axis()["s"][:, k]
        if name in fixed:
            return np.asarray(fixed[name](), dtype=float)
        joint = self._joint_series(name)
        if joint is not None:
            return joint
        match = re.fullmatch(r"actuator(\d+)", name)
        if match and int(match[1]) < r.actuator.shape[1]:
            return np.asarray(r.actuator[:, int(match[1])], dtype=float)
        raise KeyError(name)

    def metric(self, name: str) -> float:
        """The metric ``name`` (NaN where its series is missing or empty)."""
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices: the metric is NaN, as documented
            try:
                return self._metric(name)
            except (KeyError, IndexError, ValueError):
                return float("nan")

    def _metric(self, name: str) -> float:
        r = self.result
        if name == "peak_body_error_xy_m":
            return float(self.body_error_xy().max())
        if name == "final_body_error_xy_m":
            return float(self.body_error_xy()[-1])
        if name == "rms_body_error_xy_m":
            return float(np.sqrt(np.mean(np.square(self.body_error_xy()))))
        if name in _POSITION_COMPONENT:
            p = np.asarray(r.position[:, _POSITION_COMPONENT[name]], dtype=float)
            return float(np.abs(p - p[0]).max())
        if name == "peak_world_error_xy_m":
            d = np.asarray(r.position, dtype=float)[:, :2]
            return float(np.hypot(*(d - d[0]).T).max())
        if name in ("peak_roll_error_rad", "peak_pitch_error_rad"):
            angle = self.euler()[:, 0 if name == "peak_roll_error_rad" else 1]
            return float(np.abs(np.angle(np.exp(1j * angle))).max())
        if name in ("peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad"):
            k = ("peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad").index(name)
            e = self.euler()[:, k]
            return float(np.abs(e - e[0]).max())
        if name == "peak_yaw_error_rad":
            return float(np.abs(self.axis()["error"][:, 2]).max())
        if name == "peak_displacement_m":
            p = np.asarray(r.position, dtype=float)
            return float(np.linalg.norm(p - p[0], axis=1).max())
        if name == "simulated_time_s":
            return float(r.time[-1])
        if name == "healthy":
            return float(self.health().healthy)
        if name == "max_saturated_fraction":
            return float(max(self.health().saturated_fraction.values(), default=0.0))
        if name == "peak_unachieved_force_N":
            return self.health().peak_unachieved_force
        if name == "peak_unachieved_moment_Nm":
            return self.health().peak_unachieved_moment
        if name in _HEALTH_OPTIONAL:
            value = getattr(self.health(), _HEALTH_OPTIONAL[name])
            return float("nan") if value is None else float(value)
        for prefix, statistic in STATISTICS.items():
            if name.startswith(prefix + "_"):
                return statistic(self.get(name[len(prefix) + 1:]))
        raise KeyError(name)
