"""Replay scores: RMSE of roll, pitch, yaw change and depth change, and the no-skill scores, of sequences whose
values are worked out by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from uvms.errors import UvmsInputError
from uvms.logs import Log, Series, scores
from uvms.logs.score import wrap

from .files import POSE_HEADER, POSE_XYZW, pose_rows, write_csv

DEG = 180.0 / math.pi


def _series(roll=(0, 0, 0), pitch=(0, 0, 0), yaw=(0, 0, 0), depth=(0, 0, 0)):
    return Series(*(np.array(v, dtype=float) for v in (roll, pitch, yaw, depth)))


def test_wrap_maps_into_minus_pi_to_pi():
    assert wrap([3 * math.pi / 2, -3 * math.pi / 2, math.pi, 0.25]) == pytest.approx(
        [-math.pi / 2, math.pi / 2, -math.pi, 0.25], abs=1e-15)


def test_rmse_and_no_skill_of_known_sequences():
    """Roll errors (0, 0, 0.3): rms sqrt(0.09 / 3); pitch log (0.1, 0.2, 0.4) held at 0.1: rms of (0, 0.1, 0.3)
    = sqrt(0.1 / 3); depth log (5, 5.5, 6), sim (2, 2.5, 2.5): change errors (0, 0, -0.5), rms sqrt(0.25 / 3)."""
    log = _series(roll=(0, 0.1, 0.2), pitch=(0.1, 0.2, 0.4), depth=(5, 5.5, 6))
    sim = _series(roll=(0, 0.1, 0.5), pitch=(0.1, 0.2, 0.4), depth=(2, 2.5, 2.5))
    result = scores(log, sim)
    assert result.samples == 3
    assert result.roll_rmse_deg == pytest.approx(math.sqrt(0.09 / 3) * DEG, rel=1e-14)
    assert result.pitch_rmse_deg == 0.0
    assert result.depth_change_rmse_m == pytest.approx(math.sqrt(0.25 / 3), rel=1e-14)
    assert result.roll_no_skill_rmse_deg == pytest.approx(math.sqrt((0.01 + 0.04) / 3) * DEG, rel=1e-14)
    assert result.pitch_no_skill_rmse_deg == pytest.approx(math.sqrt((0.01 + 0.09) / 3) * DEG, rel=1e-14)
    assert result.depth_change_no_skill_rmse_m == pytest.approx(math.sqrt((0.25 + 1.0) / 3), rel=1e-14)


def test_yaw_change_wraps_through_plus_minus_pi():
    """The log turns from 179 deg to -179 deg (a change of +2 deg); a simulation from 0 to 2 deg has no error,
    one from 0 to 0 has 2 deg at one of two samples: rms sqrt(4 / 2) deg."""
    log = _series(roll=(0, 0), pitch=(0, 0), yaw=np.radians([179, -179]), depth=(0, 0))
    turned = scores(log, _series(roll=(0, 0), pitch=(0, 0), yaw=np.radians([0, 2]), depth=(0, 0)))
    held = scores(log, _series(roll=(0, 0), pitch=(0, 0), yaw=(0, 0), depth=(0, 0)))
    assert turned.yaw_change_rmse_deg == pytest.approx(0.0, abs=1e-12)
    assert held.yaw_change_rmse_deg == pytest.approx(math.sqrt(2.0), rel=1e-12)
    assert held.yaw_change_no_skill_rmse_deg == pytest.approx(math.sqrt(2.0), rel=1e-12)
    wrapped_roll = scores(_series(roll=np.radians([179, 179]), pitch=(0, 0), yaw=(0, 0), depth=(0, 0)),
                          _series(roll=np.radians([-179, -179]), pitch=(0, 0), yaw=(0, 0), depth=(0, 0)))
    assert wrapped_roll.roll_rmse_deg == pytest.approx(2.0, rel=1e-12)


def test_to_dict_names_carry_units():
    result = scores(_series(), _series())
    assert list(result.to_dict()) == [
        "samples", "roll_rmse_deg", "pitch_rmse_deg", "yaw_change_rmse_deg", "depth_change_rmse_m",
        "roll_no_skill_rmse_deg", "pitch_no_skill_rmse_deg", "yaw_change_no_skill_rmse_deg",
        "depth_change_no_skill_rmse_m"]


def test_a_simulation_scored_against_a_log_in_another_frame(tmp_path):
    """A log in enu yawing 0 -> 30 -> 60 deg and rising 0 -> 1 -> 2 m (depth 0, -1, -2); the same motion
    simulated in ned is yaw 0, -30, -60 deg and depth 0, -1, -2: no error; the no-skill scores are
    rms(0, 30, 60) deg = sqrt(1500) deg and rms(0, 1, 2) m = sqrt(5 / 3) m."""
    c, s = math.cos(math.radians(15)), math.sin(math.radians(15))
    write_csv(tmp_path / "pose.csv", POSE_HEADER, pose_rows(
        [0, 1, 2], [[0, 0, 0], [0, 0, 1], [0, 0, 2]], [[0, 0, 0, 1], [0, 0, s, c], [0, 0, 0.5, math.sqrt(3) / 2]]))
    log = Log.from_dict({"frame": "enu", "pose": {"file": "pose.csv", **POSE_XYZW}}, base_dir=tmp_path)
    result = log.score([0, 1, 2], roll=[0, 0, 0], pitch=[0, 0, 0], yaw=np.radians([0, -30, -60]),
                       depth=[0, -1, -2], frame="ned")
    assert result.yaw_change_rmse_deg == pytest.approx(0.0, abs=1e-12)
    assert result.depth_change_rmse_m == pytest.approx(0.0, abs=1e-15)
    assert result.yaw_change_no_skill_rmse_deg == pytest.approx(math.sqrt(1500.0), rel=1e-12)
    assert result.depth_change_no_skill_rmse_m == pytest.approx(math.sqrt(5 / 3), rel=1e-14)
    same_frame = log.score([0, 1, 2], roll=[0, 0, 0], pitch=[0, 0, 0], yaw=np.radians([0, -30, -60]),
                           depth=[0, -1, -2])              # read as enu: the yaw goes the wrong way
    assert same_frame.yaw_change_rmse_deg == pytest.approx(math.sqrt((60 ** 2 + 120 ** 2) / 3), rel=1e-12)
    with pytest.raises(UvmsInputError, match=r"^yaw: expected 3 finite values \(one per time\), found shape \(2,\)"):
        log.score([0, 1, 2], roll=[0, 0, 0], pitch=[0, 0, 0], yaw=[0, 0], depth=[0, 0, 0])
    with pytest.raises(UvmsInputError, match=r"^times: expected times within the replay's \[0, 2\] s"):
        log.score([0, 3], roll=[0, 0], pitch=[0, 0], yaw=[0, 0], depth=[0, 0])
