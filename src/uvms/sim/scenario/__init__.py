"""Scenario files: what to simulate (model, duration, integrator, inputs, controller, actuators) in one YAML file.

A scenario is validated like a model file (pydantic v2, unknown keys rejected, one-line errors naming the file
and the dotted field path), then checked against its model (joint count of torque vectors and initial joint
angles, controller name). ``docs/scenarios.md`` documents every field; the bundled scenarios
(``uvms/scenarios/*.yaml``, loadable by name) are the paper's three cases of Section 6 and three of the BlueROV2
Heavy + Alpha 5.

    scenario = load_scenario("paper_case2_released")     # or a path
    result = run_scenario(scenario)                       # -> uvms.sim.result.Result

The package, like :mod:`uvms.model`: :mod:`~uvms.sim.scenario.schema` (the file's fields),
:mod:`~uvms.sim.scenario.load` (reading and checking a file against its model) and
:mod:`~uvms.sim.scenario.build` (the :class:`Scenario`, its initial state, inputs, controller and run); every
public name is importable from here.
"""

from __future__ import annotations

from uvms.sim.scenario.build import (
    Scenario,
    apply_overrides,
    build_controller,
    build_initial_state,
    plan_scenario,
    run_scenario,
    tracker_for,
)
from uvms.sim.scenario.environment import flow_parts
from uvms.sim.scenario.load import bundled_scenarios, load_scenario, resolve_scenario_path, scenario_from_data
from uvms.sim.scenario.schema import (
    INTEGRATORS,
    ConstantTorques,
    ControllerSpec,
    CurrentSpec,
    CurrentTableSpec,
    EnvironmentOverrides,
    EnvironmentSpec,
    FieldSpec,
    HealthSpec,
    InitialStateSpec,
    InputsSpec,
    JointTorques,
    JointMotionSpec,
    JointTrajectorySpec,
    ModelOverrides,
    OutputsSpec,
    PowerLawSpec,
    ProfileSpec,
    ScenarioSpec,
    SpatialCurrentSpec,
    SpectrumTableSpec,
    Tolerances,
    TorqueStep,
    WavesSpec,
)

__all__ = [
    "INTEGRATORS", "ConstantTorques", "ControllerSpec", "CurrentSpec", "CurrentTableSpec", "EnvironmentOverrides",
    "EnvironmentSpec", "FieldSpec", "PowerLawSpec", "ProfileSpec", "SpatialCurrentSpec", "SpectrumTableSpec",
    "WavesSpec", "flow_parts",
    "HealthSpec", "InitialStateSpec", "InputsSpec", "JointTorques", "JointMotionSpec", "JointTrajectorySpec",
    "ModelOverrides", "OutputsSpec", "Scenario", "ScenarioSpec", "Tolerances", "TorqueStep", "apply_overrides",
    "build_controller", "build_initial_state", "bundled_scenarios", "load_scenario", "plan_scenario", "resolve_scenario_path",
    "run_scenario", "scenario_from_data", "tracker_for",
]
