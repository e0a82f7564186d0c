"""A scenario's ``environment`` (waves, currents varying in space) built into the keyword arguments of the
fluid object (``uvms.sim.scenario.environment.flow_parts``): the arrays against the physics modules called
directly, relative field files confined to the scenario's folder, every bad input refused by ``uvms run`` with
exit 2 and one line naming the field, and a sweep over sea states."""

from __future__ import annotations

import copy
import math
from importlib.resources import files

import numpy as np
import pytest
import yaml

from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.hydro.waves import jonswap, regular_waves, significant_height
from uvms.sim.scenario import load_scenario, scenario_from_data

CASE2 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())
REGULAR = {"type": "regular", "height": 0.5, "period": 4.0, "direction": 0.0, "water_depth": 20.0}
IRREGULAR = {"type": "irregular", "spectrum": "jonswap", "significant_height": 0.5, "peak_period": 4.0,
             "components": 50, "seed": 3, "water_depth": 20.0}


def scenario(environment=None, tmp_path=None, **changes):
    data = copy.deepcopy(CASE2)
    data.update(name="short", duration=0.2, **changes)
    if environment is not None:
        data["environment"] = environment
    if tmp_path is None:
        return scenario_from_data(data)
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return load_scenario(path)


def test_regular_waves_are_the_physics_modules_waves_with_the_models_gravity():
    s = scenario({"waves": REGULAR})
    parts = s.flow_parts()
    g = float(np.linalg.norm(s.model.gravity))
    want = regular_waves(0.5, 4.0, direction=0.0, water_depth=20.0, gravity=g)
    assert all(np.array_equal(a, b) for a, b in zip(parts["waves"][:5], want[:5]))
    assert parts["waves"].water_depth == 20.0 and parts["surface"] == 0.0
    k = parts["waves"].wavenumber[0]
    assert (2 * math.pi / 4.0) ** 2 == pytest.approx(g * k * math.tanh(20.0 * k), rel=1e-13)   # w^2 = g k tanh kh
    assert parts["profile"] is None and parts["field"] is None


def test_deep_water_by_default_and_the_uniform_part_from_the_model_or_inputs():
    s = scenario({"waves": {k: v for k, v in REGULAR.items() if k != "water_depth"}, "surface": -1.5})
    parts = s.flow_parts()
    assert parts["waves"].water_depth == math.inf and parts["surface"] == -1.5
    assert np.array_equal(parts["velocity"], s.model.current[None, :])
    assert np.array_equal(parts["acceleration"], s.model.fluid_acceleration[None, :])
    data = copy.deepcopy(CASE2)
    data.update(duration=0.2, environment={"waves": REGULAR})
    data["inputs"]["current"] = {"table": {"times": [0.0, 0.2], "velocity": [[0, 0, 0], [0.2, 0, 0]]}}
    parts = scenario_from_data(data).flow_parts()
    assert np.allclose(np.interp(0.1, parts["times"], parts["velocity"][:, 0]), 0.1)
    assert np.allclose(parts["acceleration"][parts["times"] < 0.2 - 1e-9, 0], 1.0)        # the table's slope


def test_irregular_jonswap_sea_has_the_spectrum_variance_in_its_range():
    parts = scenario({"waves": IRREGULAR | {"spreading": 4.0, "direction": 0.5}}).flow_parts()
    waves = parts["waves"]
    assert waves.amplitude.shape == (50,)
    wp = 2 * math.pi / 4.0
    w = np.linspace(0.5 * wp, 4 * wp, 200001)
    m0 = np.trapezoid(jonswap(w, 0.5, 4.0, 3.3), w)
    assert 0.5 * np.sum(waves.amplitude ** 2) == pytest.approx(m0, rel=1e-6)
    assert np.all(np.abs(waves.direction - 0.5) < math.pi / 2) and np.ptp(waves.direction) > 0
    assert significant_height(waves) == pytest.approx(0.5, rel=0.02)


def test_table_spectrum_and_frequency_range():
    table = {"frequencies": [0.5, 1.0, 1.5], "densities": [0.0, 0.02, 0.0]}
    waves = {"type": "irregular", "spectrum": "table", "table": table, "components": 20}
    parts = scenario({"waves": waves}).flow_parts()
    assert 0.5 * np.sum(parts["waves"].amplitude ** 2) == pytest.approx(0.01, rel=1e-12)
    assert np.all((parts["waves"].omega > 0.5) & (parts["waves"].omega < 1.5))


def test_profile_table_and_power_law():
    table = {"profile": {"depth": [0.0, 5.0, 10.0], "velocity": [[0.3, 0, 0], [0.2, 0.1, 0], [0, 0, 0]]}}
    profile = scenario({"current": table}).flow_parts()["profile"]
    assert np.array_equal(profile.depth, [0.0, 5.0, 10.0]) and np.array_equal(profile.velocity[1], [0.2, 0.1, 0])
    law = {"profile": {"power_law": {"surface_velocity": [0.5, 0.0, 0.0], "water_depth": 10.0}}}
    profile = scenario({"current": law}).flow_parts()["profile"]
    d = np.array([0.0, 2.5, 9.0])
    assert np.allclose(np.interp(d, profile.depth, profile.velocity[:, 0]), 0.5 * ((10 - d) / 10) ** (1 / 7),
                       atol=0.5 / 100)


def _field_csv(path, nan=False):
    rows = ["x,y,z,t,u,v,w"]
    for t in (0.0, 1.0):
        for z in (0.0, 5.0):
            for y in (-2.0, 2.0):
                for x in (-2.0, 2.0):
                    rows.append(f"{x},{y},{z},{t},{0.1 * z},{'nan' if nan and t else 0.0},0.0")
    path.write_text("\n".join(rows) + "\n")


def test_field_file_relative_to_the_scenario(tmp_path):
    _field_csv(tmp_path / "flow.csv")
    field = scenario({"current": {"field": {"file": "flow.csv", "outside": "hold"}}}, tmp_path).flow_parts()["field"]
    assert field.outside == "hold" and field.velocity.shape == (2, 2, 2, 2, 3)
    assert np.array_equal(field.velocity[:, 1, :, :, 0], np.full((2, 2, 2), 0.5))


def test_field_file_outside_the_scenario_folder_is_refused(tmp_path):
    inner = tmp_path / "inner"
    inner.mkdir()
    _field_csv(tmp_path / "flow.csv")
    with pytest.raises(UvmsInputError, match="outside") as info:
        scenario({"current": {"field": {"file": "../flow.csv"}}}, inner)
    assert info.value.path == "environment.current.field.file"


BAD = {  # environment -> the text of the one error line (after "case.yaml: ")
    "zero_height": ({"waves": REGULAR | {"height": 0.0}}, "environment.waves.height: expected a number > 0"),
    "negative_period": ({"waves": REGULAR | {"period": -4.0}}, "environment.waves.period: expected a number > 0"),
    "zero_depth": ({"waves": REGULAR | {"water_depth": 0.0}}, "environment.waves.water_depth: expected a number > 0"),
    "negative_hs": ({"waves": IRREGULAR | {"significant_height": -0.5}},
                    "environment.waves.significant_height: expected a number > 0"),
    "zero_tp": ({"waves": IRREGULAR | {"peak_period": 0.0}}, "environment.waves.peak_period: expected a number > 0"),
    "peak_outside": ({"waves": IRREGULAR | {"frequency_range": [2.0, 6.0]}},
                     "environment.waves.frequency_range: expected the spectrum's peak (1.571 rad/s) inside"),
    "table_peak_outside": ({"waves": {"type": "irregular", "spectrum": "table", "frequency_range": [1.2, 2.0],
                                      "table": {"frequencies": [0.5, 1.0, 1.5], "densities": [0, 1, 0]}}},
                           "environment.waves.frequency_range: expected the spectrum's peak (1 rad/s) inside"),
    "regular_with_spectrum": ({"waves": REGULAR | {"spectrum": "jonswap"}},
                              "environment.waves.spectrum: not a field of type: regular"),
    "missing_height": ({"waves": {"type": "regular", "period": 4.0}}, "environment.waves.height: expected a value"),
    "missing_spectrum": ({"waves": {"type": "irregular"}}, "environment.waves.spectrum: expected jonswap"),
    "peak_factor_too_big": ({"waves": IRREGULAR | {"peak_factor": 9.0}},
                            "environment.waves.peak_factor: expected a number <= 7"),
    "profile_not_increasing": ({"current": {"profile": {"depth": [0.0, 3.0, 2.0], "velocity": [[0, 0, 0]] * 3}}},
                               "environment.current.profile.depth: expected strictly increasing depths"),
    "profile_and_field": ({"current": {"profile": {"depth": [0.0], "velocity": [[0, 0, 0]]},
                                       "field": {"file": "flow.csv"}}},
                          "environment.current: expected exactly one of 'profile' or 'field', found both"),
    "field_outside_flag": ({"current": {"field": {"file": "flow.csv", "outside": "wrap"}}},
                           "environment.current.field.outside: expected 'hold', 'zero' or 'error'"),
    "field_nan": ({"current": {"field": {"file": "nan.csv"}}},
                  "environment.current.field.file"),
    "field_missing": ({"current": {"field": {"file": "none.csv"}}}, "environment.current.field.file"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_environment_exits_2_with_one_line(tmp_path, monkeypatch, capsys, case):
    environment, expected = BAD[case]
    _field_csv(tmp_path / "flow.csv")
    _field_csv(tmp_path / "nan.csv", nan=True)
    data = copy.deepcopy(CASE2)
    data.update(name="short", duration=0.2, environment=environment)
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    monkeypatch.chdir(tmp_path)
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("uvms: error: ") and "Traceback" not in captured.err
    assert f"case.yaml: {expected}" in lines[0], lines[0]
    if case == "field_nan":
        assert "nan.csv" in lines[0] and "finite" in lines[0]
    assert not (tmp_path / "out").exists()


def test_sweep_over_sea_states_builds_each_sea():
    from uvms.sweep import sweep_from_data

    sweep = sweep_from_data({"base": "bluerov2_heavy_alpha5_waves", "parameters": {
        "environment.waves.significant_height": [0.25, 0.5, 1.0], "environment.waves.peak_period": [4.0, 6.0]}})
    assert len(sweep.runs) == 6
    for run in sweep.runs:
        data = sweep.scenario_data(run)
        waves = scenario_from_data(data).flow_parts()["waves"]
        hs, tp = (run.parameters[f"environment.waves.{k}"] for k in ("significant_height", "peak_period"))
        wp = 2 * math.pi / tp
        w = np.linspace(0.5 * wp, 4 * wp, 100001)
        assert 0.5 * np.sum(waves.amplitude ** 2) == pytest.approx(np.trapezoid(jonswap(w, hs, tp), w), rel=1e-6)


def test_bundled_waves_scenario_is_the_worked_example():
    s = load_scenario("bluerov2_heavy_alpha5_waves")
    waves = s.flow_parts()["waves"]
    assert s.spec.initial_state.position[2] == 3.0 and s.model.convention == "ned"           # 3 m deep
    assert s.spec.environment.waves.significant_height == 0.5 and s.spec.environment.waves.peak_period == 4.0
    assert significant_height(waves) == pytest.approx(0.5, rel=0.01)
    assert s.spec.controller.name == "smc-ab"


def test_docs_environment_has_a_row_for_every_field():
    import re
    from pathlib import Path

    import uvms.sim.scenario as scenario

    text = (Path(__file__).resolve().parents[2] / "docs" / "environment.md").read_text()
    rows = set(re.findall(r"^\| `([a-z_.]+)` \|", text, flags=re.M))
    for spec in ("EnvironmentSpec", "WavesSpec", "SpatialCurrentSpec", "PowerLawSpec", "FieldSpec"):
        fields = set(getattr(scenario, spec).model_fields)
        assert fields <= rows, (spec, fields - rows)
    assert "| `environment` |" in (Path(__file__).resolve().parents[2] / "docs" / "scenarios.md").read_text()


def _flow_stand_in(times, velocity, acceleration, profile=None, field=None, waves=None, surface=0.0):
    """A stand-in for ``uvms.hydro.flow.Flow`` (built on the fluid branch) that checks the interface the two
    issue-27 branches share: the keywords, the attribute names, shapes and dtypes."""
    T = times.shape[0]
    assert times.shape == (T,) and velocity.shape == (T, 3) and acceleration.shape == (T, 3)
    assert all(a.dtype == np.float64 for a in (times, velocity, acceleration))
    if profile is not None:
        K = profile.depth.shape[0]
        assert profile.velocity.shape == (K, 3) and np.all(np.diff(profile.depth) > 0)
    if field is not None:
        shape = (field.t.size, field.z.size, field.y.size, field.x.size, 3)
        assert field.velocity.shape == shape and field.outside in ("hold", "zero", "error")
        assert all(np.all(np.diff(a) > 0) for a in (field.x, field.y, field.z, field.t))
    if waves is not None:
        M = waves.amplitude.shape[0]
        for name in ("amplitude", "omega", "wavenumber", "direction", "phase"):
            assert getattr(waves, name).shape == (M,) and getattr(waves, name).dtype == np.float64
        assert isinstance(waves.water_depth, float) and waves.water_depth > 0
    assert isinstance(surface, float)
    return "flow"


def test_flow_parts_fit_the_shared_interface(tmp_path):
    from uvms.hydro.currents import CurrentField, CurrentProfile
    from uvms.hydro.waves import WaveComponents

    assert WaveComponents._fields == ("amplitude", "omega", "wavenumber", "direction", "phase", "water_depth")
    assert CurrentProfile._fields == ("depth", "velocity")
    assert CurrentField._fields == ("x", "y", "z", "t", "velocity", "outside")
    _field_csv(tmp_path / "flow.csv")
    for environment in ({"waves": IRREGULAR | {"spreading": 2.0}}, {"waves": REGULAR},
                        {"current": {"field": {"file": "flow.csv"}}},
                        {"current": {"profile": {"power_law": {"surface_velocity": [0.2, 0, 0], "water_depth": 9.0}}},
                         "waves": REGULAR}):
        parts = scenario(environment, tmp_path).flow_parts()
        assert set(parts) == {"times", "velocity", "acceleration", "profile", "field", "waves", "surface"}
        assert _flow_stand_in(**parts) == "flow"


def test_bundled_sea_state_sweep_grids_height_period_and_seed():
    from uvms.sweep import load_sweep

    sweep = load_sweep("bluerov2_waves_sea_states")
    assert len(sweep.runs) == 3 * 2 * 3 * 2
    states = {tuple(r.parameters.values()) for r in sweep.runs}
    assert states == {(h, t, s) for h in (0.25, 0.5, 1.0) for t in (4.0, 6.0) for s in (1, 2, 3)}
    run = next(r for r in sweep.runs if tuple(r.parameters.values()) == (1.0, 6.0, 2))
    waves = scenario_from_data(sweep.scenario_data(run)).flow_parts()["waves"]
    assert significant_height(waves) == pytest.approx(1.0, rel=0.01)
    assert not np.array_equal(waves.phase, load_scenario("bluerov2_heavy_alpha5_waves").flow_parts()["waves"].phase)


def test_a_body_leaving_a_field_with_no_outside_exits_2_naming_the_scenario_field(tmp_path, capsys):
    """The paper's vehicle starts outside a field box that says ``outside: error``: one line, exit 2, naming
    the scenario file and its field, and no half-written run folder."""
    rows = ["x,y,z,t,u,v,w"] + [f"{x},{y},{z},0.0,0.0,0.0,0.0" for z in (50.0, 60.0) for y in (-1.0, 1.0)
                                for x in (-1.0, 1.0)]
    (tmp_path / "box.csv").write_text("\n".join(rows) + "\n")
    data = copy.deepcopy(CASE2)
    data.update(name="short", duration=0.2, environment={"current": {"field": {"file": "box.csv",
                                                                                "outside": "error"}}})
    path = tmp_path / "case.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and "case.yaml: environment.current.field.outside: a body left the field's box" in lines[0]
    assert not (tmp_path / "out" / "result.json").exists()
