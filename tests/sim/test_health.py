"""Run health (issue #16): saturated thrusters, the wrench that could not be produced, the attitude; a lost
run is flagged with one warning line and stays complete."""

from __future__ import annotations

import copy
import io
import json
import math
import sys
from importlib.resources import files

import numpy as np
import pytest
import yaml

from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sim.health import HealthLimits, run_health
from uvms.sim.metrics import compute_metrics

from .test_metrics import constructed

CASE3 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case3_controlled.yaml").read_text())
NAN = float("nan")


def hand_result(roll_deg: float = 70.0):
    """Five samples at uneven times, two thrusters limited to [-5, 5] N, an unproduced wrench, a roll."""
    time = [0.0, 0.1, 0.3, 0.6, 1.0]
    signals = {"thrust_cmd_a": np.array([NAN, 5.0, 2.0, -5.0, 1.0]),
               "thrust_cmd_b": np.array([NAN, 0.0, 0.0, 0.0, 5.0]),
               **{f"unachieved_{c}": np.array([NAN, 0.0, 0.0, 0.0, 0.0]) for c in "KMNZ"},
               "unachieved_X": np.array([NAN, 3.0, 0.0, -4.0, 0.0]),
               "unachieved_Y": np.array([NAN, 4.0, 0.0, 0.0, 0.0])}
    signals["unachieved_N"] = np.array([NAN, 0.0, -2.0, 0.0, 0.0])
    euler = [[0, 0, 0], [math.radians(roll_deg), 0, 0], [0, math.radians(-10.0), 0], [0, 0, 0], [0, 0, 0]]
    metadata = {"thrust_limits_N": {"a": [-5.0, 5.0], "b": [-5.0, 5.0]}}
    return constructed(np.zeros((5, 3)), euler, signals=signals, time=time, metadata=metadata)


def test_health_values_by_hand():
    """Zero-order hold: sample k holds for t[k+1] - t[k] = 0.1, 0.2, 0.3, 0.4, 0 s; sample 0 is NaN (before
    the first update), so 0.9 s count. Thruster a is at a limit during 0.2 + 0.4 s: 2/3; b only at the last
    sample, which holds for no time: 0."""
    h = run_health(hand_result())
    assert h.saturated_fraction == pytest.approx({"a": 0.6 / 0.9, "b": 0.0}, rel=1e-14)
    assert h.peak_unachieved["X"] == 4.0 and h.peak_unachieved["Y"] == 4.0 and h.peak_unachieved["N"] == 2.0
    assert h.rms_unachieved["X"] == pytest.approx(math.sqrt((9 * 0.2 + 16 * 0.4) / 0.9), rel=1e-14)
    assert h.rms_unachieved["N"] == pytest.approx(math.sqrt(4 * 0.3 / 0.9), rel=1e-14)
    assert h.peak_unachieved_force == pytest.approx(5.0, rel=1e-15)          # |(3, 4, 0)| at t = 0.1 s
    assert h.peak_unachieved_moment == 2.0
    assert h.max_abs_roll == pytest.approx(math.radians(70.0), rel=1e-12)
    assert h.max_abs_pitch == pytest.approx(math.radians(10.0), rel=1e-12)
    assert not h.healthy
    assert h.warning == ("unhealthy run (control lost?): |roll| reached 70.0 deg (limit 60 deg); thruster a "
                         "saturated 67 % of the time (limit 25 %); wrench not produced: peak 5 N, 2 N m")
    named = compute_metrics(hand_result(), ["healthy", "max_saturated_fraction", "peak_unachieved_force_N",
                                            "max_abs_roll_rad", "max_abs_pitch_rad"])
    assert named == pytest.approx({"healthy": 0.0, "max_saturated_fraction": 0.6 / 0.9, "peak_unachieved_force_N": 5.0,
                                   "max_abs_roll_rad": math.radians(70.0), "max_abs_pitch_rad": math.radians(10.0)},
                                  rel=1e-12)


def test_limits_decide_and_come_from_the_metadata():
    assert run_health(hand_result(), limits=HealthLimits(math.radians(80.0), 0.7)).healthy
    r = hand_result(roll_deg=30.0)
    only_saturation = run_health(r)
    assert not only_saturation.healthy and "roll" not in only_saturation.warning
    r.metadata["health_limits"] = {"attitude_limit": math.radians(20.0), "saturation_limit": 0.9}
    h = run_health(r)
    assert not h.healthy and h.warning.startswith("unhealthy run (control lost?): |roll| reached 30.0 deg (limit "
                                                  "20 deg)")
    assert "thruster" not in h.warning
    assert r.summary()["health"]["limits"] == {"attitude_limit_rad": math.radians(20.0), "saturation_limit": 0.9}


def test_without_thrust_limits_saturation_is_not_assessed():
    r = hand_result(roll_deg=0.0)
    r.metadata.pop("thrust_limits_N")
    h = run_health(r)
    assert h.healthy and h.saturated_fraction == {} and h.warning == ""
    assert h.peak_unachieved_force == pytest.approx(5.0)                      # still reported


def _weak_thrusters(tmp_path, duration=3.0):
    """Paper case 3 with the model file's four thrusters limited to 1 N (ideal thrusters), `actuators: model`."""
    model = yaml.safe_load((files("uvms.model") / "models" / "paper.yaml").read_text())
    for thruster in model["thrusters"]:
        thruster.update(model="ideal", max_thrust=1.0)
    (tmp_path / "weak.yaml").write_text(yaml.safe_dump(model, sort_keys=False))
    data = copy.deepcopy(CASE3)
    data.update(name="weak", duration=duration, model="weak.yaml", actuators="model")
    path = tmp_path / "weak_case.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_a_saturated_vehicle_is_flagged_and_a_healthy_run_is_not(tmp_path):
    """The paper's case 3 (its Healey thrusters with a sway thruster, 52 N each) holds station: healthy. The
    same case with 1 N thrusters cannot resist the arm's reaction: saturated most of the time, unhealthy, yet
    complete."""
    from uvms.sim.scenario import load_scenario, run_scenario

    paper = run_scenario(load_scenario("paper_case3_controlled"))
    health = paper.summary()["health"]
    assert paper.complete and health["healthy"] and health["warning"] == ""
    assert set(health["saturated_fraction"]) == {"surge_port", "surge_starboard", "heave", "sway"}
    assert max(health["saturated_fraction"].values()) == 0.0 and health["peak_unachieved_force_N"] < 1e-9

    weak = run_scenario(load_scenario(_weak_thrusters(tmp_path)))
    health = weak.summary()["health"]
    assert weak.complete and not health["healthy"]
    assert health["saturated_fraction"]["sway"] > 0.9 and health["peak_unachieved_force_N"] > 10.0
    assert "\n" not in health["warning"] and "saturated" in health["warning"]


def test_uvms_run_prints_one_warning_line_and_exits_0(tmp_path, monkeypatch):
    path = _weak_thrusters(tmp_path, duration=1.0)
    stdout, stderr = io.StringIO(), io.StringIO()
    monkeypatch.setattr(sys, "stdout", stdout)
    monkeypatch.setattr(sys, "stderr", stderr)
    code = main(["run", str(path), "-o", str(tmp_path / "out")])
    assert code == 0
    lines = [line for line in stderr.getvalue().splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("uvms: warning: unhealthy run (control lost?): thruster ")
    assert "UNHEALTHY" in stdout.getvalue()
    saved = json.loads((tmp_path / "out" / "result.json").read_text())
    assert saved["complete"] is True and saved["health"]["healthy"] is False
    assert saved["metadata"]["thrust_limits_N"]["sway"] == [-1.0, 1.0]


@pytest.mark.parametrize("health, path, words", [
    ({"saturation_limit": 1.5}, "health.saturation_limit", "expected a number <= 1, found 1.5"),
    ({"attitude_limit": 0}, "health.attitude_limit", "expected a number > 0, found 0"),
    ({"attitude": 1.0}, "health.attitude", "unknown key; expected one of: attitude_limit, saturation_limit"),
])
def test_scenario_health_limits_are_checked(health, path, words):
    from uvms.sim.scenario import scenario_from_data

    with pytest.raises(UvmsInputError) as info:
        scenario_from_data({**copy.deepcopy(CASE3), "health": health}, source="case.yaml")
    assert str(info.value) == f"case.yaml: {path}: {words}"
