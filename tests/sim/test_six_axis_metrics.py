"""Six-axis metrics of ``uvms.sim.metrics`` (issue 16): world-frame horizontal error, depth error, roll and pitch
errors from level, checked by hand on constructed results and against SciPy's Euler angles on a tumbling run."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import uvms
from uvms.sim.metrics import NAMED, check_metric, compute_metrics
from uvms.sim.run import simulate
from uvms.state import State

from tests.sim.test_metrics import constructed

SIX = ("peak_world_error_xy_m", "peak_depth_error_m", "peak_roll_error_rad", "peak_pitch_error_rad")


def test_six_axis_metrics_by_hand():
    """World xy: |(3, 4)| = 5 whatever the yaw (the body-frame error would rotate it); depth: |z - z0| peaks at
    0.5 (z down); roll and pitch from level, not from the start: roll starts at 0.1 and peaks at |-0.3|,
    pitch at |-0.4|."""
    position = [[1.0, 1.0, 2.0], [4.0, 5.0, 2.2], [1.0, 2.0, 1.5]]
    euler = [[0.1, 0.05, 0.7], [-0.3, 0.2, 2.0], [0.2, -0.4, -1.0]]
    m = compute_metrics(constructed(position, euler), SIX + ("peak_abs_z_m", "peak_abs_roll_rad"))
    assert m["peak_world_error_xy_m"] == pytest.approx(5.0, rel=1e-15)
    assert m["peak_depth_error_m"] == pytest.approx(0.5, rel=1e-15) == m["peak_abs_z_m"]
    assert m["peak_roll_error_rad"] == pytest.approx(0.3, rel=1e-12)
    assert m["peak_abs_roll_rad"] == pytest.approx(0.4, rel=1e-12)         # from the start: another number
    assert m["peak_pitch_error_rad"] == pytest.approx(0.4, rel=1e-12)
    for name in SIX:
        assert name in NAMED
        check_metric(name)


def test_six_axis_metrics_against_scipy_on_a_tumbling_run():
    """A vehicle-only run spun about all three axes and drifting: the metrics equal the same maxima computed
    from the recorded positions and SciPy's ZYX Euler angles of the recorded quaternions."""
    vehicle = uvms.load_model("paper").vehicle_only()
    start = State.from_euler(vehicle, position=[0.2, -0.1, 0.3], euler=[0.1, -0.2, 0.4],
                             nu=[0.8, -0.6, 0.5, 0.3, -0.2, 0.15])
    result = simulate(vehicle, start, duration=3.0, step=1e-3, body_wrench=[2.0, -1.0, 1.5, 5.0, 3.0, -4.0],
                      record_period=0.01)
    assert result.complete
    p = result.states[:, 0:3]
    wxyz = result.states[:, 3:7]
    yaw_pitch_roll = Rotation.from_quat(wxyz[:, [1, 2, 3, 0]]).as_euler("ZYX")
    expected = {"peak_world_error_xy_m": np.hypot(p[:, 0] - p[0, 0], p[:, 1] - p[0, 1]).max(),
                "peak_depth_error_m": np.abs(p[:, 2] - p[0, 2]).max(),
                "peak_roll_error_rad": np.abs(yaw_pitch_roll[:, 2]).max(),
                "peak_pitch_error_rad": np.abs(yaw_pitch_roll[:, 1]).max()}
    assert expected["peak_roll_error_rad"] > 0.3 and expected["peak_world_error_xy_m"] > 0.1   # it does move
    m = compute_metrics(result, SIX)
    for name, value in expected.items():
        assert m[name] == pytest.approx(value, rel=1e-12, abs=1e-14), name
    assert math.isfinite(m["peak_depth_error_m"])
