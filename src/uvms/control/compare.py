"""Controllers side by side on the paper's scenario (Section 6, case 3 "vehicle released, control on").

Every case runs the bundled scenario file :data:`PAPER_SCENARIO` (``paper_case3_controlled``: vehicle released
at rest at the origin, the paper's joint torques, 10 s, RK4 at 1 ms, controller updated every 10 ms), read
through :meth:`uvms.sim.scenario.Scenario.simulate_options`, with these changes: the case's controller; the
file's joint torques on joint 1 of an arm of any number of joints, the other joints none
(:func:`scenario_torques`); and ideal actuation (the commanded body wrench is applied as is, so that the
comparison isolates the control law) unless ``actuation`` is given. The metrics are named metrics of
:mod:`uvms.sim.metrics`, computed from the integrated states the same way for every controller:

- ``peak_xy_error_mm``: peak of ``|[R^T (p - p_0)]_xy|`` (body-frame horizontal error, Figures 5-6) [mm];
- ``peak_yaw_error_deg``: peak ``|wrap(psi - psi_0)|`` [deg];
- ``max_abs_s_<axis>``: peak ``|s| = |vel + lambda e|`` (Eq. 24, body-velocity surface) with the paper's
  ``lambda`` (also for PID);
- ``rms_command_<X|Y|N>``: RMS of the commanded surge and sway force [N] and yaw moment [N m];
- ``chatter_<X|Y|N>``: sign changes of the command's first difference between updates (smooth: few).
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms.sim.metrics import Series, paper_bandwidth, sign_changes  # noqa: F401  (sign_changes re-exported)

PAPER_SCENARIO = "paper_case3_controlled"
"""The bundled scenario every comparison runs (``src/uvms/scenarios/``)."""

PAPER_BANDWIDTH = paper_bandwidth()
"""The paper's ``lambda`` [1/s] (:class:`~uvms.control.smc.SlidingModeParameters`' default), used to compute
``s`` for every controller."""

COMMANDS = (("X", "N"), ("Y", "N"), ("N", "Nm"))
"""The commanded wrench components compared (surge force, sway force, yaw moment) and their units."""


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
"""The bundled comparison: the paper's controller, Newton-Euler feed-forward with a perfect and with a noisy,
delayed IMU (0.05 m/s^2 and rad/s^2 white noise, 2 samples late), the vehicle-only model, and PID."""

SLIDING_MODE = ("smc-ab", "smc-ne", "smc-vehicle")


def axis_series(result, *, bandwidth: float = PAPER_BANDWIDTH, surface: str = "body_velocity",
                position_desired=None, yaw_desired: float | None = None) -> dict[str, np.ndarray]:
    """Per recorded sample, the surge, sway and yaw ``error``, ``rate`` (the surface's ``vel``, see
    :meth:`uvms.sim.result.AxisErrors.rates`) and ``s = rate + lambda error``, each (K, 3), from the states
    (:meth:`uvms.sim.result.Result.axis_errors`; desired pose: the initial one unless given)."""
    axes = result.axis_errors(position_desired, yaw_desired)
    rate = axes.rates(surface)
    return {"error": axes.error, "rate": rate, "s": rate + bandwidth * axes.error}


def metrics(result, *, bandwidth: float = PAPER_BANDWIDTH) -> dict[str, float]:
    """The comparison metrics of one run (module docstring), from :mod:`uvms.sim.metrics`."""
    series = Series(result, bandwidth=bandwidth)
    out: dict[str, float] = {
        "peak_xy_error_mm": series.metric("peak_body_error_xy_m") * 1e3,
        "peak_yaw_error_deg": float(np.degrees(series.metric("peak_yaw_error_rad"))),
    }
    for axis in ("surge", "sway", "yaw"):
        out[f"max_abs_s_{axis}"] = series.metric(f"max_abs_surface_{axis}")
    for name, unit in COMMANDS:                    # a run without the signal (or only NaN) counts 0
        value = series.metric(f"rms_command_{name}")
        out[f"rms_command_{name}_{unit}"] = value if np.isfinite(value) else 0.0
    for name, _ in COMMANDS:
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


def run_case(model, case: Case, *, duration: float | None = None, step: float | None = None,
             period: float | None = None, hydro_scale: float | None = None, joint_torques=None, actuation=None):
    """Simulate one case of the paper scenario (:data:`PAPER_SCENARIO`) and return its
    :class:`~uvms.sim.result.Result`.

    ``duration``, ``step`` and the controller's ``period`` default to the scenario file's; ``hydro_scale`` (if
    given) sets the model error of the sliding-mode controllers unless the case's own parameters set it;
    ``joint_torques`` defaults to the file's schedule on joint 1 (:func:`scenario_torques`); ``actuation``
    (an :class:`~uvms.sim.run.Actuation`) to ideal actuation.
    """
    from uvms.control.registry import make_controller
    from uvms.sim.health import actuation_metadata
    from uvms.sim.run import Actuation, simulate
    from uvms.sim.scenario import load_scenario

    scenario = load_scenario(PAPER_SCENARIO).with_model(model)
    spec = scenario.spec
    period = spec.controller.period if period is None else period
    controller = None
    if case.controller is not None:
        parameters = dict(case.parameters)
        if hydro_scale is not None and case.controller in SLIDING_MODE:
            parameters.setdefault("hydro_scale", hydro_scale)
        controller = make_controller(case.controller, model, period=period, parameters=parameters)
    actuation = actuation if actuation is not None else Actuation()
    options = scenario.simulate_options()
    metadata = {**options["metadata"], "controller": case.controller, "case": case.label}
    for key in ("actuators", "thrust_limits_N"):  # the file's; this run's actuation is ``actuation``
        metadata.pop(key, None)
    options.update(duration=spec.duration if duration is None else duration, step=spec.step if step is None else step,
                   joint_torques=scenario_torques(model) if joint_torques is None else joint_torques,
                   controller=controller, actuation=actuation, control_period=period,
                   metadata={**metadata, "actuators": "ideal" if not actuation.thrusters else None,
                             **actuation_metadata(actuation)})
    return simulate(**options)


def run_cases(model, cases: tuple[Case, ...] | None = None, *, progress: Callable[[str], None] | None = None,
              **options) -> dict[str, Any]:
    """``{label: Result}`` for every case (default :data:`DEFAULT_CASES`); ``options`` as :func:`run_case`."""
    results = {}
    for case in cases or DEFAULT_CASES:
        if progress is not None:
            progress(case.label)
        results[case.label] = run_case(model, case, **options)
    return results


def compare_controllers(model, cases: tuple[Case, ...] | None = None, *, duration: float | None = None,
                        step: float | None = None, period: float | None = None, hydro_scale: float | None = None,
                        joint_torques=None, actuation=None, progress: Callable[[str], None] | None = None):
    """Run every case on the paper scenario and tabulate :func:`metrics`.

    Returns:
        pandas.DataFrame, one row per case: ``case``, ``controller``, the metrics, ``complete`` (False if the
        run diverged), ``healthy`` (:mod:`uvms.sim.health`) and ``wall_time_s``.
    """
    import pandas as pd

    rows = []
    for case in cases or DEFAULT_CASES:
        if progress is not None:
            progress(case.label)
        wall0 = _time.perf_counter()
        result = run_case(model, case, duration=duration, step=step, period=period, hydro_scale=hydro_scale,
                          joint_torques=joint_torques, actuation=actuation)
        wall = _time.perf_counter() - wall0
        rows.append({"case": case.label, "controller": case.controller or "none", **metrics(result),
                     "complete": bool(result.complete), "healthy": bool(result.health().healthy),
                     "wall_time_s": wall})
    return pd.DataFrame(rows)
