"""The one validation kit (``uvms.schema_base``): one strictness and one error line for model, scenario and
sweep files."""

from __future__ import annotations

import copy
from importlib.resources import files

import pytest
import yaml
from pydantic import ValidationError

from uvms.errors import UvmsInputError
from uvms.model.load import load_model
from uvms.schema_base import (
    Positive,
    RunName,
    Spec,
    Vec3,
    fail,
    sanitised_name,
    validation_input_error,
)
from uvms.sim.scenario import load_scenario, scenario_from_data
from uvms.sweep.spec import sweep_from_data

PAPER_MODEL = (files("uvms.model") / "models" / "paper.yaml").read_text()
CASE2 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())


class _Case(Spec):
    duration: Positive
    offset: Vec3 = (0.0, 0.0, 0.0)
    name: RunName | None = None


def _line(data) -> str:
    with pytest.raises(ValidationError) as info:
        _Case.model_validate(data)
    return str(validation_input_error(info.value.errors(), "case.yaml", schema=_Case))


def test_one_strictness_numeric_strings_are_refused_in_every_file(tmp_path):
    """A quoted "1e-3" is a string everywhere (model, scenario, sweep); the unquoted 1e-3 is a number."""
    model = tmp_path / "m.yaml"
    model.write_text(PAPER_MODEL.replace("mass: 32.0                      #", 'mass: "32.0"                    #', 1))
    with pytest.raises(UvmsInputError) as info:
        load_model(model)
    assert str(info.value) == f"{model}: vehicle.mass: expected a finite number, found '32.0'"

    scenario = tmp_path / "s.yaml"
    scenario.write_text("model: paper\nduration: 0.01\nstep: 1e-3\n")       # YAML 1.1 would read a string
    assert load_scenario(scenario).spec.step == 0.001
    with pytest.raises(UvmsInputError, match=r"^step: expected a finite number, found '1e-3'$"):
        scenario_from_data({**copy.deepcopy(CASE2), "step": "1e-3"})

    sweep = {"base": str(files("uvms") / "scenarios" / "paper_case2_released.yaml"),
             "parameters": {"duration": {"uniform": ["0.1", 0.2]}}, "runs": 2}
    with pytest.raises(UvmsInputError, match=r"parameters\.duration\.uniform: expected \[low, high\], found"):
        sweep_from_data(sweep, source="sweep.yaml")


def test_booleans_are_refused_with_the_yaml_reason():
    line = _line({"duration": True})
    assert line == ("case.yaml: duration: expected a number, found True (YAML reads true/false, yes/no, on/off as "
                    "booleans)")
    assert _line({"duration": float("nan")}) == "case.yaml: duration: expected a finite number, found nan"
    assert _line({"duration": -1}) == "case.yaml: duration: expected a number > 0, found -1"
    assert _line({"duration": 1, "offset": [1, "2", 3]}) == ("case.yaml: offset: expected a list of 3 finite "
                                                             "numbers, found [1, '2', 3]")


def test_an_unknown_key_is_reported_first_with_the_allowed_keys():
    """A typo'd key also leaves its intended field missing: the typo is the one to report."""
    assert _line({"duraton": 1.0}) == ("case.yaml: duraton: unknown key; expected one of: duration, name, offset "
                                       "(and 1 more error)")


def test_fail_subpath_extends_the_field_path_even_at_index_0():
    from pydantic import field_validator

    class _Ordered(Spec):
        values: tuple[int, ...]

        @field_validator("values")
        @classmethod
        def _first_positive(cls, values):
            if values[0] <= 0:
                raise fail("expected a positive first value", 0)
            return values

    with pytest.raises(ValidationError) as info:
        _Ordered.model_validate({"values": [0, 1]})
    error = validation_input_error(info.value, None)
    assert (error.path, error.message) == ("values[0]", "expected a positive first value")


def test_union_tags_are_left_out_of_paths():
    errors = [{"type": "missing", "loc": ("inputs", "mapping", "constant"), "msg": "Field required", "input": {}}]
    error = validation_input_error(errors, "s.yaml", union_tags=("mapping", "list"))
    assert str(error) == "s.yaml: inputs.constant: expected a value (required field), found none"


@pytest.mark.parametrize("text, name", [("paper case 3", "paper_case_3"), ("..hidden", "hidden"), ("", "run"),
                                        ("a" * 150, "a" * 100), ("é-x", "x"), ("a b", "a_b")])
def test_sanitised_names_are_valid_run_names(text, name):
    assert sanitised_name(text, "run") == name
    assert _Case.model_validate({"duration": 1, "name": name}).name == name
