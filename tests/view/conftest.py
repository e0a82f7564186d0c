"""Shared fixtures of the 3-D view tests: the bundled paper model, a real short run saved by ``uvms run``, and a
synthetic run with known motion and thrust signals (no simulation needed)."""

from __future__ import annotations

import copy
import io
import sys
from importlib.resources import files

import numpy as np
import pytest
import yaml

from uvms.cli import main

CASE2 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())
THRUSTERS = ("surge_port", "surge_starboard", "heave", "sway")   # the 'paper-sway' layout


@pytest.fixture(scope="session")
def paper():
    import uvms

    return uvms.load_model("paper")


def run_cli(argv, monkeypatch=None):
    """``main(argv)`` with stdout and stderr captured: (exit code, stdout, stderr)."""
    out, err = io.StringIO(), io.StringIO()
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(sys, "stdout", out)
        mp.setattr(sys, "stderr", err)
        code = main([str(a) for a in argv])
    return code, out.getvalue(), err.getvalue()


@pytest.fixture(scope="session")
def short_run(tmp_path_factory):
    """Paper case 2 (joint 1 driven by 2.5 N m, vehicle released) for 1 s, saved by ``uvms run``."""
    tmp = tmp_path_factory.mktemp("short")
    data = copy.deepcopy(CASE2)
    data.update(name="short", duration=1.0, outputs={"record_period": 0.01})
    path = tmp / "short.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    code, _, err = run_cli(["run", path, "-o", tmp / "run"])
    assert code == 0, err
    return tmp / "run"


def synthetic_result(model, K: int = 41, duration: float = 2.0):
    """A run with known motion: the vehicle moves 0.4 m north and yaws 90 degrees, joint 1 turns by pi, and
    the surge_port thruster's command ramps from -10 N to +20 N (the others hold 5 N)."""
    from uvms.dynamics.poses import forward_kinematics
    from uvms.rotations import quaternion_from_euler
    from uvms.sim.result import Result
    from uvms.state import State

    t = np.linspace(0.0, duration, K)
    s = t / duration
    n = model.n_joints
    states = np.zeros((K, 13 + 2 * n))
    states[:, 0] = 0.4 * s
    for k in range(K):
        states[k, 3:7] = quaternion_from_euler(np.array([0.0, 0.0, 0.5 * np.pi * s[k]]))
    states[:, 13] = np.pi * s
    ee = np.array([forward_kinematics(model, State(states[k, :3], states[k, 3:7], np.zeros(6), states[k, 13:13 + n],
                                                   np.zeros(n))).end_effector_position for k in range(K)])
    signals = {f"thrust_cmd_{name}": np.full(K, 5.0) for name in THRUSTERS}
    signals["thrust_cmd_surge_port"] = -10.0 + 30.0 * s
    return Result(time=t, states=states, n_joints=n, end_effector=ee, joint_torques=np.zeros((K, n)),
                  signals=signals, metadata={"scenario": "synthetic", "vehicle": "released", "controller": None})


SYNTHETIC_SCENARIO = """name: synthetic
model: paper
duration: 2.0
actuators: paper-sway
"""


@pytest.fixture(scope="session")
def synthetic_run(tmp_path_factory, paper):
    """:func:`synthetic_result` saved as a run folder (result.csv, result.json, scenario.yaml)."""
    folder = tmp_path_factory.mktemp("synthetic") / "run"
    result = synthetic_result(paper)
    result.save(folder)
    (folder / "scenario.yaml").write_text(SYNTHETIC_SCENARIO)
    return folder, result
