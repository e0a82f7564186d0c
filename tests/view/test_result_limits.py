"""Saved runs that are too large, too deep or nonsensical are refused at once with one line (issue
"Hardening", items 3, 4 and 6): ``result.csv`` over its size or column limit, ``result.json`` over its size or
nesting limit, times that are NaN, infinite or decreasing; drawing survives values near 1e308 and refuses a
run with nothing to draw; ``uvms animate`` finds a model given by a relative path. Synthetic runs: no
simulation."""

from __future__ import annotations

import json
import shutil
import time
from importlib.resources import files

import numpy as np
import pytest

from uvms.errors import UvmsInputError
from uvms.sim.result import (MAX_HEADER_BYTES, MAX_SUMMARY_BYTES, MAX_TABLE_BYTES, MAX_TABLE_COLUMNS, Result,
                             load_result_summary, load_result_table)

from .conftest import run_cli, synthetic_result
from .test_outputs_kept import uvms_run_folder

COMMANDS = ("plot", "animate", "load")


def _refused_everywhere(run, needle: str, tmp_path) -> None:
    """``uvms plot``, ``uvms animate`` and ``Result.load`` each refuse ``run`` with one line containing
    ``needle``, in under a second, writing nothing."""
    for command in COMMANDS:
        start = time.perf_counter()
        if command == "load":
            with pytest.raises(UvmsInputError, match=needle) as info:
                Result.load(run)
            assert "\n" not in str(info.value)
        else:
            out = tmp_path / f"out-{command}.{'png' if command == 'plot' else 'html'}"
            code, _, err = run_cli([command, run, "-o", out])
            assert code == 2 and err.count("\n") == 1 and "Traceback" not in err, err
            assert needle in err and not out.exists(), err
        assert time.perf_counter() - start < 1.0, command


@pytest.fixture
def run(tmp_path, paper):
    return uvms_run_folder(tmp_path, paper)


def test_a_result_csv_over_the_size_limit_is_refused_at_once(run, tmp_path):
    header = (run / "result.csv").read_text().splitlines()[0]
    with open(run / "result.csv", "w") as fh:                       # a sparse file: no disk space used
        fh.write(header + "\n")
        fh.truncate(MAX_TABLE_BYTES + 1)
    _refused_everywhere(run, "result.csv: refused: larger than 256 MiB", tmp_path)


@pytest.mark.parametrize("count", [MAX_TABLE_COLUMNS + 1, 1_000_000])
def test_a_result_csv_with_too_many_columns_is_refused_at_once(run, tmp_path, count):
    names = ["t_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", "ee_x_m", "ee_y_m"]
    names += [f"c{k}" for k in range(count - len(names))]
    (run / "result.csv").write_text(",".join(names) + "\n" + ",".join(["0"] * count) + "\n")
    needle = "columns, more than the 10,000" if len(",".join(names)) <= MAX_HEADER_BYTES else "header line longer"
    _refused_everywhere(run, needle, tmp_path)


def test_a_result_json_nested_100000_deep_is_refused_at_once(run, tmp_path):
    (run / "result.json").write_text('{"metadata": ' + "[" * 100_000 + "]" * 100_000 + "}")
    _refused_everywhere(run, "result.json: refused: nested more than 64 levels deep", tmp_path)


def test_a_deep_json_in_strings_is_not_nesting(run):
    summary = json.loads((run / "result.json").read_text())
    summary["message"] = "[" * 1000 + '{"\\"'
    (run / "result.json").write_text(json.dumps(summary))
    assert load_result_summary(run)["message"] == summary["message"]


def test_a_result_json_over_the_size_limit_is_refused_at_once(run, tmp_path):
    with open(run / "result.json", "w") as fh:
        fh.write("{}")
        fh.truncate(MAX_SUMMARY_BYTES + 1)
    _refused_everywhere(run, "result.json: refused: larger than 16 MiB", tmp_path)


def test_a_null_metadata_is_no_metadata(run):
    summary = json.loads((run / "result.json").read_text())
    summary["metadata"] = None
    (run / "result.json").write_text(json.dumps(summary))
    assert load_result_summary(run)["metadata"] is None


def _set_times(run, times):
    lines = (run / "result.csv").read_text().splitlines()
    for k, t in times.items():
        cells = lines[k + 1].split(",")
        cells[0] = t
        lines[k + 1] = ",".join(cells)
    (run / "result.csv").write_text("\n".join(lines) + "\n")


@pytest.mark.parametrize("times, needle", [
    ({3: "nan"}, "column 't_s': expected finite times, found nan in row 4"),
    ({0: "inf"}, "column 't_s': expected finite times, found inf in row 1"),
    ({5: "-inf"}, "expected finite times, found -inf in row 6"),
    ({5: "0.01"}, "column 't_s': expected times that do not decrease, found 0.01 after 0.2 in row 6"),
])
def test_nan_infinite_or_decreasing_times_are_refused(run, tmp_path, times, needle):
    _set_times(run, times)
    _refused_everywhere(run, needle, tmp_path)


def test_a_replay_of_a_result_built_in_python_checks_its_times(paper):
    from uvms.view.animate import frame_samples, replay

    result = synthetic_result(paper)
    object.__setattr__(result, "time", np.where(np.arange(len(result.time)) == 4, np.nan, result.time))
    with pytest.raises(UvmsInputError, match="t_s: expected finite times, found nan in sample 5"):
        replay(result, paper)
    with pytest.raises(UvmsInputError, match="finite time span"):
        frame_samples(np.array([-1e308, 1e308]), fps=20, speed=1, max_frames=10)
    samples, fps = frame_samples(np.array([0.0, 1.0, 1e300]), fps=20, speed=1, max_frames=250)
    assert list(samples) == [0, 1, 2] and fps > 0                      # a huge span: no overflow


def test_values_near_the_float_limit_are_left_out_of_the_drawing(run, tmp_path):
    table = load_result_table(run).astype(float)
    table.loc[10:, "x_m"] = 1e308
    table.loc[12, "y_m"] = -np.inf
    table.to_csv(run / "result.csv", index=False)
    code, stdout, err = run_cli(["plot", run])
    assert code == 0, err
    assert (run / "timeseries.png").read_bytes().startswith(b"\x89PNG")


def test_the_drawing_notes_what_it_left_out(paper):
    from uvms.plots import timeseries_figure

    table = synthetic_result(paper).to_dataframe().astype(float)
    table.loc[3, "z_m"] = 1e308
    table.loc[4, "z_m"] = np.inf
    fig = timeseries_figure(table, title="t")
    assert "2 values not finite or beyond 1e+100 not drawn" in fig.get_suptitle()


def test_a_run_with_nothing_to_draw_is_refused(run, tmp_path):
    table = load_result_table(run)
    for column in table.columns[1:]:
        table[column] = np.nan
    table.to_csv(run / "result.csv", index=False)
    code, _, err = run_cli(["plot", run])
    assert code == 2 and err.count("\n") == 1 and "nothing to draw" in err and "result.csv" in err, err
    assert not (run / "timeseries.png").exists()


def test_animate_finds_a_model_given_by_a_relative_path(tmp_path, paper):
    """The copied ``scenario.yaml`` says ``model: models/mine.yaml``, relative to the scenario's own folder,
    which ``result.json`` records (``metadata.scenario_folder``); an older run: ``metadata.scenario_source``."""
    project = tmp_path / "project"
    (project / "models").mkdir(parents=True)
    shutil.copy(files("uvms") / "model" / "models" / "paper.yaml", project / "models" / "mine.yaml")
    scenario = "name: synthetic\nmodel: models/mine.yaml\nduration: 2.0\nactuators: paper-sway\n"
    runs = tmp_path / "elsewhere"
    runs.mkdir()
    new = uvms_run_folder(runs, paper, "new", scenario, {"scenario_folder": str(project)})
    old = uvms_run_folder(runs, paper, "old", scenario, {"scenario_source": str(project / "case.yaml")})
    for run in (new, old):
        code, stdout, err = run_cli(["animate", run, "--fps", "2"])
        assert code == 0, err
        assert (run / "animation.html").is_file()
    lost = uvms_run_folder(runs, paper, "lost", scenario, {"scenario_folder": str(tmp_path / "gone")})
    code, _, err = run_cli(["animate", lost, "--fps", "2"])
    assert code == 2 and "no such model file" in err and err.count("\n") == 1, err


@pytest.mark.parametrize("case", ["huge_position", "nan_joint"])
def test_a_replay_stops_before_a_pose_it_cannot_draw(paper, case):
    from uvms.view.animate import REPLAY_LIMIT, replay

    result = synthetic_result(paper)
    states = result.states.copy()
    if case == "huge_position":
        states[20:, 0] = 1e308
    else:
        states[20:, 13] = np.nan
    object.__setattr__(result, "states", states)
    rp = replay(result, paper, fps=20)
    assert rp.times[-1] == pytest.approx(result.time[19]) and len(rp.snaps) == 20
    assert f"stops at t = {result.time[19]:.4g} s" in rp.title
    assert np.all(np.abs(rp.vehicle_path) < REPLAY_LIMIT)


def test_a_replay_with_no_drawable_pose_is_one_line(run, tmp_path):
    table = load_result_table(run).astype(float)
    table["x_m"] = np.inf
    table.to_csv(run / "result.csv", index=False)
    code, _, err = run_cli(["animate", run, "-o", tmp_path / "a.html"])
    assert code == 2 and err.count("\n") == 1 and "nothing to replay" in err, err
    assert not (tmp_path / "a.html").exists()


def test_a_run_of_a_scenario_with_a_relative_model_path_can_be_animated(tmp_path, monkeypatch):
    """End to end: ``uvms run`` records the scenario's folder, so ``uvms animate`` run from anywhere finds the
    model the run used (the copied ``scenario.yaml`` says ``model: models/mine.yaml``)."""
    import yaml

    from .conftest import CASE2

    project = tmp_path / "project"
    (project / "models").mkdir(parents=True)
    shutil.copy(files("uvms") / "model" / "models" / "paper.yaml", project / "models" / "mine.yaml")
    data = dict(CASE2, name="relative", duration=0.05, model="models/mine.yaml")
    (project / "case.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    monkeypatch.chdir(project)
    code, _, err = run_cli(["run", "case.yaml", "-o", tmp_path / "runs" / "r"])
    assert code == 0, err
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    code, stdout, err = run_cli(["animate", tmp_path / "runs" / "r", "--fps", "10"])
    assert code == 0, err
    assert (tmp_path / "runs" / "r" / "animation.html").is_file()


def test_a_playback_speed_that_makes_the_replay_endless_is_one_line(synthetic_run, tmp_path):
    code, _, err = run_cli(["animate", synthetic_run[0], "-o", tmp_path / "a.html", "--speed", "1e-320"])
    assert code == 2 and err.count("\n") == 1 and "--speed: expected a playback speed" in err, err
    assert not (tmp_path / "a.html").exists()
