"""The bundled BlueROV2 Heavy + Reach Alpha 5 model and its station-keeping + reach scenario."""

from __future__ import annotations

import numpy as np
import pytest

import uvms
from uvms.cli import main
from uvms.model.load import bundled_models
from uvms.sim.scenario import bundled_scenarios, load_scenario, run_scenario
from uvms.thrusters.layouts import layout_matrix


@pytest.fixture(scope="module")
def model():
    return uvms.load_model("bluerov2_heavy_alpha5")


def test_bundled_and_valid(capsys):
    assert "bluerov2_heavy_alpha5" in bundled_models()
    assert "bluerov2_heavy_alpha5_reach" in bundled_scenarios()
    assert main(["validate", "bluerov2_heavy_alpha5"]) == 0
    assert "valid" in capsys.readouterr().out


def test_model_numbers_follow_the_sources(model):
    # docs/vehicle_sources.md: [VB] 13.5 kg vehicle, [RDML-A] arm 1.412 kg in total
    assert model.mass.sum() == pytest.approx(13.5 + 1.412, rel=1e-12)
    assert model.joint_names == ("axis_e", "axis_d", "axis_c", "axis_b")
    # [VB] damping enters as Fossen's form on the vehicle: X_u 13.7, X_u|u| 141 (magnitudes)
    assert model.damping_linear[0][3, 3] == 13.7 and model.damping_quadratic[0][3, 3] == 141.0
    assert model.damping_quadratic[0][5, 5] == 190.0
    # eight T200 table thrusters; the vectored Heavy layout reaches all six axes
    assert len(model.thrusters) == 8 and all(t.model == "table" for t in model.thrusters)
    assert np.linalg.matrix_rank(layout_matrix(model.thrusters)) == 6
    # every arm link has its collision cylinder as a shape (from_collision)
    assert list(model.shape_count) == [1, 1, 1, 1, 1]
    # trimmed neutral (the stated trim-foam assumption)
    assert model.buoyancy_mass.sum() == pytest.approx(model.mass.sum(), abs=1e-3)


def test_station_keeping_while_the_arm_reaches():
    scenario = load_scenario("bluerov2_heavy_alpha5_reach")
    result = run_scenario(scenario)
    assert result.complete
    t = result.time
    q = result.q
    # the arm reached the far knot (t = 5 s and 7 s) and came back
    for time, want in ((5.0, [0.05, 2.0, 2.6, 0.05]), (7.0, [0.05, 2.0, 2.6, 0.05]), (14.0, [0.05, 0.4, 0.4, 0.05])):
        k = int(np.argmin(np.abs(t - time)))
        np.testing.assert_allclose(q[k], want, atol=0.02)
    # the vehicle held its horizontal position and heading (PID on surge, sway and yaw)
    xy = result.position[:, :2]
    assert np.max(np.abs(xy)) < 0.01
    assert np.max(np.abs(result.euler[:, 2])) < 0.01
