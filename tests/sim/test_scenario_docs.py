"""``docs/scenarios.md`` documents every field a scenario file accepts, every ``actuators`` value and every
registered controller; ``docs/controllers.md`` lists every controller module (read from the code, so a new
field, layout or controller without its documentation fails here)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

DOCS = Path(__file__).resolve().parents[2] / "docs"


def _section(text: str, heading: str) -> str:
    start = text.index(heading)
    end = text.find("\n### ", start + len(heading))
    end = text.find("\n## ", start + len(heading)) if end < 0 else end
    return text[start:] if end < 0 else text[start:end]


def _table_fields(section: str) -> set[str]:
    return set(re.findall(r"^\| `([a-z_.]+)` \|", section, flags=re.M))


@pytest.fixture(scope="module")
def scenarios_md() -> str:
    return (DOCS / "scenarios.md").read_text()


@pytest.mark.parametrize("heading, spec", [
    ("### Top level", "ScenarioSpec"), ("### `inputs`", "InputsSpec"), ("### `initial_state`", "InitialStateSpec"),
    ("### `controller`", "ControllerSpec"), ("### `outputs`", "OutputsSpec"),
    ("**Joint trajectory.**", "JointTrajectorySpec"), ("**Joint motion.**", "JointMotionSpec"),
])
def test_every_scenario_field_has_a_row(scenarios_md, heading, spec):
    import uvms.sim.scenario as scenario

    fields = set(getattr(scenario, spec).model_fields)
    assert fields <= _table_fields(_section(scenarios_md, heading)), fields - _table_fields(
        _section(scenarios_md, heading))


def test_every_actuators_value_is_documented(scenarios_md):
    from uvms.thrusters.layouts import layout_names

    row = next(line for line in scenarios_md.splitlines() if line.startswith("| `actuators` |"))
    values = set(re.findall(r"`([a-z-]+)`", row.split("|")[2]))
    assert values == {*layout_names(), "model"}


def test_every_registered_controller_is_listed(scenarios_md):
    from uvms.control.registry import BUILTIN_MODULES, controller_names

    known = ", ".join(controller_names())
    assert f"unknown controller 'smc'; known: {known}" in scenarios_md
    row = next(line for line in scenarios_md.splitlines() if line.startswith("| `name` | string | **required** |"))
    assert all(f"`{name}`" in row for name in controller_names())
    assert f"expected one of: {known}" in (DOCS / "sweeps.md").read_text()
    controllers_md = (DOCS / "controllers.md").read_text()
    for module in BUILTIN_MODULES:
        assert f"| `{module.rsplit('.', 1)[-1]}.py` |" in controllers_md, module
