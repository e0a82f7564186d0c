"""The loop that advances a :class:`~uvms.sim.plan.RunPlan` with its events in Python: between two events (a
controller update, an arm update, a change in the torque schedule, the end) every input is held (zero-order
hold) and the integrator advances the state.

There is one event loop (:mod:`uvms.sim.compiled_loop`): its schedule, its rule for the updates kept in the
log and its signal layout are compiled. :class:`PythonEvents` drives the same compiled event (through
:func:`~uvms.sim.compiled_loop.event_start` and :func:`~uvms.sim.compiled_loop.event_end`) and does in Python
only what must be Python: the user's own controller (today's protocol: ``controller.update(Measurement) ->
ControlOutput``) or arm callable, and an adaptive integrator (scipy's ``solve_ivp``) between events; a bundled
controller or arm input in such a run is compiled as in :func:`~uvms.sim.compiled_loop.advance`. Both loops
are cut into calls of about :data:`uvms.sim.run.CHUNK_SECONDS` by :func:`uvms.sim.chunks.run_in_chunks`, so that Ctrl-C and
``progress`` respond.

Both record the updates: the step, the held joint torques and the logged signals of each, for the result's
zero-order-hold reconstruction (:mod:`uvms.sim.record`).
"""

from __future__ import annotations

import numpy as np

from uvms import checks
from uvms.control.base import ControlOutput, Measurement
from uvms.sim.chunks import COMMAND_NAMES, Outcome, run_in_chunks
from uvms.sim.integrate import check_state, derivative, rk4, unpack
from uvms.state import JOINTS, NU, QUATERNION


class PythonLog:
    """The compiled :class:`~uvms.sim.compiled_loop.Log` of a run with events in Python, read as
    :class:`~uvms.sim.compiled_loop.CompiledLog` is, plus a Python controller's own signals: ``per_update``,
    one dict (name -> value) per kept update."""

    def __init__(self, log, names: tuple, per_update: list) -> None:
        from uvms.sim.compiled_loop import CompiledLog

        self.compiled = CompiledLog(log, names)
        self.steps, self.torques = self.compiled.steps, self.compiled.torques
        self.per_update = per_update

    def held(self, which: np.ndarray) -> dict[str, np.ndarray]:
        """Each signal's value at every recorded row (the update ``which[r]`` holding row ``r``), sorted by name;
        the command and allocation signals are the compiled ones (a controller's entry of the same name yields)."""
        from uvms.sim.record import held_signals

        held = held_signals(self.per_update, which) if self.per_update else {}
        held.update(self.compiled.held(which))
        return {k: held[k] for k in sorted(held)}


class AdaptiveSegments:
    """Advances a plan's state with ``scipy.integrate.solve_ivp`` (:class:`~uvms.sim.options.Adaptive`) from
    one event to the next, recording on the same grid as RK4."""

    def __init__(self, plan) -> None:
        self.plan = plan
        self.reason = ""

    def __call__(self, done: int, steps: int) -> tuple[int, int]:
        """``steps`` steps from step ``done``: ``(done, code)`` as :func:`~uvms.sim.integrate.rk4` returns them
        (code -1 with :attr:`reason` when the solver gave up)."""
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
                return k, code
            n_out = rec.count[0]
            if j < len(grid) and n_out < rec.times.shape[0]:
                rec.times[n_out] = grid[j] * h
                rec.states[n_out] = y
                rec.count[0] = n_out + 1
        if not sol.success:
            self.reason = f"the {method} solver stopped ({sol.message})"
            return (int(round(sol.t[-1] / h)) if sol.t.size else done), -1
        return done + steps, 0


class PythonController:
    """A controller's update in Python (the :class:`~uvms.control.base.Controller` protocol): its checked wrench
    written into the compiled loop's ``wrench`` (allocated and logged there), its own signals returned."""

    def __init__(self, plan, wrench: np.ndarray, sensors=None) -> None:
        self.plan = plan
        self.controller = plan.controller
        self.wrench = wrench
        self.xdot = np.zeros(plan.x.size)
        self.sensors = sensors          # a uvms.sim.sensing.LiveSensors, or None

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
            time=t, state=state, joint_torques=plan.held.joint_torques.copy(), nu_dot_source=self.true_nu_dot(t),
            sensors=dict(self.sensors.latest) if self.sensors is not None else None))
        self.wrench[:] = checks.returned_vector(getattr(out, "wrench", None), 6, "controller.update().wrench",
                                                " [moment; force]", t)
        return dict(out.signals)


class PythonEvents:
    """``advance(start, stop)`` of :func:`run_in_chunks` with the events in Python (module docstring): at each
    event the compiled :func:`~uvms.sim.compiled_loop.event_start` (the schedule; a compiled arm), the user's
    Python arm and controller, the compiled :func:`~uvms.sim.compiled_loop.event_end` (a compiled controller,
    the allocation, the signal layout, the log and the next event); then RK4 (compiled, cut at ``stop``) or the
    adaptive solver (from event to event, never cut: a cut would restart its step-size control)."""

    def __init__(self, plan) -> None:
        from uvms.sim.compiled_loop import compiled_arm, compiled_controller, compiled_run

        self.plan = plan
        self.run = compiled_run(plan)
        self.arm_compiled, self.controller_compiled = compiled_arm(plan), compiled_controller(plan)
        self.sensors = None
        if plan.recording.sensors and not self.controller_compiled:
            from uvms.sim.sensing import LiveSensors

            self.sensors = LiveSensors(plan)        # a Python controller reads them (Measurement.sensors)
        self.controller = (None if self.controller_compiled else
                           PythonController(plan, self.run.control.wrench, self.sensors))
        self.per_update: list = []
        self.signals: dict = {}
        self.adaptive = None if plan.integrator.name == "rk4" else AdaptiveSegments(plan)

    @property
    def reason(self) -> str:
        return self.adaptive.reason if self.adaptive is not None else ""

    def __call__(self, start: int, stop: int) -> tuple[int, int]:
        from uvms.sim.compiled_loop import ARM, CONTROL, event_end, event_start

        plan, loop = self.plan, self.run.loop
        h, n = plan.timing.h, plan.layout.n_joints
        horizon = stop if self.adaptive is None else plan.timing.n_total
        done = start
        while done < stop:
            if self.sensors is not None:
                self.sensors.sample(done)           # before the step's updates (the left limit)
            due = event_start(loop, done, self.arm_compiled)
            python_arm = due & ARM and not self.arm_compiled
            python_control = due & CONTROL and self.controller is not None
            if python_arm or python_control:
                t = done * h
                state = unpack(plan.x, n)
                if python_arm:
                    plan.held.joint_torques[:] = plan.arm(t, state)
                if python_control:
                    self.signals = self.controller(t, state)
            kept, nxt = event_end(loop, done, due, self.controller_compiled, horizon)
            if due and self.controller is not None:
                self.per_update[kept - 1:] = [self.signals]     # the compiled log's drop rule, kept in step
            if self.sensors is not None:
                nxt = min(nxt, self.sensors.next_sample(done))
            if self.adaptive is None:
                k, code = rk4(plan.plant, plan.held, plan.x, 0.0, h, nxt - done, done, plan.samples)
                done += k
            else:
                done, code = self.adaptive(done, nxt - done)
            if code != 0:
                return done, code
        return done, 0

    def log(self) -> PythonLog:
        """What the run logged (:func:`uvms.sim.record.result_of`)."""
        return PythonLog(self.run.log, self.run.signal_names, self.per_update)


def run_python(plan, chunking) -> tuple[Outcome, PythonLog]:
    """Advance ``plan`` to its end (or divergence) with the events in Python (module docstring)."""
    events = PythonEvents(plan)
    return run_in_chunks(plan, chunking, events), events.log()
