"""The simulated sensors of a run (:mod:`uvms.sensors`), sampled on its recorded rows.

A sensor samples every ``1 / rate`` seconds, a whole number of steps (``round(1 / (rate h))``) that is a
whole multiple of the recording's steps (checked before the run; with sensors and no ``record_period`` the
rows are taken at the greatest common divisor of the sensors' periods). At each of its rows the truth is the
recorded state, the body acceleration ``nu_dot`` of the plant's derivative at that state with the inputs held
over the step that follows the row (the row's joint torques and the actuator command of the controller update
holding it: the same zero-order hold the integrator applied), and the water at the mount
(:func:`uvms.hydro.flow.fluid_at`). ``docs/sensors.md``; ``docs/conventions.md``, "Sensors".

:class:`LiveSensors` samples the same models during a run with its events in Python, for a Python controller's
``Measurement.sensors`` (a bundled controller's ``feedback: measured`` samples them compiled:
:mod:`uvms.control.estimator`).
"""

from __future__ import annotations

import math

import numpy as np

from uvms import checks
from uvms.sensors import KINDS, SensorRecord, Truth
from uvms.state import JOINTS, NU, POSITION, QUATERNION

SENSOR_TYPES = tuple(KINDS.values())


def checked_sensors(sensors) -> tuple:
    """``sensors`` (a sequence of :mod:`uvms.sensors` objects) as a tuple, each with a positive finite rate and
    a name of its own."""
    if sensors is None:
        return ()
    if isinstance(sensors, SENSOR_TYPES):
        sensors = (sensors,)
    sensors = tuple(sensors)
    names = set()
    for i, sensor in enumerate(sensors):
        if not isinstance(sensor, SENSOR_TYPES):
            raise checks.fail(f"sensors[{i}]", f"expected a uvms.sensors Imu, PressureSensor, Dvl or Encoders, "
                                                f"got {checks.show(sensor)}")
        if not (isinstance(sensor.rate, (int, float)) and math.isfinite(sensor.rate) and sensor.rate > 0):
            raise checks.fail(f"sensors.{sensor.name}.rate", f"expected a positive rate [Hz], got "
                                                             f"{checks.show(sensor.rate)}")
        if sensor.name in names:
            raise checks.fail(f"sensors.{sensor.name}", "expected each sensor's name once")
        names.add(sensor.name)
    return sensors


def sensor_steps(sensors: tuple, h: float) -> list[int]:
    """Each sensor's period in whole steps of ``h`` (at least one)."""
    return [max(1, int(round(1.0 / (s.rate * h)))) for s in sensors]


def record_every_for(sensors: tuple, h: float, every: int | None) -> int | None:
    """The recording's steps between rows with ``sensors``: ``every`` (given by a ``record_period``) when each
    sensor's period is a whole multiple of it, else an error naming the sensor; with ``every=None`` the greatest
    common divisor of the sensors' periods. ``None`` without sensors and ``every``."""
    if not sensors:
        return every
    steps = sensor_steps(sensors, h)
    if every is None:
        return math.gcd(*steps)
    for sensor, k in zip(sensors, steps):
        if k % every:
            raise checks.fail(f"sensors.{sensor.name}.rate",
                              f"expected a period (1 / rate = {k} steps of {h:g} s) that is a whole multiple of the "
                              f"record period ({every} steps): change the rate or the record_period")
    return every


def row_truth(plan, t, x, tau, signals) -> Truth:
    """The :class:`~uvms.sensors.Truth` of every recorded row (module docstring)."""
    from uvms.dynamics.plant import Held
    from uvms.rotations import rotations_from_quaternions
    from uvms.sim.chunks import COMMAND_NAMES
    from uvms.sim.integrate import derivative
    from uvms.thrusters.command import allocate_command, thrust_command

    n = plan.layout.n_joints
    held = plan.held
    nu_dot = np.zeros((t.shape[0], 6))
    xdot = np.zeros(x.shape[1])
    commands = None
    if plan.controller is not None and all(c in signals for c in COMMAND_NAMES):
        wrenches = np.stack([signals[c] for c in COMMAND_NAMES], axis=1)
        allocation = thrust_command(plan.thrusters)
        m = len(plan.thrusters)
        commands = np.zeros((t.shape[0], held.command.shape[0]))
        extra = np.zeros(m + 6 if m else 0)
        for r in range(t.shape[0]):
            allocate_command(allocation, np.ascontiguousarray(wrenches[r]), commands[r], extra)
    for r in range(t.shape[0]):
        row = Held(np.ascontiguousarray(tau[r], dtype=float), held.body_wrench, held.ee_wrench,
                   commands[r] if commands is not None else held.command)
        derivative(plan.plant, row, float(t[r]), np.ascontiguousarray(x[r]), xdot)
        nu_dot[r] = xdot[NU:JOINTS]
    quaternion = x[:, QUATERNION:NU] / np.linalg.norm(x[:, QUATERNION:NU], axis=1, keepdims=True)
    surface = float(plan.water.surface) if plan.water is not None else 0.0
    return Truth(time=t, position=x[:, POSITION:QUATERNION], rotation=rotations_from_quaternions(quaternion),
                 nu=x[:, NU:JOINTS], nu_dot=nu_dot, q=x[:, JOINTS:JOINTS + n],
                 gravity=np.asarray(plan.model.gravity, dtype=float), convention=plan.model.convention,
                 surface=surface)


def sensor_records(plan, t, x, tau, signals) -> dict[str, SensorRecord]:
    """Each sensor's :class:`~uvms.sensors.SensorRecord` from the recorded rows ``t`` (K,), ``x`` (K, N), the
    held joint torques ``tau`` (K, n) and the signals (module docstring), by name."""
    sensors = plan.recording.sensors
    if not sensors:
        return {}
    h = plan.timing.h
    step = np.round(t / h).astype(np.int64)
    wanted = np.zeros(t.shape[0], dtype=bool)
    picks = []
    for s, k in zip(sensors, sensor_steps(sensors, h)):
        rows = np.flatnonzero(step % k == 0)
        picks.append(rows)
        wanted[rows] = True
    index = np.flatnonzero(wanted)
    truth = row_truth(plan, t[index], x[index], tau[index], {k: v[index] for k, v in signals.items()})
    where = np.full(t.shape[0], -1)
    where[index] = np.arange(index.size)
    out = {}
    for sensor, rows in zip(sensors, picks):
        own = Truth(*(f[where[rows]] if isinstance(f, np.ndarray) and f.ndim and f.shape[0] == index.size
                      and name != "gravity" else f for name, f in zip(Truth._fields, truth)))
        out[sensor.name] = sensor.measure(own, plan.water) if sensor.kind == "dvl" else sensor.measure(own)
    return out


class LiveSensors:
    """The sensors sampled during a run with its events in Python (:mod:`uvms.sim.loop`), for a Python
    controller's :attr:`~uvms.control.base.Measurement.sensors`: at each of a sensor's sample steps, before that
    step's arm and controller updates, the sensor's model (:meth:`reading`) on the state there. The truth is the
    one :func:`row_truth` takes, but the inputs held are those of the step that ends at the sample (the left
    limit: a sensor samples before the controller acts on its sample; at step 0 no input is held yet, neither
    joint torques nor a command), so an accelerometer's sample at a step where an input changes differs from the
    recorded one (the right limit); every other channel is the recorded sample's. The errors are the sensor's own (:meth:`errors`) drawn once for the whole run, so sample ``k`` has
    the recorded sample's noise. ``docs/sensors.md``, "Controllers fed measurements"."""

    def __init__(self, plan) -> None:
        from uvms.checks import MAX_RECORDED_VALUES

        self.plan = plan
        self.sensors = plan.recording.sensors
        self.steps = sensor_steps(self.sensors, plan.timing.h)
        n_total = plan.timing.n_total
        counts = [n_total // k + 1 for k in self.steps]
        if sum(counts) * 6 > MAX_RECORDED_VALUES:
            raise checks.fail("sensors", f"expected at most {MAX_RECORDED_VALUES // 6:.3g} sensor samples in a run "
                                         f"(their noise is drawn before it), found {sum(counts):.3g}")
        self.errors = [s.errors(c) for s, c in zip(self.sensors, counts)]
        self.latest: dict = {}
        self._xdot = np.zeros(plan.x.size)

    def next_sample(self, done: int) -> int:
        """The first sample step after ``done``."""
        return min((done // k + 1) * k for k in self.steps)

    def sample(self, done: int) -> None:
        """Sample every sensor due at step ``done`` into :attr:`latest` (a :class:`~uvms.sensors.Reading` each)."""
        from uvms.rotations import rotations_from_quaternions
        from uvms.sensors import Reading
        from uvms.sim.integrate import derivative

        due = [i for i, k in enumerate(self.steps) if done % k == 0]
        if not due:
            return
        plan = self.plan
        t = done * plan.timing.h
        x = plan.x.copy()
        n = plan.layout.n_joints
        nu_dot = np.zeros((1, 6))
        if any(self.sensors[i].kind == "imu" for i in due):
            derivative(plan.plant, plan.held, t, x, self._xdot)
            nu_dot[0] = self._xdot[NU:JOINTS]
        quaternion = x[QUATERNION:NU] / np.linalg.norm(x[QUATERNION:NU])
        truth = Truth(time=np.array([t]), position=x[None, POSITION:QUATERNION],
                      rotation=rotations_from_quaternions(quaternion[None]), nu=x[None, NU:JOINTS], nu_dot=nu_dot,
                      q=x[None, JOINTS:JOINTS + n], gravity=np.asarray(plan.model.gravity, dtype=float),
                      convention=plan.model.convention,
                      surface=float(plan.water.surface) if plan.water is not None else 0.0)
        for i in due:
            sensor, k = self.sensors[i], done // self.steps[i]
            errors = {name: e[k:k + 1] for name, e in self.errors[i].items()}
            record = (sensor.reading(truth, errors, plan.water) if sensor.kind == "dvl"
                      else sensor.reading(truth, errors))
            self.latest[sensor.name] = Reading.of(record)
