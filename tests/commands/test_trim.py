"""``uvms trim MODEL [--q NAME=VALUE ...] [--json]``: text and JSON on the console; a trim with no solution and
bad ``--q`` values are one line on stderr and exit 2."""

from __future__ import annotations

import json
import math

import pytest

from uvms.cli import main


def test_text_trim_of_the_bundled_vehicle(capsys):
    """Arm stretched out (q = 0): the BlueROV2 Heavy + Alpha 5 rests nose up (its foam trims it for q_d = q_c = 0.4);
    the ballast that levels it goes to the front, low."""
    assert main(["trim", "bluerov2_heavy_alpha5"]) == 0
    out, err = capsys.readouterr()
    assert err == ""
    assert "rests at:           roll" in out and "pitch 1.658 deg" in out
    assert "to level it:" in out and "kg point mass at (0.23," in out
    assert sum(line.startswith("warning: sliding-mode controller") for line in out.splitlines()) == 1
    assert sum("outside [" in line for line in out.splitlines()) == 1       # the three axes on that one line


def test_json_trim_with_joint_names(capsys):
    assert main(["trim", "bluerov2_heavy_alpha5", "--q", "axis_d=0.4", "axis_c=0.4", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["q"] == {"axis_e": 0.0, "axis_d": 0.4, "axis_c": 0.4, "axis_b": 0.0}
    assert data["level"] is True and data["ballast"] is None
    assert abs(data["rest"]["pitch_rad"]) < math.radians(0.01)
    assert data["net_buoyancy_N"] == pytest.approx(0.003, abs=0.001)


def test_foam_ballast_in_a_region(capsys):
    assert main(["trim", "bluerov2_heavy_alpha5", "--ballast", "foam", "--foam-density", "350", "--region",
                 "-0.2", "-0.2", "-0.12", "0.2", "0.2", "0", "--json"]) == 0
    b = json.loads(capsys.readouterr().out)["ballast"]
    assert b["kind"] == "foam" and b["unit"] == "m^3" and b["amount"] > 0
    assert b["position_m"][0] == pytest.approx(-0.2) and b["position_m"][2] == pytest.approx(-0.12)


@pytest.mark.parametrize("argv, expected", [
    (["--max", "0.01"], "uvms: error: ballast: cannot float level: no point mass of at most 0.01 kg"),
    (["--q", "axis_z=1"], "uvms: error: --q: model 'bluerov2_heavy_alpha5' has no joint 'axis_z'"),
    (["--q", "axis_d"], "uvms: error: --q: expected NAME=VALUE"),
    (["--q", "axis_d=1", "axis_d=2"], "uvms: error: --q: joint 'axis_d' is given twice"),
    (["--ballast", "foam", "--foam-density", "1100"], "uvms: error: --foam-density: expected a foam density"),
])
def test_bad_input_is_one_line_and_exit_2(capsys, argv, expected):
    assert main(["trim", "bluerov2_heavy_alpha5", *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.startswith(expected) and err.count("\n") == 1


def test_repeated_q_options_add_up(capsys):
    """``--q a=1 --q b=2`` gives both joints (argparse's extend), as ``--q a=1 b=2`` does."""
    from uvms.cli import main

    assert main(["trim", "bluerov2_heavy_alpha5", "--q", "axis_d=0.4", "--q", "axis_c=0.4", "--json"]) == 0
    apart = capsys.readouterr().out
    assert main(["trim", "bluerov2_heavy_alpha5", "--q", "axis_d=0.4", "axis_c=0.4", "--json"]) == 0
    assert capsys.readouterr().out == apart


@pytest.mark.parametrize("argv, expected", [
    (["--max", "-1"], "uvms: error: --max: expected a finite number >= 0, found -1.0"),
    (["--region", "nan", "0", "0", "1", "1", "1"], "uvms: error: --region: expected finite corners"),
    (["--region", "0.2", "-0.2", "-0.1", "-0.2", "0.2", "0.1"],
     "uvms: error: --region: expected the lower corner first (x0 <= x1)"),
    (["--ballast", "foam", "--foam-density", "1100"], "uvms: error: --foam-density: expected a foam density"),
    (["--foam-density", "nan"], "uvms: error: --foam-density: expected a foam density"),
    (["--min-arm", "inf"], "uvms: error: --min-arm: expected a finite number >= 0, found inf"),
])
def test_options_are_checked_when_no_ballast_is_needed(capsys, argv, expected):
    """The arm at its start pose: the BlueROV2 rests level (no ballast computed), yet every option is checked."""
    level = ["trim", "bluerov2_heavy_alpha5", "--q", "axis_d=0.4", "axis_c=0.4"]
    assert main(level) == 0 and "level already" in capsys.readouterr().out
    assert main([*level, *argv]) == 2
    out, err = capsys.readouterr()
    assert out == "" and err.startswith(expected) and err.count("\n") == 1
