"""The whole closed loop compiled: controller updates, thrust allocation, arm trackers and RK4 in one numba
function (:func:`advance`), with no Python between two calls.

At each event step (a controller update, an arm update, a torque-schedule breakpoint)::

    tau      <- arm_torques(arm, t, x)                              (every event, or at the arm's period)
    nu_dot   <- the plant's true acceleration with the held inputs  (only for a controller that measures it)
    wrench   <- controller_update(controller, t, x, tau, nu_dot)    (at the controller's period)
    command  <- allocate_command(allocation, wrench)                (thrusts -> actuator commands)
    log the update (step, tau, signals); RK4 to the next event

as :func:`uvms.sim.loop.run_python` does with Python objects. A call advances from ``start`` to ``stop`` and
can be resumed: events at ``stop`` are processed by the next call. The function holds no Python object and
releases the GIL (``nogil``), so :func:`uvms.rollout` runs several in threads.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, types
from numba.experimental import structref

from uvms.control.arm import arm_torques
from uvms.control.kernels import controller_update
from uvms.dynamics.plant import plant_data
from uvms.jit import kernel
from uvms.sim.integrate import derivative_kernel, rk4_steps
from uvms.state import JOINTS, NU
from uvms.thrusters.command import allocate_command


class Control(NamedTuple):
    """The compiled controller, arm and allocation of a run, and their scratch."""

    controller: tuple           # uvms.control.compiled.ControllerData
    arm: tuple                  # uvms.control.arm.ArmData
    allocation: tuple           # uvms.thrusters.command.ThrustCommand
    wrench: np.ndarray          # (6,) the last commanded body wrench [K M N X Y Z]
    xdot: np.ndarray            # (N,) scratch: the state derivative for a measured acceleration
    allocation_signals: np.ndarray  # (m + 6,) thrusts and unachieved wrench of the last allocation (m = 0: empty)
    signals: np.ndarray         # (S,) [controller signals | wrench | allocation signals] of the last update


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


@njit(cache=True, inline="always")
def _is_event(schedule, done):
    if done == 0:
        return True
    if schedule.control_every > 0 and done % schedule.control_every == 0:
        return True
    if schedule.arm_every > 0 and done % schedule.arm_every == 0:
        return True
    b = schedule.breakpoints
    for k in range(b.shape[0]):
        if b[k] == done:
            return True
    return False


@njit(cache=True, inline="always")
def _next_event(schedule, done, stop):
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
def _update(plant, held, control, schedule, x, done):
    """The event at step ``done``: arm torques, controller, allocation (module docstring)."""
    t = done * schedule.h
    if schedule.arm_every == 0 or done % schedule.arm_every == 0:
        arm_torques(control.arm, t, x, held.joint_torques)
    if schedule.control_every > 0 and done % schedule.control_every == 0:
        ctrl = control.controller
        if ctrl.needs_acceleration:
            derivative_kernel(plant, held, t, x, control.xdot)
        controller_update(ctrl, t, x, held.joint_torques, control.xdot[NU:JOINTS], control.wrench)
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
        if _is_event(schedule, done):
            _update(plant, held, control, schedule, x, done)
            _log_update(log, record.every, done, held.joint_torques, control.signals)
        nxt = _next_event(schedule, done, stop)
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


# ----------------------------------------------------------------------------------------- the Python side


def compilable(plan) -> bool:
    """Whether ``plan`` runs entirely in :func:`advance`: RK4, and a bundled controller (or none) and a
    constant, scheduled or bundled-tracker arm input (anything else is the user's Python: :mod:`uvms.sim.loop`)."""
    from uvms.sim.inputs import TorqueSchedule

    source = plan.arm.source
    arm_ok = source is None or isinstance(source, (np.ndarray, TorqueSchedule)) or hasattr(source, "compiled")
    return plan.integrator.name == "rk4" and arm_ok and (plan.controller is None or
                                                         getattr(plan.controller, "compiled_update", False))


class CompiledRun(NamedTuple):
    """The compiled pieces of a plan: what :func:`advance` takes besides the plant, the :class:`Loop` holding
    them all, and the signal names."""

    control: Control
    schedule: Schedule
    log: Log
    loop: Loop
    signal_names: tuple


def compiled_run(plan, n_updates: int | None = None) -> CompiledRun:
    """Build the compiled controller, arm and allocation of ``plan`` (:func:`compilable` must hold);
    ``n_updates`` bounds the controller's updates (default: the run's; it sizes a noisy IMU's noise table)."""
    from uvms.control.arm import constant_arm, schedule_arm
    from uvms.control.kernels import no_controller
    from uvms.sim.inputs import TorqueSchedule
    from uvms.sim.loop import COMMAND_NAMES
    from uvms.thrusters.command import thrust_command, thrust_command_names

    timing, n = plan.timing, plan.layout.n_joints
    source = plan.arm.source
    if source is None:
        arm = constant_arm(np.zeros(n))
    elif isinstance(source, TorqueSchedule):
        arm = schedule_arm(source, timing.h)
    elif isinstance(source, np.ndarray):
        arm = constant_arm(source)
    else:
        arm = source.compiled()
    names: tuple = ()
    if plan.controller is None:
        controller = no_controller()
    else:
        if hasattr(plan.controller, "reset"):
            plan.controller.reset()
        controller = plan.controller.compiled(n_updates or timing.n_total // plan.control_every + 2)
        names = tuple(plan.controller.signal_names) + COMMAND_NAMES + tuple(thrust_command_names(plan.thrusters))
    m = len(plan.thrusters)
    control = Control(controller=controller, arm=arm, allocation=thrust_command(plan.thrusters),
                      wrench=np.zeros(6), xdot=np.zeros(plan.x.size),
                      allocation_signals=np.zeros(m + 6 if m else 0), signals=np.zeros(len(names)))
    schedule = Schedule(timing.h, timing.n_total, plan.control_every, plan.arm.every,
                        np.array(sorted(b for b in set(plan.arm.breakpoints) if 0 < b < timing.n_total),
                                 dtype=np.int64))
    log = update_log(plan.samples.times.shape[0] + 2, n, len(names))
    loop = _new_loop(plan.plant, plan.held, control, schedule, plan.samples, log, plan.x)
    return CompiledRun(control, schedule, log, loop, names)


class CompiledLog:
    """A :class:`Log` read as :class:`uvms.sim.loop.UpdateLog` is (for :func:`uvms.sim.record.result_of`)."""

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
    """Advance ``plan`` to its end (or divergence) in calls of :func:`advance` sized like the Python loop's
    RK4 calls (Ctrl-C and progress in between)."""
    import time as _time

    from uvms.sim.loop import Outcome

    run = compiled_run(plan)
    done, code, chunk = 0, 0, chunking.first
    n_total = plan.timing.n_total
    while done < n_total and code == 0:
        tic = _time.perf_counter()
        stop = min(n_total, done + chunk)
        new_done, code = advance_loop(run.loop, done, stop)
        chunk = chunking.next(stop - done, _time.perf_counter() - tic, chunk)
        done = new_done
        if code == 0:
            plan.report_progress(done)
    return Outcome(done, code), CompiledLog(run.log, run.signal_names)
