"""What a vehicle controller sees and returns (the interface every controller implements).

A controller runs at its own rate (``period``, zero-order hold in between). At each update it receives a
:class:`Measurement` (time, the measured state, the joint torques being applied, and the vehicle's true body
acceleration for sensor models such as a simulated IMU to corrupt) and returns a :class:`ControlOutput`: the
commanded body wrench ``f_0 = [moment; force]`` (body axes; allocated to thrusters afterwards) and named
scalar signals to log (``s_surge``, ``Phi``, ...).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np

from uvms.state import State


class Measurement:
    """What the controller can use at an update.

    Attributes:
        time: [s].
        state: vehicle pose and velocity, joint angles and rates (perfect measurement).
        joint_torques: (n,) torques applied at the joints over the coming interval [N m].
        nu_dot: (6,) the vehicle's true body acceleration ``[omega_dot; v_dot]`` at this instant (for IMU
            models; an honest controller never uses it directly). The simulator passes ``nu_dot_source``, a
            function evaluated only if a controller asks (one dynamics evaluation saved per update otherwise).
        sensors: the latest reading of each simulated sensor of the run (``simulate(sensors=...)``, a scenario's
            ``sensors:``), by sensor name: a :class:`uvms.sensors.Reading` whose ``values`` hold its channels
            (``reading["gyro_z"]`` [rad/s]; ``accel_*`` [m/s^2], ``pressure`` [Pa], ``depth`` [m], ``bottom_*``,
            ``water_*`` [m/s], ``bottom_valid`` (1/0), ``altitude`` [m], encoders' joints [rad or m]) and its
            ``time`` [s], the sample's (at or before the update: each sensor samples at its own rate). Empty
            without sensors. ``docs/sensors.md``, "Controllers fed measurements".
    """

    __slots__ = ("time", "state", "joint_torques", "sensors", "_nu_dot", "_nu_dot_source")

    def __init__(self, time: float, state: State, joint_torques: np.ndarray, nu_dot: np.ndarray | None = None,
                 *, nu_dot_source: Callable[[], np.ndarray] | None = None, sensors: dict | None = None) -> None:
        if nu_dot is None and nu_dot_source is None:
            raise ValueError("Measurement needs nu_dot or nu_dot_source")
        self.time = time
        self.state = state
        self.joint_torques = joint_torques
        self.sensors = {} if sensors is None else sensors
        self._nu_dot = None if nu_dot is None else np.asarray(nu_dot, dtype=float)
        self._nu_dot_source = nu_dot_source

    @property
    def nu_dot(self) -> np.ndarray:
        if self._nu_dot is None:
            self._nu_dot = np.asarray(self._nu_dot_source(), dtype=float)
        return self._nu_dot


@dataclass(frozen=True)
class ControlOutput:
    """A controller's command: body wrench (6,) ``[moment; force]`` [N m, N] and logged signals."""

    wrench: np.ndarray
    signals: dict[str, float] = field(default_factory=dict)


class Controller(Protocol):
    """A vehicle controller: ``period`` [s] and ``update(measurement) -> ControlOutput``; ``reset()`` before a run."""

    period: float

    def reset(self) -> None: ...

    def update(self, measurement: Measurement) -> ControlOutput: ...


class ArmCommand(Protocol):
    """Joint torques as a function of time and state (a schedule, or a trajectory-tracking arm controller)."""

    def torques(self, time: float, state: State) -> np.ndarray: ...
