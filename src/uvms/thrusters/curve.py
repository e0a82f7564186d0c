"""Thrust curve and step responses of a Healey thruster (the computation behind ``uvms thruster-curve``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from uvms.thrusters.healey import HealeyParameters, StepResponse, rise_time, steady_state, step_response


@dataclass(frozen=True, eq=False)
class ThrustCurve:
    """Steady state and step-response rise time at each voltage.

    Attributes:
        voltage: (n,) applied voltages [V].
        omega: (n,) steady propeller speed [rad/s].
        inflow: (n,) steady axial inflow [m/s].
        thrust: (n,) steady thrust [N].
        rise_time: (n,) 63 % thrust rise time of a step from rest [s] (``nan`` at 0 V).
    """

    voltage: np.ndarray
    omega: np.ndarray
    inflow: np.ndarray
    thrust: np.ndarray
    rise_time: np.ndarray


def thrust_curve(params: HealeyParameters, voltages: np.ndarray, *, duration: float = 0.5,
                 dt: float = 1e-4) -> ThrustCurve:
    """Steady state (closed form) and 63 % rise time (step from rest, ``duration`` [s] sampled every ``dt``)."""
    voltages = np.asarray(voltages, dtype=float)
    steady = np.array([steady_state(params, v) for v in voltages]).reshape(-1, 3)
    rise = np.array([
        rise_time(r.time, r.thrust, final=t) if v != 0 else math.nan
        for v, t in zip(voltages, steady[:, 2])
        for r in [step_response(params, v, duration, dt)]
    ])
    return ThrustCurve(voltages, steady[:, 0], steady[:, 1], steady[:, 2], rise)


def step_responses(params: HealeyParameters, voltages, *, duration: float = 0.2,
                   dt: float = 1e-4) -> tuple[StepResponse, ...]:
    """Step responses from rest at each voltage [V], ``duration`` [s] sampled every ``dt`` [s]."""
    return tuple(step_response(params, float(v), duration, dt) for v in voltages)


def default_voltages(params: HealeyParameters, step: float = 3.0) -> np.ndarray:
    """Voltages from ``-Vmax`` to ``+Vmax`` every ``step`` [V] (both limits included)."""
    if step <= 0:
        raise ValueError(f"voltage step must be positive, got {step}")
    n = math.floor(params.max_voltage / step + 1e-9)
    half = np.arange(1, n + 1) * step
    if half.size == 0 or not math.isclose(half[-1], params.max_voltage):
        half = np.append(half, params.max_voltage)
    return np.concatenate([-half[::-1], [0.0], half])
