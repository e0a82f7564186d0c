"""uvms: simulation and station-keeping control of underwater vehicle-manipulator systems.

Public API (stable names)::

    load_model(name_or_path) -> Model          State.from_euler(model, position=, euler=, nu=, q=, qd=)
    forward_dynamics(model, state, ...)        inverse_dynamics(model, state, nu_dot=, qdd=)
    mass_matrix(model, state)                  end_effector_position(model, state)
    linearize(model, state, ...)               trim(model, q=...)       trimmed_state(model, q=...)
    frame_pose(model, state, name)             frame_poses(model, state)
    simulate(model, initial_state, ...)        hydrodynamic_wrenches(model, state, ...)
    rollout(model, trials, duration=, ...)     Simulator(model, state, step=, ...): reset(), step(duration)
    Dynamics(model): forward, inverse, mass_matrix (the checked owner of a model's compiled plant)
    Log.load(path): a recorded run (pose, IMU, joints, thrusters); .resample(t), .initial_state(model), .score()
    replay(model, log) -> Replay               identify(model, experiments, parameters, held_out=...)

Names are imported on first use so that ``import uvms`` (and ``uvms --help``) stays fast.
"""

from __future__ import annotations

import importlib
from typing import Any

from uvms import _cache  # noqa: F401  (sets numba's cache folder before anything compiles)

__version__ = "0.1.0"

_EXPORTS = {
    "Accelerations": "uvms.dynamics.api",
    "forward_dynamics": "uvms.dynamics.api",
    "inverse_dynamics": "uvms.dynamics.api",
    "mass_matrix": "uvms.dynamics.api",
    "linearize": "uvms.dynamics.linearize",
    "Linearization": "uvms.dynamics.linearize",
    "bias_forces": "uvms.dynamics.api",
    "end_effector_position": "uvms.dynamics.poses",
    "forward_kinematics": "uvms.dynamics.poses",
    "frame_pose": "uvms.dynamics.poses",
    "frame_poses": "uvms.dynamics.poses",
    "FramePose": "uvms.dynamics.poses",
    "Frame": "uvms.model.model",
    "Model": "uvms.model.model",
    "load_model": "uvms.model.load",
    "State": "uvms.state",
    "Log": "uvms.logs.log",
    "replay": "uvms.replays.run",
    "Replay": "uvms.replays.run",
    "identify": "uvms.identify.fit",
    "Experiment": "uvms.identify.experiment",
    "simulate": "uvms.sim.run",
    "Inputs": "uvms.sim.options",
    "Recording": "uvms.sim.options",
    "Actuation": "uvms.sim.options",
    "rollout": "uvms.sim.batch",
    "Trial": "uvms.sim.batch",
    "Batch": "uvms.sim.batch",
    "Simulator": "uvms.sim.stepper",
    "BatchSimulator": "uvms.sim.batch_stepper",
    "Dynamics": "uvms.dynamics.api",
    "Result": "uvms.sim.result",
    "TorqueSchedule": "uvms.sim.inputs",
    "CommandSchedule": "uvms.sim.inputs",
    "JointMotion": "uvms.sim.joint_motion",
    "hydrodynamic_wrenches": "uvms.dynamics.inspect",
    "show": "uvms.view",
    "trim": "uvms.analysis.trim",
    "trimmed_state": "uvms.analysis.trim",
}

__all__ = sorted(_EXPORTS) + ["__version__"]


_SUBMODULES = ("logs", "identify", "replays", "reproduce", "sweep", "control", "thrusters", "hydro", "sim", "dynamics", "model")


def __getattr__(name: str) -> Any:
    if name in _SUBMODULES:
        return importlib.import_module(f"uvms.{name}")
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'uvms' has no attribute {name!r}")


def __dir__() -> list[str]:
    return __all__
