"""Scenario files: bundled scenarios, one-line errors with field paths, model resolution and overrides, inputs,
controllers from the registry (a stand-in registry module while the real one is being written)."""

from __future__ import annotations

import copy
import sys
import types
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
import yaml

from uvms.control.base import ControlOutput
from uvms.errors import UvmsInputError
from uvms.model import load_model
from uvms.sim.scenario import bundled_scenarios, load_scenario, run_scenario, scenario_from_data

CASE2 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())
PAPER_MODEL = Path(str(files("uvms.model") / "models" / "paper.yaml"))


def scenario(mutate=None, **kwargs):
    """Paper case 2 with its data changed in place by ``mutate``."""
    data = copy.deepcopy(CASE2)
    if mutate is not None:
        mutate(data)
    return scenario_from_data(data, source="case.yaml", **kwargs)


def error_of(mutate) -> str:
    with pytest.raises(UvmsInputError) as info:
        scenario(mutate)
    return str(info.value)


class _HoldStill:
    """A stand-in controller: PD on the body-frame position and yaw."""

    def __init__(self, period, gain):
        self.period, self.gain, self.resets = period, gain, 0

    def reset(self):
        self.resets += 1

    def update(self, m):
        e = m.state.rotation.T @ m.state.position
        wrench = np.zeros(6)
        wrench[3:5] = -self.gain * e[:2] - 0.5 * self.gain * m.state.nu[3:5]
        wrench[2] = -0.1 * self.gain * m.state.euler[2] - 0.05 * self.gain * m.state.nu[2]
        return ControlOutput(wrench=wrench, signals={"s_surge": float(m.state.nu[3] + e[0])})


@pytest.fixture
def fake_registry(monkeypatch):
    """A ``uvms.control.registry`` module with one controller, ``hold-still`` (parameter ``gain``)."""
    module = types.ModuleType("uvms.control.registry")
    module.controller_names = lambda: ("hold-still",)

    def make_controller(name, model, *, period=0.01, parameters=None):  # the real registry's signature
        parameters = parameters or {}
        unknown = set(parameters) - {"gain"}
        if unknown:
            raise ValueError(f"unknown parameter(s) {sorted(unknown)}")
        if "gain" in parameters and parameters["gain"] < 0:
            raise UvmsInputError("expected a number >= 0", path="controller.parameters.gain")
        return _HoldStill(period, float(parameters.get("gain", 100.0)))

    module.make_controller = make_controller
    monkeypatch.setitem(sys.modules, "uvms.control.registry", module)
    return module


# ------------------------------------------------------------------------------------------ bundled


def test_bundled_scenarios_are_the_three_paper_cases():
    # plus the BlueROV2 Heavy + Alpha 5 reach of issue 13 (tests/sim/test_bluerov.py) and its six-axis hold of
    # issue 16 (tests/control/test_compare_scenarios.py) and its station keeping in waves of issue 27
    # (tests/sim/test_scenario_environment.py)
    assert bundled_scenarios() == ["bluerov2_heavy_alpha5_hold6", "bluerov2_heavy_alpha5_reach",
                                   "bluerov2_heavy_alpha5_waves", "paper_case1_fixed",
                                   "paper_case2_released", "paper_case3_controlled"]


@pytest.mark.parametrize("name", ["paper_case1_fixed", "paper_case2_released"])
def test_bundled_uncontrolled_scenarios_load(name):
    s = load_scenario(name)
    assert s.name == name
    assert s.spec.duration == 10.0 and s.spec.step == 0.001 and s.spec.controller is None
    assert s.fixed_base == (name == "paper_case1_fixed")
    schedule = s.spec.inputs.torque_schedule()
    np.testing.assert_array_equal(schedule.times, [0.0, 2.0])
    np.testing.assert_array_equal(schedule.torques, [[2.5, 0, 0], [0.01, 0, 0]])
    assert s.model.name == "paper" and s.model.n_joints == 3
    assert Path(s.source).name == f"{name}.yaml"


def test_bundled_controlled_scenario_loads():
    pytest.importorskip("uvms.control.registry")
    s = load_scenario("paper_case3_controlled")
    assert s.spec.controller is not None and s.spec.actuators == "paper-sway"


def test_controlled_scenario_without_the_controller_is_an_unknown_controller(monkeypatch):
    monkeypatch.setitem(sys.modules, "uvms.control.registry", None)  # import fails as if it did not exist
    with pytest.raises(UvmsInputError, match=r"controller\.name: unknown controller 'smc-ab'"):
        load_scenario("paper_case3_controlled")


def test_unknown_scenario_name_lists_the_bundled_ones():
    with pytest.raises(UvmsInputError, match="no such file or bundled scenario.*paper_case2_released"):
        load_scenario("paper_case9")


# ------------------------------------------------------------------------------------------ errors

BAD = {  # change to case 2 -> (field path, part of the message)
    "typo_top": (lambda d: d.update(duraton=1.0), "duraton", "unknown key; expected one of: actuators"),
    "typo_nested": (lambda d: d["inputs"].update(joint_torqes=[]), "inputs.joint_torqes", "unknown key"),
    "typo_in_step": (lambda d: d["inputs"]["joint_torques"][1].update(torque=[0, 0, 0]),
                     "inputs.joint_torques[1].torque", "expected one of: from, torques"),
    "typo_constant": (lambda d: d["inputs"].update(joint_torques={"konstant": [1, 2, 3]}),
                      "inputs.joint_torques.konstant", "expected one of: constant"),
    "wrong_type": (lambda d: d.update(duration="ten"), "duration", "expected a finite number, found 'ten'"),
    "wrong_type_vector": (lambda d: d["initial_state"].update(euler=[0, 0]), "initial_state.euler",
                          "expected a list of 3 finite numbers"),
    "wrong_type_torques": (lambda d: d["inputs"].update(joint_torques=2.5), "inputs.joint_torques",
                           "expected a list of {from: t, torques: [...]} entries or a mapping"),
    "negative_duration": (lambda d: d.update(duration=-1.0), "duration", "expected a number > 0, found -1"),
    "zero_step": (lambda d: d.update(step=0), "step", "expected a number > 0, found 0"),
    "step_longer_than_run": (lambda d: d.update(duration=0.01, step=0.1), "step", "expected a step <= duration"),
    "too_many_steps": (lambda d: d.update(duration=1e300), "step", "expected at most 1e+09 steps in the duration"),
    "torque_length": (lambda d: d["inputs"]["joint_torques"][1].update(torques=[0.01, 0]),
                      "inputs.joint_torques[1].torques", "expected 3 values (one per joint of model 'paper')"),
    "constant_torque_length": (lambda d: d["inputs"].update(joint_torques={"constant": [1, 2, 3, 4]}),
                               "inputs.joint_torques.constant", "expected 3 values"),
    "q_length": (lambda d: d["initial_state"].update(q=[0.1]), "initial_state.q", "expected 3 values"),
    "schedule_start": (lambda d: d["inputs"]["joint_torques"][0].update({"from": 0.5}), "inputs.joint_torques",
                       "expected the first entry to start at 'from: 0'"),
    "schedule_order": (lambda d: d["inputs"]["joint_torques"][1].update({"from": 0.0}), "inputs.joint_torques[1]",
                       "expected 'from' times in increasing order"),
    "integrator": (lambda d: d.update(integrator="euler"), "integrator", "expected 'rk4', 'DOP853'"),
    "vehicle": (lambda d: d.update(vehicle="free"), "vehicle", "expected 'released' or 'fixed'"),
    "actuators": (lambda d: d.update(actuators="jets"), "actuators", "expected 'model' or one of 'ideal', 'paper'"),
    "missing_model": (lambda d: d.update(model="models/nowhere.yaml"), "model",
                      "no such model file /base/models/nowhere.yaml"),
    "current_both": (lambda d: d["inputs"].update(current={"constant": [0, 0, 0],
                                                           "table": {"times": [0], "velocity": [[0, 0, 0]]}}),
                     "inputs.current", "expected exactly one of 'constant' or 'table'"),
    "current_rows": (lambda d: d["inputs"].update(current={"table": {"times": [0, 1], "velocity": [[0, 0, 0]]}}),
                     "inputs.current.table.velocity", "expected one row per time (2), found 1"),
    "negative_scale": (lambda d: d.update(model_overrides={"drag_scale": -0.4}), "model_overrides.drag_scale",
                       "expected a number >= 0"),
    "run_name": (lambda d: d.update(name="../escape"), "name", "expected a name of up to 100 letters"),
    "controller_period": (lambda d: d.update(controller={"name": "x", "period": 1e-4}), "controller.period",
                          "expected a period >= step"),
    "record_period": (lambda d: d.update(outputs={"record_period": 1e-5}), "outputs.record_period",
                      "expected a record period >= step"),
    "not_a_mapping": (lambda d: d.update(tolerances=[1e-6, 1e-8]), "tolerances", "expected a mapping"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_scenario_is_one_line_naming_file_and_field(case):
    mutate, path, message = BAD[case]
    data = copy.deepcopy(CASE2)
    mutate(data)
    with pytest.raises(UvmsInputError) as info:
        scenario_from_data(data, source="case.yaml", base_dir="/base")
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"case.yaml: {path}: "), text
    assert message in text, text


def test_unknown_controller_is_reported(fake_registry):
    assert error_of(lambda d: d.update(controller={"name": "smc"})) == (
        "case.yaml: controller.name: unknown controller 'smc'; known: hold-still")


def test_bad_controller_parameters_are_reported(fake_registry):
    text = error_of(lambda d: d.update(controller={"name": "hold-still", "parameters": {"gian": 1.0}}))
    assert text == "case.yaml: controller.parameters: invalid controller parameters: unknown parameter(s) ['gian']"
    text = error_of(lambda d: d.update(controller={"name": "hold-still", "parameters": {"gain": -1.0}}))
    assert text == "case.yaml: controller.parameters.gain: expected a number >= 0"


def test_numbers_written_like_1e_3_are_numbers(tmp_path):
    path = tmp_path / "s.yaml"
    path.write_text("model: paper\nduration: 1e-1\nstep: 1e-3\ntolerances: {rtol: 1e-8}\n")
    s = load_scenario(path)
    assert (s.spec.duration, s.spec.step, s.spec.tolerances.rtol) == (0.1, 0.001, 1e-8)
    assert s.name == "s"  # from the file name


def test_yaml_error_and_empty_file(tmp_path):
    broken = tmp_path / "broken.yaml"
    broken.write_text("model: paper\nduration: [1.0\n")
    with pytest.raises(UvmsInputError, match=r"broken\.yaml: line \d+, column \d+: invalid YAML"):
        load_scenario(broken)
    empty = tmp_path / "empty.yaml"
    empty.write_text("")
    with pytest.raises(UvmsInputError, match="expected a mapping of scenario fields.*found an empty file"):
        load_scenario(empty)


# ------------------------------------------------------------------------------------------ model


def test_relative_model_path_resolves_against_the_scenario_folder(tmp_path, monkeypatch):
    (tmp_path / "models").mkdir()
    (tmp_path / "models" / "arm.yaml").write_text(PAPER_MODEL.read_text().replace("name: paper", "name: copy"))
    (tmp_path / "scenarios").mkdir()
    path = tmp_path / "scenarios" / "s.yaml"
    path.write_text("model: ../models/arm.yaml\nduration: 1.0\n")
    monkeypatch.chdir("/")
    assert load_scenario(path).model.name == "copy"


def test_invalid_model_file_names_scenario_field_and_model_file(tmp_path):
    (tmp_path / "bad.yaml").write_text(PAPER_MODEL.read_text().replace("mass: 32.0 ", "mass: -32.0 "))
    path = tmp_path / "s.yaml"
    path.write_text("model: bad.yaml\nduration: 1.0\n")
    with pytest.raises(UvmsInputError) as info:
        load_scenario(path)
    assert str(info.value).startswith(f"{path}: model: {tmp_path / 'bad.yaml'}: vehicle.mass: expected a number > 0, "
                                      "found -32.0")


def test_overrides_scale_hydrodynamics_and_replace_the_environment():
    base = load_model("paper")
    s = scenario(lambda d: d.update(model_overrides={
        "added_mass_scale": 0.4, "drag_scale": 0.5,
        "environment": {"current": [0.1, 0.0, 0.0], "density": 1025.0, "gravity": [0, 0, 9.8]}}))
    m = s.model
    ratio = 1025.0 / 1000.0
    np.testing.assert_allclose(m.added_mass, 0.4 * ratio * base.added_mass)
    np.testing.assert_allclose(m.buoyancy_mass, ratio * base.buoyancy_mass)
    np.testing.assert_allclose(m.vehicle_drag_coefficient, 0.5 * base.vehicle_drag_coefficient)
    np.testing.assert_allclose(m.link_drag_coefficient, 0.5 * base.link_drag_coefficient)
    assert m.vehicle_rotational_drag_coefficient == pytest.approx(0.5 * base.vehicle_rotational_drag_coefficient)
    assert m.density == 1025.0
    np.testing.assert_array_equal(m.current, [0.1, 0, 0])
    np.testing.assert_array_equal(m.gravity, [0, 0, 9.8])
    np.testing.assert_array_equal(m.mass, base.mass)


def test_no_overrides_leave_the_model_unchanged():
    base, m = load_model("paper"), scenario().model
    for name in ("added_mass", "buoyancy_mass", "vehicle_drag_coefficient", "current", "gravity"):
        np.testing.assert_array_equal(getattr(m, name), getattr(base, name))


# ------------------------------------------------------------------------------------------ inputs


def test_inputs_initial_state_and_current_table():
    s = scenario(lambda d: d.update(
        initial_state={"position": [1, 2, 3], "euler": [0, 0, 0.5], "q": [0.1, 0.2, 0.3]},
        inputs={"joint_torques": {"constant": [1, 0, -1]}, "body_wrench": [0, 0, 1, 2, 0, 0],
                "current": {"table": {"times": [0, 2, 4], "velocity": [[0, 0, 0], [0.2, 0, 0], [0.2, 0.4, 0]]}}}))
    st = s.initial_state()
    np.testing.assert_array_equal(st.position, [1, 2, 3])
    np.testing.assert_allclose(st.euler, [0, 0, 0.5], atol=1e-15)
    np.testing.assert_array_equal(st.q, [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(s.spec.inputs.torque_schedule()(5.0), [1, 0, -1])
    table = s.current()
    from uvms.sim.integrate import interpolate

    def at(values, t):
        out = np.zeros(3)
        interpolate(table.times, values, t, out)
        return out

    np.testing.assert_allclose(at(table.velocity, 1.0), [0.1, 0, 0], atol=1e-12)      # linear between knots
    np.testing.assert_allclose(at(table.velocity, 3.0), [0.2, 0.2, 0], atol=1e-12)
    # the fluid acceleration is each segment's slope, and zero once the table holds its last value
    np.testing.assert_allclose(at(table.acceleration, 1.0), [0.1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(at(table.acceleration, 3.0), [0, 0.2, 0], atol=1e-12)
    np.testing.assert_allclose(at(table.acceleration, 4.5), [0, 0, 0], atol=1e-12)
    const = scenario(lambda d: d["inputs"].update(current={"constant": [0.3, 0, 0]})).current()
    np.testing.assert_array_equal(const.velocity, [[0.3, 0, 0]])


def test_hash_is_of_the_file_text(tmp_path):
    import hashlib

    path = tmp_path / "s.yaml"
    path.write_text("# comment\nmodel: paper\nduration: 1.0\n")
    s = load_scenario(path)
    assert s.text == path.read_text()
    assert s.sha256 == hashlib.sha256(path.read_bytes()).hexdigest()


# ------------------------------------------------------------------------------------------ running


def test_run_scenario_is_the_simulation_of_its_inputs():
    from uvms.sim.run import simulate

    s = scenario(lambda d: d.update(duration=0.05))
    calls = []
    result = run_scenario(s, progress=lambda t, total: calls.append((t, total)))
    assert result.complete and result.time[-1] == pytest.approx(0.05)
    assert result.metadata["scenario"] == "paper_case2_released"
    assert result.metadata["scenario_sha256"] == s.sha256
    assert calls and calls[-1] == pytest.approx((0.05, 0.05))
    direct = simulate(load_model("paper"), duration=0.05, step=0.001, joint_torques=np.array([2.5, 0, 0]))
    np.testing.assert_array_equal(result.states, direct.states)


def test_run_scenario_with_a_registry_controller(fake_registry):
    s = scenario(lambda d: d.update(duration=0.1, controller={"name": "hold-still", "period": 0.02,
                                                              "parameters": {"gain": 50.0}}))
    result = run_scenario(s)
    assert result.complete
    assert {"s_surge", "command_X", "command_Y", "command_N"} <= set(result.signals)
    assert np.any(result.signals["command_X"] != 0)
    assert result.metadata["controller"] == "hold-still"


def test_adaptive_integrator_and_tolerances_reach_the_simulation():
    rk4 = run_scenario(scenario(lambda d: d.update(duration=0.02)))
    dop = run_scenario(scenario(lambda d: d.update(duration=0.02, integrator="DOP853",
                                                   tolerances={"rtol": 1e-9, "atol": 1e-12})))
    assert dop.complete and dop.metadata["integrator"] == "DOP853"
    np.testing.assert_allclose(dop.q[-1], rk4.q[-1], rtol=1e-8, atol=1e-12)


TRAJECTORY = {"times": [0.0, 1.0, 2.0], "angles": [[0.0, 0.0, 0.0], [0.8, 0.4, -0.4], [1.2, 0.0, 0.2]]}


@pytest.mark.parametrize("tracker", ["computed_torque", "pd"])
def test_joint_trajectory_is_tracked(tracker):
    """A pilot's master-arm motion replayed: the arm ends at the last knot (clamped vehicle)."""
    gains = {} if tracker == "computed_torque" else {"kp": [2.0, 1.0, 0.3], "kd": [1.0, 0.3, 0.05], "period": 0.002}
    data = {"model": "paper", "duration": 4.0, "vehicle": "fixed",
            "inputs": {"joint_trajectory": {**TRAJECTORY, "tracker": tracker, **gains}}}
    result = run_scenario(scenario_from_data(data))
    assert result.complete
    tol = 1e-3 if tracker == "computed_torque" else 0.05
    np.testing.assert_allclose(result.q[-1], TRAJECTORY["angles"][-1], atol=tol)


def test_joint_trajectory_checks():
    bad = {"model": "paper", "duration": 1.0, "inputs": {"joint_trajectory": {"times": [0.0, 1.0],
                                                                              "angles": [[0, 0, 0], [1, 1]]}}}
    with pytest.raises(UvmsInputError, match=r"inputs\.joint_trajectory\.angles\[1\]"):
        scenario_from_data(bad)
    both = {"model": "paper", "duration": 1.0, "inputs": {"joint_torques": {"constant": [0, 0, 0]},
                                                          "joint_trajectory": TRAJECTORY}}
    with pytest.raises(UvmsInputError, match="not both"):
        scenario_from_data(both)
