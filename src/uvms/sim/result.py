"""Results of a run: labelled time series, a summary, and atomic saving (CSV + JSON).

Nothing here is recomputed by the integrator: the states are what was integrated, everything else
(Euler angles, body-frame errors, end-effector path) is derived from them on demand.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, NamedTuple

import numpy as np

from uvms.output import atomic_write_text  # noqa: F401  (re-exported: result files are written through it)
from uvms.errors import UvmsInputError, show

# uvms.rotations and uvms.state (numba) are imported where used: reading a run folder's files, and
# refusing a bad one, does not wait for the compiler to load.


class AxisErrors(NamedTuple):
    """Per sample, the surge, sway and yaw errors and rates of :meth:`Result.axis_errors` (each (K, 3))."""

    error: np.ndarray
    error_rate: np.ndarray
    velocity: np.ndarray

    def rates(self, surface: str = "body_velocity") -> np.ndarray:
        """The ``vel`` of ``s = vel + lambda e`` (Eq. 24): ``velocity`` (``"body_velocity"``) or ``error_rate``."""
        return self.velocity if surface == "body_velocity" else self.error_rate


@dataclass(frozen=True, eq=False)
class Result:
    """A simulated run.

    Attributes:
        time: (K,) [s].
        states: (K, N) state vectors (:mod:`uvms.state` layout).
        n_joints: arm joints ``n``.
        end_effector: (K, 3) end-effector position in the world [m].
        joint_torques: (K, n) applied joint torques [N m].
        signals: controller and actuator signals, name -> (K,) array (e.g. ``s_surge``, ``command_X``).
        complete: False if the run stopped early (divergence); ``message`` says why.
        metadata: run metadata (versions, scenario hash, wall time, integrator, step; the model's
            ``joint_names`` and ``joint_types``, which name the joint columns: :mod:`uvms.sim.columns`).
        sensors: the simulated sensors' samples, name -> :class:`uvms.sensors.SensorRecord` (each at its own
            rate: its own ``time`` and columns; ``docs/sensors.md``).
    """

    time: np.ndarray
    states: np.ndarray
    n_joints: int
    end_effector: np.ndarray
    joint_torques: np.ndarray
    signals: dict[str, np.ndarray] = field(default_factory=dict)
    complete: bool = True
    message: str = ""
    metadata: dict[str, Any] = field(default_factory=dict)
    sensors: dict[str, Any] = field(default_factory=dict)

    def _slice(self, name: str) -> np.ndarray:
        from uvms.state import actuator_count, layout

        n_act = actuator_count(self.n_joints, self.states.shape[1])
        return self.states[:, layout(self.n_joints, n_act)[name]]

    @property
    def position(self) -> np.ndarray:
        """(K, 3) vehicle position in the world (x north, y east, z down) [m]."""
        return self._slice("position")

    @property
    def quaternion(self) -> np.ndarray:
        return self._slice("quaternion")

    @property
    def euler(self) -> np.ndarray:
        """(K, 3) ZYX Euler angles (roll, pitch, yaw) [rad], yaw unwrapped over time."""
        from uvms.rotations import euler_from_rotations

        e = euler_from_rotations(self.rotations())
        if len(e):
            e[:, 2] = np.unwrap(e[:, 2])
        return e

    def rotations(self) -> np.ndarray:
        """(K, 3, 3) body-to-world rotations ``R`` of the samples."""
        from uvms.rotations import rotations_from_quaternions

        return rotations_from_quaternions(self.quaternion)

    @property
    def nu(self) -> np.ndarray:
        """(K, 6) body velocity ``[omega; v]`` [rad/s, m/s]."""
        return self._slice("nu")

    @property
    def q(self) -> np.ndarray:
        return self._slice("q")

    @property
    def qd(self) -> np.ndarray:
        return self._slice("qd")

    @property
    def actuator(self) -> np.ndarray:
        return self._slice("actuator")

    @property
    def joint_names(self) -> tuple[str, ...]:
        """The model's joint names (``metadata["joint_names"]``; ``joint1 ...`` when the run does not say)."""
        from uvms.sim.columns import default_joint_names

        names = self.metadata.get("joint_names")
        return tuple(map(str, names)) if names and len(names) == self.n_joints else default_joint_names(self.n_joints)

    def joint_columns(self):
        """The :class:`~uvms.sim.columns.JointColumns` of this run (``q_<joint>_rad`` ..., by joint name)."""
        from uvms.sim.columns import joint_columns

        types = self.metadata.get("joint_types")
        return joint_columns(self.joint_names, types if types and len(types) == self.n_joints else None)

    def body_frame_error(self, position_ref=None) -> np.ndarray:
        """(K, 3) vehicle position error from ``position_ref`` (default: the initial position), in the
        vehicle's body axes ``R^T (p - p_ref)`` [m] (the paper's Figures 5-6)."""
        ref = self.position[0] if position_ref is None else np.asarray(position_ref, dtype=float)
        return np.einsum("kji,kj->ki", self.rotations(), self.position - ref).reshape(-1, 3)

    def axis_errors(self, position_desired=None, yaw_desired: float | None = None) -> AxisErrors:
        """Surge, sway and yaw errors of every sample from a held pose (default: the initial one), with their
        rates, vectorised over the samples (the quantities of the sliding-mode laws, Eqs. 24-29, as
        :func:`uvms.control.sliding_kernels.axis_kinematics_into` computes them for one state).

        ``error`` (K, 3): ``e_x, e_y`` of ``e = R^T (p - p_d)`` [m] and ``wrap(psi - psi_d)`` to (-pi, pi]
        [rad]; ``error_rate`` (K, 3): ``(e_dot_x, e_dot_y, psi_dot)`` with ``e_dot = v - omega x e`` and Eq. 1's
        ``psi_dot = (sin(phi) q + cos(phi) r) / cos(theta)``; ``velocity`` (K, 3): ``(u, v, r)``."""
        from uvms.rotations import euler_from_rotations

        R = self.rotations()
        p_d = self.position[0] if position_desired is None else np.asarray(position_desired, dtype=float)
        e = np.einsum("kji,kj->ki", R, self.position - p_d).reshape(-1, 3)
        euler = euler_from_rotations(R)
        psi_d = (euler[0, 2] if len(euler) else 0.0) if yaw_desired is None else float(yaw_desired)
        yaw_error = -((-(euler[:, 2] - psi_d) + np.pi) % (2.0 * np.pi) - np.pi)
        nu = self.nu
        e_dot = nu[:, 3:] - np.cross(nu[:, :3], e)
        phi, theta = euler[:, 0], euler[:, 1]
        psi_dot = (np.sin(phi) * nu[:, 1] + np.cos(phi) * nu[:, 2]) / np.cos(theta)
        return AxisErrors(error=np.column_stack([e[:, 0], e[:, 1], yaw_error]),
                          error_rate=np.column_stack([e_dot[:, 0], e_dot[:, 1], psi_dot]),
                          velocity=np.column_stack([nu[:, 3], nu[:, 4], nu[:, 2]]))

    def columns(self) -> dict[str, np.ndarray]:
        """Every labelled series as ``name -> (K,)`` (units in the names)."""
        cols: dict[str, np.ndarray] = {"t_s": self.time}
        for k, a in enumerate("xyz"):
            cols[f"{a}_m"] = self.position[:, k]
        for k, a in enumerate(("roll", "pitch", "yaw")):
            cols[f"{a}_rad"] = self.euler[:, k]
        for k, a in enumerate("pqr"):
            cols[f"{a}_rad_s"] = self.nu[:, k]
        for k, a in enumerate("uvw"):
            cols[f"{a}_m_s"] = self.nu[:, 3 + k]
        names = self.joint_columns()                  # q_<joint>_rad ... (uvms.sim.columns)
        for values, labels in ((self.q, names.q), (self.qd, names.qd), (self.joint_torques, names.tau)):
            for j, label in enumerate(labels):
                cols[label] = values[:, j]
        for k, a in enumerate("xyz"):
            cols[f"ee_{a}_m"] = self.end_effector[:, k]
        for k in range(self.actuator.shape[1]):
            cols[f"actuator{k}"] = self.actuator[:, k]
        for name, values in self.signals.items():
            cols[name] = values
        return cols

    def to_dataframe(self):
        """The time series as a pandas DataFrame (one column per labelled series)."""
        import pandas as pd

        table = pd.DataFrame(self.columns())
        table.attrs["frame"] = self.metadata.get("frame", "ned")
        return table

    def to_mcap(self, path, model, *, thrusters=None):
        """Write this run of ``model`` as ROS 2 messages in an MCAP file (:func:`uvms.ros.write_mcap`,
        ``docs/ros.md``; the optional extra ``uvms[ros]``). Returns the path."""
        from uvms.ros import write_mcap

        return write_mcap(self, path, model=model, thrusters=thrusters)

    def summary(self) -> dict[str, Any]:
        """Peaks, final state and run health (JSON-ready); the numbers are :mod:`uvms.sim.metrics`' named
        metrics and :func:`uvms.sim.health.run_health`."""
        from uvms.sim.metrics import Series

        K = len(self.time)
        series = Series(self)
        e = series.euler()

        def peaks(names: tuple[str, ...]) -> list[float]:
            return [series.metric(n) for n in names] if K else []

        summ: dict[str, Any] = {
            "complete": self.complete,
            "message": self.message,
            "duration_s": float(self.time[-1] - self.time[0]) if K else 0.0,
            "peak_abs_position_m": peaks(("peak_abs_x_m", "peak_abs_y_m", "peak_abs_z_m")),
            "peak_abs_euler_rad": peaks(("peak_abs_roll_rad", "peak_abs_pitch_rad", "peak_abs_yaw_rad")),
            "peak_body_error_xy_m": series.metric("peak_body_error_xy_m") if K else 0.0,
            "final": {
                "time_s": float(self.time[-1]) if K else 0.0,
                "position_m": self.position[-1].tolist() if K else [],
                "euler_rad": e[-1].tolist() if K else [],
                "q_rad": self.q[-1].tolist() if K else [],
                "end_effector_m": self.end_effector[-1].tolist() if K else [],
            },
            "peak_abs_signal": {k: series.metric(f"max_abs_{k}") for k, v in self.signals.items() if len(v)},
            "health": series.health().as_dict() if K else None,
            "metadata": self.metadata,
        }
        return summ

    def health(self, **options):
        """:func:`uvms.sim.health.run_health` of this run (``options``: ``limits``, ``thrusters``)."""
        from uvms.sim.health import run_health

        return run_health(self, **options)

    def save(self, directory, *, name: str = "result") -> Path:
        """Write ``<name>.csv`` and ``<name>.json`` (summary) into ``directory``, each atomically, and each
        simulated sensor's table ``<name>.<sensor>.csv`` (``t_s`` and its columns, at its own rate)."""
        directory = Path(directory)
        cols = self.columns()
        header = ",".join(cols)
        data = np.column_stack(list(cols.values())) if len(self.time) else np.zeros((0, len(cols)))
        import io

        buf = io.StringIO()
        np.savetxt(buf, data, delimiter=",", header=header, comments="", fmt="%.10g")
        atomic_write_text(directory / f"{name}.csv", buf.getvalue())
        atomic_write_text(directory / f"{name}.json", json.dumps(self.summary(), indent=2, default=_json_default))
        for sensor, record in self.sensors.items():
            table = np.column_stack([record.time, *record.columns.values()])
            buf = io.StringIO()
            np.savetxt(buf, table, delimiter=",", header=",".join(["t_s", *record.columns]), comments="",
                       fmt="%.17g")
            atomic_write_text(directory / f"{name}.{sensor}.csv", buf.getvalue())
        return directory

    # -- reading back, looking at it (notebooks)

    @classmethod
    def load(cls, directory, *, name: str = "result") -> "Result":
        """A saved run (``uvms run -o DIR``, or :meth:`save`) read back from ``DIR/<name>.csv`` and ``.json``
        through the checked readers :func:`load_result_table` and :func:`load_result_summary`.

        The orientation is rebuilt from the saved ZYX Euler angles (the quaternion itself is not saved);
        series a table lacks (an older file) are zero, the end effector NaN. Unknown columns become
        ``signals``. The joints are the table's ``q_<joint>_rad`` (or ``_m``) columns in order, and an older
        file's numbered ``q1_rad ...`` columns are read as joints 1, 2, ... (:func:`uvms.sim.columns.table_joints`);
        the run's ``joint_names`` come from its metadata. A missing or damaged file is a one-line
        :class:`~uvms.errors.UvmsInputError`.
        """
        import re

        check_result_files(directory, name)          # sizes and nesting: refused before anything heavy
        from uvms.rotations import quaternion_from_euler
        from uvms.sim.columns import table_joints

        table = load_result_table(directory, name)
        summary = load_result_summary(directory, name)
        K = len(table)

        def column(label: str, default: float = 0.0) -> np.ndarray:
            return table[label].to_numpy(dtype=float) if label in table.columns else np.full(K, default)

        def columns(labels: list[str], default: float = 0.0) -> np.ndarray:
            return np.column_stack([column(c, default) for c in labels]) if labels else np.zeros((K, 0))

        _, joint_cols = table_joints(table.columns)
        n = len(joint_cols.q)
        n_act = sum(1 for c in table.columns if re.fullmatch(r"actuator\d+", c))
        euler = columns([f"{a}_rad" for a in ("roll", "pitch", "yaw")])
        quaternion = np.array([quaternion_from_euler(e) for e in euler]).reshape(K, 4)
        parts = [columns([f"{a}_m" for a in "xyz"]), quaternion,
                 columns([f"{a}_rad_s" for a in "pqr"] + [f"{a}_m_s" for a in "uvw"]),
                 columns(list(joint_cols.q)), columns(list(joint_cols.qd)),
                 columns([f"actuator{k}" for k in range(n_act)])]
        known = {"t_s"} | {f"{a}_m" for a in "xyz"} | {f"{a}_rad" for a in ("roll", "pitch", "yaw")} | {
            f"{a}_rad_s" for a in "pqr"} | {f"{a}_m_s" for a in "uvw"} | {f"ee_{a}_m" for a in "xyz"} | set(
            joint_cols.all()) | {f"actuator{k}" for k in range(n_act)}
        result = cls(
            time=column("t_s"), states=np.hstack(parts), n_joints=n,
            end_effector=columns([f"ee_{a}_m" for a in "xyz"], np.nan),
            joint_torques=columns(list(joint_cols.tau)),
            signals={c: table[c].to_numpy(dtype=float) for c in table.columns if c not in known},
            complete=bool(summary.get("complete", True)), message=str(summary.get("message") or ""),
            metadata=dict(summary.get("metadata") or {}))
        sensors = result.metadata.get("sensors") or {}
        if isinstance(sensors, dict) and sensors:
            from uvms.sensors import SensorRecord

            records = {}
            for sensor, about in sensors.items():
                if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", str(sensor)) or not isinstance(about, dict):
                    raise UvmsInputError(f"expected sensor names of letters, digits and '_' with their kind, found "
                                         f"{str(sensor)[:40]!r}", str(Path(directory) / f"{name}.json"),
                                         "metadata.sensors")
                t = load_sensor_table(Path(directory) / f"{name}.{sensor}.csv")
                records[sensor] = SensorRecord(str(sensor), str(about.get("kind", "")), str(about.get("frame_id", sensor)),
                                               t["t_s"].to_numpy(dtype=float),
                                               {c: t[c].to_numpy(dtype=float) for c in t.columns if c != "t_s"})
            object.__setattr__(result, "sensors", records)
        object.__setattr__(result, "_directory", Path(directory))   # where it came from (its scenario.yaml)
        return result

    def state(self, k: int):
        """The :class:`~uvms.state.State` of sample ``k`` (negative counts from the end)."""
        from uvms.state import State, actuator_count, layout

        K = len(self.time)
        if not -K <= int(k) < K:
            raise IndexError(f"sample {k} out of range: the run has {K} samples")
        x = self.states[int(k)]
        sl = layout(self.n_joints, actuator_count(self.n_joints, self.states.shape[1]))
        return State(position=x[sl["position"]], quaternion=x[sl["quaternion"]], nu=x[sl["nu"]], q=x[sl["q"]],
                     qd=x[sl["qd"]], actuator=x[sl["actuator"]])

    def plot(self, *, title: str | None = None):
        """The time-series figure of ``uvms plot`` (:func:`uvms.plots.timeseries_figure`), a matplotlib Figure."""
        from uvms.plots import timeseries_figure

        return timeseries_figure(self.to_dataframe(), title=title or self._label())

    def animate(self, model=None, *, fps: float | None = None, speed: float = 1.0, max_frames: int | None = None,
                thrusters=None):
        """The run replayed in 3-D: a plotly Figure with play/pause and a time slider
        (:func:`uvms.view.animate_run`; ``fps`` and ``max_frames`` default to its defaults). ``model`` defaults
        to the model of the run folder's ``scenario.yaml`` when the result was read with :meth:`load`."""
        from uvms.view import DEFAULT_FPS, DEFAULT_MAX_FRAMES, animate_run

        return animate_run(self, model, fps=DEFAULT_FPS if fps is None else fps, speed=speed,
                           max_frames=DEFAULT_MAX_FRAMES if max_frames is None else max_frames, thrusters=thrusters)

    def _label(self) -> str:
        return str(self.metadata.get("scenario") or "run")

    def __repr__(self) -> str:
        K = len(self.time)
        span = f"t = {self.time[0]:.6g}..{self.time[-1]:.6g} s" if K else "no samples"
        state = "complete" if self.complete else f"INCOMPLETE ({self.message})" if self.message else "INCOMPLETE"
        return (f"Result({self._label()!r}, {K} samples, {span}, {self.n_joints} joints, "
                f"{len(self.signals)} signals, {state})")

    def _repr_html_(self) -> str:
        import html

        K = len(self.time)
        meta = self.metadata
        rows = [("scenario", self._label()), ("samples", f"{K}"),
                ("time", f"{self.time[0]:.6g} .. {self.time[-1]:.6g} s" if K else "-"),
                ("joints", f"{self.n_joints}"), ("vehicle", meta.get("vehicle") or "-"),
                ("controller", meta.get("controller") or "off"),
                ("signals", ", ".join(list(self.signals)[:8]) + (", ..." if len(self.signals) > 8 else "") or "-"),
                ("complete", "yes" if self.complete else f"no: {self.message}")]
        if K:
            rows.append(("final position", "[" + ", ".join(f"{v:+.4g}" for v in self.position[-1]) + "] m"))
        body = "".join(f"<tr><th style='text-align:left'>{html.escape(str(a))}</th>"
                       f"<td style='text-align:left'>{html.escape(str(b))}</td></tr>" for a, b in rows)
        return f"<div><b>uvms Result</b> (.plot(), .animate(), .to_dataframe())<table>{body}</table></div>"


def _json_default(obj):
    if isinstance(obj, np.ndarray):
        return obj.tolist()
    if isinstance(obj, (np.floating, np.integer)):
        return obj.item()
    return str(obj)


PLOTTED_COLUMNS = ("t_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", "ee_x_m", "ee_y_m")
"""Columns every saved run's table has (what ``uvms plot`` needs at the least)."""

MAX_TABLE_BYTES = 256 * 1024 * 1024
"""Largest ``result.csv`` read back [bytes] (256 MiB: a 100 s run of the BlueROV2 Heavy + Alpha 5 recorded every
millisecond is about 90 MiB). Checked with ``stat`` before reading, so a refusal takes milliseconds."""

MAX_TABLE_COLUMNS = 10_000
"""Most columns of a ``result.csv`` (a model with 100 joints and 100 thrusters has about 700 with its signals).
Counted on the header line, read on its own (at most :data:`MAX_HEADER_BYTES`), before the table is parsed."""

MAX_HEADER_BYTES = 1024 * 1024
"""Longest header line of a ``result.csv`` [bytes]."""

MAX_SUMMARY_BYTES = 16 * 1024 * 1024
"""Largest ``result.json`` read back [bytes]; nested at most :data:`uvms.safe_json.MAX_DEPTH` levels."""

_SUMMARY_TYPES = {"complete": bool, "message": str, "metadata": dict, "health": dict}
_METADATA_TYPES = {"scenario": str, "vehicle": str, "controller": str}


def _check_table_file(path: Path) -> None:
    """Refuse, before parsing, a table larger than :data:`MAX_TABLE_BYTES` or with more than
    :data:`MAX_TABLE_COLUMNS` columns (one line naming the file); a refusal reads at most the header line."""
    from uvms.safe_json import size_text

    try:
        size = path.stat().st_size
        if size > MAX_TABLE_BYTES:
            raise UvmsInputError(f"refused: larger than {size_text(MAX_TABLE_BYTES)} ({size_text(size)}), more than a "
                                 "uvms run writes", str(path))
        with path.open("rb") as fh:
            header = fh.readline(MAX_HEADER_BYTES + 1)
    except OSError as exc:
        raise UvmsInputError(f"cannot read the table: {exc.strerror or exc}", str(path)) from None
    if len(header) > MAX_HEADER_BYTES:
        raise UvmsInputError(f"refused: a header line longer than {size_text(MAX_HEADER_BYTES)}, not a uvms result "
                             "table", str(path))
    columns = header.count(b",") + 1
    if columns > MAX_TABLE_COLUMNS:
        raise UvmsInputError(f"refused: {columns:,} columns, more than the {MAX_TABLE_COLUMNS:,} a uvms result "
                             "table may have", str(path))


def check_times(time, source: str | None = None) -> None:
    """Refuse sample times that cannot be replayed: not finite (NaN, inf) or decreasing. One line, naming the
    first bad sample; a run uvms wrote has finite, increasing times."""
    time = np.asarray(time, dtype=float).reshape(-1)
    bad = np.flatnonzero(~np.isfinite(time))
    if bad.size:
        raise UvmsInputError(f"expected finite times, found {time[bad[0]]} in sample {bad[0] + 1}", source, "t_s")
    back = np.flatnonzero(time[1:] < time[:-1])
    if back.size:
        k = int(back[0]) + 1
        raise UvmsInputError(f"expected times that do not decrease, found {time[k]:.6g} after {time[k - 1]:.6g} "
                             f"in sample {k + 1}", source, "t_s")
    if time.size and not math.isfinite(float(time[-1]) - float(time[0])):   # Python floats: inf, no warning
        raise UvmsInputError(f"expected a finite time span, found {time[0]:.6g}..{time[-1]:.6g} s", source, "t_s")


def load_sensor_table(path: Path):
    """A saved sensor's table (``t_s`` and its columns, :meth:`Result.save`) as a DataFrame of numbers, checked
    as a result table is (size, columns, numbers, times): a one-line :class:`~uvms.errors.UvmsInputError`."""
    import pandas as pd

    if not path.is_file():
        raise UvmsInputError("no such sensor table (the run's metadata lists it)", str(path))
    _check_table_file(path)
    try:
        table = pd.read_csv(path)
    except (ValueError, pd.errors.ParserError) as exc:
        raise UvmsInputError(f"not a sensor table: {' '.join(str(exc).split())[:120]}", str(path)) from None
    if "t_s" not in table.columns or any(table[c].dtype.kind not in "fiu" for c in table.columns):
        raise UvmsInputError("not a sensor table: expected a t_s column and numbers in every column", str(path))
    check_times(table["t_s"].to_numpy(dtype=float), str(path))
    return table


def check_result_files(directory, name: str = "result") -> None:
    """The checks of :func:`load_result_table` and :func:`load_result_summary` that need no parsing (the run
    folder and its table exist; sizes, column count and JSON nesting within their limits), done first by
    ``uvms plot`` and ``uvms animate`` so that a refusal comes before any heavy import (well under 1 s)."""
    directory = Path(directory)
    if not directory.is_dir():
        raise UvmsInputError("no such run directory", str(directory))
    path = directory / f"{name}.csv"
    if not path.is_file():
        raise UvmsInputError(f"no {name}.csv here (write one with 'uvms run SCENARIO -o DIR')", str(directory))
    _check_table_file(path)
    load_result_summary(directory, name)


def load_result_table(directory, name: str = "result"):
    """A saved run's ``<name>.csv`` as a pandas DataFrame of numbers, checked: a missing, damaged, oversized
    (:data:`MAX_TABLE_BYTES`, :data:`MAX_TABLE_COLUMNS`) or foreign table is a one-line
    :class:`~uvms.errors.UvmsInputError` naming the file, and the column and row; so are times ``t_s`` that are
    not finite or that decrease."""
    directory = Path(directory)
    path = directory / f"{name}.csv"
    if not directory.is_dir():
        raise UvmsInputError("no such run directory", str(directory))
    if not path.is_file():
        raise UvmsInputError(f"no {name}.csv here (write one with 'uvms run SCENARIO -o DIR')", str(directory))
    _check_table_file(path)
    import pandas as pd   # after the size checks: a refusal does not wait for pandas to import
    try:
        table = pd.read_csv(path)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError, OSError) as exc:
        raise UvmsInputError(f"cannot read the table: {' '.join(str(exc).split())[:200]}", str(path)) from None
    missing = [c for c in PLOTTED_COLUMNS if c not in table.columns]
    if missing or table.empty:
        what = f"missing columns {', '.join(missing)}" if missing else "no rows"
        raise UvmsInputError(f"not a uvms result table: {what}", str(path))
    for column in table.columns:
        values = table[column]
        if pd.api.types.is_bool_dtype(values) or not pd.api.types.is_numeric_dtype(values):
            numbers = pd.to_numeric(values, errors="coerce")
            row = int(numbers.isna().to_numpy().nonzero()[0][0]) if numbers.isna().any() else 0
            raise UvmsInputError(f"expected numbers, found {show(values.iloc[row])} in row {row + 1}",
                                 str(path), f"column {show(column)}")
    try:
        check_times(table["t_s"].to_numpy(dtype=float), str(path))
    except UvmsInputError as exc:
        raise UvmsInputError(exc.message.replace("sample", "row"), exc.source, "column 't_s'") from None
    return table


def load_result_summary(directory, name: str = "result") -> dict:
    """A saved run's ``<name>.json`` (``{}`` when there is none), checked: at most :data:`MAX_SUMMARY_BYTES` and
    :data:`uvms.safe_json.MAX_DEPTH` levels deep (refused before parsing), and what is there has the types
    :meth:`Result.summary` writes, else a one-line :class:`~uvms.errors.UvmsInputError` naming the field."""
    from uvms.safe_json import read_json

    path = Path(directory) / f"{name}.json"
    if not path.exists():
        return {}
    summary = read_json(path, max_bytes=MAX_SUMMARY_BYTES)
    if not isinstance(summary, dict):
        raise UvmsInputError(f"expected a mapping, found {show(summary)}", str(path))
    for fields, where, prefix in ((_SUMMARY_TYPES, summary, ""), (_METADATA_TYPES, summary.get("metadata") or {},
                                                                   "metadata.")):
        for key, kind in fields.items():
            if key in where and where[key] is not None and not isinstance(where[key], kind):
                raise UvmsInputError(f"expected {kind.__name__}, found {show(where[key])}", str(path),
                                     prefix + key)
    return summary
