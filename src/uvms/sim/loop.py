"""The loops that advance a :class:`~uvms.sim.plan.RunPlan`: between two events (a controller update, an arm
update, a change in the torque schedule, the end) every input is held (zero-order hold) and the integrator
advances the state.

- :func:`run_python`: the events in Python. Used when the controller or the arm is the user's own Python
  object (today's protocol: ``controller.update(Measurement) -> ControlOutput``), or with an adaptive
  integrator. The compiled RK4 loop (:func:`uvms.sim.integrate.rk4`) advances the state between events, in
  calls of about :data:`CHUNK_SECONDS` so that Ctrl-C and ``progress`` respond.

Both record the updates (:class:`UpdateLog`): the step, the held joint torques and the logged signals of
each, for the result's zero-order-hold reconstruction (:mod:`uvms.sim.record`).
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field

import numpy as np

from uvms import checks
from uvms.control.base import ControlOutput, Measurement
from uvms.sim.integrate import check_state, derivative, rk4, unpack
from uvms.state import JOINTS, NU, QUATERNION

COMMAND_NAMES = tuple(f"command_{a}" for a in ("K", "M", "N", "X", "Y", "Z"))
"""Logged commanded body wrench ``[K, M, N, X, Y, Z]`` (moments about and forces along the body axes)."""


@dataclass
class Outcome:
    """How a loop ended: steps done, the divergence code (0: none; else :func:`~uvms.sim.integrate.check_state`'s)
    and a reason when an adaptive solver gave up."""

    done: int = 0
    code: int = 0
    reason: str = ""


@dataclass
class UpdateLog:
    """The updates of a run that hold recorded rows: ``steps`` (global step of each), ``torques`` and
    ``signals`` (one dict per update, name -> value)."""

    steps: list = field(default_factory=list)
    torques: list = field(default_factory=list)
    signals: list = field(default_factory=list)

    def add(self, done: int, every: int, tau: np.ndarray, signals: dict) -> None:
        """Log an update at step ``done``; the previous one is dropped if no row was recorded while it held
        (rows are recorded every ``every`` steps)."""
        if self.steps and -(-self.steps[-1] // every) * every >= done:
            self.steps.pop()
            self.torques.pop()
            self.signals.pop()
        self.steps.append(done)
        self.torques.append(np.array(tau, dtype=float))
        self.signals.append(signals)

    def held(self, which: np.ndarray) -> dict[str, np.ndarray]:
        """Each signal's value at every recorded row (the update ``which[r]`` holding row ``r``)."""
        from uvms.sim.record import held_signals

        return held_signals(self.signals, which)


class Rk4Segments:
    """Advances a plan's state with the compiled RK4 loop, in calls of ``chunking.first`` steps at first and
    then of ``chunking.next(steps, seconds, current)`` (sized from the last call's cost: see
    :data:`uvms.sim.run.CHUNK_SECONDS`)."""

    def __init__(self, plan, chunking) -> None:
        self.plan = plan
        self.next_chunk = chunking.next
        self.chunk = chunking.first

    def __call__(self, done: int, steps: int) -> Outcome:
        plan = self.plan
        h = plan.timing.h
        k_done = code = 0
        while k_done < steps and code == 0:       # bounded calls: Ctrl-C and progress between them
            chunk = min(steps - k_done, self.chunk)
            tic = _time.perf_counter()
            k, code = rk4(plan.plant, plan.held, plan.x, 0.0, h, chunk, done + k_done, plan.samples)
            self.chunk = self.next_chunk(chunk, _time.perf_counter() - tic, self.chunk)
            k_done += k
            if code == 0 and k_done < steps:
                plan.report_progress(done + k_done)
        return Outcome(done + k_done, code)


class AdaptiveSegments:
    """Advances a plan's state with ``scipy.integrate.solve_ivp`` (:class:`~uvms.sim.options.Adaptive`),
    recording on the same grid as RK4."""

    def __init__(self, plan) -> None:
        self.plan = plan

    def __call__(self, done: int, steps: int) -> Outcome:
        from scipy.integrate import solve_ivp

        plan = self.plan
        h, rec, x = plan.timing.h, plan.samples, plan.x
        method = plan.integrator.method

        def f(t, y):
            dy = np.zeros(y.size)
            derivative(plan.plant, plan.held, t, np.ascontiguousarray(y), dy)
            return dy

        grid = [k for k in range(done + 1, done + steps + 1) if k % rec.every == 0]
        t1 = (done + steps) * h
        t_eval = [min(k * h, t1) for k in grid]
        if not grid or grid[-1] != done + steps:
            t_eval.append(t1)
        sol = solve_ivp(f, (done * h, t1), x, method=method, rtol=plan.integrator.rtol, atol=plan.integrator.atol,
                        max_step=max(h, 1e-6) * 50, t_eval=t_eval)
        for j in range(sol.y.shape[1]):                 # every output sample is checked, as RK4 checks every step
            y = sol.y[:, j].copy()
            y[QUATERNION:NU] /= np.linalg.norm(y[QUATERNION:NU])
            code = check_state(y, plan.layout.n_joints, plan.recording.bounds)
            k = int(round(sol.t[j] / h))
            x[:] = y
            if code != 0:
                return Outcome(k, code)
            n_out = rec.count[0]
            if j < len(grid) and n_out < rec.times.shape[0]:
                rec.times[n_out] = grid[j] * h
                rec.states[n_out] = y
                rec.count[0] = n_out + 1
        if not sol.success:
            k = int(round(sol.t[-1] / h)) if sol.t.size else done
            return Outcome(k, -1, f"the {method} solver stopped ({sol.message})")
        return Outcome(done + steps)


class PythonController:
    """A controller's update in Python (the :class:`~uvms.control.base.Controller` protocol), its wrench
    allocated to the actuators and logged with the command and allocation signals."""

    def __init__(self, plan) -> None:
        from uvms.thrusters.command import thrust_command, thrust_command_names

        self.plan = plan
        self.controller = plan.controller
        self.allocation = thrust_command(plan.thrusters)
        self.allocation_names = thrust_command_names(plan.thrusters)
        self.allocation_signals = np.zeros(len(self.allocation_names))
        self.xdot = np.zeros(plan.x.size)
        if hasattr(self.controller, "reset"):
            self.controller.reset()

    def true_nu_dot(self, t: float):
        """The vehicle's true body acceleration now, with the held inputs (evaluated only if asked for)."""
        plan = self.plan
        x = plan.x.copy()

        def evaluate():
            derivative(plan.plant, plan.held, t, x, self.xdot)
            return self.xdot[NU:JOINTS].copy()
        return evaluate

    def __call__(self, t: float, state) -> dict:
        plan = self.plan
        out: ControlOutput = self.controller.update(Measurement(
            time=t, state=state, joint_torques=plan.held.joint_torques.copy(), nu_dot_source=self.true_nu_dot(t)))
        wrench = checks.returned_vector(getattr(out, "wrench", None), 6, "controller.update().wrench",
                                        " [moment; force]", t)
        from uvms.thrusters.command import allocate_command

        allocate_command(self.allocation, wrench, plan.held.command, self.allocation_signals)
        signals = dict(out.signals)
        signals.update(zip(COMMAND_NAMES, wrench.tolist()))
        signals.update(zip(self.allocation_names, self.allocation_signals.tolist()))
        return signals


def run_python(plan, chunking) -> tuple[Outcome, UpdateLog]:
    """Advance ``plan`` to its end (or divergence) with the events in Python (module docstring)."""
    h, n = plan.timing.h, plan.layout.n_joints
    segments = Rk4Segments(plan, chunking) if plan.integrator.name == "rk4" else AdaptiveSegments(plan)
    controller = PythonController(plan) if plan.controller is not None else None
    log = UpdateLog()
    signals: dict = {}
    outcome = Outcome()
    for event in plan.events():
        done = outcome.done
        t = done * h
        state = unpack(plan.x, n)
        if plan.arm.due(done):
            plan.held.joint_torques[:] = plan.arm(t, state)
        if controller is not None and done % plan.control_every == 0:
            signals = controller(t, state)
        log.add(done, plan.samples.every, plan.held.joint_torques, signals)
        outcome = segments(done, event - done)
        if outcome.code != 0:
            break
        plan.report_progress(outcome.done)
    return outcome, log
