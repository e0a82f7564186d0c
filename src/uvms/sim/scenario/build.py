"""What a validated scenario builds: its model's overrides, initial state, inputs, controller, and the run.

A :class:`Scenario` is a validated file (:mod:`uvms.sim.scenario.schema`) with its resolved model
(:mod:`uvms.sim.scenario.load` makes one). :meth:`Scenario.simulate_options` is the one translation of a
scenario into the keyword arguments of :func:`uvms.sim.run.simulate`; :func:`run_scenario` runs it.

Built once. Loading builds the pieces that can refuse a scenario, the trimmed initial state (no rest attitude)
and the controller (unknown name, bad parameters), so that a bad file fails before anything runs; the scenario
keeps them: the initial state (immutable) for every run, the controller (it holds a run's state) for the first
run, which takes it; a later run builds a fresh one.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from uvms.errors import UvmsInputError
from uvms.model.model import Model
from uvms.sim.health import actuation_metadata
from uvms.sim.inputs import CurrentTable
from uvms.sim.result import Result
from uvms.sim.scenario.schema import (ControllerSpec, InitialStateSpec, JointMotionSpec, JointTrajectorySpec,
                                     ModelOverrides, ScenarioSpec)
from uvms.state import State

if TYPE_CHECKING:
    from uvms.sim.plan import RunPlan


@dataclass(frozen=True, eq=False)
class Scenario:
    """A validated scenario and its resolved model.

    Attributes:
        spec: the validated file content.
        model: the model with ``model_overrides`` applied.
        source: the scenario file (``None`` when built from data).
        sha256: hex digest of ``text``.
        text: the file's text (copied verbatim next to results).
        folder: the folder its relative data files (a current field, a joint-motion table) resolve against
            and must lie in: :attr:`data_folder` (``None``: the scenario file's folder, else the working one).
    """

    spec: ScenarioSpec
    model: Model
    source: str | None
    sha256: str
    text: str
    folder: Path | None = None
    _built: dict[str, Any] = field(default_factory=dict, init=False, repr=False)
    """The pieces built so far (module doc): ``"initial_state"`` and, until a run takes it, ``"controller"``."""

    @property
    def name(self) -> str:
        return self.spec.name or "scenario"

    @property
    def data_folder(self) -> Path:
        """The folder relative data files resolve against (:attr:`folder`, else the scenario file's folder,
        else the working folder): a saved run's copy of a scenario reads them where the scenario was."""
        if self.folder is not None:
            return Path(self.folder)
        return Path(self.source).parent if self.source is not None else Path.cwd()

    @property
    def fixed_base(self) -> bool:
        return self.spec.vehicle == "fixed"

    def initial_state(self) -> State:
        """The file's initial state; with ``trimmed: true`` its roll and pitch are the rest attitude of the
        model with the arm at ``q`` (:func:`uvms.analysis.trim.trimmed_state`, ``docs/scenarios.md``). Built on
        the first call (loading makes it for a trimmed start), the same (immutable) state afterwards.

        Raises:
            UvmsInputError: ``trimmed: true`` and the system has no stable rest attitude (one line).
        """
        if "initial_state" not in self._built:
            self._built["initial_state"] = build_initial_state(self.spec.initial_state, self.model, self.source)
        return self._built["initial_state"]

    def current(self) -> CurrentTable | None:
        """The current input (``None``: the model's environment)."""
        from uvms.sim.scenario.environment import uniform_current

        return uniform_current(self.spec, self.model)

    def flow_parts(self) -> dict[str, Any]:
        """The keyword arguments of :class:`uvms.hydro.flow.Flow` for this scenario (uniform current, profile,
        field, waves, surface; :func:`uvms.sim.scenario.environment.flow_parts`), built once: loading builds
        them for a scenario with waves or a current varying in space, so that a bad wave or current input fails
        before anything runs."""
        if "flow_parts" not in self._built:
            from uvms.sim.scenario.environment import flow_parts

            self._built["flow_parts"] = flow_parts(self.spec, self.model, self.source, self.data_folder)
        return self._built["flow_parts"]

    def joint_motion(self):
        """The prescribed joint motion (``None`` without one), built once (:func:`build_joint_motion`)."""
        if self.spec.inputs.joint_motion is None:
            return None
        if "joint_motion" not in self._built:
            self._built["joint_motion"] = build_joint_motion(self.spec.inputs.joint_motion, self, self.source)
        return self._built["joint_motion"]

    def make_controller(self):
        """A fresh controller from the registry (``None`` without one): the one loading built, if no run has
        taken it yet, else a new one."""
        c = self.spec.controller
        if c is None:
            return None
        spare = self._built.pop("controller", None)
        return spare if spare is not None else build_controller(c, self.model, self.source)

    def next_controller(self):
        """The controller the next run will take (built now if no spare is kept), left in place: what
        ``uvms run`` checks before simulating (``None`` without one)."""
        c = self.spec.controller
        if c is None:
            return None
        if self._built.get("controller") is None:
            self._built["controller"] = build_controller(c, self.model, self.source)
        return self._built["controller"]

    def prebuild(self) -> None:
        """Build now what can refuse the scenario (a trimmed initial state, the controller) and keep it for the
        run (module doc).

        Raises:
            UvmsInputError: no rest attitude, unknown controller or bad controller parameters (one line).
        """
        if self.spec.initial_state.trimmed:
            self.initial_state()                          # no rest attitude: fail now
        self.joint_motion()                               # a bad table, unknown joint, too short: fail now
        from uvms.sim.scenario.environment import has_real_water

        if has_real_water(self.spec):
            self.flow_parts()                             # bad waves, a bad current profile or field file: fail now
        if self.spec.controller is not None and "controller" not in self._built:
            self._built["controller"] = build_controller(self.spec.controller, self.model, self.source)

    def with_model(self, model: Model) -> Scenario:
        """The same scenario on another (already loaded) model: its initial state, current, controller and
        ``actuators: model`` are built for ``model``."""
        return replace(self, model=model)

    def simulate_options(self) -> dict[str, Any]:
        """The keyword arguments of :func:`uvms.sim.run.simulate` that run this scenario: the one translation
        of a scenario file into a simulation (:func:`run_scenario`, ``uvms compare``, ``uvms reproduce``;
        callers that change one input replace its entry, e.g. ``controller`` or ``actuation``, and then call
        :func:`uvms.sim.health.actuation_metadata` for a new ``actuation``)."""
        from uvms.sim.run import Actuation
        from uvms.sim.scenario.environment import has_real_water

        spec = self.spec
        current, flow = self.current(), None
        if has_real_water(spec):                  # waves or a current varying in space: the water as a Flow
            from uvms.hydro.flow import Flow

            current, flow = None, Flow(**self.flow_parts())
        inputs = spec.inputs
        joint_torques = inputs.torque_schedule()
        control_period = None                     # the vehicle controller runs at its own period
        if inputs.joint_trajectory is not None:
            joint_torques = tracker_for(inputs.joint_trajectory, self.model)
            control_period = inputs.joint_trajectory.period
        motion = self.joint_motion()
        actuation = Actuation.named(spec.actuators, self.model)
        metadata = {"scenario": self.name, "scenario_source": self.source, "scenario_sha256": self.sha256,
                    "model_source": self.model.source, "vehicle": spec.vehicle, "actuators": spec.actuators,
                    "controller": spec.controller.name if spec.controller else None,
                    "health_limits": spec.health.model_dump(),
                    **actuation_metadata(actuation)}
        return dict(
            model=self.model, initial_state=self.initial_state(), duration=spec.duration, step=spec.step,
            integrator=spec.integrator, fixed_base=self.fixed_base, joint_torques=joint_torques, joint_motion=motion,
            body_wrench=np.array(inputs.body_wrench), ee_wrench=np.array(inputs.ee_wrench), current=current, flow=flow,
            controller=self.make_controller(), actuation=actuation, control_period=control_period,
            record_period=spec.outputs.record_period, rtol=spec.tolerances.rtol, atol=spec.tolerances.atol,
            metadata=metadata, sensors=self.sensors())

    def sensors(self) -> tuple:
        """The file's ``sensors:`` as :mod:`uvms.sensors` objects (:func:`~uvms.sim.scenario.sensor_specs.build_sensors`)."""
        from uvms.sim.scenario.sensor_specs import build_sensors

        return build_sensors(self.spec.sensors, self.model, self.source)


def run_scenario(scenario: Scenario, *, progress: Callable[[float, float], None] | None = None) -> Result:
    """Simulate a scenario (:meth:`Scenario.simulate_options`). A diverging run returns a :class:`Result` with
    ``complete = False`` and the reason in ``message`` (nothing is raised); ``progress(t, duration)`` is called
    after each integration segment. The result's summary carries its run health (:mod:`uvms.sim.health`)."""
    from uvms.sim.run import simulate

    try:
        return simulate(**scenario.simulate_options(), progress=progress)
    except UvmsInputError as exc:
        if exc.path == "current.field.outside" and exc.source is None:   # the scenario's field, by its name there
            raise UvmsInputError(exc.message, scenario.source, "environment.current.field.outside") from None
        raise


def plan_scenario(scenario: Scenario) -> RunPlan:
    """The checked run of a scenario, not yet run (:func:`uvms.sim.run.prepare` of the same
    :meth:`Scenario.simulate_options` that :func:`run_scenario` simulates): :func:`uvms.sim.batch.run_plans`
    runs many at once, each result equal to :func:`run_scenario`'s."""
    from uvms.sim.run import prepare

    return prepare(**scenario.simulate_options())


# ---------------------------------------------------------------------------------------------- pieces


def apply_overrides(model: Model, overrides: ModelOverrides) -> Model:
    """The model with hydrodynamic scale factors and environment replacements applied.

    A new fluid density also scales every added-mass matrix and displaced-fluid mass by ``rho_new / rho``
    (same geometry, another fluid); drag uses the density directly.
    """
    if overrides.added_mass_scale != 1.0 or overrides.drag_scale != 1.0:
        model = model.with_hydrodynamics_scaled(added_mass=overrides.added_mass_scale, drag=overrides.drag_scale)
    env = overrides.environment
    changes: dict[str, Any] = {}
    if env.current is not None:
        changes["current"] = np.array(env.current)
    if env.gravity is not None:         # in the model's frame; refused when it points up there
        from uvms.frames import check_gravity

        changes["gravity"] = check_gravity(env.gravity, model.convention, path="model_overrides.environment.gravity")
    if env.density is not None:
        ratio = env.density / model.density
        changes.update(density=env.density, added_mass=model.added_mass * ratio,
                       buoyancy_mass=model.buoyancy_mass * ratio)
    return model.replace(**changes) if changes else model


def build_initial_state(spec: InitialStateSpec, model: Model, source: str | None = None) -> State:
    """The :class:`~uvms.state.State` of ``initial_state`` on ``model`` (:meth:`Scenario.initial_state`).

    Raises:
        UvmsInputError: ``trimmed: true`` and the system has no stable rest attitude (one line naming
            ``initial_state.trimmed`` in ``source``).
    """
    euler = spec.euler
    if spec.trimmed:
        from uvms.analysis.trim import trimmed_state

        try:
            rest = trimmed_state(model, spec.q, position=spec.position, yaw=spec.euler[2])
        except UvmsInputError as exc:
            raise UvmsInputError(exc.message, source, "initial_state.trimmed") from None
        euler = rest.euler
    return State.from_euler(model, position=spec.position, euler=euler, nu=spec.nu, q=spec.q, qd=spec.qd)


def build_joint_motion(spec: JointMotionSpec, scenario: Scenario, source: str | None = None):
    """The :class:`~uvms.sim.joint_motion.JointMotion` of ``inputs.joint_motion`` (a file's path relative to the
    scenario's :attr:`~Scenario.data_folder`), checked against the model and the duration.

    Raises:
        UvmsInputError: an unreadable or malformed table, a missing column, an unknown or missing joint,
            non-increasing times, a non-finite value, a table shorter than the run (one line naming the field).
    """

    from uvms.sim.joint_motion import JointMotion

    field = "inputs.joint_motion"
    options = {"boundary": spec.boundary, "smoothing": spec.smoothing}
    if spec.file is not None:
        from uvms.input_paths import data_file

        path = data_file(spec.file, scenario.data_folder, source, f"{field}.file")
    try:
        if spec.file is not None:
            motion = JointMotion.from_csv(path, time=spec.time, columns=dict(spec.columns), **options)
        else:
            motion = JointMotion.from_arrays(np.array(spec.times), [list(r) for r in spec.angles], joints=spec.joints,
                                             **options)
        motion.for_model(scenario.model, "joints")
    except UvmsInputError as exc:
        where = f"{field}.file ({exc.source})" if exc.source and spec.file is not None else field
        raise UvmsInputError(exc.message, source, f"{where}.{exc.path}" if exc.path else where) from None
    if scenario.spec.duration > motion.duration * (1.0 + 1e-12):
        raise UvmsInputError(f"expected a table covering the duration ({scenario.spec.duration:g} s), found "
                             f"{motion.duration:g} s", source, field)
    return motion


def tracker_for(trajectory: JointTrajectorySpec, model: Model):
    """The arm controller that tracks ``joint_trajectory`` on ``model``, callable as ``(t, state) -> tau``
    (:class:`~uvms.control.arm.ComputedTorqueArm` or, ``tracker: pd``, :class:`~uvms.control.arm.PdArm`)."""
    from uvms.control.arm import ComputedTorqueArm, JointTrajectory, PdArm

    path = JointTrajectory(np.array(trajectory.times), np.array(trajectory.angles))
    gains = {k: v for k, v in (("kp", trajectory.kp), ("kd", trajectory.kd)) if v is not None}
    if trajectory.tracker == "pd":
        return PdArm(path, period=trajectory.period, **gains)
    return ComputedTorqueArm(model, path, base=trajectory.base, period=trajectory.period, **gains)


def _registry():
    """:mod:`uvms.control.registry`, or ``None`` when it cannot be imported (every controller is then unknown).
    Looked up on each call, so that a stand-in module in ``sys.modules`` is the one used."""
    try:
        return importlib.import_module("uvms.control.registry")
    except ModuleNotFoundError as exc:
        if exc.name != "uvms.control.registry":
            raise
        return None


def build_controller(spec: ControllerSpec, model: Model, source: str | None = None):
    """A new controller from the registry (:func:`uvms.control.registry.make_controller`) for ``model``.

    Raises:
        UvmsInputError: unknown controller, invalid parameters (one line naming the ``controller`` field in
            ``source``).
    """
    registry = _registry()
    names = tuple(registry.controller_names()) if registry is not None else ()
    if spec.name not in names:
        known = ", ".join(names) if names else "none available (uvms.control.registry is missing)"
        raise UvmsInputError(f"unknown controller {spec.name!r}; known: {known}", source, "controller.name")
    try:
        return registry.make_controller(spec.name, model, period=spec.period, parameters=dict(spec.parameters))
    except UvmsInputError as exc:
        path = exc.path or "parameters"
        path = path if path.startswith("controller") else f"controller.{path}"
        raise UvmsInputError(exc.message, source, path) from None
    except (ValueError, TypeError, KeyError) as exc:
        message = " ".join(str(exc).split()) or type(exc).__name__
        raise UvmsInputError(f"invalid controller parameters: {message}", source, "controller.parameters") from None
