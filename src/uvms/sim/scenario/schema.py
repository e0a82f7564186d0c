"""The scenario file's schema: what to simulate (model, duration, integrator, inputs, controller, actuators).

Validated like a model file (pydantic v2, unknown keys rejected, one-line errors naming the file and the dotted
field path); ``docs/scenarios.md`` documents every field. This module holds the file's content only: the checks
against the model and the loading are :mod:`uvms.sim.scenario.load`'s, what is built from a validated file
(initial state, inputs, controller, the run) :mod:`uvms.sim.scenario.build`'s.

Field types and strictness come from :mod:`uvms.schema_base` (the kit shared with model and sweep files): a
number is a YAML number (the loader reads ``1e-3`` as one); a quoted ``"1e-3"`` is a string and is refused.
"""

from __future__ import annotations

from typing import Annotated, Any, Literal

import numpy as np
from pydantic import (
    AfterValidator,
    BeforeValidator,
    Discriminator,
    Field,
    Strict,
    Tag,
    field_validator,
    model_validator,
)

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
    numbers,
    show,
)
from uvms.sim.health import HealthLimits
from uvms.sim.inputs import TorqueSchedule
from uvms.sim.scenario.sensor_specs import KIND_TAGS, SensorsSpec

INTEGRATORS = ("rk4", "DOP853", "LSODA", "Radau", "RK45")
"""``rk4``: compiled fixed-step RK4; the others: ``scipy.integrate.solve_ivp`` methods."""

UNION_TAGS = ("list", "mapping", *KIND_TAGS)
"""Tags of this schema's list-or-mapping unions; left out of the field paths of error messages."""


def _list_or_mapping(value: Any) -> str:
    return "mapping" if isinstance(value, dict) else "list"


class EnvironmentOverrides(Spec):
    """Replace the model file's environment (``None``: keep the model's value)."""

    current: Vec3 | None = None                   # constant current velocity, world frame [m/s]
    density: Positive | None = None               # rho [kg/m^3]; added and displaced mass scale with it
    gravity: Vec3 | None = None                   # a_g, world frame of the model's `frame` [m/s^2]


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


class SpectrumTableSpec(Spec):
    """A user wave spectrum: one-sided density ``densities`` [m^2 s/rad] at ``frequencies`` [rad/s], linear in
    between, zero outside."""

    frequencies: Vector                           # angular frequencies [rad/s], increasing, > 0
    densities: Vector                             # S(omega) [m^2 s/rad], >= 0

    @model_validator(mode="after")
    def _consistent(self) -> SpectrumTableSpec:
        f, s = self.frequencies, self.densities
        if len(f) < 2 or len(f) > MAX_TABLE_ROWS:
            raise fail(f"expected 2 to {MAX_TABLE_ROWS} frequencies, found {len(f)}", "frequencies")
        if f[0] <= 0 or any(b <= a for a, b in zip(f, f[1:])):
            raise fail(f"expected positive frequencies in increasing order, found {show(list(f))}", "frequencies")
        if len(s) != len(f):
            raise fail(f"expected one density per frequency ({len(f)}), found {len(s)}", "densities")
        if any(v < 0 for v in s) or max(s) <= 0:
            raise fail(f"expected densities >= 0, not all zero, found {show(list(s))}", "densities")
        return self

    def peak(self) -> float:
        """The frequency of the largest density [rad/s]."""
        return self.frequencies[max(range(len(self.densities)), key=self.densities.__getitem__)]


MAX_TABLE_ROWS = 10_000
"""Most rows of a spectrum or current-profile table in a scenario file."""

_REGULAR_KEYS = ("height", "period", "phase")
_IRREGULAR_KEYS = ("spectrum", "significant_height", "peak_period", "peak_factor", "components", "seed",
                   "spreading", "frequency_range", "table")


class WavesSpec(Spec):
    """Linear (Airy) waves (``docs/environment.md``): ``type: regular`` (``height``, ``period``, ``phase``) or
    ``type: irregular`` (a spectrum, its components and seed); both take ``direction`` and ``water_depth``."""

    type: Literal["regular", "irregular"]
    direction: Annotated[float, BeforeValidator(finite_number)] = 0.0   # travel direction, +x toward +y [rad]
    water_depth: Positive | None = None           # h below the mean surface [m]; default: deep water
    height: Positive | None = None                # regular: H = 2 a [m]
    period: Positive | None = None                # regular: T [s]
    phase: Annotated[float, BeforeValidator(finite_number)] = 0.0       # regular: phi [rad] (0: crest at origin)
    spectrum: Literal["jonswap", "pierson_moskowitz", "table"] | None = None   # irregular
    significant_height: Positive | None = None    # irregular: H_s [m] (jonswap, pierson_moskowitz)
    peak_period: Positive | None = None           # irregular: T_p [s] (jonswap, pierson_moskowitz)
    peak_factor: Annotated[float, BeforeValidator(finite_number), Field(ge=1, le=7)] = 3.3   # jonswap gamma [-]
    components: Annotated[int, Strict(), Field(ge=1, le=10_000)] = 50     # irregular: how many [-]
    seed: Annotated[int, Strict(), Field(ge=0)] = 0                     # irregular: random frequencies, phases
    spreading: NonNegative | None = None          # irregular: s of cos^2s spreading; default: one direction
    frequency_range: Annotated[tuple[float, float], numbers(2, minimum=0.0)] | None = None   # [rad/s]
    table: SpectrumTableSpec | None = None        # spectrum: table

    @model_validator(mode="after")
    def _fields_of_the_type(self) -> WavesSpec:
        own, other = (_REGULAR_KEYS, _IRREGULAR_KEYS) if self.type == "regular" else (_IRREGULAR_KEYS, _REGULAR_KEYS)
        for key in other:
            if key in self.model_fields_set:
                raise fail(f"not a field of type: {self.type} (its fields: {', '.join(own)}, direction, "
                           f"water_depth)", key)
        if self.type == "regular":
            for key in ("height", "period"):
                if getattr(self, key) is None:
                    raise fail("expected a value (required for type: regular), found none", key)
            return self
        if self.spectrum is None:
            raise fail("expected jonswap, pierson_moskowitz or table (required for type: irregular), found none",
                       "spectrum")
        analytic = self.spectrum != "table"
        needed = ("significant_height", "peak_period") if analytic else ("table",)
        unused = ("table",) if analytic else ("significant_height", "peak_period", "peak_factor")
        for key in needed:
            if getattr(self, key) is None:
                raise fail(f"expected a value (required for spectrum: {self.spectrum}), found none", key)
        for key in unused:
            if key in self.model_fields_set:
                raise fail(f"not used by spectrum: {self.spectrum}", key)
        if self.spectrum == "pierson_moskowitz" and "peak_factor" in self.model_fields_set:
            raise fail("not used by spectrum: pierson_moskowitz (jonswap with peak_factor 1 is the same)",
                       "peak_factor")
        lo, hi = self.frequencies()
        if not 0.0 < lo < hi:
            raise fail(f"expected 0 < lower < upper [rad/s], found {show([lo, hi])}", "frequency_range")
        peak = self.peak()
        if not lo <= peak <= hi:
            raise fail(f"expected the spectrum's peak ({peak:.4g} rad/s) inside the frequency range, found "
                       f"[{lo:.4g}, {hi:.4g}] rad/s", "frequency_range")
        return self

    def peak(self) -> float:
        """An irregular sea's peak frequency [rad/s]: ``2 pi / T_p``, or a table's largest density."""
        return self.table.peak() if self.spectrum == "table" else 2.0 * np.pi / self.peak_period

    def frequencies(self) -> tuple[float, float]:
        """The discretised range [rad/s]: ``frequency_range``, else ``(0.5, 4) omega_p`` for an analytic
        spectrum (:data:`uvms.hydro.waves.DEFAULT_RANGE`) and the table's own range."""
        if self.frequency_range is not None:
            return self.frequency_range
        if self.spectrum == "table":
            return self.table.frequencies[0], self.table.frequencies[-1]
        from uvms.hydro.waves import DEFAULT_RANGE

        wp = self.peak()
        return DEFAULT_RANGE[0] * wp, DEFAULT_RANGE[1] * wp


class PowerLawSpec(Spec):
    """DNV-RP-C205 Eq. 4.1.3: ``v(d) = surface_velocity ((h - d) / h)^exponent`` for depths ``0 <= d <= h``."""

    surface_velocity: Vec3                        # world [m/s]
    water_depth: Positive                         # h [m]
    exponent: Positive = 1.0 / 7.0                # alpha [-]


class ProfileSpec(Spec):
    """A current against depth below the mean surface, added to the uniform current: a table (``depth``,
    ``velocity``) or a ``power_law``."""

    depth: Vector | None = None                   # [m], positive down, increasing
    velocity: tuple[Vec3, ...] | None = None      # world [m/s], one row per depth
    power_law: PowerLawSpec | None = None

    @model_validator(mode="after")
    def _one_form(self) -> ProfileSpec:
        table = self.depth is not None or self.velocity is not None
        if table == (self.power_law is not None):
            raise fail(f"expected either depth and velocity or power_law, found {'both' if table else 'neither'}")
        if table:
            if self.depth is None or self.velocity is None:
                raise fail("expected both depth and velocity", "depth" if self.depth is None else "velocity")
            if len(self.depth) > MAX_TABLE_ROWS:
                raise fail(f"expected at most {MAX_TABLE_ROWS} depths, found {len(self.depth)}", "depth")
            if any(b <= a for a, b in zip(self.depth, self.depth[1:])):
                raise fail(f"expected strictly increasing depths, found {show(list(self.depth))}", "depth")
            if len(self.velocity) != len(self.depth):
                raise fail(f"expected one row per depth ({len(self.depth)}), found {len(self.velocity)}",
                           "velocity")
        return self


class FieldSpec(Spec):
    """A gridded current read from ``file`` (CSV or NetCDF, ``docs/environment.md``), added to the uniform
    current; ``outside``: what it is off the grid."""

    file: Annotated[str, Field(min_length=1)]     # relative to the scenario file, inside its folder
    outside: Literal["hold", "zero", "error"] = "error"


class SpatialCurrentSpec(Spec):
    """A current that varies in space (exactly one of ``profile`` or ``field``)."""

    profile: ProfileSpec | None = None
    field: FieldSpec | None = None

    @model_validator(mode="after")
    def _one_form(self) -> SpatialCurrentSpec:
        if (self.profile is None) == (self.field is None):
            raise fail(f"expected exactly one of 'profile' or 'field', found "
                       f"{'both' if self.profile is not None else 'neither'}")
        return self


class EnvironmentSpec(Spec):
    """Real water (``docs/environment.md``): waves and a current varying in space, both added to the uniform
    current (``inputs.current`` or the model's)."""

    waves: WavesSpec | None = None
    current: SpatialCurrentSpec | None = None
    surface: Annotated[float, BeforeValidator(finite_number)] = 0.0   # world z of the mean free surface [m]


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


class JointMotionSpec(Spec):
    """A prescribed joint motion (:class:`uvms.sim.joint_motion.JointMotion`): every joint follows it exactly,
    from a CSV table file (``file``, ``time``, ``columns``) or inline (``times``, ``angles``)."""

    file: Annotated[str, Field(min_length=1)] | None = None   # CSV table (relative: to the scenario file)
    time: Annotated[str, Field(min_length=1)] | None = None   # the file's column of times [s]
    columns: dict[str, Annotated[str, Field(min_length=1)]] | None = None   # joint name -> the file's column
    times: Vector | None = None                   # inline: row times [s], increasing
    angles: tuple[Vector, ...] | None = None      # inline: one row per time, one value per joint [rad or m]
    joints: tuple[str, ...] | None = None         # inline: the joint of each angle column (default: joint order)
    boundary: Literal["not-a-knot", "clamped", "natural"] = "not-a-knot"   # the cubic spline's end condition
    smoothing: Positive | Literal["gcv"] | None = None    # a smoothing spline's penalty [s^3], or "gcv"

    @model_validator(mode="after")
    def _one_form(self) -> JointMotionSpec:
        table = self.file is not None
        inline = self.times is not None or self.angles is not None
        if table == inline:
            raise fail(f"expected either file (with time and columns) or times and angles, found "
                       f"{'both' if table else 'neither'}")
        if table and (self.time is None or not self.columns):
            raise fail("expected the file's time column and columns {joint: column}", "time" if self.time is None
                       else "columns")
        if inline and (self.times is None or self.angles is None):
            raise fail("expected both times and angles", "times" if self.times is None else "angles")
        if inline and len(self.angles) != len(self.times):
            raise fail(f"expected one row of angles per time ({len(self.times)}), found {len(self.angles)}",
                       "angles")
        return self


class InputsSpec(Spec):
    """External inputs, held between updates (zero-order hold)."""

    joint_torques: JointTorques | None = None     # [N m]; default: zero
    joint_trajectory: JointTrajectorySpec | None = None   # instead of joint_torques: track a joint trajectory
    joint_motion: JointMotionSpec | None = None   # instead of both: the joints follow a table exactly
    body_wrench: Vec6 = ZERO6                     # on the vehicle, body axes [moment; force] [N m, N]
    ee_wrench: Vec6 = ZERO6                       # on the end effector, its axes [moment; force] [N m, N]
    current: CurrentSpec | None = None            # default: the model's environment current

    @model_validator(mode="after")
    def _one_arm_input(self) -> InputsSpec:
        if self.joint_torques is not None and self.joint_trajectory is not None:
            raise fail("expected joint_torques or joint_trajectory, not both", "joint_trajectory")
        if self.joint_motion is not None and (self.joint_torques is not None or self.joint_trajectory is not None):
            raise fail("expected joint_motion or a joint torque input (joint_torques, joint_trajectory), not both",
                       "joint_motion")
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
    environment: EnvironmentSpec = EnvironmentSpec()   # waves, currents varying in space
    controller: ControllerSpec | None = None
    actuators: str = "ideal"                      # thruster layout (uvms.thrusters.layouts)
    outputs: OutputsSpec = OutputsSpec()
    health: HealthSpec = HealthSpec()
    sensors: SensorsSpec = {}                     # name -> simulated sensor (docs/sensors.md)

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
