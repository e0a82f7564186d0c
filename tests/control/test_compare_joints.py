"""Issue 17: ``uvms compare --model`` with an arm of another joint count.

The paper's torque schedule (Section 6) drives joint 1 only; any arm gets it on joint 1 and nothing elsewhere
(the paper's own model gets exactly :func:`uvms.sim.inputs.paper_torques`). A model without an arm is refused in
one line naming ``--model`` (it used to be a traceback: ``ValueError ... has 4 joints``).
"""

from __future__ import annotations

import copy
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
import yaml

import uvms
from uvms.cli import main
from uvms.control.compare import scenario_torques
from uvms.errors import UvmsInputError

PAPER = yaml.safe_load(Path(str(files("uvms.model") / "models" / "paper.yaml")).read_text())


def _model_file(tmp_path, n_joints: int) -> Path:
    data = copy.deepcopy(PAPER)
    if n_joints == 0:
        del data["arm"]
    else:
        links = data["arm"]["links"]
        while len(links) < n_joints:
            extra = copy.deepcopy(links[-1])
            extra["name"] = f"link{len(links) + 1}"
            links.append(extra)
        del links[n_joints:]
    path = tmp_path / f"arm{n_joints}.yaml"
    path.write_text(yaml.safe_dump(data))
    return path


def test_the_paper_model_gets_exactly_the_paper_schedule():
    from uvms.sim.inputs import paper_torques

    schedule = scenario_torques(uvms.load_model("paper"))
    np.testing.assert_array_equal(schedule.times, paper_torques().times)
    np.testing.assert_array_equal(schedule.torques, paper_torques().torques)


@pytest.mark.parametrize("n", [1, 2, 4, 6])
def test_any_arm_gets_the_paper_torques_on_joint_1_only(tmp_path, n):
    schedule = scenario_torques(uvms.load_model(_model_file(tmp_path, n)))
    expected = np.zeros((2, n))
    expected[:, 0] = [2.5, 0.01]                  # Section 6: 2.5 N m, then 0.01 N m after 2 s
    np.testing.assert_array_equal(schedule.torques, expected)
    np.testing.assert_array_equal(schedule.times, [0.0, 2.0])


def test_a_model_without_an_arm_is_refused(tmp_path):
    with pytest.raises(UvmsInputError, match=r"^model: expected a model with an arm .* 0 joints"):
        scenario_torques(uvms.load_model(_model_file(tmp_path, 0)))


def test_cli_compare_refuses_a_model_without_an_arm_in_one_line(tmp_path, capsys):
    assert main(["compare", "--model", str(_model_file(tmp_path, 0)), "--duration", "0.02"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("uvms: error: --model: expected a model with an arm") and err.count("\n") == 1


@pytest.mark.parametrize("n", [1, 4])
def test_cli_compare_runs_on_an_arm_of_another_joint_count(tmp_path, capsys, n):
    out_json = tmp_path / "table.json"
    assert main(["compare", "--model", str(_model_file(tmp_path, n)), "--duration", "0.05",
                 "--json", str(out_json)]) == 0
    import json

    rows = json.loads(out_json.read_text())["rows"]
    assert len(rows) == 5 and all(r["complete"] for r in rows)
    assert all(np.isfinite(r["peak_xy_error_mm"]) for r in rows)
