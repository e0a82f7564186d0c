"""The floors of the package (issue "Make the floors real"): the analyses of a model at rest (trim, the
``uvms validate`` report) are a floor of their own, ``uvms.analysis``, above the dynamics and the controllers
and below the simulation; the model floor imports none of them. The split packages keep one public API."""

from __future__ import annotations

import re
import sys
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src" / "uvms"


def _imports(folder: str) -> list[tuple[str, str]]:
    """``(file, imported uvms module)`` of every import in ``src/uvms/<folder>``."""
    pattern = re.compile(r"^\s*(?:from|import)\s+(uvms(?:\.\w+)*)", flags=re.M)
    return [(str(path.relative_to(SRC)), name) for path in sorted((SRC / folder).rglob("*.py"))
            for name in pattern.findall(path.read_text())]


def test_the_model_floor_imports_no_analysis_control_or_simulation():
    offending = [(f, m) for f, m in _imports("model")
                 if m.startswith(("uvms.analysis", "uvms.control", "uvms.sim", "uvms.dynamics.api"))]
    assert not offending, offending
    assert not (SRC / "model" / "trim.py").exists() and not (SRC / "model" / "report.py").exists()


def test_the_analysis_floor_imports_nothing_above_it():
    above = ("uvms.sim", "uvms.reproduce", "uvms.commands", "uvms.cli", "uvms.sweep", "uvms.gym", "uvms.view")
    offending = [(f, m) for f, m in _imports("analysis") if m.startswith(above)]
    assert not offending, offending


def test_trim_and_the_model_report_live_in_the_analysis_floor():
    import uvms
    from uvms.analysis.report import model_report
    from uvms.analysis.trim import trim, trimmed_state

    assert uvms.trim is trim and uvms.trimmed_state is trimmed_state
    assert model_report.__module__ == "uvms.analysis.report"


def test_reproduce_exposes_plain_names():
    """``uvms.reproduce`` is a package (cases, claims, report, write) whose constants are plain module
    attributes (no module ``__getattr__``) read from the scenario files."""
    import uvms.reproduce as reproduce
    from uvms.reproduce import cases, report, write
    from uvms.sim.scenario import load_scenario

    for module in (reproduce, cases, report, write, sys.modules["uvms.reproduce.claims"]):
        assert "__getattr__" not in vars(module), module.__name__
    spec = load_scenario(reproduce.CASE_SCENARIOS["controlled"]).spec
    assert vars(reproduce)["DURATION"] == spec.duration and vars(reproduce)["STEP"] == spec.step
    assert vars(reproduce)["CONTROL_PERIOD"] == spec.controller.period
    assert callable(reproduce.claims) and reproduce.paper is write.paper
    assert set(reproduce.__all__) <= set(vars(reproduce))


def test_the_scenario_package_keeps_its_names():
    import uvms.sim.scenario as scenario

    assert set(scenario.__all__) <= set(vars(scenario))
    assert {"load_scenario", "run_scenario", "plan_scenario", "scenario_from_data", "bundled_scenarios",
            "resolve_scenario_path", "Scenario", "ScenarioSpec", "apply_overrides"} <= set(scenario.__all__)
