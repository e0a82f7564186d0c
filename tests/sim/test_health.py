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


def _health_lines(stderr: str) -> list[str]:
    """The non-empty stderr lines of a ``uvms run``, less the one line in which a sliding-mode controller with
    the paper's fixed ``b`` bounds says that they miss the plant (said before the run, docs/controllers.md):
    what is left is what run health said."""
    lines = [line for line in stderr.splitlines() if line.strip()]
    bounds = [line for line in lines if line.startswith("uvms: warning: sliding-mode controller: its b bounds miss")]
    assert len(bounds) <= 1, lines
    return [line for line in lines if line not in bounds]


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
    lines = _health_lines(stderr.getvalue())
    assert len(lines) == 1 and lines[0].startswith("uvms: warning: unhealthy run (control lost?): thruster ")
    assert "UNHEALTHY" in stdout.getvalue()
    saved = json.loads((tmp_path / "out" / "result.json").read_text())
    assert saved["complete"] is True and saved["health"]["healthy"] is False
    assert saved["metadata"]["thrust_limits_N"]["sway"] == [-1.0, 1.0]


@pytest.mark.parametrize("health, path, words", [
    ({"saturation_limit": 1.5}, "health.saturation_limit", "expected a number <= 1, found 1.5"),
    ({"attitude_limit": 0}, "health.attitude_limit", "expected a number > 0, found 0"),
    ({"attitude": 1.0}, "health.attitude", "unknown key; expected one of: attitude_limit, saturation_limit, "
                                           "station_limit, unproduced_limit"),
    ({"station_limit": -1.0}, "health.station_limit", "expected a number > 0, found -1.0"),
    ({"unproduced_limit": 2}, "health.unproduced_limit", "expected a number <= 1, found 2"),
])
def test_scenario_health_limits_are_checked(health, path, words):
    from uvms.sim.scenario import scenario_from_data

    with pytest.raises(UvmsInputError) as info:
        scenario_from_data({**copy.deepcopy(CASE3), "health": health}, source="case.yaml")
    assert str(info.value) == f"case.yaml: {path}: {words}"


# ------------------------------------------------------------------ loss of station, unproducible wrench

def _allocated_run(commands, thrusters):
    """A constructed run whose logged wrench signals are what the layout's allocation gives for each commanded
    wrench row (``commands`` (K, 6) [K M N X Y Z]): ``unachieved`` is the residual of the Python bounded
    least squares (:func:`uvms.thrusters.allocation.allocate`), independent of the compiled loop's."""
    from uvms.thrusters.allocation import allocate
    from uvms.thrusters.layouts import layout_matrix, thrust_limits

    commands = np.asarray(commands, dtype=float)
    Lambda, (lower, upper) = layout_matrix(thrusters), thrust_limits(thrusters)
    residual = np.array([allocate(Lambda, w, lower, upper).residual for w in commands])
    K = len(commands)
    signals = {**{f"command_{a}": commands[:, j] for j, a in enumerate("KMNXYZ")},
               **{f"unachieved_{a}": residual[:, j] for j, a in enumerate("KMNXYZ")}}
    return constructed(np.zeros((K, 3)), np.zeros((K, 3)), signals=signals, time=np.linspace(0.0, 1.0, K))


def _wrench(X=0.0, Y=0.0, N=0.0, K=5):
    return np.tile([0.0, 0.0, N, X, Y, 0.0], (K, 1))


def test_unproducible_share_in_closed_form():
    """The paper's three thrusters (two surge, one heave) span no sway force: a pure sway command is 100 %
    unproducible, the component of the command outside range(Lambda) (its projection on the left null space,
    computed by SVD); a pure surge command 0 %; 30 N sway with 40 N surge 3/5; a surge command beyond the two
    surge thrusters' limits the residual of the bounded allocation, (X - 2 T_max) / X."""
    from uvms.thrusters.allocation import unachievable_part
    from uvms.thrusters.layouts import layout, layout_matrix, thrust_limits

    paper = layout("paper")
    sway = _allocated_run(_wrench(Y=80.0), paper)
    h = run_health(sway)
    assert h.unproduced_share_force == 1.0 and h.unproduced_share_moment == 0.0
    assert compute_metrics(sway, ["unproduced_force_share"]) == {"unproduced_force_share": 1.0}
    outside = unachievable_part(layout_matrix(paper), _wrench(Y=80.0)[0])      # SVD: the left null space
    np.testing.assert_allclose(outside, [0, 0, 0, 0, 80.0, 0], atol=1e-12)
    np.testing.assert_allclose(sway.signals["unachieved_Y"], outside[4])
    assert not h.healthy and h.warning == (
        "unhealthy run (control lost?): 100 % of the commanded force could not be produced by the thrusters "
        "(limit 25 %); wrench not produced: peak 80 N, 0 N m")

    surge = run_health(_allocated_run(_wrench(X=40.0, N=2.0), paper))
    assert surge.unproduced_share_force == pytest.approx(0.0, abs=1e-12) and surge.healthy
    assert surge.unproduced_share_moment == pytest.approx(0.0, abs=1e-12) and surge.warning == ""

    mixed = run_health(_allocated_run(_wrench(X=40.0, Y=30.0), paper))
    assert mixed.unproduced_share_force == pytest.approx(0.6, rel=1e-12)

    t_max = float(thrust_limits(paper)[1][0])
    beyond = run_health(_allocated_run(_wrench(X=2 * t_max + 20.0), paper))
    assert beyond.unproduced_share_force == pytest.approx(20.0 / (2 * t_max + 20.0), rel=1e-9)

    with_sway = run_health(_allocated_run(_wrench(Y=30.0), layout("paper-sway")))
    assert with_sway.unproduced_share_force == pytest.approx(0.0, abs=1e-12) and with_sway.healthy


def test_unproduced_share_weights_the_samples_and_its_limit_decides():
    """Shares weight each sample by its hold time and by the commanded magnitude; a short 100 % burst in a long
    run of produced commands is a small share; ``unproduced_limit`` decides."""
    from uvms.thrusters.layouts import layout

    commands = np.vstack([_wrench(Y=10.0, K=1), _wrench(X=10.0, K=9)])      # 1 of 9 held intervals sway
    r = _allocated_run(commands, layout("paper"))
    h = run_health(r)
    assert h.unproduced_share_force == pytest.approx(1 / 9, rel=1e-12) and h.healthy
    assert not run_health(r, limits=HealthLimits(unproduced_limit=0.1)).healthy
    r.metadata["health_limits"] = {"unproduced_limit": 0.05}
    assert "could not be produced" in run_health(r).warning


def test_station_departure_by_hand_and_across_waypoints():
    """|e| = 0, 0.6, 1.3, 0.2 m: the vehicle left its station by 1.3 m (limit 1 m: unhealthy). A set point that
    moves 3 m away (a waypoint at t = 2 s) starts a new segment: only the rise above the lowest distance since
    then counts (3.0 -> 0.5 -> 0.9: 0.4 m)."""
    from uvms.sim.health import station_departure

    t = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0]
    e_surge = np.array([NAN, 0.0, 0.6, 1.2, 0.2, 0.2])
    e_sway = np.array([NAN, 0.0, 0.0, 0.5, 0.0, 0.0])
    r = constructed(np.zeros((6, 3)), np.zeros((6, 3)), signals={"e_surge": e_surge, "e_sway": e_sway}, time=t)
    h = run_health(r)
    assert h.station_departure == pytest.approx(1.3, rel=1e-12) and not h.healthy
    assert h.warning == "unhealthy run (control lost?): left its station by 1.3 m (limit 1 m)"
    assert run_health(r, limits=HealthLimits(station_limit=1.5)).healthy
    assert h.as_dict()["station"] == {"peak_departure_m": pytest.approx(1.3), "limit_m": 1.0}
    named = compute_metrics(r, ["peak_station_departure_m", "unproduced_force_share", "unproduced_moment_share"])
    assert named["peak_station_departure_m"] == pytest.approx(1.3) and math.isnan(named["unproduced_force_share"])

    moving = np.array([NAN, 0.0, 3.0, 0.5, 0.9, 0.5])
    assert station_departure(t, moving[:, None]) == pytest.approx(3.0)
    assert station_departure(t, moving[:, None], changes=[2.0]) == pytest.approx(0.4)
    r = constructed(np.zeros((6, 3)), np.zeros((6, 3)), signals={"e_heave": moving}, time=t,
                    metadata={"set_point_changes_s": [2.0], "step_s": 0.001})
    assert run_health(r).healthy and run_health(r).station_departure == pytest.approx(0.4)


def test_set_point_changes_are_the_updates_at_or_after_each_waypoint():
    """Waypoints at 0.5 s, 0.123 s and beyond the run, a controller every 10 steps of 1 ms: the set point changes
    at the updates of 0.5 s and 0.13 s (the first at or after the waypoint's time)."""
    from types import SimpleNamespace

    from uvms.sim.health import set_point_metadata
    from uvms.sim.plan import Timing

    controller = SimpleNamespace(parameters=SimpleNamespace(waypoints=((0.5, 1, 0, 0, 0, 0, 0),
                                                                       (0.123, 0, 0, 0, 0, 0, 0),
                                                                       (9.0, 0, 0, 0, 0, 0, 0))))
    plan = SimpleNamespace(controller=controller, control_every=10, timing=Timing.of(1.0, 0.001))
    changes = set_point_metadata(plan)["set_point_changes_s"]
    assert changes == pytest.approx([0.13, 0.5], rel=1e-12)
    assert set_point_metadata(SimpleNamespace(controller=None, control_every=0, timing=plan.timing)) == {}


def test_runs_without_a_station_or_thrusters_are_not_assessed():
    """No logged position error (no controller) and no commanded wrench: neither check applies (None)."""
    h = run_health(hand_result(roll_deg=0.0))
    assert h.station_departure is None and h.unproduced_share_force is None and h.unproduced_share_moment is None
    assert h.as_dict()["unproduced"] == {"force_share": None, "moment_share": None, "limit": 0.25}


def _side_current(tmp_path, actuators: str, duration: float = 20.0):
    """Paper case 3 (smc-ab) with ``actuators`` in a 0.4 m/s current from the side (world y)."""
    data = copy.deepcopy(CASE3)
    data.update(name=f"side_{actuators}", duration=duration, actuators=actuators)
    data["inputs"]["current"] = {"constant": [0.0, 0.4, 0.0]}
    path = tmp_path / f"side_{actuators}.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_the_papers_three_thrusters_in_a_side_current_lose_their_station(tmp_path, monkeypatch):
    """The issue's case: the paper's layout (no sway thruster) in a 0.4 m/s side current is swept several metres
    off station while nearly all the commanded force is sway that no thruster produces: unhealthy, both said on
    one warning line, exit 0. Nothing saturates (the old health said healthy). The logged unproduced force is the
    component of the command outside range(Lambda) (SVD projection, computed here independently) at every
    update. With the sway thruster the same run holds its station: healthy."""
    from uvms.sim.scenario import load_scenario, run_scenario
    from uvms.thrusters.allocation import unachievable_part
    from uvms.thrusters.layouts import layout, layout_matrix

    result = run_scenario(load_scenario(_side_current(tmp_path, "paper")))
    h = result.health()
    assert result.complete and not h.healthy and max(h.saturated_fraction.values()) == 0.0
    assert h.station_departure > 3.0 and h.unproduced_share_force > 0.95
    assert "left its station by" in h.warning and "of the commanded force could not be produced" in h.warning
    commanded = np.column_stack([result.signals[f"command_{a}"] for a in "KMNXYZ"])
    unproduced = np.column_stack([result.signals[f"unachieved_{a}"] for a in "KMNXYZ"])
    ok = np.all(np.isfinite(commanded), axis=1)
    Lambda = layout_matrix(layout("paper"))
    expected = np.array([unachievable_part(Lambda, w) for w in commanded[ok]])
    np.testing.assert_allclose(unproduced[ok], expected, atol=1e-9 * np.abs(commanded[ok]).max())

    held = run_scenario(load_scenario(_side_current(tmp_path, "paper-sway")))
    assert held.health().healthy and held.health().station_departure < 0.05

    stdout, stderr = io.StringIO(), io.StringIO()
    monkeypatch.setattr(sys, "stdout", stdout)
    monkeypatch.setattr(sys, "stderr", stderr)
    assert main(["run", str(_side_current(tmp_path, "paper", duration=10.0)), "-o", str(tmp_path / "out")]) == 0
    lines = _health_lines(stderr.getvalue())
    assert len(lines) == 1 and lines[0].startswith("uvms: warning: unhealthy run (control lost?): ")
    assert "could not be produced" in lines[0]
    saved = json.loads((tmp_path / "out" / "result.json").read_text())
    assert saved["health"]["healthy"] is False and saved["health"]["unproduced"]["force_share"] > 0.95


def test_the_bundled_six_axis_hold_stays_healthy():
    """The BlueROV2 Heavy + Alpha 5 holding six axes while the arm reaches: on station within a millimetre,
    every commanded wrench produced."""
    from uvms.sim.scenario import load_scenario, run_scenario

    h = run_scenario(load_scenario("bluerov2_heavy_alpha5_hold6")).health()
    assert h.healthy and h.warning == ""
    assert h.station_departure < 1e-3 and h.unproduced_share_force < 1e-9 and h.unproduced_share_moment < 1e-9


def test_a_command_of_rounding_size_is_not_unproduced_many_times_over():
    """A vehicle resting at its set point commands a moment of rounding size (3e-17 N m) that the allocation's
    projection leaves unproduced at the same size (4e-16 N m): none of it counts (``UNPRODUCED_FLOOR``), where
    the bare ratio said 1300 % and made every such station-keeping run unhealthy. A real shortfall still counts."""
    from uvms.sim.health import UNPRODUCED_FLOOR, unproduced_share

    weights = np.full(4, 0.01)
    commanded = np.array([[3e-17, -1e-17, 2e-17]] * 4)
    rounding = np.array([[4e-16, 0.0, -1e-16]] * 4)
    assert np.sum(np.linalg.norm(rounding, axis=1)) / np.sum(np.linalg.norm(commanded, axis=1)) > 10.0
    assert unproduced_share(commanded, rounding, weights) == 0.0
    real = np.array([[0.0, 0.0, 2.0]] * 4)
    assert unproduced_share(np.array([[0.0, 0.0, 4.0]] * 4), real, weights) == pytest.approx(0.5, rel=1e-15)
    just_above = np.array([[0.0, 0.0, 2.0 * UNPRODUCED_FLOOR]] * 4)
    assert unproduced_share(np.array([[0.0, 0.0, 4.0 * UNPRODUCED_FLOOR]] * 4), just_above, weights) == \
        pytest.approx(0.5, rel=1e-12)
