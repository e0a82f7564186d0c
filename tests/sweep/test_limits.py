"""Sweep files that would be too big, or that point ``base`` at something that is not a scenario: refused in one
line, before anything is built, without echoing unbounded values or the content of other files."""

from __future__ import annotations

import time

import pytest
import yaml

from tests.sweep.helpers import write_sweep
from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sweep import load_sweep, sweep_from_data
from uvms.sweep.spec import MAX_RUNS, run_count

GRID = list(range(1000))
HUGE = {  # sweep data -> (field, count in the message)
    "4 grids of 1000": ({"parameters": {f"model_overrides.p{k}": GRID for k in range(4)}}, "parameters",
                        "2,000,000,000,000"),
    "grid x draws": ({"runs": 1000, "parameters": {"duration": {"uniform": [0.1, 0.2]}, "step": GRID}}, "parameters",
                     "2,000,000"),
    "draws x controllers": ({"runs": 1_000_000, "parameters": {"duration": {"uniform": [0.1, 0.2]}}}, "runs",
                            "2,000,000"),
    "grid forms": ({"parameters": {"a.b": {"grid": GRID}, "a.c": GRID, "a.d": {"grid": list(range(2))}}},
                   "parameters", "4,000,000"),
    "20 grids of 10": ({"parameters": {f"x.p{k}": list(range(10)) for k in range(20)}}, "parameters",
                       "about 10^20"),
}


@pytest.mark.parametrize("case", sorted(HUGE))
def test_a_huge_sweep_is_refused_before_anything_is_built(tmp_path, capsys, case):
    extra, field, count = HUGE[case]
    data = {"name": "huge", "base": "paper_case3_controlled", "controllers": ["smc-ab", "smc-vehicle"], **extra}
    path = tmp_path / "huge.yaml"
    path.write_text(yaml.safe_dump(data))
    began = time.perf_counter()
    with pytest.raises(UvmsInputError) as caught:
        load_sweep(path)
    elapsed = time.perf_counter() - began
    assert elapsed < 1.0, elapsed  # a refusal bound: nothing of the 10^6+ runs was built
    error = caught.value
    assert error.source == str(path) and error.path == field
    assert f"expected at most {MAX_RUNS:,} runs in one sweep, found {count}" in error.message
    assert len(str(error)) < 500 and "\n" not in str(error)
    assert main(["sweep", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and f"{path}: {field}: expected at most" in err
    assert not (tmp_path / "out").exists()


def test_the_limit_itself_is_allowed_and_counted_without_building():
    spec = sweep_from_data({"base": "paper_case3_controlled", "parameters": {"duration": [0.1, 0.2]}}).spec
    assert run_count(spec) == 2
    big = spec.model_copy(update={"runs": MAX_RUNS // 4, "controllers": ("smc-ab", "smc-vehicle")})
    assert run_count(big) == MAX_RUNS


@pytest.mark.parametrize("length", [150, 5000])
def test_long_parameter_names_are_cut_in_the_message(length):
    keys = ["x." + "a" * length + str(k) for k in range(3)]
    with pytest.raises(UvmsInputError) as caught:
        sweep_from_data({"base": "paper_case3_controlled", "parameters": {key: GRID for key in keys}})
    expected = "expected at most" if length < 200 else "expected a field path of at most 200 characters"
    assert expected in str(caught.value) and len(str(caught.value)) < 500


SECRET = "TOPSECRET-token-4f1c"
NOT_SCENARIOS = {  # file content -> what the message says it found
    "text": (f"{SECRET}\nsecond line {SECRET}\n", "found a YAML string"),
    "passwd-like": (f"root:x:0:0:{SECRET}:/root:/bin/bash\n", "found a YAML string"),
    "a list": (f"- {SECRET}\n- two\n", "found a YAML list"),
    "a number": ("12345\n", "found a YAML number"),
    "empty": ("", "found an empty file"),
}


@pytest.mark.parametrize("case", sorted(NOT_SCENARIOS))
def test_a_base_that_is_not_a_scenario_is_named_not_echoed(tmp_path, capsys, case):
    text, found = NOT_SCENARIOS[case]
    target = tmp_path / "private" / "notes.txt"
    target.parent.mkdir()
    target.write_text(text)
    path = write_sweep(tmp_path)
    data = yaml.safe_load(path.read_text())
    data["base"] = str(target)
    path.write_text(yaml.safe_dump(data))
    assert main(["sweep", str(path), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and SECRET not in err and "12345" not in err
    assert f"{path}: base: {target}: expected a scenario file (a mapping of scenario fields), {found}" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("field, value, message", [
    ("parameters", {f"x.p{k}": 1.0 for k in range(100_000)}, "parameters: expected at most 1000 parameters"),
    ("metrics", ["peak_body_error_xy_m"] * 100_000, "metrics: expected at most 1000 metrics"),
    ("controllers", ["smc-ab"] * 100_000, "controllers: expected at most 1000 controllers"),
    ("metrics", ["peak_body_error_xy_m", "rms_command_X", "peak_body_error_xy_m"],
     "metrics[2]: expected each metric once, found 'peak_body_error_xy_m' twice"),
    ("parameters", {"inputs.current": {"value": {"constant": [0, 0, 0]}}, "inputs.current.constant": [[0, 0, 0]]},
     "parameters.inputs.current: overlaps parameter 'inputs.current.constant'"),
    ("parameters", {"inputs.joint_torques[0].torques": [[0, 0, 0]], "inputs.joint_torques": {"value": []}},
     "parameters.inputs.joint_torques: overlaps parameter 'inputs.joint_torques[0].torques'"),
])
def test_long_lists_are_refused_quickly_in_one_line(tmp_path, field, value, message):
    data = {"name": "wide", "base": "paper_case3_controlled", field: value}
    began = time.perf_counter()
    with pytest.raises(UvmsInputError) as caught:
        sweep_from_data(data, source="wide.yaml")
    assert time.perf_counter() - began < 1.0  # a refusal bound: no quadratic scan of the list
    assert message in str(caught.value) and len(str(caught.value)) < 600, str(caught.value)
