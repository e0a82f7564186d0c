"""Scenario files: what to simulate (model, duration, integrator, inputs, controller, actuators) in one YAML file.

A scenario is validated like a model file (pydantic v2, unknown keys rejected, one-line errors naming the file
and the dotted field path), then checked against its model (joint count of torque vectors and initial joint
angles, controller name). ``docs/scenarios.md`` documents every field; the bundled scenarios
(``uvms/scenarios/*.yaml``, loadable by name) are the paper's three cases of Section 6 and two of the BlueROV2
Heavy + Alpha 5.

    scenario = load_scenario("paper_case2_released")     # or a path
    result = run_scenario(scenario)                       # -> uvms.sim.result.Result

Field types and strictness come from :mod:`uvms.schema_base` (the kit shared with model and sweep files): a
number is a YAML number (the loader reads ``1e-3`` as one); a quoted ``"1e-3"`` is a string and is refused.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable
from dataclasses import dataclass, replace
from importlib.resources import files
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BeforeValidator,
    Discriminator,
    Field,
    Tag,
    Strict,
    ValidationError,
    field_validator,
    model_validator,
)

from uvms.bundled import bundled_names, resolve_path
from uvms.errors import UvmsInputError
from uvms.model.load import bundled_models, load_model
from uvms.safe_yaml import read_yaml_mapping
from uvms.model.model import Model
from uvms.schema_base import (
    ZERO3,
    ZERO6,
    NonNegative,
    Positive,
    RunName,
    Spec,
    Vec3,
    Vec6,
    Vector,
    fail,
    finite_number,
    sanitised_name,
    show,
    validation_input_error,
)
from uvms.sim.health import HealthLimits, actuation_metadata
from uvms.sim.inputs import CurrentTable, TorqueSchedule
from uvms.sim.result import Result
from uvms.state import State

if TYPE_CHECKING:
    from uvms.sim.plan import RunPlan

_SCENARIOS = files("uvms") / "scenarios"

INTEGRATORS = ("rk4", "DOP853", "LSODA", "Radau", "RK45")
"""``rk4``: compiled fixed-step RK4; the others: ``scipy.integrate.solve_ivp`` methods."""

_UNION_TAGS = ("list", "mapping")
"""Tags of this schema's list-or-mapping unions; left out of the field paths of error messages."""


def _list_or_mapping(value: Any) -> str:
    return "mapping" if isinstance(value, dict) else "list"


# ---------------------------------------------------------------------------------------------- schema


class EnvironmentOverrides(Spec):
    """Replace the model file's environment (``None``: keep the model's value)."""

    current: Vec3 | None = None                   # constant current velocity, world frame [m/s]
    density: Positive | None = None               # rho [kg/m^3]; added and displaced mass scale with it
    gravity: Vec3 | None = None                   # a_g, world frame (z down) [m/s^2]


class ModelOverrides(Spec):
    """Changes applied to the loaded model (the file itself is never modified)."""

    added_mass_scale: NonNegative = 1.0           # multiplies every added-mass matrix [-]
    drag_scale: NonNegative = 1.0                 # multiplies every drag coefficient [-]
    environment: EnvironmentOverrides = EnvironmentOverrides()


class Tolerances(Spec):
    """Error tolerances of the adaptive integrators (ignored by ``rk4``)."""

    rtol: Positive = 1e-10
    atol: Positive = 1e-12


class InitialStateSpec(Spec):
    """Initial state; every part defaults to zero (the paper's Section 6). ``trimmed: true`` starts at the roll
    and pitch the system rests at with the arm at ``q`` (:func:`uvms.trimmed_state`); ``euler`` then gives the
    yaw only (its roll and pitch must be left zero)."""

    position: Vec3 = ZERO3                        # vehicle position, world [m]
    euler: Vec3 = ZERO3                           # ZYX Euler angles (roll, pitch, yaw) [rad]
    nu: Vec6 = ZERO6                              # body velocity [p q r u v w] [rad/s, m/s]
    q: Vector | None = None                       # joint angles (n) [rad]
    qd: Vector | None = None                      # joint rates (n) [rad/s]
    trimmed: Annotated[bool, Strict()] = False    # roll and pitch: the rest attitude with the arm at q

    @model_validator(mode="after")
    def _trimmed_yaw_only(self) -> InitialStateSpec:
        if self.trimmed and (self.euler[0] != 0.0 or self.euler[1] != 0.0):
            raise fail(f"expected [0, 0, yaw] with trimmed: true (roll and pitch come from the trim), found "
                       f"{show(list(self.euler))}", "euler")
        return self


class TorqueStep(Spec):
    """One row of a piecewise-constant schedule: ``torques`` [N m] from time ``from`` [s] on."""

    start: NonNegative = Field(alias="from")
    torques: Vector

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        return _only_keys(data, "from", "torques")  # the generic message would list 'start', not 'from'


class ConstantTorques(Spec):
    """Constant joint torques [N m] for the whole run."""

    constant: Vector

    @model_validator(mode="before")
    @classmethod
    def _known_keys(cls, data: Any) -> Any:
        return _only_keys(data, "constant")  # the generic message cannot tell the union's two forms apart


def _only_keys(data: Any, *keys: str) -> Any:
    if isinstance(data, dict):
        for key in data:
            if key not in keys:
                raise fail(f"unknown key; expected one of: {', '.join(keys)}", str(key))
    return data


def _schedule_order(steps: tuple[TorqueStep, ...]) -> tuple[TorqueStep, ...]:
    if not steps:
        raise fail("expected at least one {from: t, torques: [...]} entry, found an empty list")
    if steps[0].start != 0.0:
        raise fail(f"expected the first entry to start at 'from: 0', found from: {steps[0].start:g}")
    for k in range(1, len(steps)):
        if steps[k].start <= steps[k - 1].start:
            raise fail(f"expected 'from' times in increasing order, found {steps[k].start:g} after "
                       f"{steps[k - 1].start:g}", k)
    return steps


def _joint_torques_form(value: Any) -> Any:
    if not isinstance(value, (list, tuple, dict)):
        raise fail("expected a list of {from: t, torques: [...]} entries or a mapping {constant: [...]}, "
                   f"found {show(value)}")
    return value


JointTorques = Annotated[
    Annotated[tuple[TorqueStep, ...], AfterValidator(_schedule_order), Tag("list")]
    | Annotated[ConstantTorques, Tag("mapping")],
    Discriminator(_list_or_mapping),
    BeforeValidator(_joint_torques_form),
]


class CurrentTableSpec(Spec):
    """World current velocity [m/s] at ``times`` [s], linear in between and held outside."""

    times: Vector
    velocity: tuple[Vec3, ...]
    acceleration: tuple[Vec3, ...] | None = None  # fluid acceleration a_f [m/s^2]; default: d(velocity)/dt

    @model_validator(mode="after")
    def _consistent(self) -> CurrentTableSpec:
        if any(t < 0 for t in self.times) or any(b <= a for a, b in zip(self.times, self.times[1:])):
            raise fail(f"expected times >= 0 in increasing order, found {show(list(self.times))}", "times")
        for name in ("velocity", "acceleration"):
            rows = getattr(self, name)
            if rows is not None and len(rows) != len(self.times):
                raise fail(f"expected one row per time ({len(self.times)}), found {len(rows)}", name)
        return self


class CurrentSpec(Spec):
    """A constant current or a table in time (exactly one of them)."""

    constant: Vec3 | None = None                  # world frame [m/s]
    table: CurrentTableSpec | None = None

    @model_validator(mode="after")
    def _one_form(self) -> CurrentSpec:
        if (self.constant is None) == (self.table is None):
            found = "both" if self.constant is not None else "neither"
            raise fail(f"expected exactly one of 'constant' or 'table', found {found}")
        return self


class JointTrajectorySpec(Spec):
    """A joint-space trajectory (e.g. a pilot's master-arm motion) tracked by an arm controller
    (:mod:`uvms.control.arm`): clamped cubic spline through the knots."""

    times: Vector                                 # knot times [s], increasing
    angles: tuple[Vector, ...]                    # joint angles at each knot (n each) [rad]
    tracker: Literal["computed_torque", "pd"] = "computed_torque"
    kp: Positive | Vector | None = None           # one or per joint: [1/s^2] computed torque, [N m/rad] pd
    kd: Positive | Vector | None = None           # one or per joint: [1/s] computed torque, [N m s/rad] pd
    base: Literal["fixed", "moving"] = "fixed"    # computed torque: vehicle motion assumed by the model
    period: Positive = 0.01                       # arm-controller update period [s]

    @model_validator(mode="after")
    def _knots(self) -> JointTrajectorySpec:
        if len(self.angles) != len(self.times):
            raise fail(f"expected one row of angles per knot time ({len(self.times)}), found {len(self.angles)}",
                       "angles")
        if any(b <= a for a, b in zip(self.times, self.times[1:])):
            raise fail(f"expected increasing knot times, found {show(list(self.times))}", "times")
        n = len(self.angles[0]) if self.angles else 0
        for name in ("kp", "kd"):
            gain = getattr(self, name)
            if isinstance(gain, tuple) and len(gain) != n:
                raise fail(f"expected one gain or {n} (one per joint), found {len(gain)}", name)
        return self

    def tracker_for(self, model):
        """The arm controller, callable as ``(t, state) -> tau``."""
        from uvms.control.arm import ComputedTorqueArm, JointTrajectory, PdArm

        trajectory = JointTrajectory(np.array(self.times), np.array(self.angles))
        gains = {k: v for k, v in (("kp", self.kp), ("kd", self.kd)) if v is not None}
        if self.tracker == "pd":
            return PdArm(trajectory, period=self.period, **gains)
        return ComputedTorqueArm(model, trajectory, base=self.base, period=self.period, **gains)


class InputsSpec(Spec):
    """External inputs, held between updates (zero-order hold)."""

    joint_torques: JointTorques | None = None     # [N m]; default: zero
    joint_trajectory: JointTrajectorySpec | None = None   # instead of joint_torques: track a joint trajectory
    body_wrench: Vec6 = ZERO6                     # on the vehicle, body axes [moment; force] [N m, N]
    ee_wrench: Vec6 = ZERO6                       # on the end effector, its axes [moment; force] [N m, N]
    current: CurrentSpec | None = None            # default: the model's environment current

    @model_validator(mode="after")
    def _one_arm_input(self) -> InputsSpec:
        if self.joint_torques is not None and self.joint_trajectory is not None:
            raise fail("expected joint_torques or joint_trajectory, not both", "joint_trajectory")
        return self

    def torque_schedule(self) -> TorqueSchedule | None:
        """The joint torques as a :class:`TorqueSchedule` (``None``: zero)."""
        tau = self.joint_torques
        if tau is None:
            return None
        if isinstance(tau, ConstantTorques):
            return TorqueSchedule.constant(tau.constant)
        return TorqueSchedule(times=np.array([s.start for s in tau]), torques=np.array([s.torques for s in tau]))

    def torque_vectors(self) -> list[tuple[str, tuple[float, ...]]]:
        """Every torque vector with its field path (for the joint-count check)."""
        tau = self.joint_torques
        if tau is None:
            return []
        if isinstance(tau, ConstantTorques):
            return [("inputs.joint_torques.constant", tau.constant)]
        return [(f"inputs.joint_torques[{k}].torques", s.torques) for k, s in enumerate(tau)]


class ControllerSpec(Spec):
    """A vehicle controller from :mod:`uvms.control.registry`."""

    name: Annotated[str, Field(min_length=1)]
    period: Positive = 0.01                       # update period, zero-order hold in between [s]
    parameters: dict[str, Any] = {}               # passed to the registry's factory as they are


class OutputsSpec(Spec):
    """What is recorded."""

    record_period: Positive | None = None         # [s]; default: every step (at most 20 000 samples)


class HealthSpec(Spec):
    """When the run counts as unhealthy (:mod:`uvms.sim.health`): an attitude past ``attitude_limit``, a
    thruster saturated more than ``saturation_limit`` of the time, the vehicle farther than ``station_limit``
    off its station, or more than ``unproduced_limit`` of the commanded force or moment not produced."""

    attitude_limit: Positive = HealthLimits.attitude_limit            # largest |roll| or |pitch| [rad] (60 deg)
    saturation_limit: Annotated[float, BeforeValidator(finite_number), Field(ge=0, le=1)] = \
        HealthLimits.saturation_limit                                   # fraction of the run [-]
    station_limit: Positive = HealthLimits.station_limit              # distance off the set point [m]
    unproduced_limit: Annotated[float, BeforeValidator(finite_number), Field(ge=0, le=1)] = \
        HealthLimits.unproduced_limit                                   # share of the commanded force [-]


class ScenarioSpec(Spec):
    """A whole scenario file."""

    name: RunName | None = None                   # default: the file name without .yaml
    description: str | None = None
    model: Annotated[str, Field(min_length=1)]    # bundled model name or a path (relative: to this file)
    model_overrides: ModelOverrides = ModelOverrides()
    duration: Positive                            # [s]
    step: Positive = 0.001                        # RK4 step; recording grid of the adaptive integrators [s]
    integrator: Literal["rk4", "DOP853", "LSODA", "Radau", "RK45"] = "rk4"
    tolerances: Tolerances = Tolerances()
    vehicle: Literal["released", "fixed"] = "released"
    initial_state: InitialStateSpec = InitialStateSpec()
    inputs: InputsSpec = InputsSpec()
    controller: ControllerSpec | None = None
    actuators: str = "ideal"                      # thruster layout (uvms.thrusters.layouts)
    outputs: OutputsSpec = OutputsSpec()
    health: HealthSpec = HealthSpec()

    @field_validator("actuators")
    @classmethod
    def _known_layout(cls, name: str) -> str:
        from uvms.thrusters.layouts import layout_names

        if name not in (*layout_names(), "model"):
            raise fail(f"expected 'model' or one of {', '.join(repr(n) for n in layout_names())}, found {show(name)}")
        return name

    @model_validator(mode="after")
    def _consistent(self) -> ScenarioSpec:
        if self.step > self.duration:
            raise fail(f"expected a step <= duration ({self.duration:g} s), found {self.step:g} s", "step")
        from uvms.sim.run import MAX_STEPS

        if self.duration / self.step > MAX_STEPS:
            raise fail(f"expected at most {MAX_STEPS:.0e} steps in the duration ({self.duration:g} s), found "
                       f"{self.duration / self.step:.3g}", "step")
        if self.controller is not None and self.controller.period < self.step:
            raise fail(f"expected a period >= step ({self.step:g} s), found {self.controller.period:g} s",
                       "controller.period")
        if self.outputs.record_period is not None and self.outputs.record_period < self.step:
            raise fail(f"expected a record period >= step ({self.step:g} s), found {self.outputs.record_period:g} s",
                       "outputs.record_period")
        return self


# ---------------------------------------------------------------------------------------------- scenario


@dataclass(frozen=True, eq=False)
class Scenario:
    """A validated scenario and its resolved model.

    Attributes:
        spec: the validated file content.
        model: the model with ``model_overrides`` applied.
        source: the scenario file (``None`` when built from data).
        sha256: hex digest of ``text``.
        text: the file's text (copied verbatim next to results).
    """

    spec: ScenarioSpec
    model: Model
    source: str | None
    sha256: str
    text: str

    @property
    def name(self) -> str:
        return self.spec.name or "scenario"

    @property
    def fixed_base(self) -> bool:
        return self.spec.vehicle == "fixed"

    def initial_state(self) -> State:
        """The file's initial state; with ``trimmed: true`` its roll and pitch are the rest attitude of the
        model with the arm at ``q`` (:func:`uvms.analysis.trim.trimmed_state`, ``docs/scenarios.md``).

        Raises:
            UvmsInputError: ``trimmed: true`` and the system has no stable rest attitude (one line).
        """
        s = self.spec.initial_state
        euler = s.euler
        if s.trimmed:
            from uvms.analysis.trim import trimmed_state

            try:
                rest = trimmed_state(self.model, s.q, position=s.position, yaw=s.euler[2])
            except UvmsInputError as exc:
                raise UvmsInputError(exc.message, self.source, "initial_state.trimmed") from None
            euler = rest.euler
        return State.from_euler(self.model, position=s.position, euler=euler, nu=s.nu, q=s.q, qd=s.qd)

    def current(self) -> CurrentTable | None:
        """The current input (``None``: the model's environment)."""
        c = self.spec.inputs.current
        if c is None:
            return None
        if c.table is None:
            return CurrentTable.constant(c.constant, self.model.fluid_acceleration)
        t = np.array(c.table.times, dtype=float)
        v = np.array(c.table.velocity, dtype=float)
        if c.table.acceleration is not None:
            return CurrentTable(t, v, np.array(c.table.acceleration, dtype=float))
        return CurrentTable.from_velocity_table(t, v, self.spec.duration, self.spec.step)

    def make_controller(self):
        """A fresh controller from the registry (``None`` without one)."""
        c = self.spec.controller
        return None if c is None else _make_controller(c, self.model, self.source)

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

        spec = self.spec
        inputs = spec.inputs
        joint_torques = inputs.torque_schedule()
        control_period = None                     # the vehicle controller runs at its own period
        if inputs.joint_trajectory is not None:
            joint_torques = inputs.joint_trajectory.tracker_for(self.model)
            control_period = inputs.joint_trajectory.period
        actuation = Actuation.named(spec.actuators, self.model)
        metadata = {"scenario": self.name, "scenario_source": self.source, "scenario_sha256": self.sha256,
                    "model_source": self.model.source, "vehicle": spec.vehicle, "actuators": spec.actuators,
                    "controller": spec.controller.name if spec.controller else None,
                    "health_limits": spec.health.model_dump(),
                    **actuation_metadata(actuation)}
        return dict(
            model=self.model, initial_state=self.initial_state(), duration=spec.duration, step=spec.step,
            integrator=spec.integrator, fixed_base=self.fixed_base, joint_torques=joint_torques,
            body_wrench=np.array(inputs.body_wrench), ee_wrench=np.array(inputs.ee_wrench), current=self.current(),
            controller=self.make_controller(), actuation=actuation, control_period=control_period,
            record_period=spec.outputs.record_period, rtol=spec.tolerances.rtol, atol=spec.tolerances.atol,
            metadata=metadata)


def bundled_scenarios() -> list[str]:
    """Names of the scenarios shipped with uvms."""
    return bundled_names(_SCENARIOS)


def resolve_scenario_path(name_or_path: str | os.PathLike[str]) -> Path:
    """An existing file path as given, else the bundled scenario of that name."""
    return resolve_path(name_or_path, _SCENARIOS, "scenario")


def load_scenario(name_or_path: str | os.PathLike[str]) -> Scenario:
    """Load and validate a scenario: a bundled name (see :func:`bundled_scenarios`) or a YAML file path.

    Raises:
        UvmsInputError: missing file, YAML syntax error, invalid content, missing or invalid model file,
            torque or joint vectors of the wrong length, unknown controller (one-line message).
    """
    path = resolve_scenario_path(name_or_path)
    data = read_yaml_mapping(path, "scenario fields")
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:  # pragma: no cover - read_yaml read it a moment ago
        raise UvmsInputError(f"cannot read: {exc}", str(path)) from None
    return scenario_from_data(data, source=str(path), base_dir=path.parent, text=text, default_name=path.stem)


def scenario_from_data(data: Any, *, source: str | None = None, base_dir: str | os.PathLike[str] | None = None,
                       text: str | None = None, default_name: str = "scenario") -> Scenario:
    """Validate scenario ``data`` (the parsed YAML mapping); relative model paths resolve against ``base_dir``
    (default: the working directory). ``text`` (default: a YAML dump of ``data``) is hashed and kept."""
    import yaml

    try:
        spec = ScenarioSpec.model_validate(data)
    except ValidationError as exc:
        raise validation_input_error(exc, source, schema=ScenarioSpec, union_tags=_UNION_TAGS) from None
    if spec.name is None:
        spec = spec.model_copy(update={"name": sanitised_name(default_name, "scenario")})
    if text is None:
        text = yaml.safe_dump(data, sort_keys=False)
    model = _resolve_model(spec, source, Path(base_dir) if base_dir is not None else Path.cwd())
    _check_against_model(spec, model, source)
    scenario = Scenario(spec=spec, model=model, source=source, sha256=hashlib.sha256(text.encode()).hexdigest(),
                        text=text)
    if spec.initial_state.trimmed:
        scenario.initial_state()                          # no rest attitude: fail now
    if spec.controller is not None:
        _make_controller(spec.controller, model, source)  # unknown name or bad parameters: fail now
    return scenario


def run_scenario(scenario: Scenario, *, progress: Callable[[float, float], None] | None = None) -> Result:
    """Simulate a scenario (:meth:`Scenario.simulate_options`). A diverging run returns a :class:`Result` with
    ``complete = False`` and the reason in ``message`` (nothing is raised); ``progress(t, duration)`` is called
    after each integration segment. The result's summary carries its run health (:mod:`uvms.sim.health`)."""
    from uvms.sim.run import simulate

    return simulate(**scenario.simulate_options(), progress=progress)


def plan_scenario(scenario: Scenario) -> RunPlan:
    """The checked run of a scenario, not yet run (:func:`uvms.sim.run.prepare` of the same
    :meth:`Scenario.simulate_options` that :func:`run_scenario` simulates): :func:`uvms.sim.batch.run_plans`
    runs many at once, each result equal to :func:`run_scenario`'s."""
    from uvms.sim.run import prepare

    return prepare(**scenario.simulate_options())


# ---------------------------------------------------------------------------------------------- helpers


def _resolve_model(spec: ScenarioSpec, source: str | None, base_dir: Path) -> Model:
    """Load ``spec.model`` (a path relative to ``base_dir``, or a bundled name) and apply the overrides."""
    candidate = Path(spec.model).expanduser()
    if not candidate.is_absolute():
        candidate = base_dir / candidate
    if candidate.exists():
        target: str | Path = candidate
    elif spec.model in bundled_models():
        target = spec.model
    else:
        raise UvmsInputError(f"no such model file {candidate} (nor a bundled model: {', '.join(bundled_models())})",
                             source, "model")
    try:
        model = load_model(target)
    except UvmsInputError as exc:
        raise UvmsInputError(str(exc), source, "model") from None
    return apply_overrides(model, spec.model_overrides)


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
    if env.gravity is not None:
        changes["gravity"] = np.array(env.gravity)
    if env.density is not None:
        ratio = env.density / model.density
        changes.update(density=env.density, added_mass=model.added_mass * ratio,
                       buoyancy_mass=model.buoyancy_mass * ratio)
    return model.replace(**changes) if changes else model


def _check_against_model(spec: ScenarioSpec, model: Model, source: str | None) -> None:
    """Vector lengths that depend on the model's joint count ``n``."""
    n = model.n_joints
    vectors = spec.inputs.torque_vectors()
    vectors += [(f"initial_state.{k}", getattr(spec.initial_state, k)) for k in ("q", "qd")]
    if spec.inputs.joint_trajectory is not None:
        vectors += [(f"inputs.joint_trajectory.angles[{k}]", row)
                    for k, row in enumerate(spec.inputs.joint_trajectory.angles)]
    for path, values in vectors:
        if values is not None and len(values) != n:
            raise UvmsInputError(f"expected {n} values (one per joint of model {model.name!r}), found "
                                 f"{len(values)}: {show(list(values))}", source, path)


def _registry():
    """:mod:`uvms.control.registry`, or ``None`` while it does not exist."""
    import importlib

    try:
        return importlib.import_module("uvms.control.registry")
    except ModuleNotFoundError as exc:
        if exc.name != "uvms.control.registry":
            raise
        return None


def _make_controller(spec: ControllerSpec, model: Model, source: str | None):
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
