"""Synthetic logs for the identification tests: the runs a known model makes from tilted starts, recorded at
20 Hz, with white noise of known size added to each logged signal."""

from __future__ import annotations

import numpy as np

import uvms
from uvms.identify import Experiment
from uvms.identify.experiment import result_signals
from uvms.rotations import quaternion_from_euler


def noisy_experiments(truth, starts, seed: int, duration: float, scale: dict[str, float]) -> list[Experiment]:
    """One :class:`~uvms.identify.Experiment` per start attitude ``(roll, pitch, yaw)`` [rad]: ``truth``'s run of
    ``duration`` [s] (RK4 at 5 ms) with ``N(0, scale[s]^2)`` noise on each signal ``s`` of ``scale``."""
    rng = np.random.default_rng(seed)
    out = []
    for k, euler in enumerate(starts):
        state = uvms.State.zero(truth).replace(quaternion=quaternion_from_euler(np.array(euler)))
        run = uvms.simulate(truth, state, duration=duration, step=0.005, record_period=0.05)
        clean = result_signals(run, run.time, tuple(scale))
        noisy = {s: v + rng.normal(0.0, scale[s], v.shape) for s, v in clean.items()}
        out.append(Experiment(f"trial{seed}-{k}", state, duration, run.time, noisy, step=0.005))
    return out
