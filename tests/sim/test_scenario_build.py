"""A scenario builds its controller and its trimmed initial state once (``uvms.sim.scenario.build``): loading
builds what can refuse the file and keeps it, the run takes it; a second run gets a fresh controller, another
model rebuilds both. The package keeps the file's schema free of building."""

from __future__ import annotations

import copy
import re
import sys
import types
from importlib.resources import files

import numpy as np
import pytest
import yaml

from uvms.control.base import ControlOutput
from uvms.sim.scenario import load_scenario, scenario_from_data

CASE2 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())


class _Still:
    def __init__(self, period):
        self.period = period

    def reset(self):
        pass

    def update(self, m):
        return ControlOutput(wrench=np.zeros(6))


@pytest.fixture
def built(monkeypatch):
    """A stand-in ``uvms.control.registry`` whose ``make_controller`` records every controller it builds."""
    made = []
    module = types.ModuleType("uvms.control.registry")
    module.controller_names = lambda: ("still",)

    def make_controller(name, model, *, period=0.01, parameters=None):
        made.append(_Still(period))
        return made[-1]

    module.make_controller = make_controller
    monkeypatch.setitem(sys.modules, "uvms.control.registry", module)
    return made


def controlled():
    data = copy.deepcopy(CASE2)
    data["controller"] = {"name": "still", "period": 0.01}
    return scenario_from_data(data, source="case.yaml")


def test_loading_and_running_build_the_controller_once(built):
    s = controlled()
    assert len(built) == 1                                   # loading built it (a bad controller fails there)
    assert s.simulate_options()["controller"] is built[0]    # and the run takes that one
    assert len(built) == 1


def test_every_further_run_gets_a_fresh_controller(built):
    s = controlled()
    first, second = s.simulate_options()["controller"], s.simulate_options()["controller"]
    assert first is built[0] and second is built[1] and first is not second
    assert s.make_controller() is built[2]


def test_another_model_builds_its_own_controller(built):
    s = controlled()
    other = s.with_model(s.model.with_hydrodynamics_scaled(added_mass=0.5, drag=0.5))
    assert other.simulate_options()["controller"] is built[1]
    assert s.simulate_options()["controller"] is built[0]


def test_a_trimmed_start_is_built_once(monkeypatch):
    import uvms.analysis.trim as trim

    calls = []
    original = trim.trimmed_state

    def counted(*args, **kwargs):
        calls.append(args)
        return original(*args, **kwargs)

    monkeypatch.setattr(trim, "trimmed_state", counted)
    s = scenario_from_data({"model": "bluerov2_heavy_alpha5", "duration": 1.0,
                            "initial_state": {"trimmed": True, "q": [0.05, 2.0, 2.6, 0.05]}})
    assert len(calls) == 1                                   # loading checked the rest attitude by building it
    start = s.simulate_options()["initial_state"]
    assert s.simulate_options()["initial_state"] is start and s.initial_state() is start
    assert len(calls) == 1
    s.with_model(s.model).initial_state()
    assert len(calls) == 2


def test_an_untrimmed_scenario_builds_nothing_while_loading(built):
    s = load_scenario("paper_case2_released")
    assert s._built == {} and built == []


def test_the_schema_builds_nothing():
    """The file's schema holds no building: the arm tracker is :func:`uvms.sim.scenario.build.tracker_for`."""
    from uvms.sim.scenario import JointTrajectorySpec, schema, tracker_for

    assert not hasattr(JointTrajectorySpec, "tracker_for")
    assert tracker_for.__module__ == "uvms.sim.scenario.build"
    source = (files("uvms") / "sim" / "scenario" / "schema.py").read_text()
    assert not re.search(r"^\s*from uvms\.control|^\s*import uvms\.control", source, flags=re.M)
    assert "make_controller" not in source and "ComputedTorqueArm" not in source
    assert schema.ScenarioSpec.__module__ == "uvms.sim.scenario.schema"
