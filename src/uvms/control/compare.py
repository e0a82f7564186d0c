"""Controllers side by side on the paper's scenario (Section 6, case 3 "vehicle released, control on").

Every case runs the same simulation: vehicle released at rest at the origin, the paper's joint torques
(:func:`uvms.sim.inputs.paper_torques`: 2.5 N m on joint 1 for 2 s, then 0.01 N m; on an arm of any number
of joints the other joints get none, :func:`scenario_torques`), 10 s, RK4 at 1 ms, ideal actuation (the
commanded body wrench is applied as is), controller updated every 10 ms. The metrics are computed from the
integrated states, the same way for every controller:

- ``peak_xy_error_mm``: peak of ``|[R^T (p - p_0)]_xy|`` (body-frame horizontal error, Figures 5-6) [mm];
- ``peak_yaw_error_deg``: peak ``|wrap(psi - psi_0)|`` [deg];
- ``max_abs_s_<axis>``: peak ``|s| = |e_dot + lambda e|`` with the paper's ``lambda`` (also for PID);
- ``rms_command_<X|Y|N>``: RMS of the commanded surge and sway force [N] and yaw moment [N m];
- ``chatter_<X|Y|N>``: sign changes of the command's first difference between updates (smooth: few).
"""

from __future__ import annotations

import time as _time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from uvms.control.smc import axis_kinematics

PAPER_BANDWIDTH = 3.14
"""The paper's ``lambda`` [1/s], used to compute ``s`` for every controller."""

COMMANDS = (("X", "N"), ("Y", "N"), ("N", "Nm"))
"""The commanded wrench components compared (surge force, sway force, yaw moment) and their units."""


@dataclass(frozen=True)
class Case:
    """One row of the comparison: a label, a registered controller name (``None``: control off), parameters."""

    label: str
    controller: str | None
    parameters: dict[str, Any] = field(default_factory=dict)


DEFAULT_CASES: tuple[Case, ...] = (
    Case("smc-ab", "smc-ab"),
    Case("smc-ne (perfect IMU)", "smc-ne"),
    Case("smc-ne (noisy IMU)", "smc-ne", {"imu_noise": 0.05, "imu_delay": 2, "imu_seed": 1}),
    Case("smc-vehicle", "smc-vehicle"),
    Case("pid", "pid"),
)
"""The bundled comparison: the paper's controller, Newton-Euler feed-forward with a perfect and with a noisy,
delayed IMU (0.05 m/s^2 and rad/s^2 white noise, 2 samples late), the vehicle-only model, and PID."""

SLIDING_MODE = ("smc-ab", "smc-ne", "smc-vehicle")


def sign_changes(values: np.ndarray, relative_tolerance: float = 1e-6) -> int:
    """Sign changes of the first difference of ``values``; differences within ``relative_tolerance`` times
    ``max |values|`` (held samples, rounding noise) are skipped. A smooth signal has few, chatter many."""
    x = np.asarray(values, dtype=float)
    x = x[np.isfinite(x)]
    if x.size < 3:
        return 0
    d = np.diff(x)
    d = d[np.abs(d) > relative_tolerance * max(np.abs(x).max(), 1e-300)]
    return int(np.count_nonzero(np.diff(np.sign(d)) != 0))


def axis_series(result, *, bandwidth: float = PAPER_BANDWIDTH, surface: str = "body_velocity",
                position_desired=None, yaw_desired: float | None = None) -> dict[str, np.ndarray]:
    """Per recorded sample, the surge, sway and yaw ``error``, ``rate`` (the surface's ``vel``, see
    :meth:`uvms.control.smc.AxisKinematics.rates`) and ``s = rate + lambda error``, each (K, 3), computed
    from the states (desired pose: the initial one unless given)."""
    from uvms.sim.integrate import unpack

    n = result.n_joints
    states = [unpack(x, n) for x in result.states]
    p_d = np.array(states[0].position if position_desired is None else position_desired, dtype=float)
    psi_d = float(states[0].euler[2]) if yaw_desired is None else float(yaw_desired)
    error = np.zeros((len(states), 3))
    rate = np.zeros((len(states), 3))
    for k, st in enumerate(states):
        kin = axis_kinematics(st, p_d, psi_d)
        error[k], rate[k] = kin.error, kin.rates(surface)
    return {"error": error, "rate": rate, "s": rate + bandwidth * error}


def metrics(result, *, bandwidth: float = PAPER_BANDWIDTH) -> dict[str, float]:
    """The comparison metrics of one run (module docstring)."""
    series = axis_series(result, bandwidth=bandwidth)
    e = series["error"]
    out: dict[str, float] = {
        "peak_xy_error_mm": float(np.hypot(e[:, 0], e[:, 1]).max() * 1e3),
        "peak_yaw_error_deg": float(np.degrees(np.abs(e[:, 2]).max())),
    }
    for j, axis in enumerate(("surge", "sway", "yaw")):
        out[f"max_abs_s_{axis}"] = float(np.abs(series["s"][:, j]).max())
    for name, unit in COMMANDS:
        command = result.signals.get(f"command_{name}")
        valid = command[np.isfinite(command)] if command is not None else np.zeros(1)
        out[f"rms_command_{name}_{unit}"] = float(np.sqrt(np.mean(valid**2))) if valid.size else 0.0
    for name, _ in COMMANDS:
        command = result.signals.get(f"command_{name}")
        out[f"chatter_{name}"] = sign_changes(command) if command is not None else 0
    return out


def scenario_torques(model):
    """The paper's joint-torque schedule (Section 6) for ``model``'s arm: joint 1 gets the paper's torques,
    every other joint none (the paper's own joints 2 and 3 get none either), so any arm of at least one joint
    runs the paper's scenario; the paper's 3-joint model gets exactly :func:`~uvms.sim.inputs.paper_torques`.

    Raises:
        UvmsInputError: a model without an arm (nothing for the schedule to drive).
    """
    from uvms import checks
    from uvms.sim.inputs import TorqueSchedule, paper_torques

    n = checks.model(model).n_joints
    if n == 0:
        raise checks.fail("model", f"expected a model with an arm (the scenario drives joint 1 with the paper's "
                                   f"torques), got {model.name!r} with 0 joints")
    paper = paper_torques()
    torques = np.zeros((paper.times.size, n))
    k = min(n, paper.torques.shape[1])            # a shorter arm drops the paper's joints 2-3: zero torque
    torques[:, :k] = paper.torques[:, :k]
    return TorqueSchedule(times=paper.times, torques=torques)


def run_case(model, case: Case, *, duration: float = 10.0, step: float = 1e-3, period: float = 0.01,
             hydro_scale: float | None = None, joint_torques=None, actuation=None):
    """Simulate one case of the paper scenario and return its :class:`~uvms.sim.result.Result`.

    ``hydro_scale`` (if given) sets the model error of the sliding-mode controllers unless the case's own
    parameters set it; ``joint_torques`` defaults to the paper's schedule (:func:`scenario_torques`).
    """
    from uvms.control.registry import make_controller
    from uvms.sim.run import simulate

    controller = None
    if case.controller is not None:
        parameters = dict(case.parameters)
        if hydro_scale is not None and case.controller in SLIDING_MODE:
            parameters.setdefault("hydro_scale", hydro_scale)
        controller = make_controller(case.controller, model, period=period, parameters=parameters)
    return simulate(model, duration=duration, step=step, joint_torques=scenario_torques(model) if joint_torques is None
                    else joint_torques, controller=controller, actuation=actuation, control_period=period,
                    metadata={"case": case.label})


def run_cases(model, cases: tuple[Case, ...] | None = None, *, progress: Callable[[str], None] | None = None,
              **options) -> dict[str, Any]:
    """``{label: Result}`` for every case (default :data:`DEFAULT_CASES`); ``options`` as :func:`run_case`."""
    results = {}
    for case in cases or DEFAULT_CASES:
        if progress is not None:
            progress(case.label)
        results[case.label] = run_case(model, case, **options)
    return results


def compare_controllers(model, cases: tuple[Case, ...] | None = None, *, duration: float = 10.0,
                        step: float = 1e-3, period: float = 0.01, hydro_scale: float | None = None,
                        joint_torques=None, actuation=None, progress: Callable[[str], None] | None = None):
    """Run every case on the paper scenario and tabulate :func:`metrics`.

    Returns:
        pandas.DataFrame, one row per case: ``case``, ``controller``, the metrics, ``complete`` (False if the
        run diverged) and ``wall_time_s``.
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
                     "complete": bool(result.complete), "wall_time_s": wall})
    return pd.DataFrame(rows)
