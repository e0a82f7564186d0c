"""Running the paper's Section 6 cases and measuring them (:mod:`uvms.reproduce`).

Cases (10 s each, RK4 at 1 ms, the paper's joint torques ``[2.5, 0, 0]`` N m until 2 s then ``[0.01, 0, 0]``),
each defined by its bundled scenario file (:data:`CASE_SCENARIOS`):

- ``fixed``: vehicle clamped, control off (a land-based arm: "the pilot's true intent");
- ``released``: vehicle released, control off;
- ``controlled``: vehicle released, ``smc-ab`` with the paper's values and the paper's 60 % model error
  (controller model added mass and drag = 0.4 x the plant's), updated every 10 ms.

Actuators: ``ideal`` (the commanded wrench is applied), ``healey`` (Healey thrusters in the paper layout plus a
sway thruster) or ``paper-layout`` (the paper's three Healey thrusters, which cannot push sideways). The
metrics of a run (:func:`case_metrics`, :func:`command_activity`, :func:`plant_effective_inertia`) are what the
claims (:mod:`uvms.reproduce.claims`) are judged on.
"""

from __future__ import annotations

from typing import Any, Callable

import numpy as np

from uvms.control.compare import IMU_NOISE
from uvms.control.smc import SlidingModeParameters
from uvms.safe_yaml import read_yaml_mapping
from uvms.sim.scenario import ScenarioSpec, resolve_scenario_path

_PAPER = SlidingModeParameters()
"""The paper's controller values: the defaults of the sliding-mode parameters, their one definition."""
PAPER_LAMBDA = _PAPER.bandwidth[0]         # the same on every paper axis
"""Sliding-surface bandwidth lambda [1/s] (appendix)."""
PAPER_PHI = _PAPER.boundary_layer[0]
"""Boundary-layer thickness Phi (appendix)."""
PAPER_MODEL_ERROR = _PAPER.hydro_scale
"""Controller model's added mass and drag = 0.4 x the plant's: the paper's "differed by 60 %"."""
ACTUATORS = {"ideal": "ideal", "healey": "paper-sway", "paper-layout": "paper"}
"""``--actuators`` choices and the thruster layout each one uses."""
AXES = ("surge", "sway", "yaw")
COMMAND_OF_AXIS = {"surge": "X", "sway": "Y", "yaw": "N"}
PAPER_B = dict(zip(AXES, _PAPER.b_limits()))
"""The paper's bounds ``[b_min, b_max]`` of Eqs. 27-29 [kg, kg, kg m^2] (the defaults of :mod:`uvms.control.smc`)."""


CASE_SCENARIOS = {"fixed": "paper_case1_fixed", "released": "paper_case2_released",
                  "controlled": "paper_case3_controlled"}
"""The bundled scenario file (``src/uvms/scenarios/``) that defines each case: duration, step, joint torques,
vehicle fixed or released, controller, its period and parameters (the paper's: the defaults). The report
overrides only the actuators of the controlled case (``--actuators``) and, for the chatter check, the
boundary layer (Phi / 100)."""


def _case_spec(case: str):
    """The validated content of a case's scenario file (the schema only: its model is not loaded)."""
    return ScenarioSpec.model_validate(read_yaml_mapping(resolve_scenario_path(CASE_SCENARIOS[case]),
                                                         "scenario fields"))


_CONTROLLED = _case_spec("controlled")
DURATION = _CONTROLLED.duration
"""Duration [s] of the controlled case: its scenario file's value (read, never re-typed; the same in every case)."""
STEP = _CONTROLLED.step
"""RK4 step [s], from the same file."""
CONTROL_PERIOD = _CONTROLLED.controller.period
"""The controller's update period [s], from the same file."""


def _simulate_case(model, case: str, actuators: str, *, boundary_layer: float | None = None):
    """One case, as its scenario file defines it (:data:`CASE_SCENARIOS`, through
    :meth:`~uvms.sim.scenario.Scenario.simulate_options`) on ``model``, the controlled case with ``actuators``
    and, if given, the controller's ``boundary_layer``."""
    from uvms.control.registry import make_controller
    from uvms.sim.health import actuation_metadata
    from uvms.sim.run import Actuation, simulate
    from uvms.sim.scenario import load_scenario

    scenario = load_scenario(CASE_SCENARIOS[case]).with_model(model)
    spec = scenario.spec
    options = scenario.simulate_options()
    metadata = {key: value for key, value in options["metadata"].items() if key != "thrust_limits_N"}
    if spec.controller is not None:
        parameters = dict(spec.controller.parameters)
        if boundary_layer is not None:
            parameters["boundary_layer"] = boundary_layer
        actuation = Actuation.named(ACTUATORS[actuators])
        options.update(controller=make_controller(spec.controller.name, model, period=spec.controller.period,
                                                  parameters=parameters),
                       actuation=actuation, control_period=spec.controller.period)
        metadata.update(actuation_metadata(actuation))
    options["metadata"] = {**metadata, "case": case, "actuators": actuators}
    return simulate(**options)


def case_metrics(result, fixed, *, bandwidth: float = PAPER_LAMBDA, phi: float = PAPER_PHI) -> dict[str, Any]:
    """The metrics of one case (see ``docs/reproduce.md``), named metrics of :mod:`uvms.sim.metrics`; ``fixed``
    is the fixed-base run for the end-effector path."""
    from uvms.sim.metrics import Series

    series = Series(result, bandwidth=bandwidth)
    s_states = series.axis()["s"]
    dt = float(np.median(np.diff(result.time)))

    def or_zero(value: float) -> float:
        return value if np.isfinite(value) else 0.0

    out: dict[str, Any] = {
        "peak_abs_x_m": series.metric("peak_abs_x_m"),
        "peak_abs_y_m": series.metric("peak_abs_y_m"),
        "peak_abs_yaw_rad": series.metric("peak_abs_yaw_rad"),   # unwrapped: a drift past 180 deg counts in full
        "peak_body_error_xy_m": series.metric("peak_body_error_xy_m"),
        "peak_body_error_x_m": series.metric("max_abs_axis_error_surge"),   # R^T (p - p0), as Figs. 5-6 draw it
        "peak_body_error_y_m": series.metric("max_abs_axis_error_sway"),
        "peak_ee_deviation_m": float(np.linalg.norm(result.end_effector - fixed.end_effector, axis=1).max()),
        "max_abs_s": {}, "time_outside_boundary_s": {}, "peak_command": {}, "command_sign_changes": {},
        "final_q": result.q[-1].tolist(),
        "complete": bool(result.complete),
    }
    for j, axis in enumerate(AXES):
        s = result.signals.get(f"s_{axis}", s_states[:, j])      # the controller's own s where it logged one
        s = np.where(np.isfinite(s), s, s_states[:, j])
        out["max_abs_s"][axis] = float(np.abs(s).max())
        out["time_outside_boundary_s"][axis] = float(np.count_nonzero(np.abs(s) > phi) * dt)
        command = f"command_{COMMAND_OF_AXIS[axis]}"
        out["peak_command"][axis] = or_zero(series.metric(f"max_abs_{command}"))
        out["command_sign_changes"][axis] = int(or_zero(series.metric(f"sign_changes_{command}")))
    return out


def plant_effective_inertia(model, result, *, every: int = 50) -> dict[str, list[float]]:
    """Range over a run of the plant's effective surge/sway mass and yaw inertia, ``1 / (IA_0^-1)_jj`` with
    ``IA_0`` the articulated inertia of the whole system at the vehicle (arm and added mass included): the
    quantity the paper's ``b`` bounds (Eqs. 27-29) must contain."""
    from uvms.dynamics.api import Dynamics

    dynamics = Dynamics(model)
    values = []
    for k in range(0, len(result.time), every):
        inverse = np.linalg.inv(dynamics.vehicle_articulated_inertia(result.state(k)))
        values.append([1.0 / inverse[j, j] for j in (3, 4, 2)])     # X (surge), Y (sway), N (yaw) of [K M N X Y Z]
    v = np.array(values)
    return {axis: [float(v[:, j].min()), float(v[:, j].max())] for j, axis in enumerate(AXES)}


def command_activity(result) -> dict[str, float]:
    """Precision and chatter of one controlled run: ``peak_xy_error_mm``, ``peak_yaw_error_deg`` (as
    :func:`uvms.control.compare.metrics`), ``chatter`` (slope sign changes of X, Y and N summed) and
    ``increment_rms_N`` (RMS of the step-to-step change of the commanded X and Y forces [N], counting only the
    samples where the command changes: the size of the chatter)."""
    from uvms.control.compare import metrics

    m = metrics(result)
    steps = []
    for name in ("X", "Y"):
        c = result.signals.get(f"command_{name}")
        if c is not None:
            d = np.diff(c[np.isfinite(c)])
            steps.append(d[d != 0])
    steps = np.concatenate(steps) if steps else np.zeros(0)
    return {"peak_xy_error_mm": m["peak_xy_error_mm"], "peak_yaw_error_deg": m["peak_yaw_error_deg"],
            "chatter": int(m["chatter_X"] + m["chatter_Y"] + m["chatter_N"]),
            "increment_rms_N": float(np.sqrt(np.mean(steps**2))) if steps.size else 0.0}


def _chatter(controlled, small) -> dict:
    from uvms.sim.metrics import sign_changes

    return {"paper": {k: sign_changes(controlled.signals[f"command_{k}"]) for k in ("X", "Y", "N")},
            "small": {k: sign_changes(small.signals[f"command_{k}"]) for k in ("X", "Y", "N")}}


def _check_choice(value: str, choices, option: str) -> None:
    if value not in choices:
        from uvms.errors import UvmsInputError

        raise UvmsInputError(f"unknown {option.lstrip('-')} {value!r}; expected one of: {', '.join(choices)}",
                             path=option)


def run(model=None, *, actuators: str = "ideal", progress: Callable[[str], None] | None = None) -> dict:
    """The three runs ``{"fixed", "released", "controlled"}: Result``."""
    import uvms

    _check_choice(actuators, ACTUATORS, "--actuators")
    model = model or uvms.load_model("paper")
    results = {}
    for case in ("fixed", "released", "controlled"):
        if progress:
            progress(f"case {case}")
        results[case] = _simulate_case(model, case, actuators)
    return results


def comparison(model, *, factors=(0.4, 1.0, 1.6), actuators=("ideal", "healey"),
               progress: Callable[[str], None] | None = None):
    """Controllers side by side on the controlled case: ``smc-ab``, ``smc-ne`` (noisy IMU), ``smc-vehicle``,
    ``pid``, for each model-error factor and actuator set. Returns a pandas DataFrame."""
    import pandas as pd

    from uvms.control.compare import Case, compare_controllers
    from uvms.sim.run import Actuation

    cases = (Case("smc-ab", "smc-ab"),
             Case("smc-ne (noisy IMU)", "smc-ne", dict(IMU_NOISE)),
             Case("smc-vehicle", "smc-vehicle"), Case("pid", "pid"))
    frames = []
    for act in actuators:
        for factor in factors:
            if progress:
                progress(f"comparison: {act} actuators, model error factor {factor}")
            df = compare_controllers(model, cases, hydro_scale=factor, actuation=Actuation.named(ACTUATORS[act]))
            df.insert(1, "actuators", act)
            df.insert(2, "model_error_factor", factor)
            frames.append(df)
    return pd.concat(frames, ignore_index=True)
