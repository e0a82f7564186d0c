"""The one metrics module (``uvms.sim.metrics``) and ``Result.axis_errors``: values checked against hand
computation on constructed results and against the compiled per-state axis kinematics of the controllers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uvms.rotations import quaternion_from_euler
from uvms.sim.metrics import NAMED, check_metric, compute_metrics, sign_changes
from uvms.sim.result import Result


def constructed(position, euler, nu=None, signals=None, time=None, metadata=None) -> Result:
    """A vehicle-only Result (no joints) with the given poses, written out state by state."""
    position = np.asarray(position, dtype=float)
    K = len(position)
    nu = np.zeros((K, 6)) if nu is None else np.asarray(nu, dtype=float)
    quaternion = np.array([quaternion_from_euler(np.asarray(e, dtype=float)) for e in euler])
    return Result(time=np.arange(K, dtype=float) if time is None else np.asarray(time, dtype=float),
                  states=np.hstack([position, quaternion, nu]), n_joints=0, end_effector=np.zeros((K, 3)),
                  joint_torques=np.zeros((K, 0)), signals=signals or {}, metadata=metadata or {})


def test_named_metrics_by_hand():
    """Yaw 90 deg: a world displacement (1, 0, 0) is (0, -1, 0) in body axes; yaw 0 -> 1.5 -> 3.0 -> 3.5 rad:
    the unwrapped change peaks at 3.5, the wrapped error at 3.0 (3.5 wraps to 3.5 - 2 pi)."""
    position = [[0, 0, 0], [1, 0, 0], [1, 2, -0.5], [0, 0, 0]]
    euler = [[0, 0, 0], [0, 0, 1.5], [0.2, -0.1, 3.0], [0, 0, 3.5]]
    r = constructed(position, euler)
    m = compute_metrics(r, NAMED)
    assert m["peak_abs_x_m"] == 1.0 and m["peak_abs_y_m"] == 2.0 and m["peak_abs_z_m"] == 0.5
    assert m["peak_displacement_m"] == pytest.approx(math.sqrt(1 + 4 + 0.25), rel=1e-15)
    assert m["peak_abs_yaw_rad"] == pytest.approx(3.5, rel=1e-12)
    assert m["peak_yaw_error_rad"] == pytest.approx(3.0, rel=1e-12)
    assert m["peak_abs_roll_rad"] == pytest.approx(0.2, rel=1e-12)
    assert m["peak_abs_pitch_rad"] == pytest.approx(0.1, rel=1e-12)
    # sample 1: R = Rz(1.5), e = R^T (1, 0, 0) = (cos 1.5, -sin 1.5, 0): |e_xy| = 1; sample 2: |e| = sqrt(5.25)
    # with a 0.5 m z part, so |e_xy| = sqrt(5.25 - (R^T d)_z^2)
    R = np.array([[math.cos(3.0), -math.sin(3.0), 0], [math.sin(3.0), math.cos(3.0), 0], [0, 0, 1]]) @ \
        np.array([[math.cos(-0.1), 0, math.sin(-0.1)], [0, 1, 0], [-math.sin(-0.1), 0, math.cos(-0.1)]]) @ \
        np.array([[1, 0, 0], [0, math.cos(0.2), -math.sin(0.2)], [0, math.sin(0.2), math.cos(0.2)]])
    e2 = R.T @ np.array([1, 2, -0.5])
    xy = [0.0, 1.0, math.hypot(e2[0], e2[1]), 0.0]
    assert m["peak_body_error_xy_m"] == pytest.approx(max(xy), rel=1e-12)
    assert m["final_body_error_xy_m"] == pytest.approx(0.0, abs=1e-15)
    assert m["rms_body_error_xy_m"] == pytest.approx(math.sqrt(sum(v * v for v in xy) / 4), rel=1e-12)
    assert m["simulated_time_s"] == 3.0
    assert m["healthy"] == 1.0 and m["max_saturated_fraction"] == 0.0           # no thrusters: nothing saturates


def test_statistics_of_series_and_missing_series():
    command = np.array([np.nan, 1.0, 3.0, 2.0, 4.0, -1.0])
    r = constructed(np.zeros((6, 3)), np.zeros((6, 3)), signals={"command_X": command})
    m = compute_metrics(r, ["max_abs_command_X", "rms_command_X", "mean_command_X", "final_command_X",
                            "sign_changes_command_X", "rms_command_Y", "max_abs_roll_rad"])
    assert m["max_abs_command_X"] == 4.0 and m["final_command_X"] == -1.0 and m["mean_command_X"] == 1.8
    assert m["rms_command_X"] == pytest.approx(math.sqrt((1 + 9 + 4 + 16 + 1) / 5), rel=1e-15)
    assert m["sign_changes_command_X"] == 3.0                   # increments +2, -1, +2, -5: three sign changes
    assert math.isnan(m["rms_command_Y"]) and m["max_abs_roll_rad"] == 0.0
    assert sign_changes(command) == 3
    check_metric("sign_changes_thrust_cmd_sway")
    with pytest.raises(ValueError, match="unknown metric 'peak_error'"):
        check_metric("peak_error")


@pytest.fixture(scope="module")
def tumbling_run():
    """A short released paper run from a tilted, spinning, moving start (every axis excited)."""
    import uvms
    from uvms.sim.run import simulate
    from uvms.state import State

    model = uvms.load_model("paper")
    start = State.from_euler(model, position=[0.1, -0.2, 0.3], euler=[0.4, -0.3, 2.9],
                             nu=[0.3, -0.5, 0.8, 0.2, -0.1, 0.05], q=[0.1, 0.2, -0.3])
    return simulate(model, start, duration=0.5, step=1e-3, joint_torques=np.array([0.5, -0.2, 0.1]))


def test_axis_errors_equal_the_compiled_per_state_kinematics(tumbling_run):
    """``Result.axis_errors`` (vectorised over the samples) against the controllers' compiled
    ``axis_kinematics_into`` called state by state, for a held pose that is not the initial one."""
    from uvms.control import sliding_kernels as kernels

    r = tumbling_run
    p_d, psi_d = np.array([0.05, 0.1, 0.2]), -3.0
    axes = r.axis_errors(p_d, psi_d)
    R, table = kernels.kinematics_buffers()
    for k in range(0, len(r.time), 7):
        st = r.state(k)
        kernels.axis_kinematics_into(st.quaternion, st.position, st.nu, p_d, psi_d, R, table)
        np.testing.assert_allclose(axes.error[k], table[kernels.ERROR], rtol=0, atol=1e-12)
        np.testing.assert_allclose(axes.error_rate[k], table[kernels.ERROR_RATE], rtol=0, atol=1e-12)
        np.testing.assert_allclose(axes.velocity[k], table[kernels.VELOCITY], rtol=0, atol=1e-15)
    default = r.axis_errors()
    assert np.all(default.error[0] == 0.0)


def test_compare_metrics_come_from_the_metrics_module(tumbling_run):
    """``uvms compare``'s row and the reproduction's case metrics are the metrics module's numbers."""
    from uvms.control.compare import PAPER_BANDWIDTH, axis_series, metrics
    from uvms.control.smc import SlidingModeParameters

    r = tumbling_run
    assert (PAPER_BANDWIDTH,) * 3 == SlidingModeParameters().bandwidth      # one value on the paper axes
    m = metrics(r)
    named = compute_metrics(r, ["peak_body_error_xy_m", "peak_yaw_error_rad", "max_abs_surface_sway"])
    assert m["peak_xy_error_mm"] == named["peak_body_error_xy_m"] * 1e3
    assert m["peak_yaw_error_deg"] == math.degrees(named["peak_yaw_error_rad"])
    axes = r.axis_errors()
    s = axes.velocity + PAPER_BANDWIDTH * axes.error
    assert m["max_abs_s_sway"] == named["max_abs_surface_sway"] == np.abs(s[:, 1]).max()
    assert np.array_equal(axis_series(r)["s"], s)
    assert m["rms_command_X_N"] == 0.0 and m["chatter_X"] == 0      # no controller: no command, counted 0
