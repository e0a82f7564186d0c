"""The whole closed loop compiled: controller updates, thrust allocation, arm trackers and RK4 in one numba
function (:func:`advance`), with no Python between two calls.

At each event step (a controller update, an arm update, a torque-schedule breakpoint: :func:`_due`; and, for
a controller fed measurements, each sensor's sample step)::

    x_hat    <- sense(sensing, x)                                   (measured feedback: the sensors due now and
                                                                     the estimator, uvms.control.estimator)
    tau      <- arm_torques(arm, t, x)                              (every event, or at the arm's period)
    nu_dot   <- the plant's true acceleration with the held inputs  (only for a controller that measures it)
    wrench   <- controller_update(controller, t, x or x_hat, tau, nu_dot)   (at the controller's period)
    command  <- allocate_command(allocation, wrench)                (thrusts -> actuator commands)
    log the update (step, tau, signals); RK4 to the next event

A call advances from ``start`` to ``stop`` and can be resumed: events at ``stop`` are processed by the next
call. The function holds no Python object and releases the GIL (``nogil``), so :func:`uvms.rollout` runs
several in threads.

This module is the only event loop: its schedule (:class:`Schedule`, :func:`_due`, :func:`_next_event`), its
logging rule (:func:`_log_update`) and its signal layout (:func:`_command`) also drive the loop with events in
Python (:mod:`uvms.sim.loop`: a user's Python controller or arm, or an adaptive integrator), through the thin
wrappers :func:`event_start` and :func:`event_end`; both loops are cut into calls by
:func:`uvms.sim.chunks.run_in_chunks`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.experimental import structref

from uvms.control.arm import arm_torques
from uvms.control.estimator import next_sample, sense
from uvms.control.kernels import controller_update
from uvms.dynamics.plant import plant_data
from uvms.jit import kernel
from uvms.sim.integrate import derivative_kernel, rk4_steps
from uvms.state import JOINTS, NU
from uvms.thrusters.command import allocate_command


class Control(NamedTuple):
    """The compiled controller, arm and allocation of a run, their scratch, and the sensing of a controller fed
    measurements."""

    controller: tuple           # uvms.control.compiled.ControllerData
    arm: tuple                  # uvms.control.arm.ArmData
    allocation: tuple           # uvms.thrusters.command.ThrustCommand
    wrench: np.ndarray          # (6,) the last commanded body wrench [K M N X Y Z]
    xdot: np.ndarray            # (N,) scratch: the state derivative for a measured acceleration
    allocation_signals: np.ndarray  # (m + 6,) thrusts and unachieved wrench of the last allocation (m = 0: empty)
    signals: np.ndarray         # (S,) [controller signals | wrench | allocation signals] of the last update
    sensing: tuple              # uvms.control.estimator.SensingData (inactive: the controller reads x)


class Schedule(NamedTuple):
    """The event grid of a run, in steps of ``h`` seconds."""

    h: float
    n_total: int
    control_every: int          # 0: no controller
    arm_every: int              # 0: the torques are re-evaluated at every event (constant or schedule)
    breakpoints: np.ndarray     # (B,) int64, sorted, within (0, n_total)


class Log(NamedTuple):
    """The updates that hold recorded rows (zero-order hold): ``count[0]`` of them."""

    steps: np.ndarray           # (U,) int64 global step of each update
    torques: np.ndarray         # (U, n) held joint torques
    signals: np.ndarray         # (U, S) logged signals
    count: np.ndarray           # (1,) int64


def update_log(n_rows: int, n_joints: int, n_signals: int) -> Log:
    """An empty :class:`Log` for at most ``n_rows`` kept updates."""
    return Log(np.zeros(n_rows, dtype=np.int64), np.zeros((n_rows, n_joints)), np.zeros((n_rows, n_signals)),
               np.zeros(1, dtype=np.int64))


EVENT, ARM, CONTROL = 1, 2, 4
"""Flags of :func:`_due`: the step is an event; the joint torques are evaluated; the controller updates."""


def schedule_of(h: float, n_total: int, control_every: int, arm_every: int, breakpoints) -> Schedule:
    """The :class:`Schedule` of a run: the breakpoints (steps) sorted, once each, those within ``(0, n_total)``."""
    return Schedule(float(h), int(n_total), int(control_every), int(arm_every),
                    np.array(sorted(b for b in set(breakpoints) if 0 < b < n_total), dtype=np.int64))


@njit(cache=True, inline="always")
def _due(schedule, done):
    """What happens at step ``done``: 0 (not an event), else :data:`EVENT` plus :data:`ARM` (every event, or
    the arm's period) and :data:`CONTROL` (the controller's period)."""
    control = schedule.control_every > 0 and done % schedule.control_every == 0
    arm = schedule.arm_every > 0 and done % schedule.arm_every == 0
    event = done == 0 or control or arm
    if not event:
        b = schedule.breakpoints
        for k in range(b.shape[0]):
            if b[k] == done:
                event = True
    if not event:
        return 0
    due = EVENT
    if schedule.arm_every == 0 or arm:
        due |= ARM
    if control:
        due |= CONTROL
    return due


@njit(cache=True, inline="always")
def _next_event(schedule, done, stop):
    """The first event after step ``done`` (a multiple of a period, a breakpoint), or ``min(stop, n_total)``."""
    nxt = min(stop, schedule.n_total)
    for every in (schedule.control_every, schedule.arm_every):
        if every > 0:
            nxt = min(nxt, (done // every + 1) * every)
    b = schedule.breakpoints
    for k in range(b.shape[0]):
        if b[k] > done:
            nxt = min(nxt, b[k])
            break
    return nxt


@njit(cache=True, inline="always")
def _log_update(log, every, done, tau, signals):
    """Log the update at step ``done`` (its torques and signals); the previous one is dropped if no row was
    recorded while it held (rows every ``every`` steps: :func:`uvms.sim.record.result_of` never reads it)."""
    c = log.count[0]
    if c > 0 and ((log.steps[c - 1] + every - 1) // every) * every >= done:
        c -= 1                  # no row was recorded while the previous update held: forget it
    if c < log.steps.shape[0]:
        log.steps[c] = done
        for j in range(tau.shape[0]):
            log.torques[c, j] = tau[j]
        for j in range(signals.shape[0]):
            log.signals[c, j] = signals[j]
        log.count[0] = c + 1


@njit(cache=True, inline="always")
def _command(control, held):
    """Allocate the commanded wrench to the actuators and lay out the logged signals:
    ``[controller signals | wrench [K M N X Y Z] | allocation signals]`` (names: :func:`compiled_run`)."""
    ctrl = control.controller
    allocate_command(control.allocation, control.wrench, held.command, control.allocation_signals)
    s = control.signals
    k = 0
    for j in range(ctrl.signals.shape[0]):
        s[k] = ctrl.signals[j]
        k += 1
    for j in range(6):
        s[k] = control.wrench[j]
        k += 1
    for j in range(control.allocation_signals.shape[0]):
        s[k] = control.allocation_signals[j]
        k += 1


@njit(cache=True, inline="always")
def _control(plant, held, control, schedule, x, done, due, controller_compiled):
    """The controller's part of the event at step ``done`` (``due`` from :func:`_due`): its update (unless
    ``controller_compiled`` is false: a Python controller has written ``control.wrench``) and :func:`_command`."""
    if due & CONTROL:
        if controller_compiled:
            t = done * schedule.h
            ctrl = control.controller
            if ctrl.needs_acceleration:
                derivative_kernel(plant, held, t, x, control.xdot)
            seen = control.sensing.x_hat if control.sensing.active else x
            controller_update(ctrl, t, seen, held.joint_torques, control.xdot[NU:JOINTS], control.wrench)
        _command(control, held)


@njit(cache=True, inline="always")
def _update(plant, held, control, schedule, x, done, due):
    """The event at step ``done``: arm torques, controller, allocation (module docstring)."""
    if due & ARM:
        arm_torques(control.arm, done * schedule.h, x, held.joint_torques)
    _control(plant, held, control, schedule, x, done, due, True)


@kernel
def advance(plant, held, control, schedule, record, log, x, start, stop):
    """Advance ``x`` from global step ``start`` to ``stop`` (module docstring) on a plant's
    :class:`~uvms.dynamics.plant.PlantData`. Returns ``(done, code)``: ``code`` 0, or
    :func:`~uvms.sim.integrate.check_state`'s code of the step that left the sane range.

    A kernel (:mod:`uvms.jit`: no reference counting): taking the controller's ~170 arrays out of
    ``control`` in a reference-counted function costs an atomic increment and decrement each at every update,
    several times the cost of the update itself."""
    done = start
    h = schedule.h
    while done < stop:
        sense(control.sensing, x, done)         # a no-op unless a sensor of a measured feedback samples now
        due = _due(schedule, done)
        if due:
            _update(plant, held, control, schedule, x, done, due)
            _log_update(log, record.every, done, held.joint_torques, control.signals)
        nxt = next_sample(control.sensing, done, _next_event(schedule, done, stop))
        k, code = rk4_steps(plant, held, x, 0.0, h, nxt - done, done, record)
        done += k
        if code != 0:
            return done, code
    return done, 0


@structref.register
class LoopType(types.StructRef):
    """numba type of :class:`Loop`."""

    def preprocess_fields(self, fields):
        return tuple((name, types.unliteral(typ)) for name, typ in fields)


class Loop(structref.StructRefProxy):
    """Everything :func:`advance` takes besides the step range, behind one reference: a call from Python then
    passes one pointer instead of unboxing ~100 arrays (the step API calls it every few milliseconds of
    simulated time)."""


structref.define_proxy(Loop, LoopType, ["plant", "held", "control", "schedule", "record", "log", "x"])


@njit(cache=True)
def _new_loop(plant, held, control, schedule, record, log, x):
    return Loop(plant, held, control, schedule, record, log, x)


@njit(cache=True, nogil=True)
def advance_loop(loop, start, stop):
    """:func:`advance` on a :class:`Loop` (its plant read once into the named tuple the kernels take)."""
    return advance(plant_data(loop.plant), loop.held, loop.control, loop.schedule, loop.record, loop.log, loop.x,
                   start, stop)


@njit(cache=True)
def event_start(loop, done, arm_compiled):
    """For the loop with events in Python (:class:`uvms.sim.loop.PythonEvents`): :func:`_due` at step ``done``,
    and the compiled arm's torques when they are due (``arm_compiled``; else Python evaluates them)."""
    sense(loop.control.sensing, loop.x, done)
    due = _due(loop.schedule, done)
    if (due & ARM) != 0 and arm_compiled:
        arm_torques(loop.control.arm, done * loop.schedule.h, loop.x, loop.held.joint_torques)
    return due


@njit(cache=True)
def event_end(loop, done, due, controller_compiled, stop):
    """The rest of the event at step ``done`` for the loop with events in Python: the controller's part
    (:func:`_control`; a Python controller's wrench already in ``control.wrench``) and the log (:func:`_log_update`).
    Returns ``(kept updates, next event before or at stop)``."""
    if due:
        _control(plant_data(loop.plant), loop.held, loop.control, loop.schedule, loop.x, done, due,
                 controller_compiled)
        _log_update(loop.log, loop.record.every, done, loop.held.joint_torques, loop.control.signals)
    return loop.log.count[0], next_sample(loop.control.sensing, done, _next_event(loop.schedule, done, stop))


@njit(cache=True)
def next_event(schedule, done, stop):
    """:func:`_next_event` from Python (:func:`uvms.sim.plan.events`)."""
    return _next_event(schedule, done, stop)


# ----------------------------------------------------------------------------------------- the Python side


def compiled_arm(plan) -> bool:
    """Whether ``plan``'s joint torques are compiled: none, constant, a schedule or a bundled tracker (anything
    else is the user's Python callable)."""
    from uvms.sim.inputs import TorqueSchedule

    source = plan.arm.source
    return source is None or isinstance(source, (np.ndarray, TorqueSchedule)) or hasattr(source, "compiled")


def compiled_controller(plan) -> bool:
    """Whether ``plan``'s controller is none or a bundled one whose update is the compiled kernel's."""
    return plan.controller is None or bool(getattr(plan.controller, "compiled_update", False))


def compilable(plan) -> bool:
    """Whether ``plan`` runs entirely in :func:`advance`: RK4, and a bundled controller (or none) and a
    constant, scheduled or bundled-tracker arm input (anything else is the user's Python: :mod:`uvms.sim.loop`)."""
    return plan.integrator.name == "rk4" and compiled_arm(plan) and compiled_controller(plan)


class CompiledRun(NamedTuple):
    """The compiled pieces of a plan: what :func:`advance` takes besides the plant, the :class:`Loop` holding
    them all, and the signal names."""

    control: Control
    schedule: Schedule
    log: Log
    loop: Loop
    signal_names: tuple


def compiled_run(plan, n_updates: int | None = None) -> CompiledRun:
    """Build the compiled controller, arm and allocation of ``plan``; ``n_updates`` bounds the controller's
    updates (default: the run's; it sizes a noisy IMU's noise table). A user's Python arm (not
    :func:`compiled_arm`) gets a placeholder its Python events fill in, and a Python controller (not
    :func:`compiled_controller`) the placeholder :func:`~uvms.control.kernels.no_controller`: its signals are
    then only the command and the allocation (its own are logged in Python, :class:`uvms.sim.loop.PythonLog`)."""
    from uvms.control.arm import constant_arm, schedule_arm
    from uvms.control.kernels import no_controller
    from uvms.sim.inputs import TorqueSchedule
    from uvms.sim.chunks import COMMAND_NAMES
    from uvms.thrusters.command import thrust_command, thrust_command_names

    timing, n = plan.timing, plan.layout.n_joints
    source = plan.arm.source
    if source is None or not compiled_arm(plan):
        arm = constant_arm(np.zeros(n))
    elif isinstance(source, TorqueSchedule):
        arm = schedule_arm(source, timing.h)
    elif isinstance(source, np.ndarray):
        arm = constant_arm(source)
    else:
        arm = source.compiled()
    names: tuple = ()
    controller = no_controller()
    if plan.controller is not None:
        if hasattr(plan.controller, "reset"):
            plan.controller.reset()
        names = COMMAND_NAMES + tuple(thrust_command_names(plan.thrusters))
        if compiled_controller(plan):
            controller = plan.controller.compiled(n_updates or timing.n_total // plan.control_every + 2)
            names = tuple(plan.controller.signal_names) + names
    m = len(plan.thrusters)
    control = Control(controller=controller, arm=arm, allocation=thrust_command(plan.thrusters),
                      wrench=np.zeros(6), xdot=np.zeros(plan.x.size),
                      allocation_signals=np.zeros(m + 6 if m else 0), signals=np.zeros(len(names)),
                      sensing=measured_feedback(plan))
    schedule = plan.schedule()
    log = update_log(plan.samples.times.shape[0] + 2, n, len(names))
    loop = _new_loop(plan.plant, plan.held, control, schedule, plan.samples, log, plan.x)
    return CompiledRun(control, schedule, log, loop, names)


def measured_feedback(plan):
    """The :class:`~uvms.control.estimator.SensingData` of ``plan``: active for a bundled controller with
    ``feedback: measured`` (from the run's sensors and its initial state), else the inactive placeholder."""
    from uvms.control.estimator import no_sensing, sensing_data

    controller = plan.controller
    feedback = getattr(getattr(controller, "parameters", None), "feedback", "true_state")
    if controller is None or feedback != "measured" or not compiled_controller(plan):
        return no_sensing(plan.x.size)
    return sensing_data(plan.recording.sensors, plan.model, plan.x, h=plan.timing.h, n_total=plan.timing.n_total,
                        surface=float(plan.water.surface) if plan.water is not None else 0.0)


class CompiledLog:
    """A :class:`Log` read as :func:`uvms.sim.record.result_of` reads a log: ``steps``, ``torques``, ``held``."""

    def __init__(self, log: Log, names: tuple) -> None:
        c = int(log.count[0])
        self.steps, self.torques = log.steps[:c], log.torques[:c]
        self._signals, self._names = log.signals[:c], names

    def held(self, which: np.ndarray) -> dict[str, np.ndarray]:
        """Each signal's value at every recorded row (the update ``which[r]`` holding row ``r``)."""
        order = sorted(range(len(self._names)), key=lambda j: self._names[j])
        columns = np.ascontiguousarray(self._signals[which].T)       # one gather, then a row per signal
        return {self._names[j]: columns[j] for j in order}


def run_compiled(plan, chunking):
    """Advance ``plan`` to its end (or divergence) in calls of :func:`advance` cut by
    :func:`uvms.sim.chunks.run_in_chunks` (Ctrl-C and progress in between)."""
    from uvms.sim.chunks import run_in_chunks

    run = compiled_run(plan)
    outcome = run_in_chunks(plan, chunking, lambda start, stop: advance_loop(run.loop, start, stop))
    return outcome, CompiledLog(run.log, run.signal_names)
