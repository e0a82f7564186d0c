"""A run, prepared: the checked and normalised options of :func:`uvms.simulate` and the compiled plant they
drive (:class:`RunPlan`). Building the plan is the only place where inputs are normalised (a torque schedule,
a callable or a constant; a current table, a callable or a constant) and where the plant is assembled; the
loops in :mod:`uvms.sim.loop` only advance it.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uvms import checks
from uvms.checks import MAX_RECORDED_VALUES
from uvms.dynamics.plant import Held, Plant, build_plant, fluid_table, held_inputs
from uvms.hydro.flow import FlowData
from uvms.sim.inputs import CommandSchedule, CurrentTable, TorqueSchedule
from uvms.sim.integrate import Samples, pack, samples
from uvms.sim.options import Actuation, Adaptive, Inputs, Recording, Rk4
from uvms.state import JOINTS, State, StateLayout

MAX_STEPS = 10**9
"""Largest number of steps in one run (duration / step): ~3 hours of computing at 10 us per step."""

MAX_SAMPLES = 20000
"""Default largest number of recorded samples of a run (``Recording.period`` unset)."""



def check_record_size(rows: int, size: int, name: str = "record_period", what: str = "") -> None:
    """:class:`~uvms.errors.UvmsInputError` naming ``name`` when ``rows`` recorded states of ``size`` entries
    exceed :data:`MAX_RECORDED_VALUES` (``what``: how the rows come about, for the message)."""
    if rows * size > MAX_RECORDED_VALUES:
        raise checks.fail(name, f"expected at most {MAX_RECORDED_VALUES:.0e} recorded values (rows x {size} state "
                                f"entries), found {rows:.3g} rows{what}: record less often (a larger record_period)")


def check_steps(duration: float, step: float) -> int:
    """The number of steps of a run, ``round(duration / step)``; :class:`~uvms.errors.UvmsInputError` (a
    ``ValueError``) naming the argument unless both are positive finite numbers giving 1 to :data:`MAX_STEPS`."""
    duration = checks.number(duration, "duration", positive=True, unit="s, at least one step")
    step = checks.number(step, "step", positive=True, unit="s")
    n = duration / step
    if not 0.5 <= n <= MAX_STEPS:
        raise checks.fail("step", f"expected 1 to {MAX_STEPS:.0e} steps of {step:g} s in {duration:g} s, "
                                  f"found {n:.3g}")
    return int(round(n))


@dataclass(frozen=True)
class Timing:
    """The step grid of a run: ``n_total`` steps of ``h`` seconds in ``duration``."""

    duration: float
    h: float
    n_total: int

    @classmethod
    def of(cls, duration, step) -> "Timing":
        n_total = check_steps(duration, step)
        return cls(float(duration), float(duration) / n_total, n_total)

    def steps_of(self, period: float) -> int:
        """A period [s] in whole steps (at least one)."""
        return max(1, int(round(period / self.h)))


def checked_inputs(model, inputs: Inputs) -> Inputs:
    """``inputs`` with each field checked and normalised (constants to float64 arrays)."""
    n = model.n_joints
    tau = inputs.joint_torques
    if isinstance(tau, TorqueSchedule):
        if tau.torques.shape[1] != n:
            raise checks.fail("joint_torques", f"expected a schedule of {n} torques per row (one per joint: the model "
                                               f"has {n} joints), got {tau.torques.shape[1]}")
        checks.matrix(tau.torques, None, n, "joint_torques", " [N m]")
    elif tau is not None and not callable(tau):
        tau = checks.vector(tau, n, "joint_torques", " (one per joint)")
    current = inputs.current
    if not (current is None or isinstance(current, CurrentTable) or callable(current)):
        current = checks.vector(current, 3, "current", " (world frame, m/s)")
    if inputs.flow is not None:
        from uvms.hydro.flow import Flow

        if not isinstance(inputs.flow, Flow):
            raise checks.fail("flow", f"expected None or a uvms.hydro.flow.Flow, got {checks.show(inputs.flow)}")
        if current is not None:
            raise checks.fail("flow", "given with current: a Flow holds the run's current (its uniform part)")
    return Inputs(joint_torques=tau,
                  body_wrench=checks.optional_vector(inputs.body_wrench, 6, "body_wrench", " [moment; force]"),
                  ee_wrench=checks.optional_vector(inputs.ee_wrench, 6, "ee_wrench", " [moment; force]"),
                  current=current, fixed_base=checks.flag(inputs.fixed_base, "fixed_base"),
                  control_period=checks.optional_number(inputs.control_period, "control_period", positive=True,
                                                        unit="s"),
                  joint_motion=inputs.joint_motion, thruster_commands=inputs.thruster_commands, flow=inputs.flow)


def motion_of(model, inputs: Inputs, control: tuple, integrator, timing: Timing, rows: int):
    """The compiled :class:`~uvms.sim.prescribed.Motion` of ``inputs.joint_motion`` (``None`` without one) and
    its thruster-command table (``control = (controller, actuation)``), after the one-line refusals: another
    joint input beside it, a controller, an adaptive integrator, a run longer than the table, commands without
    a motion or without thrusters (``docs/python.md``, "Prescribed joint motion")."""
    from uvms.sim.joint_motion import JointMotion
    from uvms.sim.prescribed import motion_data

    controller, actuation = control
    motion, commands = inputs.joint_motion, inputs.thruster_commands
    if commands is not None and not isinstance(commands, CommandSchedule):
        raise checks.fail("thruster_commands", f"expected None or a uvms CommandSchedule, got {checks.show(commands)}")
    if motion is None:
        if commands is not None:
            raise checks.fail("thruster_commands", "expected a joint_motion with thruster_commands (the replay's "
                                                   "loop holds them; a vehicle controller commands the thrusters "
                                                   "otherwise)")
        return None
    if not isinstance(motion, JointMotion):
        raise checks.fail("joint_motion", f"expected None or a uvms JointMotion, got {checks.show(motion)}")
    if inputs.joint_torques is not None:
        raise checks.fail("joint_motion", "expected joint_motion or joint_torques (a torque input or an arm "
                                          "tracker), not both: the motion decides the joint torques")
    if controller is not None:
        raise checks.fail("joint_motion", "expected no vehicle controller with a joint motion (the replay's "
                                          "thrusters are off or follow thruster_commands)")
    if integrator.name != "rk4":
        raise checks.fail("joint_motion", f"expected the rk4 integrator with a joint motion, got "
                                          f"{integrator.name!r}")
    if timing.duration > motion.duration * (1.0 + 1e-12):
        raise checks.fail("joint_motion", f"expected a run no longer than the motion's table "
                                          f"({motion.duration:g} s), got duration {timing.duration:g} s")
    table = (np.zeros(0), np.zeros((0, 0))) if commands is None else (commands.times,
                                                                     commands.for_thrusters(actuation.thrusters))
    return motion_data(*motion.for_model(model), rows, table)


def checked_recording(recording: Recording) -> Recording:
    """``recording`` with each field checked (bounds as float64)."""
    try:
        limits = np.asarray(recording.bounds) if not isinstance(recording.bounds, (str, bytes)) else None
    except (ValueError, TypeError):
        limits = None
    if limits is None or limits.dtype.kind not in "biuf" or limits.shape != (4,) or not np.all(limits > 0):
        raise checks.fail("bounds", f"expected 4 positive limits (|position|, |nu|, |qd|, |actuator|), got "
                                    f"{checks.show(recording.bounds)}")
    checks.callable_or_none(recording.progress, "progress", "progress(t, duration)")
    if recording.metadata is not None and not isinstance(recording.metadata, dict):
        raise checks.fail("metadata", f"expected None or a dict, got {checks.show(recording.metadata)}")
    from uvms.sim.sensing import checked_sensors

    return Recording(period=checks.optional_number(recording.period, "record_period", positive=True, unit="s"),
                     progress=recording.progress, metadata=recording.metadata,
                     bounds=np.array(limits, dtype=np.float64), sensors=checked_sensors(recording.sensors))


def checked_control(controller, actuation) -> Actuation:
    """The controller is ``None`` or has ``update(measurement)``; the actuation (default ideal) is checked."""
    if controller is not None and not callable(getattr(controller, "update", None)):
        raise checks.fail("controller", f"expected None or a controller with update(measurement), got "
                                        f"{checks.show(controller)}")
    if actuation is not None and not isinstance(actuation, Actuation):
        raise checks.fail("actuation", f"expected None or an Actuation (e.g. Actuation.named('paper')), got "
                                       f"{checks.show(actuation)}")
    if actuation is not None:
        from uvms.thrusters.layouts import Thruster

        thrusters = actuation.thrusters
        if not isinstance(thrusters, tuple) or not all(isinstance(t, Thruster) for t in thrusters):
            raise checks.fail("actuation", f"expected thrusters that are uvms Thruster descriptions, got "
                                           f"{checks.show(thrusters)}")
    return actuation or Actuation()


def current_table(model, current, timing: Timing, flow=None) -> FlowData:
    """The run's water, compiled: a :class:`~uvms.hydro.flow.Flow` (``flow``), or a uniform current: the model's
    environment, a table, a callable sampled on the half-step grid (RK4 sees it exactly at every stage), or a
    constant."""
    if flow is not None:
        return flow.compiled(model.convention)
    if current is None:
        table = CurrentTable.constant(model.current, model.fluid_acceleration)
    elif isinstance(current, CurrentTable):
        table = current
    elif callable(current):
        table = CurrentTable.from_function(
            lambda t: checks.returned_vector(current(t), 3, "current", " (world frame, m/s)", t), timing.duration,
            timing.h)
    else:
        table = CurrentTable.constant(current, model.fluid_acceleration)
    return fluid_table(table.times, table.velocity, table.acceleration)


class ArmInput:
    """The joint torques of a run as a function of time and state: none, constant, a schedule (breakpoints
    snapped to the nearest step) or a callable arm controller held over its period."""

    def __init__(self, joint_torques, n: int, timing: Timing, control_period: float | None) -> None:
        self.source, self.n, self.h = joint_torques, n, timing.h
        self.is_callable = callable(joint_torques) and not isinstance(joint_torques, TorqueSchedule)
        period = control_period or getattr(joint_torques, "period", None) or 0.01
        self.every = timing.steps_of(period) if self.is_callable else 0
        self.breakpoints = ([int(round(tb / self.h)) for tb in joint_torques.breakpoints()
                             if 0 < tb < timing.duration] if isinstance(joint_torques, TorqueSchedule) else [])

    def due(self, done: int) -> bool:
        """Whether the torques are re-evaluated at step ``done`` (every event, or the arm's period)."""
        return not self.is_callable or done % self.every == 0

    def __call__(self, t: float, state: State) -> np.ndarray:
        src = self.source
        if src is None:
            return np.zeros(self.n)
        if isinstance(src, TorqueSchedule):                 # breakpoints snap to the nearest step
            return np.array(src(t + 0.5 * self.h), dtype=float).reshape(self.n)
        if self.is_callable:
            return checks.returned_vector(src(t, state), self.n, "joint_torques", " (one per joint)", t)
        return src


@dataclass
class RunPlan:
    """Everything a loop needs, built once by :meth:`build` (module docstring)."""

    model: Any
    timing: Timing
    layout: StateLayout
    plant: Plant
    held: Held
    x: np.ndarray
    samples: Samples
    arm: ArmInput
    controller: Any
    control_every: int
    thrusters: tuple
    fixed_base: bool
    integrator: Rk4 | Adaptive
    recording: Recording
    motion: Any = None          # uvms.sim.prescribed.Motion of a prescribed joint motion, or None
    water: Any = None           # the plant's uvms.hydro.flow.FlowData (its status read after the run)

    @classmethod
    def build(cls, model, initial_state, timing: Timing, control: tuple, options: tuple) -> "RunPlan":
        """``control = (controller, actuation)``, ``options = (inputs, integrator, recording)`` (unchecked)."""
        from uvms.thrusters.actuation import actuator_kernel, n_actuator_states

        checks.model(model)
        controller, actuation = control[0], checked_control(*control)
        inputs, integrator, recording = checked_inputs(model, options[0]), options[1], checked_recording(options[2])
        state = State.zero(model) if initial_state is None else checks.state(model, initial_state, "initial_state")
        n_act = n_actuator_states(actuator_kernel(actuation.thrusters))
        if state.actuator.size != n_act:
            state = state.replace(actuator=np.zeros(n_act))
        if inputs.fixed_base:
            state = state.replace(nu=np.zeros(6))
        every = record_every(timing, recording)
        check_record_size(timing.n_total // every + 2, JOINTS + 2 * model.n_joints + n_act)
        motion = motion_of(model, inputs, (controller, actuation), integrator, timing, timing.n_total // every + 2)
        if motion is not None and recording.sensors:
            raise checks.fail("sensors", "expected no simulated sensors with a prescribed joint_motion (their "
                                         "truth needs the free dynamics' acceleration)")
        if motion is not None:                   # the joints start on the motion
            q0, qd0, _ = inputs.joint_motion(0.0)
            order = [inputs.joint_motion.joints.index(j) for j in model.joint_names] \
                if inputs.joint_motion.joints is not None else slice(None)
            state = state.replace(q=q0[order], qd=qd0[order])
        water = current_table(model, inputs.current, timing, inputs.flow)
        known_water = getattr(controller, "set_known_water", None)
        if known_water is not None:              # a controller that can see the run's water (smc-ab's feed-forward)
            known_water(water)
        plant, _ = build_plant(model, thrusters=actuation.thrusters, fluid=water, fixed_base=inputs.fixed_base,
                               bounds=recording.bounds)
        held = held_inputs(model.n_joints, len(actuation.thrusters))
        held.body_wrench[:] = inputs.body_wrench
        held.ee_wrench[:] = inputs.ee_wrench
        x = pack(state).astype(float)
        control_every = 0
        if controller is not None:
            control_every = timing.steps_of(getattr(controller, "period", None) or inputs.control_period or 0.01)
        from uvms._cache import announce_compile

        announce_compile()                       # a cold kernel cache: the CLI says so once, before compiling
        record = samples(timing.n_total // every + 2, x.size, every)
        record.states[0] = x                     # the initial state is the first row, at t = 0
        record.count[0] = 1
        return cls(model=model, timing=timing, layout=StateLayout(model.n_joints, n_act), plant=plant, held=held,
                   x=x, samples=record,
                   arm=ArmInput(inputs.joint_torques, model.n_joints, timing, inputs.control_period),
                   controller=controller, control_every=control_every, thrusters=actuation.thrusters,
                   fixed_base=inputs.fixed_base,
                   integrator=integrator, recording=recording, motion=motion, water=water)

    def schedule(self):
        """The event grid of this run (:class:`uvms.sim.compiled_loop.Schedule`): controller period, arm period
        and torque-schedule breakpoints, in steps."""
        from uvms.sim.compiled_loop import schedule_of

        return schedule_of(self.timing.h, self.timing.n_total, self.control_every, self.arm.every,
                           self.arm.breakpoints)

    def events(self):
        """The steps at which the loop stops (:func:`events`) for this run's periods and breakpoints."""
        return events(self.timing.n_total, (self.control_every, self.arm.every), self.arm.breakpoints)

    def report_progress(self, done: int) -> None:
        if self.recording.progress is not None:
            self.recording.progress(done * self.timing.h, self.timing.duration)


def record_every(timing: Timing, recording: Recording) -> int:
    """Steps between two recorded rows: the recording period's, else enough for at most :data:`MAX_SAMPLES` rows."""
    from uvms.sim.sensing import record_every_for

    every = timing.steps_of(recording.period) if recording.period is not None else None
    every = record_every_for(recording.sensors, timing.h, every)
    return every if every is not None else max(1, int(np.ceil(timing.n_total / MAX_SAMPLES)))


def events(n_total: int, periods: tuple[int, int], breakpoints: list[int]):
    """The steps at which a loop stops, in order: multiples of each non-zero period ``(controller, arm)`` (in
    steps), the breakpoints, and ``n_total``; generated one at a time (a long run holds no list of them) by
    the loops' own rule (:func:`uvms.sim.compiled_loop._next_event`)."""
    from uvms.sim.compiled_loop import next_event, schedule_of

    control_every, arm_every = periods
    schedule = schedule_of(1.0, n_total, control_every, arm_every, breakpoints)
    event = 0
    while event < n_total:
        event = int(next_event(schedule, event, n_total))
        yield event
