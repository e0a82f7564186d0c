"""Inputs of a run: joint-torque and thruster-command schedules and time tables for the current (paper
Section 6's torques).

A :class:`TorqueSchedule` is piecewise constant: ``torques[k]`` applies for ``times[k] <= t < times[k+1]``
(the last row until the end); so is a :class:`CommandSchedule` of the thrusters' commands (a log's, replayed).
A :class:`CurrentTable` holds world-frame current velocity and fluid
acceleration at given times, interpolated linearly; a Python callable ``current(t) -> (3,)`` is sampled onto
such a table on the integrator's half-step grid, so RK4 sees it exactly at every stage.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from uvms import checks


@dataclass(frozen=True)
class TorqueSchedule:
    """Piecewise-constant joint torques [N m]: ``torques[k]`` from ``times[k]`` on."""

    times: np.ndarray      # (K,) increasing, times[0] == 0 [s]
    torques: np.ndarray    # (K, n) [N m]

    def __post_init__(self) -> None:
        t = checks.vector(self.times, None, "times", " [s]")
        one_row = isinstance(self.torques, np.ndarray | list | tuple) and np.ndim(self.torques[:1]) == 1
        tau = checks.matrix([self.torques] if one_row else self.torques, t.size, None, "torques",
                            " [N m] (one row per time)")
        if t.size == 0 or t[0] != 0.0 or np.any(np.diff(t) <= 0):
            raise checks.fail("times", "expected times that start at 0 and increase")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "torques", tau)

    def __call__(self, t: float) -> np.ndarray:
        k = int(np.searchsorted(self.times, t + 1e-12, side="right") - 1)
        return self.torques[max(k, 0)]

    def breakpoints(self) -> np.ndarray:
        """Times where the torque changes (after 0)."""
        return self.times[1:]

    @classmethod
    def constant(cls, torques) -> "TorqueSchedule":
        return cls(times=np.array([0.0]), torques=np.atleast_2d(np.asarray(torques, dtype=float)))


@dataclass(frozen=True)
class CommandSchedule:
    """Piecewise-constant actuator commands: ``commands[k]`` held from ``times[k]`` to ``times[k+1]`` (the last
    row until the end), as a logged command is held until the next one (zero-order hold).

    Each column is one thruster's command in that thruster's own unit (:mod:`uvms.thrusters.kinds`: thrust [N]
    for ideal and first-order thrusters, voltage [V] for Healey's, the table's command, e.g. an ESC pulse width
    [us], for a table thruster). ``names`` label the columns with the actuation's thruster names (any order;
    every thruster must have one); ``None``: the actuation's order. A run holds the row in force at each RK4
    step's start over the whole step (the commands change on the step grid).
    """

    times: np.ndarray              # (K,) increasing, times[0] == 0 [s]
    commands: np.ndarray           # (K, m) in each thruster's command unit
    names: tuple[str, ...] | None = None

    def __post_init__(self) -> None:
        t = checks.vector(self.times, None, "times", " [s]")
        u = checks.matrix(self.commands, t.size, None, "commands", " (one row per time, one column per thruster)")
        if t.size == 0 or t[0] != 0.0 or np.any(np.diff(t) <= 0):
            raise checks.fail("times", "expected times that start at 0 and increase")
        names = self.names
        if names is not None:
            names = tuple(names)
            if len(names) != u.shape[1] or len(set(names)) != len(names) or not all(
                    isinstance(x, str) and x for x in names):
                raise checks.fail("names", f"expected {u.shape[1]} distinct thruster names (one per column), got "
                                           f"{checks.show(self.names)}")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "commands", u)
        object.__setattr__(self, "names", names)

    def __call__(self, t: float) -> np.ndarray:
        k = int(np.searchsorted(self.times, t + 1e-12, side="right") - 1)
        return self.commands[max(k, 0)]

    def for_thrusters(self, thrusters) -> np.ndarray:
        """(K, m) the columns in the order of ``thrusters`` (each with a ``name``); a one-line error when a
        thruster has no column or a column names no thruster."""
        have = tuple(th.name for th in thrusters)
        if not have:
            raise checks.fail("thruster_commands", "expected thrusters to command (the actuation has none: pass "
                                                   "actuation=Actuation.named('model', model))")
        if self.names is None:
            if self.commands.shape[1] != len(have):
                raise checks.fail("thruster_commands", f"expected {len(have)} command columns (one per thruster: "
                                                       f"{', '.join(have)}), got {self.commands.shape[1]}")
            return self.commands
        missing = [x for x in have if x not in self.names]
        unknown = [x for x in self.names if x not in have]
        if missing or unknown:
            raise checks.fail("thruster_commands", "expected a command column for every thruster ("
                              + ", ".join(have) + ")" + (f"; missing {', '.join(missing)}" if missing else "")
                              + (f"; not a thruster: {', '.join(unknown)}" if unknown else ""))
        return self.commands[:, [self.names.index(x) for x in have]]


def paper_torques() -> TorqueSchedule:
    """Section 6: ``tau = [2.5, 0, 0]`` N m for ``t < 2`` s, then ``[0.01, 0, 0]`` N m (decimal comma read as
    2.5, ``docs/conventions.md``)."""
    return TorqueSchedule(times=np.array([0.0, 2.0]), torques=np.array([[2.5, 0.0, 0.0], [0.01, 0.0, 0.0]]))


@dataclass(frozen=True)
class CurrentTable:
    """World-frame current velocity [m/s] and fluid acceleration [m/s^2] at ``times`` [s] (linear between)."""

    times: np.ndarray          # (K,)
    velocity: np.ndarray       # (K, 3)
    acceleration: np.ndarray   # (K, 3)

    def __post_init__(self) -> None:
        t = checks.vector(self.times, None, "times", " [s]")
        if t.size == 0 or np.any(np.diff(t) <= 0):
            raise checks.fail("times", "expected at least one time, increasing")
        for name, unit in (("velocity", "m/s"), ("acceleration", "m/s^2")):
            object.__setattr__(self, name, checks.matrix(getattr(self, name), t.size, 3, name,
                                                         f" [{unit}] (one row per time)"))
        object.__setattr__(self, "times", t)

    @classmethod
    def constant(cls, velocity, acceleration=(0.0, 0.0, 0.0)) -> "CurrentTable":
        return cls(np.zeros(1), np.atleast_2d(np.asarray(velocity, dtype=float)),
                   np.atleast_2d(np.asarray(acceleration, dtype=float)))

    @classmethod
    def from_velocity_table(cls, times, velocity, duration: float, step: float) -> "CurrentTable":
        """A velocity table (linear between knots, held outside) with its exact fluid acceleration: the slope of
        each segment, zero outside the table; resampled on the integrator's half-step grid."""
        t_k = checks.vector(times, None, "times", " [s]")
        v_k = checks.matrix(velocity, t_k.size, 3, "velocity", " [m/s] (one row per time)")
        if t_k.size == 0 or np.any(np.diff(t_k) <= 0):
            raise checks.fail("times", "expected at least one time, increasing")
        if t_k.size == 1:
            return cls.constant(v_k[0])
        slopes = np.diff(v_k, axis=0) / np.diff(t_k)[:, None]

        def vel(t: float) -> np.ndarray:
            return np.array([np.interp(t, t_k, v_k[:, j]) for j in range(3)])

        def acc(t: float) -> np.ndarray:
            if t < t_k[0] or t >= t_k[-1]:
                return np.zeros(3)
            return slopes[min(int(np.searchsorted(t_k, t, side="right")) - 1, slopes.shape[0] - 1)]

        return cls.from_function(vel, duration, step, acceleration=acc)

    @classmethod
    def from_function(cls, velocity: Callable[[float], np.ndarray], duration: float, step: float,
                      acceleration: Callable[[float], np.ndarray] | None = None) -> "CurrentTable":
        """Sample ``velocity(t)`` on the half-step grid; the acceleration by central differences unless given."""
        checks.callable_or_none(velocity, "velocity", "velocity(t) -> (3,)")
        checks.callable_or_none(acceleration, "acceleration", "acceleration(t) -> (3,)")
        duration = checks.number(duration, "duration", positive=True, unit="s")
        step = checks.number(step, "step", positive=True, unit="s")
        if velocity is None or duration / step > 1e8:
            raise checks.fail("velocity" if velocity is None else "step",
                              "expected a callable velocity(t) -> (3,)" if velocity is None
                              else f"expected at most 1e8 samples in {duration:g} s, got step {step:g} s")
        t = np.arange(0.0, duration + step, step / 2.0)
        v = np.array([checks.returned_vector(velocity(ti), 3, "velocity", " [m/s]", ti) for ti in t])
        if acceleration is not None:
            a = np.array([checks.returned_vector(acceleration(ti), 3, "acceleration", " [m/s^2]", ti) for ti in t])
        else:
            a = np.gradient(v, t, axis=0) if t.size > 1 else np.zeros_like(v)
        return cls(t, v, a)
