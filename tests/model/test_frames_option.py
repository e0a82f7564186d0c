"""The model file's ``frame:`` key: default gravity per frame, gravity pointing up refused, ``uvms validate``
and ``uvms trim`` of a z-up model give the z-down answers mapped by the half turn (checked against the closed
form of the rest attitude, not our own output) and say z up, and the 3-D scene of a z-up model has +z up."""

import math

import numpy as np
import pytest
import yaml

import uvms
from uvms.analysis.report import model_report
from uvms.analysis.trim import trim
from uvms.errors import UvmsInputError
from uvms.model.load import resolve_model_path
from uvms.view.scene import scene_from_model


def paper_spec():
    return yaml.safe_load(resolve_model_path("paper").read_text())


def write(tmp_path, spec, name="m.yaml"):
    path = tmp_path / name
    path.write_text(yaml.safe_dump(spec, sort_keys=False))
    return path


def test_default_gravity_points_down_in_the_frame(tmp_path):
    spec = paper_spec()
    del spec["environment"]["gravity"]
    assert np.array_equal(uvms.load_model(write(tmp_path, spec)).gravity, [0.0, 0.0, 9.81])
    spec["frame"] = "enu"
    model = uvms.load_model(write(tmp_path, spec, "enu.yaml"))
    assert model.convention == "enu" and np.array_equal(model.gravity, [0.0, 0.0, -9.81])


@pytest.mark.parametrize("frame, gravity", [("enu", [0.0, 0.0, 9.81]), ("ned", [0.0, 0.0, -9.81]),
                                            ("ned", [9.81, 0.0, 0.0])])
def test_gravity_pointing_up_or_sideways_in_the_frame_is_refused(tmp_path, frame, gravity):
    spec = paper_spec()
    spec["frame"], spec["environment"]["gravity"] = frame, gravity
    with pytest.raises(UvmsInputError) as err:
        uvms.load_model(write(tmp_path, spec))
    text = str(err.value)
    assert "environment.gravity" in text and f"frame {frame}" in text and "\n" not in text


def test_unknown_frame_is_refused(tmp_path):
    spec = paper_spec()
    spec["frame"] = "nwu"
    with pytest.raises(UvmsInputError, match="frame"):
        uvms.load_model(write(tmp_path, spec))


def tilted(frame):
    """The paper's vehicle with its centre of buoyancy moved off the vertical (so it rests tilted), written in
    ``frame``: r_G - r_B = d = (0.01, -0.02, 0.05) in ned, (0.01, 0.02, -0.05) in enu."""
    spec = paper_spec()
    del spec["arm"]
    spec["vehicle"]["buoyancy"]["center"] = [-0.01, 0.02, -0.05]
    if frame == "enu":
        spec["frame"] = "enu"
        spec["environment"]["gravity"] = [0.0, 0.0, -9.81]
        spec["vehicle"]["buoyancy"]["center"] = [-0.01, -0.02, 0.05]
        for t in spec["thrusters"]:
            t["position"] = [t["position"][0], -t["position"][1], -t["position"][2]]
            t["direction"] = [t["direction"][0], -t["direction"][1], -t["direction"][2]]
    return spec


def test_trim_and_validate_of_a_z_up_model_are_the_z_down_answers_turned(tmp_path):
    ned = uvms.load_model(write(tmp_path, tilted("ned"), "ned.yaml"))
    enu = uvms.load_model(write(tmp_path, tilted("enu"), "enu.yaml"))
    d = np.array([0.01, -0.02, 0.05])                   # r_G - r_B in ned: the closed form (conventions "Trim")
    roll, pitch = math.atan2(d[1], d[2]), math.atan2(-d[0], math.hypot(d[1], d[2]))
    a, b = trim(ned), trim(enu)
    assert a.roll_rad == pytest.approx(roll, abs=1e-15) and a.pitch_rad == pytest.approx(pitch, abs=1e-15)
    assert b.roll_rad == pytest.approx(roll, abs=1e-15) and b.pitch_rad == pytest.approx(-pitch, abs=1e-15)
    # the levelling ballast: the same point of the vehicle, written in each frame
    np.testing.assert_allclose(b.ballast.position_m, np.diag([1, -1, -1]) @ a.ballast.position_m, atol=1e-12)
    assert b.ballast.amount == pytest.approx(a.ballast.amount, rel=1e-9)
    assert a.ballast.righting_arm_after_m > 0
    assert b.ballast.righting_arm_after_m == pytest.approx(a.ballast.righting_arm_after_m, rel=1e-9)
    assert "z up" in b.table() and "z down" not in b.table() and "z down" in a.table()
    ra, rb = model_report(ned), model_report(enu)
    assert rb.trim_roll_rad == pytest.approx(ra.trim_roll_rad) and rb.trim_pitch_rad == pytest.approx(
        -ra.trim_pitch_rad)
    np.testing.assert_allclose(rb.center_of_buoyancy_m, [-0.01, -0.02, 0.05], atol=1e-15)
    np.testing.assert_allclose(rb.static_moment_Nm, np.diag([1, -1, -1]) @ ra.static_moment_Nm, atol=1e-12)
    # thrust per axis: the same magnitudes, + and - exchanged on the axes whose sign flips (sway, heave, pitch, yaw)
    flips = np.array([False, True, True, False, True, True])
    fwd_b = np.where(flips, rb.thrust_reverse_N, rb.thrust_forward_N)
    np.testing.assert_allclose(fwd_b, ra.thrust_forward_N, rtol=1e-9)
    assert "z up" in rb.table() and "z down" not in rb.table()
    assert rb.to_dict()["frame"] == "enu"


def test_validate_command_says_z_up(tmp_path, capsys):
    from uvms.cli import main

    path = write(tmp_path, tilted("enu"), "enu.yaml")
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    assert "z up" in out and "z down" not in out and "frame:                enu" in out


def test_the_scene_of_a_z_up_model_has_plus_z_up(tmp_path):
    from uvms.view.plotly_html import scene_layout

    enu = uvms.load_model(write(tmp_path, tilted("enu"), "enu.yaml"))
    scene = scene_from_model(enu)
    assert scene.frame == "enu" and np.array_equal(scene.up, [0.0, 0.0, 1.0])
    layout = scene_layout(np.array([[-1.0, 1.0]] * 3), "t", scene)["scene"]
    assert layout["zaxis"]["range"] == [-1.0, 1.0] and layout["yaxis"]["range"] == [-1.0, 1.0]   # none reversed
    assert layout["zaxis"]["title"]["text"] == "z up [m]"
    ned = scene_from_model(uvms.load_model("paper"))
    assert np.array_equal(ned.up, [0.0, 0.0, -1.0])
    assert scene_layout(np.array([[-1.0, 1.0]] * 3), "t", ned)["scene"]["zaxis"]["range"] == [1.0, -1.0]
