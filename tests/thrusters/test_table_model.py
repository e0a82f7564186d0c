"""Datasheet (table) thrusters in model files and in the simulation loop: ``model: table`` with the bundled T200,
a CSV beside the model file, or an inline table; bad tables are one line naming the file and the field."""

from __future__ import annotations

import numpy as np
import pytest
import yaml

import uvms
from uvms.cli import main
from uvms.errors import UvmsInputError
from uvms.sim.run import Actuation, simulate
from uvms.thrusters.table import STANDARD_GRAVITY, table_thrust
from tests.helpers import assert_model_file_refused

from ..sim.test_actuation import ConstantWrench


def write_model(tmp_path, thrusters, name="table.yaml"):
    data = {
        "name": "table-test",
        "vehicle": {
            "mass": 11.5, "com": [0.0, 0.0, 0.0],
            "inertia": {"diagonal": [0.16, 0.16, 0.16], "about": "com"},
            "buoyancy": {"mass": 11.5, "center": [0.0, 0.0, -0.01]},
            "added_mass": {"diagonal": [0.12, 0.12, 0.12, 5.5, 12.7, 14.57], "about": "origin"},
            "drag": {"area": [0.0, 0.0, 0.0], "coefficient": [0.0, 0.0, 0.0],
                     "rotational": {"side": 0.0, "coefficient": 0.0}},
            "damping": {"coefficients": {"X_u": -4.03, "X_u|u|": -18.18}},
            "box": [0.46, 0.58, 0.25],
        },
        "thrusters": thrusters,
    }
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def thruster(**extra):
    return {"name": "t1", "position": [0.0, 0.0, 0.0], "direction": [1.0, 0.0, 0.0], "model": "table", **extra}


def test_bundled_t200_in_a_model(tmp_path):
    model = uvms.load_model(write_model(tmp_path, [thruster(table="t200", parameters={"time_constant": 0.05})]))
    t = model.thrusters[0]
    assert t.model == "table" and t.parameters.time_constant == 0.05
    # datasheet end points (Blue Robotics T200 public performance data, sheet "16 V"): 1900 us 5.24503549 kgf
    # forward, 1100 us -4.06947623 kgf reverse
    forward, reverse = 5.24503549333333 * STANDARD_GRAVITY, -4.06947622666667 * STANDARD_GRAVITY
    assert t.max_thrust == pytest.approx(forward, rel=1e-12)
    assert t.min_thrust == pytest.approx(reverse, rel=1e-12)
    lower, upper = uvms.thrusters.thrust_limits(model.thrusters)
    assert lower[0] == pytest.approx(reverse, rel=1e-12) and upper[0] == pytest.approx(forward, rel=1e-12)


def test_csv_beside_the_model_and_inline_table_agree(tmp_path):
    (tmp_path / "thr.csv").write_text("# my thruster\ncommand_us,thrust_N\n1100,-10\n1500,0\n1900,20\n",
                                      encoding="utf-8")
    a = uvms.load_model(write_model(tmp_path, [thruster(table="thr.csv")], "a.yaml")).thrusters[0].parameters
    b = uvms.load_model(write_model(tmp_path, [thruster(table={"command": [1100, 1500, 1900],
                                                               "thrust_N": [-10.0, 0.0, 20.0]})],
                                    "b.yaml")).thrusters[0].parameters
    np.testing.assert_array_equal(a.command, b.command)
    np.testing.assert_array_equal(a.thrust, b.thrust)
    assert a.time_constant == 0.1                     # the documented default


def test_table_thruster_in_the_loop_delivers_the_wanted_thrust_with_its_lag(tmp_path):
    """A constant 20 N surge request: the allocator commands the pulse width whose table thrust is 20 N, and
    the thrust follows T(t) = 20 (1 - exp(-t / tau)) (exact first-order response, RK4 at 1 ms)."""
    tau = 0.05
    model = uvms.load_model(write_model(tmp_path, [thruster(table="t200", parameters={"time_constant": tau})]))
    act = Actuation.named("model", model)
    r = simulate(model, duration=0.5, step=1e-3, fixed_base=True, controller=ConstantWrench([0, 0, 0, 20.0, 0, 0]),
                 actuation=act, record_period=0.01)
    assert r.complete
    p = model.thrusters[0].parameters.as_array()
    # the held command (a pulse width in us) gives 20 N through the table
    assert r.signals["thrust_cmd_t1"][-1] == pytest.approx(20.0)
    T = r.actuator[:, 0]
    expected = 20.0 * (1.0 - np.exp(-r.time / tau))
    np.testing.assert_allclose(T, expected, atol=1e-6)
    assert table_thrust(p, 1500.0) == 0.0


@pytest.mark.parametrize("entry,field", [
    (thruster(table={"command": [1100.0], "thrust_N": [1.0]}), "thrusters[0].table.command"),
    (thruster(table={"command": [1100.0, 1500.0, 1900.0], "thrust_N": [0.0, 5.0, 4.0]}),
     "thrusters[0].table.thrust_N"),
    (thruster(table="missing.csv"), "thrusters[0].table"),
    (thruster(table="t200", parameters={"time_constant": -1.0}), "thrusters[0].parameters.time_constant"),
    (thruster(), "thrusters[0]"),
])
def test_bad_table_is_one_line(tmp_path, capsys, entry, field):
    path = write_model(tmp_path, [entry])
    assert_model_file_refused(path, field)


def test_csv_that_does_not_parse_names_the_csv_and_line(tmp_path):
    (tmp_path / "bad.csv").write_text("command,thrust_N\n1100,-10\n1500,oops\n", encoding="utf-8")
    path = write_model(tmp_path, [thruster(table="bad.csv")])
    with pytest.raises(UvmsInputError) as info:
        uvms.load_model(path)
    text = str(info.value)
    assert "\n" not in text and "bad.csv" in text and "line 3" in text, text
    assert main(["validate", str(path)]) == 2
