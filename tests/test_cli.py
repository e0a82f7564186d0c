"""The ``uvms`` command line: ``validate`` on good and bad model files, exit codes, one-line errors."""

from __future__ import annotations

import copy
import importlib
import subprocess
import sys
from importlib.resources import files

import numpy as np
import pytest
import yaml

from uvms.cli import main
from uvms.commands import COMMANDS
from uvms.errors import SimulationDiverged

PAPER = yaml.safe_load((files("uvms.model") / "models" / "paper.yaml").read_text())


def write_model(tmp_path, mutate=None, name="model.yaml"):
    data = copy.deepcopy(PAPER)
    if mutate is not None:
        mutate(data)
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data))
    return path


def link(i):
    return lambda d: d["arm"]["links"][i]


BAD_INPUTS = {  # one per class of bad input: (change to the paper model, field path in the error)
    "unknown_key": (lambda d: d["vehicle"]["drag"].update(linear=1.0), "vehicle.drag.linear"),
    "missing_field": (lambda d: d["arm"]["links"][2].pop("cylinder"), "arm.links[2].cylinder"),
    "vector_shape": (lambda d: d["vehicle"]["buoyancy"].update(center=[0, 0]), "vehicle.buoyancy.center"),
    "matrix3_shape": (lambda d: d["vehicle"].update(inertia={"matrix": [[1, 0, 0], [0, 1, 0]], "about": "com"}),
                      "vehicle.inertia.matrix"),
    "matrix6_shape": (lambda d: link(1)(d).update(added_mass={"matrix": np.eye(3).tolist(), "about": "joint"}),
                      "arm.links[1].added_mass.matrix"),
    "zero_mass": (lambda d: link(1)(d).update(mass=0.0), "arm.links[1].mass"),
    "negative_mass": (lambda d: d["vehicle"].update(mass=-32.0), "vehicle.mass"),
    "negative_buoyancy": (lambda d: link(0)(d)["buoyancy"].update(mass=-1.0), "arm.links[0].buoyancy.mass"),
    "negative_radius": (lambda d: link(2)(d)["cylinder"].update(radius=-0.0125), "arm.links[2].cylinder.radius"),
    "negative_length": (lambda d: link(0)(d)["cylinder"].update(length=-0.22), "arm.links[0].cylinder.length"),
    "negative_area": (lambda d: d["vehicle"]["drag"].update(area=[0.061, -0.061, 0.061]), "vehicle.drag.area"),
    "negative_cd": (lambda d: link(1)(d).update(drag_coefficient=-1.1), "arm.links[1].drag_coefficient"),
    "negative_rot_cd": (lambda d: d["vehicle"]["drag"]["rotational"].update(coefficient=-1.0),
                        "vehicle.drag.rotational.coefficient"),
    "zero_density": (lambda d: d["environment"].update(density=0.0), "environment.density"),
    "inertia_not_psd": (lambda d: link(1)(d)["inertia"].update(diagonal=[0.0, 0.01, 0.0137]),
                        "arm.links[1].inertia.diagonal"),
    "inertia_triangle": (lambda d: d["vehicle"]["inertia"].update(diagonal=[0.1, 0.1, 1.0]),
                         "vehicle.inertia.diagonal"),
    "inertia_asymmetric": (lambda d: d["vehicle"].update(
        inertia={"matrix": [[1, 0.1, 0], [0, 1, 0], [0, 0, 1]], "about": "com"}), "vehicle.inertia.matrix"),
    "added_mass_asymmetric": (lambda d: d["vehicle"].update(
        added_mass={"matrix": (np.eye(6) + np.eye(6, k=1)).tolist(), "about": "origin"}),
        "vehicle.added_mass.matrix"),
    "added_mass_not_psd": (lambda d: link(0)(d)["added_mass"].update(diagonal=[0, 0.0017, 0.0017, 0, -0.1, 0.1]),
                           "arm.links[0].added_mass.diagonal"),
    "zero_thruster_direction": (lambda d: d.update(thrusters=[
        {"name": "t1", "position": [0, 0, 0], "direction": [0, 0, 0], "model": "ideal"}]), "thrusters[0].direction"),
    "arm_without_links": (lambda d: d["arm"].update(links=[]), "arm.links"),
    "wrong_type": (lambda d: d.update(vehicle=[1, 2, 3]), "vehicle"),
}


@pytest.mark.parametrize("case", sorted(BAD_INPUTS))
def test_validate_bad_input_one_line_exit_2(tmp_path, capsys, case):
    mutate, field_path = BAD_INPUTS[case]
    path = write_model(tmp_path, mutate, name=f"{case}.yaml")
    assert main(["validate", str(path)]) == 2
    out, err = capsys.readouterr()
    lines = err.splitlines()
    assert out == "" and len(lines) == 1 and "Traceback" not in err
    prefix = f"uvms: error: {path}: {field_path}: "
    assert lines[0].startswith(prefix) and "expected" in lines[0][len(prefix):]


def test_validate_yaml_syntax_error_names_the_line(tmp_path, capsys):
    path = tmp_path / "broken.yaml"
    path.write_text("name: broken\nvehicle:\n  mass: [32.0\n")
    assert main(["validate", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith(f"uvms: error: {path}: line ") and "invalid YAML" in err


def test_validate_good_file(tmp_path, capsys):
    path = write_model(tmp_path, lambda d: d["vehicle"]["buoyancy"].update(mass=33.0))
    assert main(["validate", str(path)]) == 0
    out, err = capsys.readouterr()
    assert err == "" and "paper: valid" in out and str(path) in out
    assert "joints:               3" in out and "total mass:           35 kg" in out
    assert "net buoyancy:         9.81 N" in out  # (36 - 35) kg * 9.81 m/s^2


def test_version_help_and_usage_errors(capsys):
    assert main(["--version"]) == 0
    assert capsys.readouterr().out.startswith("uvms ")
    assert main(["--help"]) == 0
    assert "validate" in capsys.readouterr().out
    assert main([]) == 2
    assert main(["no-such-command"]) == 2
    assert main(["sweep", "x", "--workers", "abc"]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == ["uvms: error: the following arguments are required: COMMAND (see 'uvms --help')",
                   "uvms: error: argument COMMAND: invalid choice: 'no-such-command' (choose from "
                   + ", ".join(f"'{c.replace('_', '-')}'" for c in COMMANDS) + ") (see 'uvms --help')",
                   "uvms: error: argument --workers: invalid int value: 'abc' (see 'uvms sweep --help')"]


@pytest.mark.parametrize("argv, message", [
    (["compare", "--duration", "0.0001"], "--step: expected a step <= duration (0.0001 s), found 0.001 s"),
    (["compare", "--duration", "1e300"], "--step: expected at most 1e+09 steps in --duration, found 1e+303"),
])
def test_compare_refuses_runs_of_no_steps_or_too_many(capsys, argv, message):
    assert main(argv) == 2
    assert capsys.readouterr().err == f"uvms: error: {message}\n"


def test_ctrl_c_is_one_line_and_exit_130(monkeypatch, capsys):
    def interrupted(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(importlib.import_module("uvms.commands.validate"), "run", interrupted)
    assert main(["validate", "paper"]) == 130
    assert capsys.readouterr().err == "uvms: interrupted\n"


def test_simulation_diverged_exits_3(monkeypatch, capsys):
    def diverge(args):
        raise SimulationDiverged(1.25, "joint velocity qd[2] = 3e12 rad/s", "reduce the time step")

    monkeypatch.setattr(importlib.import_module("uvms.commands.validate"), "run", diverge)
    assert main(["validate", "paper"]) == 3
    assert capsys.readouterr().err == ("uvms: error: simulation diverged at t = 1.25 s: "
                                       "joint velocity qd[2] = 3e12 rad/s; reduce the time step\n")


@pytest.mark.parametrize("argv, option", [
    (["run", "paper_case2_released", "-o", "{blocker}/run"], "--output"),
    (["compare", "--json", "{blocker}/table.json"], "--json"),
    (["reproduce", "paper", "-o", "{blocker}/paper"], "--output"),
    (["sweep", "paper_model_error", "-o", "{blocker}/sweep"], "--output"),
])
def test_an_unwritable_output_is_refused_before_any_simulation(tmp_path, monkeypatch, capsys, argv, option):
    """An output path under a file is one line and exit 2 at once: nothing is simulated first."""
    import uvms.sim.run

    def no_simulation(*args, **kwargs):
        raise AssertionError("simulated before checking the output path")

    monkeypatch.setattr(uvms.sim.run, "simulate", no_simulation)
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder")
    assert main([a.format(blocker=blocker) for a in argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("uvms: error: ") and "Traceback" not in err
    assert f"{option}: cannot be created: {blocker} is a file" in err
    assert blocker.read_text() == "not a folder"


@pytest.mark.parametrize("module_name", COMMANDS)
def test_command_modules_follow_the_protocol(module_name):
    module = importlib.import_module(f"uvms.commands.{module_name}")
    assert isinstance(module.NAME, str) and isinstance(module.HELP, str) and "\n" not in module.HELP
    assert callable(module.add_arguments) and callable(module.run)


def test_end_to_end_subprocess(tmp_path):
    good = subprocess.run([sys.executable, "-m", "uvms", "validate", "paper"], capture_output=True, text=True, check=False)
    assert good.returncode == 0 and "paper: valid" in good.stdout and good.stderr == ""
    path = write_model(tmp_path, lambda d: d["arm"]["links"][1]["inertia"].update(diagonal=[0, 0.01, 0.0137]),
                       name="bad inertia.yaml")
    bad = subprocess.run([sys.executable, "-m", "uvms", "validate", str(path)], capture_output=True, text=True, check=False)
    assert bad.returncode == 2 and bad.stdout == "" and "Traceback" not in bad.stderr
    assert bad.stderr.splitlines() == [bad.stderr.strip()]
    assert "bad inertia.yaml: arm.links[1].inertia.diagonal: expected a positive semi-definite" in bad.stderr
