"""``uvms run`` and ``uvms plot`` end to end: exit codes, one-line errors, nothing written for a bad scenario,
atomic output directories, incomplete (diverged) runs, figures."""

from __future__ import annotations

import copy
import json
from importlib.resources import files

import pandas as pd
import pytest
import yaml

from uvms.cli import main

CASE2 = yaml.safe_load((files("uvms") / "scenarios" / "paper_case2_released.yaml").read_text())
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"


def write_scenario(tmp_path, mutate=None, name="case.yaml"):
    """Paper case 2 shortened to 0.2 s (and changed by ``mutate``), written to ``tmp_path/name``."""
    data = copy.deepcopy(CASE2)
    data.update(name="short", duration=0.2)
    if mutate is not None:
        mutate(data)
    path = tmp_path / name
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return path


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    """One good short run shared by the tests that only read it: (directory, exit code, stdout, stderr)."""
    tmp_path = tmp_path_factory.mktemp("run")
    path = write_scenario(tmp_path)
    out = tmp_path / "out"
    with pytest.MonkeyPatch.context() as mp:
        import io
        import sys

        stdout, stderr = io.StringIO(), io.StringIO()
        mp.setattr(sys, "stdout", stdout)
        mp.setattr(sys, "stderr", stderr)
        code = main(["run", str(path), "-o", str(out)])
    return out, code, stdout.getvalue(), stderr.getvalue(), path


BAD = {  # change to the short scenario -> text the one error line must contain
    "typo_key": (lambda d: d.update(duraton=1.0), "case.yaml: duraton: unknown key"),
    "wrong_type": (lambda d: d.update(step="fast"), "case.yaml: step: expected a finite number, found 'fast'"),
    "missing_model_file": (lambda d: d.update(model="models/missing.yaml"),
                           "case.yaml: model: no such model file"),
    "negative_duration": (lambda d: d.update(duration=-0.2), "case.yaml: duration: expected a number > 0"),
    "wrong_torque_length": (lambda d: d["inputs"]["joint_torques"][0].update(torques=[2.5, 0]),
                            "case.yaml: inputs.joint_torques[0].torques: expected 3 values"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_scenario_exits_2_with_one_line_and_writes_nothing(tmp_path, monkeypatch, capsys, case):
    mutate, expected = BAD[case]
    path = write_scenario(tmp_path, mutate)
    monkeypatch.chdir(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    assert main(["run", str(path), "-o", str(tmp_path / "out")]) == 2
    assert main(["run", str(path)]) == 2  # default directory runs/<name>
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 2 and lines[0] == lines[1], captured.err
    assert lines[0].startswith("uvms: error: ") and expected in lines[0], lines[0]
    if case == "missing_model_file":
        assert str(tmp_path / "models" / "missing.yaml") in lines[0]
    assert "Traceback" not in captured.err + captured.out
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # no out/, no runs/, no temporary directory


def test_missing_scenario_file_exits_2(tmp_path, capsys):
    assert main(["run", str(tmp_path / "nope.yaml"), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "nope.yaml: no such file or bundled scenario" in err
    assert not (tmp_path / "out").exists()


def test_good_run_writes_results(short_run):
    out, code, stdout, stderr, path = short_run
    assert code == 0, stderr
    assert sorted(p.name for p in out.iterdir()) == [".uvms-output.json", "result.csv", "result.json",
                                                     "scenario.yaml"]
    assert json.loads((out / ".uvms-output.json").read_text())["files"] == ["result.csv", "result.json",
                                                                             "scenario.yaml"]
    assert sorted(p.name for p in out.parent.iterdir()) == ["case.yaml", "out"]  # no temporary leftovers
    table = pd.read_csv(out / "result.csv")
    expected = ["t_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s",
                "u_m_s", "v_m_s", "w_m_s", "q_joint1_rad", "q_joint2_rad", "q_joint3_rad", "qd_joint1_rad_s",
                "qd_joint2_rad_s", "qd_joint3_rad_s", "tau_joint1_Nm", "tau_joint2_Nm", "tau_joint3_Nm",
                "ee_x_m", "ee_y_m", "ee_z_m"]
    assert list(table.columns) == expected
    assert len(table) == 201 and table["t_s"].iloc[-1] == pytest.approx(0.2)
    assert table["tau_joint1_Nm"].eq(2.5).all() and table["q_joint1_rad"].iloc[-1] > 0
    summary = json.loads((out / "result.json").read_text())
    assert summary["complete"] is True and summary["message"] == ""
    assert summary["metadata"]["scenario"] == "short"
    assert (out / "scenario.yaml").read_text() == path.read_text()
    assert "short: complete" in stdout and "wall time" in stdout and "final joint angles" in stdout
    assert stderr == ""


def test_rerun_replaces_a_previous_run_but_never_a_folder_holding_other_files(tmp_path, capsys):
    path = write_scenario(tmp_path, lambda d: d.update(duration=0.01))
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out)]) == 0
    first = (out / "result.json").read_text()
    assert main(["run", str(path), "-o", str(out)]) == 0             # uvms's own files, unchanged: replaced
    assert (out / "result.json").read_text() != first                # (the wall time differs)
    (out / "result.csv").write_text("an older table")              # listed, but changed since: the user's now
    capsys.readouterr()
    assert main(["run", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "changed since uvms wrote it" in err and "result.csv" in err
    assert (out / "result.csv").read_text() == "an older table"
    assert main(["run", str(path), "-o", str(out), "--force"]) == 0   # an earlier run's folder, forced
    assert (out / "result.csv").read_text() != "an older table" and (out / "result.json").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case.yaml", "out"]

    (out / "stale.txt").write_text("the user's notes, written into an earlier run")
    (out / "figures").mkdir()
    before = {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()}
    capsys.readouterr()
    assert main(["run", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "2 entries that uvms did not write (figures, stale.txt)" in err
    assert {p.name: p.read_bytes() for p in out.iterdir() if p.is_file()} == before

    for name, files in {"precious": {"notes.txt": "keep me"},
                        "lookalike": {"result.json": "{}", "notes.txt": "precious"},
                        "thesis": {"metrics.json": "{}", "thesis.tex": "\\documentclass"}}.items():
        folder = tmp_path / name
        folder.mkdir()
        for file, text in files.items():
            (folder / file).write_text(text)
        capsys.readouterr()
        assert main(["run", str(path), "-o", str(folder)]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "uvms did not write" in err and str(folder) in err
        assert {p.name: p.read_text() for p in folder.iterdir()} == files


def test_diverging_run_exits_3_and_saves_an_incomplete_result(tmp_path, capsys):
    path = write_scenario(tmp_path, lambda d: d.update(
        duration=1.0, step=0.01, vehicle="fixed", inputs={"joint_torques": {"constant": [1e9, 0, 0]}}))
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out)]) == 3
    captured = capsys.readouterr()
    lines = captured.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("uvms: error: simulation diverged at t = "), captured.err
    assert "Traceback" not in captured.err
    summary = json.loads((out / "result.json").read_text())
    assert summary["complete"] is False and summary["message"] in lines[0]
    table = pd.read_csv(out / "result.csv")
    assert len(table) >= 1 and table["t_s"].iloc[-1] < 1.0
    assert "INCOMPLETE" in captured.out


def test_plot_writes_a_png(short_run, tmp_path, capsys):
    out = short_run[0]
    assert main(["plot", str(out)]) == 0
    png = out / "timeseries.png"
    assert png.read_bytes()[:8] == PNG_MAGIC and png.stat().st_size > 20_000
    other = tmp_path / "figs" / "short.png"
    assert main(["plot", str(out), "-o", str(other)]) == 0
    assert other.read_bytes()[:8] == PNG_MAGIC
    assert "figure saved to" in capsys.readouterr().out


def test_plot_of_a_directory_without_results_exits_2(tmp_path, capsys):
    assert main(["plot", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no result.csv here" in err
    assert main(["plot", str(tmp_path / "missing")]) == 2
    assert "no such run directory" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_controlled_run_logs_and_plots_controller_signals(tmp_path, capsys):
    pytest.importorskip("uvms.control.registry")
    from uvms.plots import _panels

    path = write_scenario(tmp_path, lambda d: d.update(
        duration=0.05, controller={"name": "smc-ab", "period": 0.01}, actuators="ideal"))
    out = tmp_path / "out"
    assert main(["run", str(path), "-o", str(out)]) == 0, capsys.readouterr().err
    table = pd.read_csv(out / "result.csv")
    assert {"command_X", "command_Y", "command_N"} <= set(table.columns)
    assert len(_panels(table)) > 5  # the commanded-wrench panels (and the controller's own signals) are drawn
    assert main(["plot", str(out)]) == 0
    assert (out / "timeseries.png").read_bytes()[:8] == PNG_MAGIC
