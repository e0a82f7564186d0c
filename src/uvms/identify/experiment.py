"""What identification compares: an :class:`Experiment` (one logged trial: its start, its inputs and the
measured signals) and the signals of a simulated run (``docs/logs.md``, "Identification").

Signals, in the model's frame convention (:mod:`uvms.frames`), at the measurement times ``t`` (seconds from the
trial's start):

| signal | definition | unit |
| --- | --- | --- |
| ``roll``, ``pitch`` | ZYX Euler angles of the vehicle (:func:`uvms.rotations.euler_zyx`) | rad |
| ``yaw`` | the yaw *change* from the start, unwrapped | rad |
| ``depth`` | the depth *change* from the start: ``z - z_0`` in ``ned``, ``-(z - z_0)`` in ``enu`` | m |
| ``x``, ``y`` | the horizontal position change from the start, world axes | m |
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms.errors import UvmsInputError
from uvms.frames import depth
from uvms.logs.score import wrap
from uvms.sim.options import Inputs
from uvms.state import State

SIGNALS = ("roll", "pitch", "yaw", "depth", "x", "y")
"""Signal names, in the order a result reports them."""

ANGLES = frozenset({"roll", "pitch", "yaw"})
"""The signals that are angles (wrapped differences, reported in degrees)."""

DEFAULT_SCALE = {"roll": np.radians(1.0), "pitch": np.radians(1.0), "yaw": np.radians(1.0), "depth": 0.01,
                 "x": 0.01, "y": 0.01}
"""Residual scale of each signal (its assumed noise level): residuals are divided by it, so one unit of the
cost is one degree of attitude or one centimetre of position."""


def signal_values(name: str, times, position, euler, frame: str = "ned") -> np.ndarray:
    """Signal ``name`` (:data:`SIGNALS`) of a trajectory sampled at ``times``: ``position`` (K, 3) [m] and
    ``euler`` (K, 3) ZYX angles [rad], first row at the start."""
    if name == "roll":
        return np.asarray(euler[:, 0], dtype=float)
    if name == "pitch":
        return np.asarray(euler[:, 1], dtype=float)
    if name == "yaw":
        yaw = np.unwrap(np.asarray(euler[:, 2], dtype=float))
        return yaw - yaw[0]
    if name == "depth":
        d = depth(np.asarray(position[:, 2], dtype=float), frame)
        return d - d[0]
    if name in ("x", "y"):
        k = "xy".index(name)
        return np.asarray(position[:, k], dtype=float) - position[0, k]
    raise UvmsInputError(f"signals: unknown signal {name!r}; expected one of {', '.join(SIGNALS)}")


def difference(name: str, a, b) -> np.ndarray:
    """``a - b`` of signal ``name``, wrapped to [-pi, pi) for an angle."""
    d = np.asarray(a, dtype=float) - np.asarray(b, dtype=float)
    return wrap(d) if name in ANGLES else d


def result_signals(result, times, names, frame: str = "ned") -> dict[str, np.ndarray]:
    """Signals ``names`` of a simulated :class:`~uvms.sim.result.Result` (changes from the run's first row),
    linearly interpolated onto ``times``. A run that stopped early holds its last value."""
    t = result.time
    position, euler = result.position, result.euler
    return {name: np.interp(times, t, signal_values(name, t, position, euler, frame)) for name in names}


@dataclass(frozen=True, eq=False)
class Experiment:
    """One trial as identification and scoring see it.

    Attributes:
        name: the trial's name (e.g. its log file's stem).
        initial_state: the state at the trial's start (``t = 0``).
        duration: simulated span [s].
        times: (K,) measurement times [s] from the start, increasing, within ``[0, duration]``.
        measured: ``{signal: (K,) values}`` in the model's frame (:data:`SIGNALS`, rad and m).
        inputs: what drives the run (e.g. a prescribed joint motion), as :class:`~uvms.sim.options.Inputs`.
        step: the RK4 step [s].
        frame: the frame convention the signals are in (the model's).
        actuation: the thrusters between the inputs' commands and the vehicle
            (:class:`~uvms.sim.options.Actuation`; ``None``: none, the thrusters off).
    """

    name: str
    initial_state: State
    duration: float
    times: np.ndarray
    measured: Mapping[str, np.ndarray]
    inputs: Inputs = field(default_factory=Inputs)
    step: float = 0.002
    frame: str = "ned"
    actuation: Any = None

    def __post_init__(self) -> None:
        from uvms import checks

        object.__setattr__(self, "step", checks.number(self.step, "step", positive=True, unit="s"))
        object.__setattr__(self, "duration", checks.number(self.duration, "duration", positive=True, unit="s"))
        times = np.asarray(self.times, dtype=float)
        if times.ndim != 1 or times.size < 2 or np.any(np.diff(times) <= 0) or not np.all(np.isfinite(times)):
            raise UvmsInputError(f"experiment {self.name!r}: expected at least two increasing finite measurement "
                                 f"times")
        if times[0] < 0.0 or times[-1] > self.duration + 1e-9:
            raise UvmsInputError(f"experiment {self.name!r}: measurement times outside [0, {self.duration:g}] s")
        measured = {}
        for k, v in self.measured.items():
            if k not in SIGNALS:
                raise UvmsInputError(f"experiment {self.name!r}: unknown signal {k!r}; expected one of "
                                     f"{', '.join(SIGNALS)}")
            v = np.asarray(v, dtype=float)
            if v.shape != times.shape or not np.all(np.isfinite(v)):
                raise UvmsInputError(f"experiment {self.name!r}: signal {k!r} must have {times.size} finite values")
            measured[k] = v
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "measured", measured)

    def record_period(self) -> float:
        """The recording period of its runs: the step, or the measurement spacing when that is a multiple."""
        spacing = float(np.min(np.diff(self.times)))
        k = max(1, int(np.floor(spacing / self.step + 1e-9)))
        return k * self.step
