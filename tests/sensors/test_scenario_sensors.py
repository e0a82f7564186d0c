"""A ``sensors:`` section in a scenario file: run, saved and read back; bad entries are one line, exit 2."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import uvms
from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sim.scenario import load_scenario, run_scenario

SENSORS = {
    "imu": {"kind": "imu", "rate": 100, "mount": {"offset": [0.1, 0.0, -0.05], "rpy": [0.0, 0.0, 0.1]},
            "gyro": {"white": 1.0e-4, "bias_instability": 4.0e-5}, "accel": {"white": 1.0e-3}, "seed": 3},
    "depth": {"kind": "pressure", "rate": 20, "noise": 20.0, "resolution": 10.0},
    "dvl": {"kind": "dvl", "rate": 5, "water_depth": 30.0, "max_altitude": 40.0, "dropout": 0.1, "noise": 0.003},
    "arm": {"kind": "encoders", "rate": 50, "counts_per_turn": 4096},
}


def _scenario(tmp_path, sensors=SENSORS, **extra):
    data = {"model": "paper", "duration": 0.2, "step": 0.001, "initial_state": {"position": [0, 0, 4.0]},
            "outputs": {"record_period": 0.01}, "sensors": sensors, **extra}
    path = tmp_path / "sensed.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


def test_a_scenarios_sensors_are_run_saved_and_read_back(tmp_path):
    """Each sensor at its own rate with the file's parameters; the pressure uses the model's density; the saved
    tables (``result.<sensor>.csv``) read back to the same numbers (17 digits)."""
    scenario = load_scenario(_scenario(tmp_path))
    result = run_scenario(scenario)
    assert list(result.sensors) == ["imu", "depth", "dvl", "arm"]
    assert [len(result.sensors[k].time) for k in result.sensors] == [21, 5, 2, 11]
    depth = result.sensors["depth"]
    model = scenario.model
    expected = 101_325.0 + model.density * np.linalg.norm(model.gravity) * result.position[::5, 2]
    assert np.all(np.abs(depth["pressure"] - expected) < 5 * 20.0 + 5.0)
    assert set(result.sensors["arm"].columns) == set(model.joint_names)
    out = tmp_path / "out"
    assert main(["run", str(_scenario(tmp_path)), "-o", str(out)]) == 0
    back = uvms.Result.load(out)
    for name, record in result.sensors.items():
        assert (out / f"result.{name}.csv").is_file()
        np.testing.assert_array_equal(back.sensors[name].time, record.time)
        for column, values in record.columns.items():
            np.testing.assert_array_equal(back.sensors[name][column], values)
    assert back.sensors["dvl"].kind == "dvl"


def test_uvms_run_names_every_file_it_saved(tmp_path, capsys):
    """The closing line lists the sensor tables too, in the section's order, and each file it names exists."""
    out = tmp_path / "out"
    assert main(["run", str(_scenario(tmp_path)), "-o", str(out)]) == 0
    line = [s for s in capsys.readouterr().out.splitlines() if "results saved to" in s]
    assert len(line) == 1
    names = ["result.csv", "result.json", "result.imu.csv", "result.depth.csv", "result.dvl.csv", "result.arm.csv",
             "scenario.yaml"]
    assert line[0].endswith(f"({', '.join(names)})"), line[0]
    assert sorted(p.name for p in out.iterdir() if not p.name.startswith(".")) == sorted(names)


@pytest.mark.parametrize("sensors, field", [
    ({"imu": {"kind": "imu", "rate": -5}}, "sensors.imu.rate"),
    ({"imu": {"kind": "gps", "rate": 5}}, "sensors.imu.kind"),
    ({"imu": {"kind": "imu", "rate": 5, "mount": {"body": "link9"}}}, "sensors.imu.mount.body"),
    ({"imu": {"kind": "imu", "rate": 5, "mount": {"body": "link1"}}}, "sensors.imu.mount.body"),
    ({"arm": {"kind": "encoders", "rate": 5, "joints": ["elbow9"]}}, "sensors.arm.joints[0]"),
    ({"dvl": {"kind": "dvl", "rate": 8}}, "sensors.dvl.rate"),
    ({"dvl": {"kind": "dvl", "rate": 5, "dropout": 1.5}}, "sensors.dvl.dropout"),
    ({"imu": {"kind": "imu", "rate": 5, "gyro": {"white": -1}}}, "sensors.imu.gyro.white"),
    ({"imu": {"kind": "imu", "rate": 5, "colour": "red"}}, "sensors.imu"),
])
def test_bad_sensor_entries_are_one_line_and_exit_2(tmp_path, sensors, field):
    path = _scenario(tmp_path, sensors)
    with pytest.raises(UvmsInputError) as info:
        load_scenario(path)
    text = str(info.value)
    assert "\n" not in text and str(path) in text and field in text, text
    assert main(["run", str(path), "-o", str(tmp_path / "o")]) == 2
