"""The step API, for users who close their own loop (model-predictive control, learning): a
:class:`Simulator` holds one compiled loop and advances it by ``step(duration, ...)`` calls, with the inputs
the caller gives held in between (zero-order hold).

Stepping continues the same step grid as one long run (step ``k`` starts at ``t = k h``), so stepping 10 s in
10 ms calls gives the same arithmetic as one 10 s :func:`uvms.simulate`. A call costs one compiled call plus
a few microseconds of Python: the whole loop is one numba structure reference
(:class:`uvms.sim.compiled_loop.Loop`).
"""

from __future__ import annotations

import numpy as np

from uvms import checks
from uvms.hydro.flow import check_status
from uvms.sim.integrate import unpack
from uvms.sim.options import Inputs, grouped
from uvms.sim.plan import MAX_STEPS, RunPlan, Timing
from uvms.state import State


STEP_CHUNK = 16384
"""Most steps one compiled call of :meth:`Simulator.step` advances: a longer call is cut into calls of this many
steps (the same step grid, so the same arithmetic), so that Ctrl-C is seen within a fraction of a second."""

HORIZON = 3600.0
"""Simulated seconds between two resets that a simulator is laid out for: a torque schedule's breakpoints
beyond it are ignored, and a controller with a pre-drawn noise table (``smc-ne`` with a noisy IMU) stops with
an error beyond it (reset, or build a new simulator)."""


class Simulator:
    """A plant (and optionally a bundled controller and arm input) advanced step by step.

    Args:
        model: a :class:`~uvms.model.Model`.
        state: the initial state (default: at rest at the origin).
        step: integration step [s].
        controller, actuation, inputs: as :func:`uvms.simulate`'s. Without a controller the body wrench (or the
            thruster commands) given to :meth:`step` drives the vehicle; without ``inputs.joint_torques`` the
            joint torques given to :meth:`step` drive the arm.
    """

    def __init__(self, model, state: State | None = None, *, step: float = 1e-3, controller=None, actuation=None,
                 inputs: Inputs | None = None) -> None:
        from uvms.sim.compiled_loop import compilable, compiled_run

        checks.model(model)
        self.model = model
        inputs = inputs or Inputs()
        if isinstance(inputs, Inputs) and inputs.joint_motion is not None:
            raise checks.fail("joint_motion", "expected no joint motion in the step API: a prescribed joint motion "
                                              "runs with uvms.simulate or uvms.rollout")
        self._own_torques = inputs.joint_torques is None
        if self._own_torques:
            inputs = Inputs(**{**inputs.__dict__, "joint_torques": np.zeros(model.n_joints)})
        timing = Timing.of(HORIZON, step)          # events (schedule breakpoints) laid out over the horizon
        self._plan = plan = RunPlan.build(model, state, timing, (controller, actuation),
                                          grouped(inputs, "rk4", None, {"record_period": HORIZON}))
        if not compilable(plan):
            raise checks.fail("controller", "expected a bundled controller and arm input (compiled) for the step API")
        self._timing = Timing(duration=MAX_STEPS * timing.h, h=timing.h, n_total=MAX_STEPS)
        self._initial = plan.x.copy()
        self._run = None
        self._done = 0
        self.reset(state)

    @property
    def time(self) -> float:
        """The simulated time [s]."""
        return self._done * self._timing.h

    @property
    def loop(self):
        """The compiled loop (:class:`uvms.sim.compiled_loop.Loop`) that :meth:`step` advances."""
        return self._loop

    @property
    def x(self) -> np.ndarray:
        """The state vector being integrated (live: :meth:`step` advances it in place)."""
        return self._plan.x

    @property
    def command_size(self) -> int:
        """Entries of the held actuator command (``max(thrusters, 6)``: the body wrench without thrusters)."""
        return self._plan.held.command.size

    @property
    def steps_done(self) -> int:
        """Global steps since the last :meth:`reset`."""
        return self._done

    @property
    def state(self) -> State:
        """The current state (a copy)."""
        return unpack(self._plan.x, self.model.n_joints)

    def check_water(self) -> None:
        """Raise the one-line :class:`~uvms.errors.UvmsInputError` of a body that left a gridded current field
        whose ``outside`` is ``"error"`` (:func:`uvms.hydro.flow.check_status`); nothing otherwise."""
        if self._plan.water is not None:
            check_status(self._plan.water)

    def reset(self, state: State | None = None) -> State:
        """Back to ``t = 0`` at ``state`` (default: the initial state) with the controller's memory cleared."""
        from uvms.sim.compiled_loop import compiled_run
        from uvms.sim.integrate import pack

        plan = self._plan
        if state is None:
            plan.x[:] = self._initial
        else:
            x = pack(checks.state(self.model, state)).astype(float)
            if x.size != plan.x.size:           # actuator states: the layout's, zero unless given
                x = np.concatenate([x[:plan.layout.actuator.start], np.zeros(plan.layout.n_actuator)])
            plan.x[:] = x
        plan.held.command[:] = 0.0
        plan.held.joint_torques[:] = 0.0
        if plan.water is not None:
            plan.water.status[0] = 0                # a field left in an earlier episode is forgotten
        run = compiled_run(plan)                   # the controller sized for the horizon's updates
        self._run = run._replace(schedule=run.schedule._replace(n_total=MAX_STEPS))
        from uvms.sim.compiled_loop import _new_loop

        c = self._run
        self._loop = _new_loop(plan.plant, plan.held, c.control, c.schedule, plan.samples, c.log, plan.x)
        self._done = 0
        return self.state

    def step(self, duration: float, *, joint_torques=None, body_wrench=None, ee_wrench=None, command=None) -> State:
        """Advance ``duration`` seconds (a whole number of steps) with the given inputs held, and return the
        state. ``joint_torques`` (n,) [N m] (when the simulator has no arm input of its own), ``body_wrench``
        and ``ee_wrench`` (6,), ``command``: the body wrench or thruster commands (without a controller)."""
        from uvms.sim.compiled_loop import advance_loop

        plan = self._plan
        steps = steps_of(duration, self._timing.h, self._done)
        if joint_torques is not None:
            if not self._own_torques:
                raise checks.fail("joint_torques", "the simulator has its own arm input (inputs.joint_torques)")
            tau = checks.vector(joint_torques, self.model.n_joints, "joint_torques", " (one per joint)")
            self._run.control.arm.constant[:] = tau        # what the arm holds at its next event
            plan.held.joint_torques[:] = tau               # and from now on
        if body_wrench is not None:
            plan.held.body_wrench[:] = checks.vector(body_wrench, 6, "body_wrench", " [moment; force]")
        if ee_wrench is not None:
            plan.held.ee_wrench[:] = checks.vector(ee_wrench, 6, "ee_wrench", " [moment; force]")
        if command is not None:
            if plan.controller is not None:
                raise checks.fail("command", "the simulator has a controller: it sets the commands")
            plan.held.command[:] = checks.vector(command, plan.held.command.size, "command", "")
        stop, code = self._done + steps, 0
        while self._done < stop and code == 0:       # bounded calls: Ctrl-C is seen between them
            self._done, code = advance_loop(self._loop, self._done, min(stop, self._done + STEP_CHUNK))
        if code != 0:
            from uvms.errors import SimulationDiverged

            self.check_water()           # a body left a field that has no outside (its NaN stopped the loop)

            what = "is not finite" if code < 0 else "left its sane range"
            from uvms.sim.record import divergence_hint

            raise SimulationDiverged(self.time, f"{self._plan.layout.quantity_name(abs(code) - 1)} {what}",
                                     divergence_hint(self._plan.model, self._timing.h))
        return self.state


def steps_of(duration, h: float, done: int = 0) -> int:
    """The whole number of steps of ``h`` seconds in a :meth:`Simulator.step` call of ``duration`` seconds, after
    ``done`` steps since the last reset: :class:`~uvms.errors.UvmsInputError` naming ``duration`` (before any
    work) unless it is at least one step and the steps since the reset stay within
    :data:`~uvms.sim.plan.MAX_STEPS` (10^9, the scenarios' limit)."""
    seconds = checks.number(duration, "duration", positive=True, unit="s")
    ratio = seconds / h                          # a float: 1e300 s is refused, not rounded to a huge integer
    steps = round(ratio) if ratio <= 2.0 * MAX_STEPS else MAX_STEPS + 1
    if steps > MAX_STEPS - done:
        raise checks.fail("duration", f"expected at most {MAX_STEPS:.0e} steps of {h:g} s since the last reset "
                                      f"({(MAX_STEPS - done) * h:.6g} s left), got {seconds:.6g} s")
    if steps < 1:
        raise checks.fail("duration", f"expected at least one step of {h:g} s, got {duration!r}")
    return int(steps)
