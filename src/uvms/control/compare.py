"""Controllers side by side on a scenario: by default the paper's (Section 6, case 3 "vehicle released,
control on"), or any scenario file (``uvms compare --scenario NAME``).

Every case runs the scenario file, read through :meth:`uvms.sim.scenario.Scenario.simulate_options`, with the
case's controller in place of the file's. The axes every case holds are the file's controller's ``axes``
(default: the paper's surge, sway, yaw; :func:`scenario_axes`), its period the file's. On the paper scenario
:data:`PAPER_SCENARIO` (``paper_case3_controlled``: vehicle released at rest at the origin, the paper's joint
torques, 10 s, RK4 at 1 ms, controller updated every 10 ms) the file's joint torques drive joint 1 of an arm of
any number of joints, the other joints none (:func:`scenario_torques`), and the actuation is ideal (the
commanded body wrench is applied as is, so that the comparison isolates the control law) unless ``actuation``
is given. Any other scenario runs its own inputs (joint torques or trajectory, current) and its own actuators
(e.g. the model's thrusters) unless ``actuation`` is given; a scenario with waves or a current varying in space
(``environment:``) also runs ``smc-ab`` with its wave feed-forward (:data:`WAVE_FEED_FORWARD_CASE`,
:mod:`uvms.control.smc_ab`).

The metrics are named metrics of :mod:`uvms.sim.metrics`, computed from the integrated states the same way for
every controller, for the axes held (:func:`metrics`). On the paper's axes (surge, sway, yaw):

- ``peak_xy_error_mm``: peak of ``|[R^T (p - p_0)]_xy|`` (body-frame horizontal error, Figures 5-6) [mm];
- ``peak_yaw_error_deg``: peak ``|wrap(psi - psi_0)|`` [deg];
- ``max_abs_s_<axis>``: peak ``|s| = |vel + lambda e|`` (Eq. 24, body-velocity surface) with the paper's
  ``lambda`` (also for PID);
- ``rms_command_<X|Y|N>``: RMS of the commanded surge and sway force [N] and yaw moment [N m];
- ``chatter_<X|Y|N>``: sign changes of the command's first difference between updates (smooth: few).

On any other set of axes (e.g. all six) the errors are those of the six-axis set point, the initial position
and yaw, level (the controllers' default; a scenario that sets another set point is refused):

- ``peak_world_xy_error_mm`` (surge or sway held): peak ``|(p - p_0)_xy|``, world frame [mm];
- ``peak_depth_error_mm`` (heave): peak ``|z - z_0|`` [mm];
- ``peak_roll_error_deg``, ``peak_pitch_error_deg`` (roll, pitch): peak ``|phi|``, ``|theta|`` [deg];
  ``peak_yaw_error_deg`` (yaw) as above;
- ``rms_command_<C>_<unit>`` and ``chatter_<C>`` for the wrench component ``C`` of every held axis
  (X, Y, Z [N]; K, M, N [N m]).
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms.sim.metrics import Series, paper_bandwidth, sign_changes  # noqa: F401  (sign_changes re-exported)

PAPER_SCENARIO = "paper_case3_controlled"
"""The bundled scenario a comparison runs by default (``src/uvms/scenarios/``)."""

PAPER_AXES: tuple[str, ...] = ("surge", "sway", "yaw")
"""The paper's held axes: the comparison's metrics are the paper's (body-frame xy error, ``|s|``) on these."""

PAPER_BANDWIDTH = paper_bandwidth()
"""The paper's ``lambda`` [1/s] (:class:`~uvms.control.smc.SlidingModeParameters`' default), used to compute
``s`` for every controller."""

COMMANDS = (("X", "N"), ("Y", "N"), ("N", "Nm"))
"""The commanded wrench components compared on the paper's axes (surge force, sway force, yaw moment) and their
units."""

AXIS_COMMAND: dict[str, tuple[str, str]] = {"surge": ("X", "N"), "sway": ("Y", "N"), "heave": ("Z", "N"),
                                            "roll": ("K", "Nm"), "pitch": ("M", "Nm"), "yaw": ("N", "Nm")}
"""The wrench component of each axis and its unit."""

SET_POINT_PARAMETERS = ("desired_position", "desired_yaw", "desired_roll", "desired_pitch", "desired_attitude",
                        "waypoints")
"""Controller parameters that move the set point away from the one the metrics measure from."""


@dataclass(frozen=True)
class Case:
    """One row of the comparison: a label, a registered controller name (``None``: control off), parameters."""

    label: str
    controller: str | None
    parameters: dict[str, Any] = field(default_factory=dict)


IMU_NOISE = {"imu_noise": 0.05, "imu_delay": 2, "imu_seed": 1}
"""``smc-ne``'s noisy IMU in the comparisons (here and ``uvms reproduce``): 0.05 m/s^2 (rad/s^2) white noise,
2 samples late, a fixed seed (repeatable)."""

DEFAULT_CASES: tuple[Case, ...] = (
    Case("smc-ab", "smc-ab"),
    Case("smc-ne (perfect IMU)", "smc-ne"),
    Case("smc-ne (noisy IMU)", "smc-ne", dict(IMU_NOISE)),
    Case("smc-vehicle", "smc-vehicle"),
    Case("pid", "pid"),
)
"""The bundled comparison on the paper's scenario (today's table, unchanged): the paper's controller, Newton-Euler
feed-forward with a perfect and with a noisy, delayed IMU (0.05 m/s^2 and rad/s^2 white noise, 2 samples late),
the vehicle-only model, and PID. (``lqr`` is in :data:`SIX_AXIS_CASES`; on the paper's scenario pass
``cases=DEFAULT_CASES + (LQR_CASE,)``.)"""

LQR_CASE = Case("lqr", "lqr")
"""The linear-quadratic baseline (:mod:`uvms.control.lqr`, designed from the plant's own model, no integrators)."""

SIX_AXIS_CASES: tuple[Case, ...] = (
    Case("smc-ab", "smc-ab"),
    Case("smc-ne (perfect IMU)", "smc-ne"),
    Case("smc-vehicle", "smc-vehicle"),
    Case("pid", "pid"),
    LQR_CASE,
)
"""The comparison on any scenario other than the paper's: the paper's controller, Newton-Euler feed-forward,
the vehicle-only model, PID and LQR, each on the scenario's axes."""

WAVE_FEED_FORWARD_CASE = Case("smc-ab (wave feed-forward)", "smc-ab", {"wave_feed_forward": True})
"""``smc-ab`` whose model sees the run's water (:mod:`uvms.control.smc_ab`), compared on scenarios with waves or a
current varying in space (``environment:``), next to ``smc-ab`` without it."""

SLIDING_MODE = ("smc-ab", "smc-ne", "smc-vehicle")


def load(scenario):
    """A :class:`~uvms.sim.scenario.Scenario` from a bundled name, a path or a scenario (returned as is)."""
    from uvms.sim.scenario import Scenario, load_scenario

    return scenario if isinstance(scenario, Scenario) else load_scenario(scenario)


def is_paper(scenario) -> bool:
    """True for the paper's scenario (:data:`PAPER_SCENARIO`, loaded from the bundled file)."""
    from uvms.sim.scenario import resolve_scenario_path

    return load(scenario).source == str(resolve_scenario_path(PAPER_SCENARIO))


def scenario_axes(scenario) -> tuple[str, ...]:
    """The axes the scenario's controller holds (its ``axes`` parameter; default and without a controller:
    :data:`PAPER_AXES`).

    Raises:
        UvmsInputError: the controller's parameters set a set point (:data:`SET_POINT_PARAMETERS`; the
            metrics measure from the initial position and yaw, level) or name bad axes.
    """
    from uvms.control.axes import axis_list
    from uvms.errors import UvmsInputError

    scenario = load(scenario)
    spec = scenario.spec.controller
    parameters = {} if spec is None else spec.parameters
    for name in SET_POINT_PARAMETERS:
        if name in parameters:
            raise UvmsInputError("expected the default set point (the comparison's errors are measured from the "
                                 "initial position and yaw, level), found a set point", scenario.source,
                                 f"controller.parameters.{name}")
    if "axes" not in parameters:
        return PAPER_AXES
    try:
        return axis_list(parameters["axes"])
    except ValueError as exc:          # pragma: no cover - the scenario's controller was built at load time
        raise UvmsInputError(str(exc), scenario.source, "controller.parameters.axes") from None


def default_cases(scenario) -> tuple[Case, ...]:
    """The cases compared on ``scenario``: :data:`DEFAULT_CASES` on the paper's, else :data:`SIX_AXIS_CASES`,
    with :data:`WAVE_FEED_FORWARD_CASE` after ``smc-ab`` when the scenario has an ``environment:`` (waves or a
    current varying in space)."""
    from uvms.sim.scenario.environment import has_real_water

    if is_paper(scenario):
        return DEFAULT_CASES
    if has_real_water(load(scenario).spec):
        return SIX_AXIS_CASES[:1] + (WAVE_FEED_FORWARD_CASE,) + SIX_AXIS_CASES[1:]
    return SIX_AXIS_CASES


def axis_series(result, *, bandwidth: float = PAPER_BANDWIDTH, surface: str = "body_velocity",
                position_desired=None, yaw_desired: float | None = None) -> dict[str, np.ndarray]:
    """Per recorded sample, the surge, sway and yaw ``error``, ``rate`` (the surface's ``vel``, see
    :meth:`uvms.sim.result.AxisErrors.rates`) and ``s = rate + lambda error``, each (K, 3), from the states
    (:meth:`uvms.sim.result.Result.axis_errors`; desired pose: the initial one unless given)."""
    axes = result.axis_errors(position_desired, yaw_desired)
    rate = axes.rates(surface)
    return {"error": axes.error, "rate": rate, "s": rate + bandwidth * axes.error}


def metrics(result, *, bandwidth: float = PAPER_BANDWIDTH, axes: tuple[str, ...] = PAPER_AXES) -> dict[str, float]:
    """The comparison metrics of one run for the held ``axes`` (module docstring), from :mod:`uvms.sim.metrics`:
    the paper's on a subset of :data:`PAPER_AXES` (its default), the six-axis ones otherwise."""
    series = Series(result, bandwidth=bandwidth)
    paper = set(axes) <= set(PAPER_AXES)
    out: dict[str, float] = {}
    if paper:
        out["peak_xy_error_mm"] = series.metric("peak_body_error_xy_m") * 1e3
        out["peak_yaw_error_deg"] = float(np.degrees(series.metric("peak_yaw_error_rad")))
        for axis in PAPER_AXES:
            out[f"max_abs_s_{axis}"] = series.metric(f"max_abs_surface_{axis}")
        commands = COMMANDS
    else:
        if {"surge", "sway"} & set(axes):
            out["peak_world_xy_error_mm"] = series.metric("peak_world_error_xy_m") * 1e3
        if "heave" in axes:
            out["peak_depth_error_mm"] = series.metric("peak_depth_error_m") * 1e3
        for axis in ("roll", "pitch", "yaw"):
            if axis in axes:
                out[f"peak_{axis}_error_deg"] = float(np.degrees(series.metric(f"peak_{axis}_error_rad")))
        commands = tuple(command for axis, command in AXIS_COMMAND.items() if axis in axes)
    for name, unit in commands:                    # a run without the signal (or only NaN) counts 0
        value = series.metric(f"rms_command_{name}")
        out[f"rms_command_{name}_{unit}"] = value if np.isfinite(value) else 0.0
    for name, _ in commands:
        value = series.metric(f"sign_changes_command_{name}")
        out[f"chatter_{name}"] = int(value) if np.isfinite(value) else 0
    return out


def scenario_torques(model):
    """The joint-torque schedule of :data:`PAPER_SCENARIO` (the paper's, Section 6) for ``model``'s arm: joint
    1 gets the file's joint-1 torques, every other joint none (the paper's own joints 2 and 3 get none either),
    so any arm of at least one joint runs the paper's scenario; the paper's 3-joint model gets exactly the file's
    schedule (:func:`~uvms.sim.inputs.paper_torques`).

    Raises:
        UvmsInputError: a model without an arm (nothing for the schedule to drive).
    """
    from uvms import checks
    from uvms.sim.inputs import TorqueSchedule
    from uvms.sim.scenario import load_scenario

    n = checks.model(model).n_joints
    if n == 0:
        raise checks.fail("model", f"expected a model with an arm (the scenario drives joint 1 with the paper's "
                                   f"torques), got {model.name!r} with 0 joints")
    paper = load_scenario(PAPER_SCENARIO).spec.inputs.torque_schedule()
    torques = np.zeros((paper.times.size, n))
    k = min(n, paper.torques.shape[1])            # a shorter arm drops the paper's joints 2-3: zero torque
    torques[:, :k] = paper.torques[:, :k]
    return TorqueSchedule(times=paper.times, torques=torques)


def run_case(model, case: Case, *, scenario=PAPER_SCENARIO, duration: float | None = None,
             step: float | None = None, period: float | None = None, hydro_scale: float | None = None,
             actuation=None):
    """Simulate one case of ``scenario`` (a bundled name, a path or a :class:`~uvms.sim.scenario.Scenario`;
    default :data:`PAPER_SCENARIO`) on ``model`` (``None``: the scenario's) and return its
    :class:`~uvms.sim.result.Result`.

    The case's controller holds the scenario's axes (:func:`scenario_axes`) unless its own parameters name them.
    ``duration``, ``step`` and the controller's ``period`` default to the scenario file's; ``hydro_scale`` (if
    given) sets the model error of the sliding-mode controllers unless the case's own parameters set it;
    ``actuation`` (an :class:`~uvms.sim.run.Actuation`) defaults to ideal actuation on the paper scenario and the
    file's actuators on any other. The joint torques are the file's inputs (on the paper scenario: its schedule
    on joint 1, :func:`scenario_torques`); for other inputs, pass a scenario with them
    (:func:`uvms.sim.scenario.scenario_from_data`).
    """
    from uvms.control.registry import make_controller
    from uvms.control.smc import warn_controller_b_bounds
    from uvms.sim.health import actuation_metadata
    from uvms.sim.run import Actuation, simulate

    scenario = load(scenario)
    paper = is_paper(scenario)
    axes = scenario_axes(scenario)
    if model is not None:
        scenario = scenario.with_model(model)
    model = scenario.model
    spec = scenario.spec
    if period is None:
        period = spec.controller.period if spec.controller is not None else 0.01
    controller = None
    if case.controller is not None:
        parameters = dict(case.parameters)
        if axes != PAPER_AXES:
            parameters.setdefault("axes", list(axes))
        if hydro_scale is not None and case.controller in SLIDING_MODE:
            parameters.setdefault("hydro_scale", hydro_scale)
        controller = make_controller(case.controller, model, period=period, parameters=parameters)
        warn_controller_b_bounds(controller)      # one line for every case that relies on bounds that miss
    options = scenario.simulate_options()
    if actuation is None:
        actuation = Actuation() if paper else options["actuation"]
    metadata = {**options["metadata"], "controller": case.controller, "case": case.label}
    for key in ("actuators", "thrust_limits_N"):  # the file's; this run's actuation is ``actuation``
        metadata.pop(key, None)
    options.update(duration=spec.duration if duration is None else duration, step=spec.step if step is None else step,
                   controller=controller, actuation=actuation,
                   metadata={**metadata, "actuators": "ideal" if not actuation.thrusters else None,
                             **actuation_metadata(actuation)})
    if paper:
        options.update(joint_torques=scenario_torques(model), control_period=period)
    return simulate(**options)


def run_cases(model, cases: tuple[Case, ...] | None = None, *, progress: Callable[[str], None] | None = None,
              **options) -> dict[str, Any]:
    """``{label: Result}`` for every case (default :func:`default_cases` of the scenario); ``options`` as
    :func:`run_case`."""
    results = {}
    for case in cases or default_cases(options.get("scenario", PAPER_SCENARIO)):
        if progress is not None:
            progress(case.label)
        results[case.label] = run_case(model, case, **options)
    return results


def compare_controllers(model, cases: tuple[Case, ...] | None = None, *, progress: Callable[[str], None] | None = None,
                        **options):
    """Run every case (default :func:`default_cases`) on the scenario and tabulate :func:`metrics` for the axes
    it holds; ``options`` are :func:`run_case`'s (``scenario``, ``duration``, ``step``, ``period``,
    ``hydro_scale``, ``actuation``).

    Returns:
        pandas.DataFrame, one row per case: ``case``, ``controller``, the metrics, ``complete`` (False if the
        run diverged), ``healthy`` (:mod:`uvms.sim.health`) and ``wall_time_s``.
    """
    import pandas as pd

    scenario = load(options.pop("scenario", PAPER_SCENARIO))
    axes = scenario_axes(scenario)
    rows = []
    for case in cases or default_cases(scenario):
        if progress is not None:
            progress(case.label)
        wall0 = _time.perf_counter()
        result = run_case(model, case, scenario=scenario, **options)
        wall = _time.perf_counter() - wall0
        rows.append({"case": case.label, "controller": case.controller or "none", **metrics(result, axes=axes),
                     "complete": bool(result.complete), "healthy": bool(result.health().healthy),
                     "wall_time_s": wall})
    return pd.DataFrame(rows)
