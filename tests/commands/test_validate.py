"""``uvms validate MODEL [--q ...] [--json]``: the statics, thrust and controller-fit report on the console and
as JSON; bad ``--q`` values are one line and exit 2."""

from __future__ import annotations

import copy
import json
from importlib.resources import files

import pytest
import yaml

from uvms.cli import main

PAPER = yaml.safe_load((files("uvms.model") / "models" / "paper.yaml").read_text())


def write_model(tmp_path, mutate):
    data = copy.deepcopy(PAPER)
    mutate(data)
    path = tmp_path / "model.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_text_report_of_the_paper_model(capsys):
    assert main(["validate", "paper"]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    assert "paper: valid" in out and "total mass:           35 kg" in out
    assert "net buoyancy:         0 N" in out
    assert "static moment:        (0, 0, 0) N m" in out
    assert "righting moment:      7.97357 N m" in out          # 32 kg x 9.81 m/s^2 x 0.0254 m
    assert "settles to:           roll 0 deg, pitch 0 deg" in out
    assert "linear programming" in out
    assert "surge  +103.6 / -103.6 N" in out and "yaw    +15.54 / -15.54 N m" in out   # 2 T, 0.3 T; T = 51.8 N
    assert "layout rank 4 of 6; cannot push in: roll, pitch" in out
    warnings = [line for line in out.splitlines() if line.startswith("warning:")]
    assert len(warnings) == 1 and "surge effective mass" in warnings[0] and "[36, 44.44] kg" in warnings[0]
    assert "sway effective mass 50.87 kg outside [36, 44.44] kg" in warnings[0]


def test_json_report(capsys):
    assert main(["validate", "paper", "--json", "--q", "0.1", "0.2", "0.3"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["valid"] is True and data["model"] == "paper"
    assert data["q"] == {"joint1": 0.1, "joint2": 0.2, "joint3": 0.3}
    assert data["total_mass_kg"] == 35.0 and data["net_buoyancy_N"] == 0.0
    assert data["thrust"]["allocation_rank"] == 4 and data["thrust"]["missing_axes"] == ["roll", "pitch"]
    assert data["thrust"]["forward_N_or_Nm"]["sway"] == pytest.approx(51.8, abs=0.05)
    assert set(data["effective_inertia_kg_or_kgm2"]) == {"surge", "sway", "heave", "roll", "pitch", "yaw"}
    assert len(data["warnings"]) == 1 and "surge" in data["warnings"][0] and "sway" in data["warnings"][0] and data["trim"]["pitch_rad"] == pytest.approx(0.0, abs=1e-12)


def test_offset_model_reports_its_trim_and_no_stable_attitude(tmp_path, capsys):
    """Vehicle CoM 0.0254 m ahead of its CoB line: tan(theta) = -0.0254 / 0.0254 -> pitch -45 deg."""
    path = write_model(tmp_path, lambda d: d["vehicle"].update(com=[0.0254, 0.0, 0.0]))
    assert main(["validate", str(path)]) == 0
    out = capsys.readouterr().out
    assert "settles to:           roll 0 deg, pitch -45 deg" in out
    assert "static moment:        (0, -7.97357, 0) N m" in out      # -a m0 g = -0.0254 x 32 x 9.81
    path = write_model(tmp_path, lambda d: d["vehicle"]["buoyancy"].update(center=[0.0, 0.0, 0.0]))
    assert main(["validate", str(path)]) == 0
    assert "no stable attitude (centre of mass and centre of buoyancy coincide)" in capsys.readouterr().out


def test_layout_without_sway_is_named(tmp_path, capsys):
    path = write_model(tmp_path, lambda d: d.update(thrusters=d["thrusters"][:3]))
    assert main(["validate", str(path)]) == 0
    assert "layout rank 3 of 6; cannot push in: sway, roll, pitch" in capsys.readouterr().out


@pytest.mark.parametrize("argv, expected", [
    (["--q", "0", "0"], "--q: expected 3 joint values (joints: joint1, joint2, joint3), found 2"),
    (["--q", "0", "nan", "0"], "--q: expected finite joint values"),
    (["--q", "0", "inf", "0"], "--q: expected finite joint values"),
    (["--q", "0", "x", "0"], "--q: expected NAME=VALUE (a joint name and a number) or numbers in joint order, found 'x'"),
])
def test_bad_q_one_line_exit_2(capsys, argv, expected):
    assert main(["validate", "paper", *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.count("\n") == 1 and err.startswith("uvms: error: ") and expected in err


def test_end_effector_is_named_as_the_model_file_names_it(capsys):
    """The BlueROV2 Heavy + Alpha 5 file says ``end_effector: tool``: the summary says ``tool`` (the frame
    between the jaw tips), and the body it is fixed in; the paper's DH end effector is a frame of its own."""
    import uvms
    from uvms.analysis.report import end_effector_name

    assert main(["validate", "bluerov2_heavy_alpha5"]) == 0
    assert "(end effector 'tool', fixed in body 'm1_link')" in capsys.readouterr().out
    assert main(["validate", "bluerov2_heavy_alpha5", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["end_effector"] == "tool" and data["end_effector_body"] == "m1_link"
    assert main(["validate", "paper"]) == 0
    assert "(end effector 'end_effector', fixed in body 'link3')" in capsys.readouterr().out
    model = uvms.load_model("bluerov2_heavy_alpha5")
    assert end_effector_name(model.with_end_effector("jaws_base_link")) == "jaws_base_link"
    assert end_effector_name(model.with_end_effector("m1_link")) == "m1_link"
